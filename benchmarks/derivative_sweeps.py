"""Operation counts of the generated derivatives by the forward and the reverse (adjoint) sweep
(``symgen.codegen.reverse``) and by the closed form (``symgen.dynamics.rnea_derivatives``, on trees
of one-coordinate joints): ``inverse_dynamics_derivatives`` against the primal
``inverse_dynamics``, per scene and on the benchmark chain ``chain:n=N``; and the explicit partials
of ``forward_dynamics_derivatives``'s implicit routes, ``implicit-dense`` against
``implicit-dense-reverse`` and ``implicit-dense-analytic`` (the whole function's operations). Mul +
add (+ the flops of library solves and products), as ``ops.json`` counts them; the generator keeps
the cheapest and records every cost in ``method_costs``.

    python benchmarks/derivative_sweeps.py    # writes benchmarks/derivative_sweeps.md and .csv
"""
import csv
import time
from pathlib import Path

from symgen.codegen.dynamics_derivatives import LOOPED_PAIRS
from symgen.codegen.generate import operation_counts

from derivative_ops import cost, load

SCENES = ["chain:n=6", "ur5", "panda", "general_chain:n=7", "four_bar", "five_bar", "arm_on_plane"]
CHAIN = [3, 10, 12, 24, 32]
FUNCTIONS = ["inverse_dynamics", "inverse_dynamics_derivatives"]
FORWARD_SCENES = ["chain:n=6", "ur5", "panda", "general_chain:n=7", "four_bar", "arm_on_plane"]


def measure(spec: str) -> dict:
    start = time.perf_counter()
    ops = operation_counts(load(spec), FUNCTIONS)
    d = ops["inverse_dynamics_derivatives"]
    row = {"scene": spec, "primal": cost(ops["inverse_dynamics"]), "derivatives": cost(d),
           "forward": d["method_costs"]["forward"], "reverse": d["method_costs"].get("reverse", ""),
           "analytic": d["method_costs"].get("analytic", ""), "sweep": d["method"],
           "seconds": time.perf_counter() - start}
    row["ratio"] = row["derivatives"] / row["primal"]
    row["saved"] = 1 - row["derivatives"] / row["forward"]
    return row


def measure_forward(spec: str) -> dict:
    costs = operation_counts(load(spec), ["forward_dynamics_derivatives"])["forward_dynamics_derivatives"]
    costs, kept = costs["method_costs"], costs["method"]
    return {"scene": spec, "forward": costs["implicit-dense"], "reverse": costs["implicit-dense-reverse"],
            "analytic": costs.get("implicit-dense-analytic", ""), "kept": kept, "best": costs[kept]}


def main() -> None:
    rows = [measure(spec) for spec in SCENES + [f"chain:n={n}" for n in CHAIN]]
    forward = [measure_forward(spec) for spec in FORWARD_SCENES]
    lines = ["# Generated derivatives: the forward and the reverse sweep, and the closed form", "",
             "`python benchmarks/derivative_sweeps.py`. Operations: mul + add plus the flops of library loops, as "
             "`ops.json` counts them (the closed form's entries are banded library products on trees of at least "
             f"`LOOPED_PAIRS` = {LOOPED_PAIRS} ancestor pairs, a chain of N having N (N + 1) / 2); "
             "`inverse_dynamics_derivatives` traced by both sweeps (`symgen.codegen.reverse`; a graph whose "
             "library solves depend on the inputs keeps the forward sweep) and, on a tree of one-coordinate "
             "joints, by the closed form (`symgen.dynamics.rnea_derivatives`); the cheapest kept. **saved**: "
             "the kept route's operations below the forward sweep's.", "",
             "| scene | inverse_dynamics | forward sweep | reverse sweep | closed form | kept | ratio to primal | saved |",
             "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['scene']} | {r['primal']} | {r['forward']} | {r['reverse'] or '-'} | "
                     f"{r['analytic'] or '-'} | {r['sweep']} | {r['ratio']:.2f} | {r['saved']:.0%} |")
    lines += ["", "## forward_dynamics_derivatives: the implicit route's explicit partials", "",
              "| scene | implicit-dense | implicit-dense-reverse | implicit-dense-analytic | route kept | its operations |",
              "|---|---|---|---|---|---|"]
    for r in forward:
        lines.append(f"| {r['scene']} | {r['forward']} | {r['reverse']} | {r['analytic'] or '-'} | {r['kept']} | "
                     f"{r['best']} |")
    here = Path(__file__).parent
    (here / "derivative_sweeps.md").write_text("\n".join(lines) + "\n")
    with open(here / "derivative_sweeps.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=["scene", "primal", "forward", "reverse", "analytic", "sweep", "derivatives", "ratio"],
                                lineterminator="\n", extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)
    with open(here / "derivative_sweeps_forward.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=["scene", "forward", "reverse", "analytic", "kept", "best"], lineterminator="\n",
                                extrasaction="ignore")
        writer.writeheader()
        writer.writerows(forward)
    print("\n".join(lines))


if __name__ == "__main__":
    main()
