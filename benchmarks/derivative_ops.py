"""Operation counts of the generated Jacobians of forward dynamics against the primal, per scene,
and their growth on the benchmark chain ``chain:n=N`` with a least-squares fit in ``N^2``.

For each scene: ``forward_dynamics`` (the route kept), ``forward_dynamics_derivatives`` and
``state_derivative_jacobian`` (the route kept, and the cost of every route traced), as ``ops.json``
counts them: mul + add plus the flops of the library loops (dense solves, banded products).

    python benchmarks/derivative_ops.py        # writes benchmarks/derivative_ops.md and .csv
"""
import csv
import time
from pathlib import Path

import numpy as np

from symgen.codegen.forward_derivatives import STRAIGHT_LINE_BUDGET
from symgen.codegen.functions import library_flops
from symgen.codegen.generate import operation_counts
from symgen.io.builtin import get_scene
from symgen.model import derive

SCENES = ["chain:n=6", "ur5", "panda", "four_bar", "five_bar", "arm_on_plane", "multi_arm:h=2"]
CHAIN = [2, 3, 4, 6, 8, 12, 16, 24, 32]
FUNCTIONS = ["forward_dynamics", "forward_dynamics_derivatives", "state_derivative_jacobian"]


def cost(ops: dict) -> int:
    return ops["total"] + library_flops(ops)


def load(spec: str):
    from symgen import load as load_spec

    try:
        return derive(get_scene(spec))
    except Exception:
        return derive(load_spec(spec))


def measure(spec: str) -> dict:
    start = time.perf_counter()
    ops = operation_counts(load(spec), FUNCTIONS)
    row = {"scene": spec, "primal": cost(ops["forward_dynamics"]),
           "derivatives": cost(ops["forward_dynamics_derivatives"]),
           "state_jacobian": cost(ops["state_derivative_jacobian"]),
           "route": ops["forward_dynamics_derivatives"]["method"],
           "routes": "; ".join(f"{k} {v}" for k, v in ops["forward_dynamics_derivatives"]["method_costs"].items()),
           "seconds": time.perf_counter() - start}
    row["ratio"] = row["derivatives"] / row["primal"]
    costs = ops["forward_dynamics_derivatives"]["method_costs"]
    row["fewest_route"] = min(costs, key=costs.get)
    row["fewest"] = costs[row["fewest_route"]]
    row["straight"] = ops["forward_dynamics_derivatives"]["total"]
    row["flops"] = library_flops(ops["forward_dynamics_derivatives"])
    return row


def fit(ns, totals) -> tuple[np.ndarray, float]:
    """Least squares ``total = a N^2 + b N + c`` and its R^2."""
    x = np.array(ns, dtype=float)
    y = np.array(totals, dtype=float)
    basis = np.stack([x * x, x, np.ones_like(x)], axis=1)
    coef, *_ = np.linalg.lstsq(basis, y, rcond=None)
    resid = y - basis @ coef
    return coef, 1.0 - float(resid @ resid) / float(((y - y.mean()) ** 2).sum())


def main() -> None:
    rows = [measure(spec) for spec in SCENES]
    chain = [measure(f"chain:n={n}") for n in CHAIN]
    coef, r2 = fit(CHAIN, [r["fewest"] for r in chain])
    lines = ["# Jacobians of forward dynamics: operation counts", "",
             "`python benchmarks/derivative_ops.py`. Operations: mul + add + library flops (solves, products), as `ops.json` "
             "counts them; `forward_dynamics` by the route it keeps, the derivatives by the cheapest of the routes "
             "traced (`symgen.codegen.forward_derivatives`).", "",
             "| scene | forward_dynamics | forward_dynamics_derivatives | ratio | state_derivative_jacobian | "
             "route kept | every route |", "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['scene']} | {r['primal']} | {r['derivatives']} | {r['ratio']:.2f} | {r['state_jacobian']} "
                     f"| {r['route']} | {r['routes']} |")
    lines += ["", "## The benchmark chain", "",
              "**fewest**: the route of `forward_dynamics_derivatives` with the fewest operations + library "
              "flops, and that count; **kept**: the route generated -- the same unless every route with fewer "
              "counts has more straight-line operations than the budget "
              f"(`STRAIGHT_LINE_BUDGET` = {STRAIGHT_LINE_BUDGET:,}: beyond it the code outgrows a core's L2 "
              "cache and one with its mass matrix in the library LU's loops runs faster), with its "
              "straight-line operations (mul + add) and library flops.", "",
              f"Least squares of **fewest** over N = {', '.join(map(str, CHAIN))}: "
              f"{coef[0]:.2f} N^2 {'-' if coef[1] < 0 else '+'} {abs(coef[1]):.1f} N "
              f"{'-' if coef[2] < 0 else '+'} {abs(coef[2]):.0f} (R^2 = {r2:.6f}).", "",
              "| N | forward_dynamics | fewest | route | ratio | fit | kept | straight-line | library flops |",
              "|---|---|---|---|---|---|---|---|---|"]
    for n, r in zip(CHAIN, chain):
        lines.append(f"| {n} | {r['primal']} | {r['fewest']} | {r['fewest_route']} | {r['fewest'] / r['primal']:.2f} | "
                     f"{coef[0] * n * n + coef[1] * n + coef[2]:.0f} | {r['route']} | {r['straight']} | {r['flops']} |")
    here = Path(__file__).parent
    (here / "derivative_ops.md").write_text("\n".join(lines) + "\n")
    with open(here / "derivative_ops.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=["scene", "primal", "derivatives", "ratio", "state_jacobian", "route",
                                                "straight", "flops", "fewest_route", "fewest", "routes"],
                                lineterminator="\n", extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows + chain)
    print("\n".join(lines))


if __name__ == "__main__":
    main()
