"""Operation counts of every generated function for the closed chains and the constrained built-ins.

For each scene of ``SCENES`` this runs ``symgen ops SCENE --json`` (a fresh interpreter per scene)
and tabulates, per generated function, what it reports: multiplications (divisions included),
additions, sin/cos, square roots, the flops of its dense LU factorizations and solves, and the
totals, next to a *baseline*: the same functions traced with library LUs only and eq. (10)
through ``P`` only (``symgen.codegen.sparse_lu.library_solves_only()``), i.e. without the
straight-line sparse elimination, the LDL^T of the mass matrix and eq. (10) by solves. Writes
``closed_chains.md`` and ``closed_chains.csv`` beside this file.

    python benchmarks/complexity/closed_chains.py
"""
from __future__ import annotations

import csv
import json
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
SCENES = ["four_bar", "five_bar", "stewart", "arm_on_plane", "multi_arm:h=1", "multi_arm:h=2", "multi_arm:h=3",
          "multi_arm:h=4"]
FIELDS = ["scene", "function", "mul", "add", "div", "trig", "sqrt", "total", "solve_flops", "total_with_solves",
          "factorizations", "pivots_checked", "baseline_total_with_solves", "baseline_factorizations"]
BASELINE = """
import json, sys
import symgen
from symgen.codegen.generate import operation_counts
from symgen.codegen.sparse_lu import library_solves_only
with library_solves_only():
    counts = operation_counts(symgen.derive(symgen.load(sys.argv[1])), None)
print(json.dumps(counts))
"""


def counts(spec: str) -> tuple[dict, float]:
    """``symgen ops SPEC --json`` and the seconds it took (derivation and tracing included)."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    t0 = time.perf_counter()
    out = subprocess.run([sys.executable, "-m", "symgen", "ops", spec, "--json"], check=True, capture_output=True,
                         text=True, env=env).stdout
    return json.loads(out), time.perf_counter() - t0


def baseline(spec: str) -> dict:
    """The counts of every function traced with library LUs and ``P`` only (module docstring)."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    out = subprocess.run([sys.executable, "-c", BASELINE, spec], check=True, capture_output=True, text=True,
                         env=env).stdout
    return json.loads(out)


def _sizes(c: dict) -> str:
    return " ".join(f"{n}x{n}" for n in c.get("factorizations", []))


def rows_of(spec: str, report: dict, base: dict) -> list[dict]:
    rows = []
    for function, c in report["functions"].items():
        flops = int(c.get("solve_flops", 0))
        b = base[function]
        rows.append(dict(scene=spec, function=function, mul=c["mul"], add=c["add"], div=c["div"], trig=c["trig"],
                         sqrt=c["sqrt"], total=c["total"], solve_flops=flops, total_with_solves=c["total"] + flops,
                         factorizations=_sizes(c), pivots_checked=sum(c.get("pivot_checks", [])),
                         baseline_total_with_solves=b["total"] + int(b["solve_flops"]),
                         baseline_factorizations=_sizes(b)))
    return rows


def write(rows: list, seconds: dict) -> None:
    with open(HERE / "closed_chains.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=FIELDS)
        writer.writeheader()
        writer.writerows(rows)
    lines = [
        "# Operation counts of the generated functions: closed chains and constrained robots",
        "",
        "Reproduce: `python benchmarks/complexity/closed_chains.py` (one `symgen ops SCENE --json` per scene).  ",
        f"Measured on: {platform.system()} {platform.machine()}, Python {platform.python_version()}.",
        "",
        "**Counting** (as `symgen ops` and the generated headers): `mul` includes divisions, `add` includes",
        "subtractions, negations and constants are free, `total = mul + add`; sin/cos (`trig`) and square roots",
        "are counted apart. The dense LU factorizations (`LU` lists their sizes) and triangular solves that a",
        "function calls are not in `total`: their flops are the `solve flops` column, and `total + solves` adds",
        "them. Straight-line eliminations (sparse LU in a static pivot order, LDL^T of the mass matrix) are",
        "scalar operations, so they are in `total`; `pivots` is how many of their pivots are checked at run time.",
        "",
        "**Baseline.** `baseline` is `total + solves` of the same function traced with library LUs only and",
        "eq. (10) through `P` only (`symgen.codegen.sparse_lu.library_solves_only()`): what the generator",
        "emitted before the straight-line routes.",
        "",
        "**No published reference.** To our knowledge no operation counts have been published for the",
        "dynamics of these closed chains (planar four- and five-bar, the 6-UPS Stewart platform, an arm in",
        "contact with a plane, H arms holding one object) in a form that could be compared with these; the",
        "open-chain comparison with published counts is in [chain.md](chain.md).",
        "",
    ]
    summary = ["inverse_dynamics", "forward_dynamics", "mass_matrix"]
    lines += ["## Summary: total (+ solve flops), and the baseline's total + solves", "",
              "| scene | " + " | ".join(f"`{f}` | baseline" for f in summary) + " |",
              "|---|" + "---|---|" * len(summary)]
    for spec in dict.fromkeys(r["scene"] for r in rows):
        got = {r["function"]: r for r in rows if r["scene"] == spec}
        cells = [f"{got[f]['total']} (+{got[f]['solve_flops']}) | {got[f]['baseline_total_with_solves']}"
                 if f in got else "– | –" for f in summary]
        lines.append(f"| `{spec}` | " + " | ".join(cells) + " |")
    lines.append("")
    for spec in dict.fromkeys(r["scene"] for r in rows):
        lines += [f"## `{spec}`", "", f"`symgen ops` took {seconds[spec]:.1f} s (derivation and tracing).", "",
                  "| function | mul | add | trig | sqrt | total | LU | pivots | solve flops | total + solves "
                  "| baseline | baseline LU |",
                  "|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for r in (r for r in rows if r["scene"] == spec):
            lines.append(f"| `{r['function']}` | {r['mul']} | {r['add']} | {r['trig']} | {r['sqrt']} | {r['total']} "
                         f"| {r['factorizations'] or '–'} | {r['pivots_checked']} | {r['solve_flops']} "
                         f"| {r['total_with_solves']} | {r['baseline_total_with_solves']} "
                         f"| {r['baseline_factorizations'] or '–'} |")
        lines.append("")
    (HERE / "closed_chains.md").write_text("\n".join(lines))


def main() -> None:
    rows, seconds = [], {}
    for spec in SCENES:
        report, seconds[spec] = counts(spec)
        rows += rows_of(spec, report, baseline(spec))
        print(spec, f"{seconds[spec]:.1f} s", flush=True)
    write(rows, seconds)


if __name__ == "__main__":
    main()
