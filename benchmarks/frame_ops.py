"""Operation counts of the generated frame functions (``frame_pose``, ``frame_jacobian``,
``frame_drift``, ``center_of_mass``, ``com_jacobian``, ``centroidal_momentum`` and its
derivatives;
:mod:`symgen.frame_kinematics`) on the benchmark chain and two arms, beside ``inverse_dynamics``
for scale. Counts as ``ops.json`` gives them: mul + add (``total``); sin/cos apart.

The frame is the tool's: ``tool0`` (UR5), ``panda_hand_tcp`` (Panda), and on ``chain:n=N`` a frame
``tip`` added on the last link, 0.1 m along its x axis.

    python benchmarks/frame_ops.py        # writes benchmarks/frame_ops.md and .csv
"""
import csv
from pathlib import Path

import symgen
from symgen.codegen.generate import operation_counts
from symgen.model import derive

SCENES = {"chain:n=6": "tip", "chain:n=32": "tip", "ur5": "tool0", "panda": "panda_hand_tcp"}
#: column -> (function, axes)
COLUMNS = {"frame_pose": ("frame_pose", "local"), "frame_jacobian": ("frame_jacobian", "local"),
           "frame_jacobian_world": ("frame_jacobian", "world_aligned"), "frame_drift": ("frame_drift", "local"),
           "frame_drift_world": ("frame_drift", "world_aligned"), "center_of_mass": ("center_of_mass", "local"),
           "com_jacobian": ("com_jacobian", "local"), "centroidal_momentum": ("centroidal_momentum", "local"),
           "centroidal_momentum_derivatives": ("centroidal_momentum_derivatives", "local"),
           "inverse_dynamics": ("inverse_dynamics", "local")}


def load(spec: str, frame: str):
    scene = symgen.load(spec)
    if frame not in scene.frames:
        last = list(scene.bodies)[-1]
        scene.add_frame(frame, last, xyz=(0.1, 0, 0))
    return derive(scene)


def measure(spec: str, frame: str) -> dict:
    model = load(spec, frame)
    row = {"scene": spec, "frame": frame, "n": model.counts.n}
    for axes in ("local", "world_aligned"):
        names = [f for f, a in COLUMNS.values() if a == axes]
        ops = operation_counts(model, names, {"frame": frame, "axes": axes})
        for column, (function, a) in COLUMNS.items():
            if a == axes:
                row[column] = ops[function]["total"] + ops[function]["solve_flops"]
    return row


def main() -> None:
    rows = [measure(spec, frame) for spec, frame in SCENES.items()]
    here = Path(__file__).parent
    fields = ["scene", "frame", "n", *COLUMNS]
    with open(here / "frame_ops.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=fields, lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
    lines = ["# Frame kinematics, centre of mass and momentum: operation counts", "",
             "`python benchmarks/frame_ops.py`. Operations: mul + add as `ops.json` counts them (sin and cos apart). "
             "`_world`: the frame's Jacobian or drift in world-aligned axes (Pinocchio's `LOCAL_WORLD_ALIGNED`), "
             "the others in its own (`LOCAL`); `inverse_dynamics` for scale.", "",
             "| " + " | ".join(fields) + " |", "|" + "---|" * len(fields)]
    lines += ["| " + " | ".join(str(r[k]) for k in fields) + " |" for r in rows]
    (here / "frame_ops.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
