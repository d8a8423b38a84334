"""Operation counts of the joint-space mass matrix ``M_q``: composite-rigid-body algorithm against
one recursion per column.

For each scene, both routes of ``symgen.codegen.builder.Builder`` are traced into one graph:
``M_q = P^T M_tree P`` with ``M_tree`` by the composite-rigid-body algorithm
(``symgen/dynamics/crba.py``), and ``M_q e_k = P^T RNEA(qdd = P e_k)`` column by column (the route
symgen used before). The operations (mul + add) each needs are counted on its live nodes, shared
kinematics included, as ``ops.json`` counts them. ``kept`` is the route ``mass_matrix`` takes
(always the composite one for a tree; the cheaper for closed chains). ``mass_matrix total`` is the
whole generated function, ``[J_m; J_f]^-T M_q [J_m; J_f]^-1`` included, as ``symgen ops`` reports
it. Writes ``mass_matrix.md`` and ``mass_matrix.csv`` beside this file.

    python benchmarks/complexity/mass_matrix.py
"""
from __future__ import annotations

import csv
import platform
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent.parent))

import symgen  # noqa: E402
from symgen.codegen.builder import Builder  # noqa: E402
from symgen.codegen.catalogue import build_function  # noqa: E402
from symgen.codegen.functions import traced_cost  # noqa: E402

CHAINS = [2, 4, 6, 8, 12, 16, 24, 35, 64, 100]
CLOSED = ["four_bar", "five_bar", "stewart", "arm_on_plane", "multi_arm:h=2", "multi_arm:h=4"]
FIELDS = ["scene", "tree_coordinates", "n", "composite", "columns", "composite_over_columns", "kept",
          "mass_matrix_total"]


def row(spec: str) -> dict:
    model = symgen.derive(symgen.load(spec))
    b = Builder(model)
    composite = b.operations(b.mass_by_composite_inertia())
    columns = b.operations(b.mass_by_columns())
    kept = b.operations(b.mass_in_joint_space())
    return {"scene": spec, "tree_coordinates": model.tree.n_coords, "n": model.counts.n,
            "composite": composite, "columns": columns,
            "composite_over_columns": f"{composite / columns:.3f}",
            "kept": "composite" if kept == composite else "columns",
            "mass_matrix_total": traced_cost(build_function(model, "mass_matrix"))}


def quadratic_fit(rows: list[dict]) -> str:
    n = np.array([r["tree_coordinates"] for r in rows], float)
    ops = np.array([r["composite"] for r in rows], float)
    coef = np.polyfit(n, ops, 2)
    resid = ops - np.polyval(coef, n)
    r2 = 1 - resid @ resid / ((ops - ops.mean()) @ (ops - ops.mean()))
    return f"{coef[0]:.3f} N^2 {coef[1]:+.2f} N {coef[2]:+.1f} (R^2 = {r2:.6f})"


def main() -> None:
    chains = [row(f"chain:n={n}") for n in CHAINS]
    closed = [row(spec) for spec in CLOSED]
    rows = chains + closed
    with open(HERE / "mass_matrix.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=FIELDS)
        writer.writeheader()
        writer.writerows(rows)
    lines = ["# Mass matrix: composite-rigid-body algorithm against one recursion per column", "",
             f"Python {platform.python_version()}. Reproduce with `python benchmarks/complexity/mass_matrix.py`. "
             "Operations are mul + add of the live nodes of `M_q` (module docstring); "
             "`mass_matrix total` is the whole generated function (ops plus solve flops).", "",
             "| " + " | ".join(FIELDS) + " |", "|" + "---|" * len(FIELDS)]
    lines += ["| " + " | ".join(f"`{r[k]}`" if k == "scene" else str(r[k]) for k in FIELDS) + " |" for r in rows]
    lines += ["", f"Composite route on the chains, least squares in N: {quadratic_fit(chains)}.", ""]
    (HERE / "mass_matrix.md").write_text("\n".join(lines), encoding="utf-8")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
