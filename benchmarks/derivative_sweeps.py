"""Operation counts of the generated derivatives by the forward and the reverse (adjoint) sweep
(``symgen.codegen.reverse``): ``inverse_dynamics_derivatives`` against the primal
``inverse_dynamics``, per scene and on the benchmark chain ``chain:n=N``; and the explicit partials
of ``forward_dynamics_derivatives``'s implicit routes, ``implicit-dense`` against
``implicit-dense-reverse`` (the whole function's operations). Mul + add (+ library-solve flops),
as ``ops.json`` counts them; the generator keeps the cheaper and records both in ``method_costs``.

    python benchmarks/derivative_sweeps.py    # writes benchmarks/derivative_sweeps.md and .csv
"""
import csv
import time
from pathlib import Path

from symgen.codegen.generate import operation_counts

from derivative_ops import cost, load

SCENES = ["chain:n=6", "ur5", "panda", "four_bar", "five_bar", "arm_on_plane"]
CHAIN = [3, 12, 24]
FUNCTIONS = ["inverse_dynamics", "inverse_dynamics_derivatives"]
FORWARD_SCENES = ["chain:n=6", "ur5", "panda", "four_bar", "arm_on_plane"]


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


def measure_forward(spec: str) -> dict:
    costs = operation_counts(load(spec), ["forward_dynamics_derivatives"])["forward_dynamics_derivatives"]
    costs, kept = costs["method_costs"], costs["method"]
    return {"scene": spec, "forward": costs["implicit-dense"], "reverse": costs["implicit-dense-reverse"],
            "sweep": "reverse" if kept == "implicit-dense-reverse" else "forward" if kept == "implicit-dense" else kept,
            "kept": kept, "best": costs[kept]}


def main() -> None:
    rows = [measure(spec) for spec in SCENES + [f"chain:n={n}" for n in CHAIN]]
    forward = [measure_forward(spec) for spec in FORWARD_SCENES]
    lines = ["# Generated derivatives: the forward and the reverse sweep", "",
             "`python benchmarks/derivative_sweeps.py`. Operations: mul + add, as `ops.json` counts them; "
             "`inverse_dynamics_derivatives` traced by both sweeps, the cheaper kept (`symgen.codegen.reverse`; "
             "a graph whose library solves depend on the inputs keeps the forward sweep).", "",
             "| scene | inverse_dynamics | forward sweep | reverse sweep | kept | ratio to primal | saved |",
             "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['scene']} | {r['primal']} | {r['forward']} | {r['reverse'] or '-'} | {r['sweep']} | "
                     f"{r['ratio']:.2f} | {r['saved']:.0%} |")
    lines += ["", "## forward_dynamics_derivatives: the implicit route's explicit partials", "",
              "| scene | implicit-dense | implicit-dense-reverse | route kept | its operations |", "|---|---|---|---|---|"]
    for r in forward:
        lines.append(f"| {r['scene']} | {r['forward']} | {r['reverse']} | {r['kept']} | {r['best']} |")
    here = Path(__file__).parent
    (here / "derivative_sweeps.md").write_text("\n".join(lines) + "\n")
    with open(here / "derivative_sweeps.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=["scene", "primal", "forward", "reverse", "sweep", "derivatives", "ratio"],
                                lineterminator="\n", extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)
    with open(here / "derivative_sweeps_forward.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=["scene", "forward", "reverse", "kept", "best"], lineterminator="\n",
                                extrasaction="ignore")
        writer.writeheader()
        writer.writerows(forward)
    print("\n".join(lines))


if __name__ == "__main__":
    main()
