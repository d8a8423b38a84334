"""Operation counts of the generated ``forward_dynamics`` by the articulated-body recursion on the
benchmark chain, against Featherstone's count of the articulated-body algorithm.

For ``chain:n=N`` over the family's sizes (``symgen.codegen.linearity.FAMILIES``), the traced
function's mul, add and their total, the library solves' flops (none remain: every solve is
eliminated in line), RBDA Table 10.1's ``(224N - 259) mul + (205N - 248) add``, the least-squares
lines of total, mul and add against N, and the cost of one more link from N = 4 on. Counts are of
the traced graph, so they do not depend on the machine. Writes ``forward_ops.md`` beside this file
(about a minute).

    python benchmarks/forward_ops.py
"""
from __future__ import annotations

import pathlib
import sys

from symgen.codegen.linearity import family_counts, fit_line

HERE = pathlib.Path(__file__).resolve().parent


def main() -> int:
    rows = family_counts("chain", None, "forward_dynamics", {"method": "articulated-body"})
    sizes = [n for n, _ in rows]
    total = [ops["total"] for _, ops in rows]
    fits = {name: fit_line(sizes, [ops[name] for _, ops in rows]) for name in ("mul", "add", "total")}
    per_link = [(b[1]["total"] - a[1]["total"]) / (b[0] - a[0]) for a, b in zip(rows[2:], rows[3:])]
    lines = ["# Operation counts of the generated forward dynamics (articulated-body route)", "",
             "Produced by `python benchmarks/forward_ops.py` (see its docstring): `forward_dynamics` of "
             "`chain:n=N` traced by the articulated-body recursion (generation option `method: articulated-body`).",
             "", "| N | mul | add | total | LU flops | RBDA mul | RBDA add | RBDA total |",
             "|---|---|---|---|---|---|---|---|"]
    for (n, ops), t in zip(rows, total):
        rbda_mul, rbda_add = 224 * n - 259, 205 * n - 248
        lines.append(f"| {n} | {ops['mul']} | {ops['add']} | {t} | {ops['solve_flops']} | {rbda_mul} | {rbda_add} | "
                     f"{rbda_mul + rbda_add} |")
    lines += ["", "| count | slope (per link) | intercept | R^2 |", "|---|---|---|---|"]
    for name, fit in fits.items():
        lines.append(f"| {name} | {fit.slope:.2f} | {fit.intercept:.1f} | {fit.r2:.6f} |")
    lines += ["", f"One more link from N = 4 on costs {min(per_link):.1f} to {max(per_link):.1f} operations "
                  f"(total, between consecutive sizes of the family).", ""]
    (HERE / "forward_ops.md").write_text("\n".join(lines), encoding="utf-8")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
