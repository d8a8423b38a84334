"""Markdown and CSV of a :class:`~symgen.complexity.sweep.Sweep`.

The CSV is long-form, one row per (method, size, stage) plus one per published formula and size:
``family, method, size, dof, stage, status, seconds, peak_mib, baseline_mib, mul, div, add,
total, trig, solve_flops, count_ops, replacements, verified``. ``status`` is ``ok``, ``limit``
(ran out of time at this size or at a smaller one, so not attempted) or ``error``. The markdown
prints "> 60 s" (the limit) where the CSV says ``limit``.
"""
from __future__ import annotations

import csv
import io
from fractions import Fraction

from . import fits
from .published import FORMULAS, LUH_WALKER_PAUL
from .sweep import OK, Sweep, dof, method_stages

CSV_FIELDS = ("family", "method", "size", "dof", "stage", "status", "seconds", "peak_mib", "baseline_mib",
              "mul", "div", "add", "total", "trig", "solve_flops", "count_ops", "replacements", "verified")
LABELS = {"symgen:inverse_dynamics": "inverse_dynamics", "symgen:mass_matrix": "mass_matrix",
          "symgen:forward_dynamics": "forward_dynamics", "symgen:task_inverse_dynamics": "task_inverse_dynamics",
          "kane": "Kane", "lagrange": "Lagrange"}


# ----------------------------------------------------------------------------- cells and series
def limit_text(sweep: Sweep) -> str:
    return f"> {sweep.time_limit:g} s"


def cell(sweep: Sweep, method: str, size: int, stage: str, key: str = "total") -> str:
    """An op count (``key`` of the stage's ``ops``), "> limit" or "error"; "" if not measured."""
    if (method, size) not in sweep.cells:
        return ""
    shown = sweep.display(method, size, stage)
    if shown != "ok":
        return limit_text(sweep) if shown == "limit" else "error"
    return str(sweep.record(method, size, stage)["ops"][key])


def seconds_cell(sweep: Sweep, method: str, size: int, stage: str) -> str:
    if (method, size) not in sweep.cells:
        return ""
    shown = sweep.display(method, size, stage)
    if shown != "ok":
        return limit_text(sweep) if shown == "limit" else "error"
    return fmt_seconds(sweep.record(method, size, stage)["seconds"])


def peak_mib(sweep: Sweep, method: str, size: int) -> float | None:
    """Peak resident memory the work added over the subprocess's baseline (MiB), None if no
    stage finished."""
    outcome = sweep.cells.get((method, size))
    if outcome is None or outcome.baseline_kib is None:
        return None
    peaks = [rec["rss_kib"] for status, rec in outcome.stages.values() if status == OK]
    return (max(peaks) - outcome.baseline_kib) / 1024 if peaks else None


def series(sweep: Sweep, method: str, stage: str, key: str = "total", min_size: int = 0):
    """``(sizes, values)`` where ``stage`` finished."""
    xs, ys = [], []
    for size in sweep.sizes:
        if size >= min_size and (method, size) in sweep.cells and sweep.display(method, size, stage) == "ok":
            xs.append(size)
            ys.append(sweep.record(method, size, stage)["ops"][key])
    return xs, ys


def fmt_seconds(s: float) -> str:
    return f"{s:.3f}" if s < 1 else f"{s:.2f}" if s < 100 else f"{s:.0f}"


def fmt_mib(m: float | None, sweep: Sweep) -> str:
    return limit_text(sweep) if m is None else f"{m:.1f}"


def fmt_num(x) -> str:
    """An exact formula value, rounded to the nearest integer (the CSV keeps two decimals)."""
    return str(round(Fraction(x)))


def markdown_table(header, rows) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(map(str, r)) + " |" for r in rows]
    return "\n".join(lines) + "\n"


def poly_text(coeffs) -> str:
    """``(65/2, 1037/12, ...)`` as ``32 1/2 n^4 + 86 5/12 n^3 + ...``."""
    terms, deg = [], len(coeffs) - 1
    for i, c in enumerate(coeffs):
        c, p = Fraction(c), deg - i
        if c == 0:
            continue
        whole, frac = divmod(abs(c), 1)
        mag = (f"{whole} {frac}" if whole else f"{frac}") if frac else f"{whole}"
        var = "" if p == 0 else "n" if p == 1 else f"n^{p}"
        body = f"{mag} {var}".strip() if not (mag == "1" and var) else var
        terms.append(("- " if c < 0 else "+ ") + body)
    text = " ".join(terms)
    return text[2:] if text.startswith("+ ") else "-" + text[1:]


