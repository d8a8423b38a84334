"""The markdown reports of a chain sweep and of a multi-arm sweep (text only, no files)."""
from __future__ import annotations

from .published import FORMULAS, LAGRANGE_EULER, LUH_WALKER_PAUL
from .sweep import Sweep, dof
from .tables import (LABELS, cell, fit_rows, fmt_mib, lwp_ratio_text, markdown_table, peak_mib,
                     published_cell, published_table, seconds_cell, slope_check_text)

SYMGEN_CHAIN = ("symgen:inverse_dynamics", "symgen:mass_matrix", "symgen:forward_dynamics")
COUNTING = (
    "**Counting.** `mul` includes divisions, `add` includes subtractions, total = mul + add; negations and "
    "constants are free; sin/cos are counted apart (`trig`) and are not in the totals. This formulation's "
    "counts are `symgen.codegen.generate.operation_counts(derive(load(SCENE)), [function])`, exactly what "
    "`symgen ops SCENE --json` prints.")
FD_SOLVE = ("The dense library solve that `forward_dynamics` calls (LU of the mass matrix) is **not** in its "
            "total; its flops are the separate `FD: LU flops` column.")
SYMPY_COUNTING = (
    "SymPy: mass "
    "matrix + forcing of `KanesMethod` / `LagrangesMethod` on the same robot (built in "
    "`symgen/complexity/mechanics.py`, checked against symgen's model), counted in the same convention by "
    "walking the expression trees (`symgen/complexity/sympy_ops.py`): *raw* = the trees as SymPy returns "
    "them, every occurrence counted; *cse* = after `sympy.cse` (replacements + reduced expressions). "
    "SymPy's own `count_ops` (which also counts negations, powers, constant divisions and sin/cos) is "
    "listed apart. Mass matrix + forcing is what forward dynamics needs before its solve, so the fair "
    "comparison for the SymPy columns is `forward_dynamics` (its solve is likewise apart); inverse "
    "dynamics from them would add the products M qdd. Published rows are the formulas (for inverse "
    "dynamics) evaluated at N.")


GROWTH_NOTE = (
    "`inverse_dynamics` never forms the mass matrix (outward velocities, inward forces: linear in N). "
    "`mass_matrix` returns the dense N x N mass matrix, so it grows as N^2: that is the size of the output, "
    "not of the formulation. `forward_dynamics` is traced both ways, the dense route (M formed, N^2, and "
    "LU-factored apart, N^3) and the articulated-body recursion (linear in N), and the cheaper is kept "
    "(`method` in `ops.json`): the counts here are the kept route's.")


def _limit_note(sweep: Sweep) -> str:
    lim, key = f"> {sweep.time_limit:g} s", "N" if sweep.family == "chain" else "H"
    return (f"Each (method, {key}) ran in its own subprocess, killed after {sweep.time_limit:g} s of wall time. "
            f"`{lim}` marks a stage that did not finish in time at that {key}, or at a smaller {key} (it was then "
            f"not attempted again); `error` marks a crash.")


def _has(sweep: Sweep, method: str) -> bool:
    return method in sweep.methods


def chain_markdown(sweep: Sweep, command: str, environment: str) -> str:
    sympy_methods = [m for m in ("kane", "lagrange") if _has(sweep, m)]
    entries = [(LABELS[m], m, "ops") for m in SYMGEN_CHAIN]
    entries += [(f"{LABELS[m]} {st}", m, st) for m in sympy_methods for st in ("raw", "cse")]
    blocks = ["# Operation counts, derivation time and memory against DOF on `chain:n=N`",
              f"Reproduce: `{command}`  \nMeasured on: {environment}.", _limit_note(sweep),
              " ".join([COUNTING, FD_SOLVE, SYMPY_COUNTING]),
              "## Operation counts (total = mul + add)", _chain_headline(sweep, sympy_methods),
              "Fits (least squares `total = a N + b` over the measured N >= 8, or over all measured N when fewer "
              "than two are >= 8; growth exponent p of `total ~ c N^p` over the measured N >= 4):",
              markdown_table(["series", "N used", "slope a (ops/DOF)", "intercept b", "R^2", "exponent p"],
                             fit_rows(sweep, entries)),
              "Published, for comparison: Lagrange-Euler grows as n^4; Luh-Walker-Paul costs 281 ops per DOF; the "
              "unverified figures are in the last section.",
              GROWTH_NOTE, slope_check_text(sweep), lwp_ratio_text(sweep, entries[:1]),
              "## This formulation: mul, add, trig and the dense solve", _symgen_detail(sweep)]
    if sympy_methods:
        blocks += ["## SymPy `physics.mechanics`: counts in symgen's convention, and SymPy's `count_ops`",
                   _sympy_detail(sweep, sympy_methods)]
    blocks += ["## Derivation time and peak memory", _chain_time(sweep, sympy_methods),
               "## Published formulas", published_table(),
               "Totals (mul + add) of the formulas **not verified** against a source found by search, kept out of "
               "the headline table:", _unverified(sweep)]
    return _join(blocks)


