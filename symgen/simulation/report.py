"""Work-precision reports: a CSV table, a markdown table, a log-log PNG plot of error against
wall time and the study's metadata as JSON (t_end, the reference's own difference, the noise
floor), written into one directory atomically by :func:`symgen.io.writer.write_tree`."""
from __future__ import annotations

import csv
import io
import json
import pathlib

import numpy as np

from ..codegen.targets import target
from ..io.writer import write_tree
from .stabilize import BAUMGARTE_GAIN
from .study import Study, monotonicity_violations, series

COLUMNS = ("backend", "method", "kind", "setting", "error", "drift", "energy_drift", "wall_time", "rhs_calls",
           "steps", "status")


def _fmt(x, digits: int = 3) -> str:
    if x is None:
        return "-"
    if isinstance(x, float) and not np.isfinite(x):
        return "-"
    return f"{x:.{digits}g}" if isinstance(x, float) else str(x)


def csv_text(study: Study) -> str:
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(COLUMNS)
    for r in study.rows:
        writer.writerow([r.backend, r.method, r.kind, repr(r.setting), repr(r.error), repr(r.drift),
                         "" if r.energy_drift is None else repr(r.energy_drift), repr(r.wall_time), r.rhs_calls,
                         r.steps, r.status])
    return buf.getvalue()


def markdown_text(study: Study, command: str | None = None) -> str:
    lines = [f"# Work-precision: `{study.scene}`, t_end = {study.t_end:g} s", ""]
    if command:
        lines += [f"Command: `{command}`", ""]
    for key, value in study.description.items():
        lines.append(f"- {key}: {value}")
    lines += [
        f"- error: final-state error `max|x - x_ref| / max(1, max|x_ref|)` against DOP853 at rtol = atol = 1e-13; "
        f"that reference differs from a tighter run (rtol 3e-14, atol 1e-14) by {study.reference_difference:.2g}, "
        f"noise floor {study.noise_floor:.2g}",
        "- drift: max constraint residual over the recorded states (m or rad); stabilization `auto` = "
        f"projection after each fixed step, Baumgarte (k = {BAUMGARTE_GAIN:g}/s) for solve_ivp",
        "- energy drift: `max|E - E0| / max T` (conservative runs only, else `-`)",
        "- wall time: integration only (code generation and compilation excluded); RHS calls: "
        "forward_dynamics + joint_rates evaluations (Radau/BDF finite-difference Jacobians included)",
        "",
        "| backend | method | step / tol | error | drift | energy drift | wall time (s) | RHS calls | steps | status |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in study.rows:
        status = r.status if len(r.status) < 60 else r.status[:57] + "..."
        lines.append(f"| {r.backend} | {r.method} | {r.kind} {r.setting:g} | {_fmt(r.error, 2)} | {_fmt(r.drift, 2)} | "
                     f"{_fmt(r.energy_drift, 2)} | {_fmt(r.wall_time, 3)} | {r.rhs_calls} | {r.steps} | {status} |")
    bad = monotonicity_violations(study)
    lines += ["", "Monotone (error falls as the step shrinks / the tolerance tightens, down to the noise floor): "
              + ("yes" if not bad else "NO -- " + "; ".join(bad))]
    return "\n".join(lines) + "\n"


def plot_png(study: Study) -> bytes:
    """Error against wall time, log-log, one line per method and backend."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.5, 5.0), dpi=110)
    colours = {}
    for (backend, method), rows in series(study).items():
        ok = [r for r in rows if r.status == "ok" and r.error > 0 and r.wall_time > 0]
        if not ok:
            continue
        colour = colours.setdefault(method, f"C{len(colours)}")
        compiled = target(backend).compiled      # compiled code: circles and solid lines
        ax.loglog([r.wall_time for r in ok], [r.error for r in ok], marker="o" if compiled else "s",
                  linestyle="-" if compiled else "--", color=colour, label=f"{method} ({backend})", markersize=4)
    ax.axhline(study.noise_floor, color="grey", linewidth=0.8, linestyle=":", label="noise floor")
    ax.set_xlabel("wall time (s)")
    ax.set_ylabel("final-state error")
    ax.set_title(f"{study.scene}: error against run time, t_end = {study.t_end:g} s")
    ax.grid(True, which="both", linewidth=0.3)
    ax.legend(fontsize=7, ncol=2)
    buf = io.BytesIO()
    fig.tight_layout()
    fig.savefig(buf, format="png", metadata={"Software": None})
    plt.close(fig)
    return buf.getvalue()


def meta_text(study: Study) -> str:
    """The study without its rows (those are the CSV), as JSON."""
    meta = {k: v for k, v in study.as_dict().items() if k != "rows"}
    return json.dumps(meta, indent=1, sort_keys=True) + "\n"


def write_files(out, files: dict[str, str | bytes], *, force: bool = False) -> pathlib.Path:
    """Write ``files`` as the directory ``out`` atomically (:func:`symgen.io.writer.write_tree`:
    a foreign non-empty directory is refused unless ``force``)."""
    return write_tree(out, files, force=force, command="symgen simulate --report")


def write_study(study: Study, out, *, force: bool = False, command: str | None = None) -> pathlib.Path:
    files = {"work_precision.csv": csv_text(study), "work_precision.md": markdown_text(study, command),
             "work_precision.png": plot_png(study), "work_precision.json": meta_text(study)}
    return write_files(out, files, force=force)
