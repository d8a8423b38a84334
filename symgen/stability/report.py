"""The stability table (markdown) and its CSV, from :class:`~.runner.CaseResult` s."""
from __future__ import annotations

import csv
import io

from .runner import FACTOR, FLOOR, MAX_RHS_CALLS, METHODS, WARN_CONDITION, CaseResult

HEADER = ("case", "kind", "condition numbers", "EOM residual", "error vs 50 digits", "verdict", "expected")
#: short names of the inverted matrices in the table
SHORT = {"[T_u1, T_a1]": "W", "[J_m; J_f]": "A", "M_mm": "M_mm"}


def _g(x) -> str:
    return "-" if x is None else f"{x:.1e}"


def _conditions(result: CaseResult) -> str:
    return ", ".join(f"{SHORT.get(name, name)} {value:.1e}" for name, value in result.conditions.items())


def _run_cell(run) -> str:
    if run.ok:
        return f"{run.rhs_calls} calls, {run.wall_time * 1e3:.0f} ms"
    return "failed: " + run.message.split(":", 1)[0]


def markdown(results: list[CaseResult], backend: str) -> str:
    """The suite's tables: verdicts, then integrators."""
    lines = [f"Stability suite, generated {backend} code. Verdict *accurate*: residual and error "
             f"<= max({FLOOR:g}, {FACTOR:g} eps cond); *error*: a typed error naming the singular matrix; "
             f"warning above cond {WARN_CONDITION:g}. Condition numbers (2-norm) of W = [T_u1, T_a1] (eq. 9), "
             "A = [J_m; J_f] (eq. 18) and M_mm (the block of M forward dynamics solves with).", "",
             "| " + " | ".join(HEADER) + " |", "|" + "---|" * len(HEADER)]
    for r in results:
        verdict = r.status + (" (warning)" if r.message and r.status == "accurate" else "")
        error = _g(r.error) + (" (vs float model)" if r.reference == "float" and r.error is not None else "")
        name = r.name + (f" ({r.backend})" if r.backend != backend else "")
        lines.append(f"| {name} | {r.kind} | {_conditions(r)} | {_g(r.residual)} | {error} | {verdict} | "
                     f"{r.expect} |")
    methods = list(METHODS)
    lines += ["", f"Integrators over each case's run (adaptive: rtol = atol = {METHODS['RK45']['rtol']:g}; rk4: "
              f"{METHODS['rk4']['steps']} steps; at most {MAX_RHS_CALLS} right-hand-side calls); "
              "'diff' is max |x_end - x_end(Radau)|.", "",
              "| case | " + " | ".join(methods) + " |", "|---|" + "---|" * len(methods)]
    for r in results:
        if not r.runs:
            lines.append(f"| {r.name} | " + " | ".join("not run (state refused)" for _ in methods) + " |")
            continue
        cells = []
        for run in r.runs:
            cell = _run_cell(run)
            if run.ok and run.difference is not None and run.method != "Radau":
                cell += f", diff {run.difference:.0e}"
            cells.append(cell)
        lines.append(f"| {r.name} | " + " | ".join(cells) + " |")
    messages = [f"- {r.name}: {r.message}" for r in results if r.message]
    if messages:
        lines += ["", "Messages:", ""] + messages
    return "\n".join(lines) + "\n"


def csv_text(results: list[CaseResult]) -> str:
    """One row per (case, method); the case's own figures repeated on each row."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(["case", "kind", "expected", "verdict", "worst_condition", "eom_residual", "error_vs_mp",
                     "tolerance", "method", "ok", "rhs_calls", "wall_time_s", "diff_vs_radau", "message"])
    for r in results:
        cond = max(r.conditions.values())
        base = [r.name, r.kind, r.expect, r.status, f"{cond:.6g}", r.residual, r.error, r.tolerance]
        for run in r.runs or [None]:
            if run is None:
                writer.writerow(base + ["", "", "", "", "", r.message])
            else:
                writer.writerow(base + [run.method, run.ok, run.rhs_calls, run.wall_time, run.difference,
                                        run.message])
    return out.getvalue()