def _join(blocks) -> str:
    return "\n".join(b.rstrip("\n") + "\n" for b in blocks)


def _chain_headline(sweep: Sweep, sympy_methods) -> str:
    header = ["N", "inverse_dynamics", "mass_matrix", "forward_dynamics", "FD: LU flops"]
    for m in sympy_methods:
        header += [f"{LABELS[m]} raw", f"{LABELS[m]} cse"]
    header += ["Lagrange-Euler [H80]", "Luh-Walker-Paul [H80]"]
    rows = []
    for n in sweep.sizes:
        row = [n] + [cell(sweep, m, n, "ops") if _has(sweep, m) else "" for m in SYMGEN_CHAIN]
        row.append(cell(sweep, "symgen:forward_dynamics", n, "ops", "solve_flops")
                   if _has(sweep, "symgen:forward_dynamics") else "")
        for m in sympy_methods:
            row += [cell(sweep, m, n, "raw"), cell(sweep, m, n, "cse")]
        row += [published_cell(LAGRANGE_EULER, n), published_cell(LUH_WALKER_PAUL, n)]
        rows.append(row)
    return markdown_table(header, rows) + (
        "\n[H80] Hollerbach (1980), as reproduced in Corke's Robotics Toolbox manual, Table 1 (see the last "
        "section; the Lagrange-Euler multiplication polynomial is evaluated as printed).\n")


def _symgen_detail(sweep: Sweep) -> str:
    header, present = ["N"], [m for m in SYMGEN_CHAIN if _has(sweep, m)]
    for m in present:
        header += [f"{LABELS[m]} mul", "add", "trig"]
    header.append("FD: LU flops")
    rows = []
    for n in sweep.sizes:
        row = [n]
        for m in present:
            row += [cell(sweep, m, n, "ops", k) for k in ("mul", "add", "trig")]
        row.append(cell(sweep, "symgen:forward_dynamics", n, "ops", "solve_flops")
                   if _has(sweep, "symgen:forward_dynamics") else "")
        rows.append(row)
    return markdown_table(header, rows)


def _sympy_detail(sweep: Sweep, methods) -> str:
    header = ["N"]
    for m in methods:
        header += [f"{LABELS[m]} raw mul", "raw add", "raw trig", "count_ops", "cse mul", "cse add", "cse trig"]
    rows = []
    for n in sweep.sizes:
        row = [n]
        for m in methods:
            row += [cell(sweep, m, n, "raw", k) for k in ("mul", "add", "trig")]
            row.append(_count_ops_cell(sweep, m, n))
            row += [cell(sweep, m, n, "cse", k) for k in ("mul", "add", "trig")]
        rows.append(row)
    return markdown_table(header, rows)


def _count_ops_cell(sweep: Sweep, method: str, n: int) -> str:
    text = cell(sweep, method, n, "raw")
    return str(sweep.record(method, n, "raw")["count_ops"]) if text.isdigit() else text


def _chain_time(sweep: Sweep, sympy_methods) -> str:
    header = ["N"]
    present = [m for m in SYMGEN_CHAIN if _has(sweep, m)]
    if present:
        header += ["symgen derive (s)"] + [f"trace {LABELS[m]} (s)" for m in present] + ["symgen peak (MiB)"]
    for m in sympy_methods:
        header += [f"{LABELS[m]} derive (s)", "raw count (s)", "cse (s)", "peak (MiB)"]
    rows = []
    for n in sweep.sizes:
        row = [n]
        if present:
            row.append(seconds_cell(sweep, present[0], n, "derive"))
            row += [seconds_cell(sweep, m, n, "ops") for m in present]
            peaks = [p for p in (peak_mib(sweep, m, n) for m in present) if p is not None]
            row.append(fmt_mib(max(peaks) if peaks else None, sweep))
        for m in sympy_methods:
            row += [seconds_cell(sweep, m, n, st) for st in ("derive", "raw", "cse")]
            row.append(fmt_mib(peak_mib(sweep, m, n), sweep))
        rows.append(row)
    return markdown_table(header, rows) + (
        "\nTimes are wall-clock seconds inside the measuring subprocess, stage by stage: symgen's derive is "
        "Steps 1-12 (`derive(load(...))`), its trace is the generation of one function (its op-counted "
        "graph, without writing files). Peak memory is the subprocess's peak resident set (Linux `VmHWM`, "
        "reset after the imports) minus its resident set after the imports (the baseline, about "
        + _baseline_text(sweep) + "); for symgen the largest of its three function runs.\n")


