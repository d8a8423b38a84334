"""PNG plots of a sweep (matplotlib, Agg backend: no display needed).

* ``chain_ops.png``: log-log op totals against N for this formulation's functions, SymPy's Kane
  and Lagrange (raw and after cse) and the published formulas (unverified ones dashed and so
  labelled);
* ``chain_time.png``: derivation time and peak memory against N;
* ``multi_arm_ops.png``: op totals against the number of arms H.

A method that ran out of time at some N simply stops there; its legend entry says from where.
"""
from __future__ import annotations

from pathlib import Path

from .published import FORMULAS
from .report import SYMGEN_CHAIN
from .sweep import Sweep
from .tables import LABELS, peak_mib, series


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _positive(xs, ys):
    """The points a log axis can show (an op count of 0, e.g. N = 1's constant mass, is left out)."""
    pts = [(x, y) for x, y in zip(xs, ys) if y > 0]
    return [x for x, _ in pts], [y for _, y in pts]


def _size_ticks(ax, sizes) -> None:
    from matplotlib.ticker import FixedLocator, NullLocator

    ax.xaxis.set_major_locator(FixedLocator(list(sizes)))
    ax.xaxis.set_minor_locator(NullLocator())
    ax.set_xticklabels([str(s) for s in sizes])


def _first_exceeded(sweep: Sweep, method: str, stage: str):
    for size in sweep.sizes:
        if (method, size) in sweep.cells and sweep.display(method, size, stage) != "ok":
            return size
    return None


def _label(sweep: Sweep, text: str, method: str, stage: str) -> str:
    stop = _first_exceeded(sweep, method, stage)
    return text if stop is None else f"{text} (> {sweep.time_limit:g} s from N = {stop})"


def chain_ops_plot(sweep: Sweep, path: Path) -> Path:
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(8, 6))
    for m, marker in zip(SYMGEN_CHAIN, "os^"):
        if m in sweep.methods:
            xs, ys = _positive(*series(sweep, m, "ops"))
            ax.plot(xs, ys, marker=marker, lw=2, label=_label(sweep, f"this formulation: {LABELS[m]}", m, "ops"))
    for m, color in (("kane", "tab:red"), ("lagrange", "tab:purple")):
        if m in sweep.methods:
            for stage, style in (("raw", "-"), ("cse", ":")):
                xs, ys = _positive(*series(sweep, m, stage))
                ax.plot(xs, ys, style, marker="x", color=color,
                        label=_label(sweep, f"SymPy {LABELS[m]} ({stage})", m, stage))
    ns = list(sweep.sizes)
    for f, color in zip(FORMULAS, ("black", "gray", "tab:olive", "tab:cyan", "tab:pink", "tab:brown")):
        ax.plot(ns, [float(f.total(n)) for n in ns], "--" if not f.verified else "-.", color=color, lw=1,
                label=f"published: {f.label()}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    _size_ticks(ax, sweep.sizes)
    ax.set_xlabel("DOF N (chain:n=N)")
    ax.set_ylabel("operations (mul + add)")
    ax.set_title("Operation count against DOF, benchmark chain")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="upper left")
    return _save(fig, plt, path)


def chain_time_plot(sweep: Sweep, path: Path) -> Path:
    plt = _pyplot()
    fig, (ax_t, ax_m) = plt.subplots(1, 2, figsize=(11, 4.5))
    runs = [(m, f"this formulation: derive + {LABELS[m]}", "ops") for m in SYMGEN_CHAIN]
    runs += [(m, f"SymPy {LABELS[m]}: derive + count + cse", "cse") for m in ("kane", "lagrange")]
    plotted = False
    for method, label, last in runs:
        if method not in sweep.methods:
            continue
        xs, ts, ms = [], [], []
        for n in sweep.sizes:
            if sweep.display(method, n, last) == "ok":
                out = sweep.cells[(method, n)]
                xs.append(n)
                ts.append(sum(rec["seconds"] for status, rec in out.stages.values() if status == "ok"))
                ms.append(max(peak_mib(sweep, method, n), 0.01))
        ax_t.plot(xs, ts, marker="o", label=_label(sweep, label, method, last))
        ax_m.plot(xs, ms, marker="o", label=label)
        plotted = plotted or bool(xs)
    for ax, ylabel in ((ax_t, "wall time (s)"), (ax_m, "peak memory above baseline (MiB)")):
        if plotted:
            ax.set_xscale("log")
            ax.set_yscale("log")
            _size_ticks(ax, sweep.sizes)
        else:
            ax.text(0.5, 0.5, f"nothing finished within {sweep.time_limit:g} s", ha="center",
                    transform=ax.transAxes)
        ax.set_xlabel("DOF N")
        ax.set_ylabel(ylabel)
        ax.grid(True, which="both", alpha=0.3)
    ax_t.axhline(sweep.time_limit, color="red", lw=0.8, ls="--", label=f"limit {sweep.time_limit:g} s")
    ax_t.legend(fontsize=7)
    ax_t.set_title("Derivation time")
    ax_m.set_title("Peak memory")
    return _save(fig, plt, path)


def multi_arm_ops_plot(sweep: Sweep, path: Path) -> Path:
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7, 5))
    for m in ("symgen:inverse_dynamics", "symgen:task_inverse_dynamics"):
        if m in sweep.methods:
            xs, ys = series(sweep, m, "ops")
            ax.plot(xs, ys, marker="o", label=_label(sweep, f"this formulation: {LABELS[m]}", m, "ops"))
    if "symgen:task_inverse_dynamics" in sweep.methods:
        xs, ys = series(sweep, "symgen:task_inverse_dynamics", "ops", "solve_flops")
        ax.plot(xs, ys, "--", marker="s", label="task_inverse_dynamics: LU flops (apart)")
    ax.set_xlabel("number of arms H (multi_arm:h=H, DOF = 6H)")
    ax.set_ylabel("operations (mul + add)")
    ax.set_title("Operation count against the number of arms")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    return _save(fig, plt, path)


def _save(fig, plt, path: Path) -> Path:
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