# ----------------------------------------------------------------------------- fits
def fit_rows(sweep: Sweep, entries) -> list:
    """One row per ``(label, method, stage)``: the line over N >= 8 (all points if fewer than two
    there), and the growth exponent over N >= 4."""
    rows = []
    for label, method, stage in entries:
        if method not in sweep.methods:
            continue
        xs, ys = series(sweep, method, stage, min_size=8)
        if len(xs) < 2:
            xs, ys = series(sweep, method, stage)
        line = fits.linear(xs, ys)
        ex, ey = series(sweep, method, stage, min_size=4)
        if len(ex) < 2:
            ex, ey = series(sweep, method, stage)
        p = fits.growth_exponent(ex, ey)
        rows.append([label, f"{xs[0]}..{xs[-1]}" if xs else "-",
                     f"{line.slope:.2f}" if line else "-", f"{line.intercept:+.1f}" if line else "-",
                     f"{line.r2:.6f}" if line else "-", f"{p:.2f}" if p is not None else "-"])
    return rows


def slope_check_text(sweep: Sweep, method: str = "symgen:inverse_dynamics") -> str:
    xs, ys = series(sweep, method, "ops")
    pts = [(x, y) for x, y in zip(xs, ys) if x in fits.SLOPE_CHECK_SIZES]
    if len(pts) != len(fits.SLOPE_CHECK_SIZES):
        return "Slope constancy over N = 8...64: not every one of these sizes was measured in this run.\n"
    check = fits.slope_constancy([x for x, _ in pts], [y for _, y in pts])
    return f"Slope constancy of inverse_dynamics over N = 8...64: {check.describe('total', 'DOF')}.\n"


def lwp_ratio_text(sweep: Sweep, entries, n: int = 6) -> str:
    """Ratios of measured totals to Luh-Walker-Paul's ``150 n - 48`` mul + ``131 n - 48`` add at n."""
    m_ref, a_ref = (int(x) for x in LUH_WALKER_PAUL.counts(n))   # integral for every n
    parts = []
    for label, method, stage in entries:
        if method not in sweep.methods or (method, n) not in sweep.cells or sweep.display(method, n, stage) != "ok":
            continue
        ops = sweep.record(method, n, stage)["ops"]
        parts.append(f"{label} {ops['total']} / {m_ref + a_ref} = {ops['total'] / (m_ref + a_ref):.3f} "
                     f"(mul {ops['mul']}/{m_ref} = {ops['mul'] / m_ref:.3f}, add {ops['add']}/{a_ref} = "
                     f"{ops['add'] / a_ref:.3f})")
    if not parts:
        return f"Ratio to Luh-Walker-Paul at N = {n}: N = {n} not measured in this run.\n"
    return f"Ratio to Luh-Walker-Paul (150N-48 mul, 131N-48 add) at N = {n}:\n\n" + \
        "\n".join(f"- {p}" for p in parts) + "\n"


# ----------------------------------------------------------------------------- CSV
def to_csv(sweep: Sweep) -> str:
    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=CSV_FIELDS, lineterminator="\n")
    writer.writeheader()
    for size in sweep.sizes:
        for method in sweep.methods:
            outcome = sweep.cells[(method, size)]
            base = outcome.baseline_kib
            for stage in method_stages(method):
                status, rec = outcome.stages[stage]
                row = dict(family=sweep.family, method=method, size=size, dof=dof(sweep.family, size), stage=stage,
                           status=sweep.display(method, size, stage))
                if status == OK:
                    row.update(seconds=f"{rec['seconds']:.4f}", peak_mib=f"{rec['rss_kib'] / 1024:.1f}",
                               baseline_mib=f"{base / 1024:.1f}" if base else "")
                    ops = rec.get("ops") or {}
                    row.update({k: ops[k] for k in ("mul", "div", "add", "total", "trig", "solve_flops") if k in ops})
                    row.update({k: rec[k] for k in ("count_ops", "replacements") if k in rec})
                writer.writerow(row)
        if sweep.family == "chain":
            for f in FORMULAS:
                m, a = f.counts(size)
                writer.writerow(dict(family="chain", method=f"published:{f.key}", size=size, dof=size,
                                     stage="formula", status="ok", mul=f"{float(m):.2f}", add=f"{float(a):.2f}",
                                     total=f"{float(m + a):.2f}", verified=str(f.verified).lower()))
    return buf.getvalue()


def published_table(n_ref: int = 6) -> str:
    rows = [[f.name, f.order, poly_text(f.mul), poly_text(f.add), fmt_num(f.counts(n_ref)[0]),
             fmt_num(f.counts(n_ref)[1]), "yes" if f.verified else "**no**", f.source + (f"; {f.note}" if f.note else "")]
            for f in FORMULAS]
    return markdown_table(["formulation", "order", "multiplications", "additions", f"mul at n={n_ref}",
                   f"add at n={n_ref}", "verified", "source"], rows)


def published_cell(formula, n: int) -> str:
    return fmt_num(formula.total(n))


__all__ = ["LABELS", "cell", "fit_rows", "fmt_mib", "fmt_num", "fmt_seconds", "limit_text", "lwp_ratio_text",
           "markdown_table", "peak_mib", "poly_text", "published_cell", "published_table", "seconds_cell", "series",
           "slope_check_text", "to_csv"]