def _baseline_text(sweep: Sweep) -> str:
    bases = [o.baseline_kib / 1024 for o in sweep.cells.values() if o.baseline_kib]
    if not bases:
        return "unknown"
    low, high = round(min(bases)), round(max(bases))
    return f"{low} MiB" if low == high else f"{low}-{high} MiB"


def _unverified(sweep: Sweep) -> str:
    formulas = [f for f in FORMULAS if not f.verified]
    rows = [[n] + [published_cell(f, n) for f in formulas] for n in sweep.sizes]
    return markdown_table(["N"] + [f.label() for f in formulas], rows)


# ----------------------------------------------------------------------------- several arms
def multi_arm_markdown(sweep: Sweep, command: str, environment: str) -> str:
    from . import fits
    from .tables import series

    fns = [m for m in ("symgen:inverse_dynamics", "symgen:task_inverse_dynamics") if _has(sweep, m)]
    header = ["H", "DOF"]
    for m in fns:
        header += [f"{LABELS[m]} mul", "add", "total", "per extra arm"]
    header += ["task: LU flops"] if "symgen:task_inverse_dynamics" in fns else []
    rows, previous = [], {}
    for h in sweep.sizes:
        row = [h, dof(sweep.family, h)]
        for m in fns:
            total = cell(sweep, m, h, "ops")
            delta = str(int(total) - previous[m]) if total.isdigit() and previous.get(m) is not None else ""
            previous[m] = int(total) if total.isdigit() else None
            row += [cell(sweep, m, h, "ops", "mul"), cell(sweep, m, h, "ops", "add"), total, delta]
        if "symgen:task_inverse_dynamics" in fns:
            row.append(cell(sweep, "symgen:task_inverse_dynamics", h, "ops", "solve_flops"))
        rows.append(row)
    blocks = ["# Operation counts against the number of arms on `multi_arm:h=H`",
              f"Reproduce: `{command}`  \nMeasured on: {environment}.", _limit_note(sweep),
              "H six-joint arms rigidly hold one object (the paper's Section 3.3); DOF = 6H. "
              + COUNTING + " The dense solves of `[J_m; J_f]` that `task_inverse_dynamics` calls (block by "
              "block, one per arm and one for the object) are **not** in its total; their flops are the separate "
              "`task: LU flops` column.",
              "## Operation counts", markdown_table(header, rows)]
    fit_lines = []
    for m in fns:
        for key, what in (("total", "total"), ("solve_flops", "LU flops")):
            if key == "solve_flops" and m != "symgen:task_inverse_dynamics":
                continue
            xs, ys = series(sweep, m, "ops", key)
            line = fits.linear(xs, ys)
            if line:
                fit_lines.append(f"- {LABELS[m]} {what}: {line.slope:.2f} H {line.intercept:+.1f} "
                                 f"(R^2 = {line.r2:.6f}), i.e. {line.slope:.1f} per arm, "
                                 f"{line.slope / 6:.1f} per DOF")
    blocks += ["Fits (least squares over the measured H); the per-arm cost is the slope:", "\n".join(fit_lines),
               "## Derivation time and peak memory", _multi_arm_time(sweep, fns)]
    return _join(blocks)


def _multi_arm_time(sweep: Sweep, fns) -> str:
    header = ["H", "derive (s)"] + [f"trace {LABELS[m]} (s)" for m in fns] + ["peak (MiB)"]
    rows = []
    for h in sweep.sizes:
        peaks = [p for p in (peak_mib(sweep, m, h) for m in fns) if p is not None]
        rows.append([h, seconds_cell(sweep, fns[0], h, "derive") if fns else ""]
                    + [seconds_cell(sweep, m, h, "ops") for m in fns]
                    + [fmt_mib(max(peaks) if peaks else None, sweep)])
    return markdown_table(header, rows) + (
        "\nPeak memory: the subprocess's peak resident set (reset after the imports) above its resident set "
        "after the imports (about " + _baseline_text(sweep) + "); the larger of the two function runs.\n")


__all__ = ["chain_markdown", "multi_arm_markdown"]
