"""Operation counts of the generated ``inverse_dynamics_derivatives`` by the forward and the
reverse (adjoint) sweep (``symgen.codegen.reverse``), against the primal ``inverse_dynamics``, per
scene and on the benchmark chain ``chain:n=N``: mul + add, as ``ops.json`` counts them (the
generator keeps the cheaper sweep and records both in ``method_costs``).

    python benchmarks/inverse_derivative_ops.py    # writes benchmarks/inverse_derivative_ops.md and .csv
"""
import csv
import time
from pathlib import Path

from symgen.codegen.generate import operation_counts

from derivative_ops import cost, load

SCENES = ["chain:n=6", "ur5", "panda", "four_bar", "five_bar", "arm_on_plane"]
CHAIN = [3, 12, 24]
FUNCTIONS = ["inverse_dynamics", "inverse_dynamics_derivatives"]


def measure(spec: str) -> dict:
    start = time.perf_counter()
    ops = operation_counts(load(spec), FUNCTIONS)
    d = ops["inverse_dynamics_derivatives"]
    row = {"scene": spec, "primal": cost(ops["inverse_dynamics"]), "derivatives": cost(d),
           "forward": d["method_costs"]["forward"], "reverse": d["method_costs"].get("reverse", ""),
           "sweep": d["method"], "seconds": time.perf_counter() - start}
    row["ratio"] = row["derivatives"] / row["primal"]
    row["saved"] = 1 - row["derivatives"] / row["forward"]
    return row


def main() -> None:
    rows = [measure(spec) for spec in SCENES + [f"chain:n={n}" for n in CHAIN]]
    lines = ["# Derivatives of inverse dynamics: forward and reverse sweeps", "",
             "`python benchmarks/inverse_derivative_ops.py`. Operations: mul + add, as `ops.json` counts them; "
             "`inverse_dynamics_derivatives` traced by both sweeps, the cheaper kept (`symgen.codegen.reverse`; "
             "a graph whose library solves depend on the inputs keeps the forward sweep).", "",
             "| scene | inverse_dynamics | forward sweep | reverse sweep | kept | ratio to primal | saved |",
             "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['scene']} | {r['primal']} | {r['forward']} | {r['reverse'] or '-'} | {r['sweep']} | "
                     f"{r['ratio']:.2f} | {r['saved']:.0%} |")
    here = Path(__file__).parent
    (here / "inverse_derivative_ops.md").write_text("\n".join(lines) + "\n")
    with open(here / "inverse_derivative_ops.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=["scene", "primal", "forward", "reverse", "sweep", "derivatives", "ratio"],
                                lineterminator="\n", extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)
    print("\n".join(lines))


if __name__ == "__main__":
    main()
