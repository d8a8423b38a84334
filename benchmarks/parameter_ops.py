"""Operation counts of the generated functions with inertial parameters folded into the code and
read at run time from ``p`` (:mod:`symgen.codegen.parameters`).

Scenes: the UR5 with a 1.5 kg payload fixed 0.1 m off its last link (the payload's ten parameters
in ``p``), the four-bar with its coupler's ten in ``p`` (a closed chain), and ``chain:n=6`` with
every body's ten in ``p`` (60). Counts as ``ops.json`` gives them: mul + add plus the flops of
library solves; they are of the traced graph, so they do not depend on the machine.

    python benchmarks/parameter_ops.py        # writes benchmarks/parameter_ops.md and .csv
"""
from __future__ import annotations

import csv
import sys
from pathlib import Path

import symgen
from symgen.codegen.generate import operation_counts
from symgen.io.urdf.examples import ur5

HERE = Path(__file__).resolve().parent
FUNCTIONS = ["inverse_dynamics", "mass_matrix", "forward_dynamics", "gravity", "coriolis_times_v"]
#: the payload of the UR5 case: mass, centre of mass, inertia about it (ixx, iyy, izz, ixy, ixz, iyz)
PAYLOAD = (1.5, (0.01, 0.02, 0.05), (0.01, 0.012, 0.008, 0.001, 0.0, 0.0005))


def ur5_with_payload(values=PAYLOAD):
    """The UR5 holding a payload body fixed 0.1 m along ``y`` of ``wrist_3_link``."""
    mass, com, inertia = values
    scene = ur5()
    scene.add_body("payload", mass, com=list(com), inertia=list(inertia))
    scene.add_joint("payload_mount", "fixed", "wrist_3_link", "payload", xyz=[0, 0.1, 0])
    return scene


def cases():
    """``(label, scene, parameters)`` of the table."""
    chain = symgen.load("chain:n=6")
    return [("ur5 + payload", ur5_with_payload(), ["payload"]),
            ("four_bar", symgen.load("four_bar"), ["coupler"]),
            ("chain:n=6", chain, sorted(chain.bodies))]


def cost(ops: dict) -> int:
    return ops["total"] + ops["solve_flops"]


def measure() -> list[dict]:
    rows = []
    for label, scene, chosen in cases():
        model = symgen.derive(scene)
        folded = operation_counts(model, FUNCTIONS)
        inputs = operation_counts(model, FUNCTIONS, parameters=chosen)
        size = 10 * len(chosen)
        for fn in FUNCTIONS:
            a, b = cost(folded[fn]), cost(inputs[fn])
            rows.append({"scene": label, "parameters": size, "function": fn, "folded": a,
                         "parameterised": b, "ratio": f"{b / a:.2f}" if a else "-"})
    return rows


def main() -> int:
    rows = measure()
    with open(HERE / "parameter_ops.csv", "w", newline="", encoding="utf-8") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]), lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
    lines = ["# Run-time inertial parameters: operation counts", "",
             "`python benchmarks/parameter_ops.py`. Operations: mul + add + library-solve flops, as `ops.json` "
             "counts them, with every constant folded and with the chosen bodies' ten inertial parameters "
             "(mass, centre of mass, inertia about it) read from the input `p` "
             "(`symgen.codegen.parameters`).", "",
             "| scene | parameters | function | folded | parameterised | ratio |", "|---|---|---|---|---|---|"]
    lines += [f"| {r['scene']} | {r['parameters']} | {r['function']} | {r['folded']} | {r['parameterised']} | "
              f"{r['ratio']} |" for r in rows]
    (HERE / "parameter_ops.md").write_text("\n".join(lines) + "\n", encoding="utf-8")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
