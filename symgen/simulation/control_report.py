"""Closed-loop reports: a markdown summary, a CSV time series and a PNG plot of one demonstration
(adaptive against frozen estimates), written atomically by :func:`symgen.io.writer.write_tree`."""
from __future__ import annotations

import csv
import io

import numpy as np

from ..io.writer import write_tree
from .closed_loop import ClosedLoopResult

#: the share of the run at its end over which "final" errors are taken (their maximum)
FINAL_SHARE = 0.2


def final(values: np.ndarray) -> float:
    """The largest value over the last :data:`FINAL_SHARE` of the samples."""
    k = max(1, int(round(len(values) * FINAL_SHARE)))
    return float(np.max(values[-k:]))


def summary(runs: dict[str, ClosedLoopResult]) -> dict:
    """Headline figures of a demonstration (adaptive and frozen runs)."""
    a, f = runs["adaptive"], runs["frozen"]
    inside = bool(np.all((a.estimates >= a.lower - 1e-12) & (a.estimates <= a.upper + 1e-12)))
    return {
        "final_task_error_adaptive": final(a.task_error), "final_task_error_frozen": final(f.task_error),
        "ratio": final(a.task_error) / max(final(f.task_error), 1e-300),
        "final_force_error_adaptive": final(a.force_error), "final_force_error_frozen": final(f.force_error),
        "lyapunov_largest_increase": float(np.max(np.diff(a.lyapunov), initial=0.0)),
        "lyapunov_start": float(a.lyapunov[0]), "lyapunov_end": float(a.lyapunov[-1]),
        "estimates_inside_bounds": inside, "rhs_calls": a.rhs_calls + f.rhs_calls,
        "wall_time": a.wall_time + f.wall_time,
    }


def csv_text(runs: dict[str, ClosedLoopResult]) -> str:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    a = runs["adaptive"]
    w.writerow(["run", "t", "task_error", "velocity_error", "force_error", "lyapunov"] + list(a.names))
    for label, r in runs.items():
        for i, t in enumerate(r.times):
            w.writerow([label, repr(float(t)), repr(float(r.task_error[i])), repr(float(r.velocity_error[i])),
                        repr(float(r.force_error[i])), repr(float(r.lyapunov[i]))]
                       + [repr(float(v)) for v in r.estimates[i]])
    return buf.getvalue()


def markdown_text(scene: str, description: str, runs: dict[str, ClosedLoopResult], settings: dict,
                  command: str | None = None) -> str:
    s, a = summary(runs), runs["adaptive"]
    lines = [f"# Adaptive control (Section 4): `{scene}`", "", description, ""]
    if command:
        lines += [f"Command: `{command}`", ""]
    lines += [f"- {k}: {v}" for k, v in settings.items()]
    lines += ["", "| | adaptive (38) | frozen estimates |", "|---|---|---|",
              f"| task error, last {FINAL_SHARE:.0%} of the run (max) | {s['final_task_error_adaptive']:.3g} "
              f"| {s['final_task_error_frozen']:.3g} |",
              f"| constraint-force error, last {FINAL_SHARE:.0%} (max, N or N m) | "
              f"{s['final_force_error_adaptive']:.3g} | {s['final_force_error_frozen']:.3g} |",
              "", f"- adaptive / frozen task error: {s['ratio']:.3g}",
              f"- Lyapunov V: {s['lyapunov_start']:.4g} -> {s['lyapunov_end']:.4g}, largest increase between "
              f"samples {s['lyapunov_largest_increase']:.2g}",
              f"- every estimate inside its bounds at every sample: {s['estimates_inside_bounds']}",
              f"- right-hand-side calls {s['rhs_calls']}, integration time {s['wall_time']:.1f} s", "",
              "| parameter | true | start | end | bounds |", "|---|---|---|---|---|"]
    for k, name in enumerate(a.names):
        lines.append(f"| {name} | {a.true[k]:.4g} | {a.estimates[0, k]:.4g} | {a.estimates[-1, k]:.4g} | "
                     f"[{a.lower[k]:.3g}, {a.upper[k]:.3g}] |")
    return "\n".join(lines) + "\n"


def plot_png(scene: str, runs: dict[str, ClosedLoopResult]) -> bytes:
    """Task error, constraint-force error, Lyapunov function and mass estimates against time."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(10, 7))
    for label, r in runs.items():
        axes[0, 0].semilogy(r.times, np.maximum(r.task_error, 1e-16), label=label)
        axes[0, 1].semilogy(r.times, np.maximum(r.force_error, 1e-16), label=label)
    a = runs["adaptive"]
    axes[1, 0].plot(a.times, a.lyapunov)
    for k, name in enumerate(a.names):
        if name.startswith("m_"):
            axes[1, 1].plot(a.times, a.estimates[:, k] / a.true[k], label=name)
    titles = ("task error |e|", "constraint-force error |eta_f - eta_fd|", "Lyapunov V (adaptive)",
              "mass estimates / true")
    for ax, title in zip(axes.flat, titles):
        ax.set_title(title)
        ax.set_xlabel("t (s)")
        ax.grid(True, which="both", alpha=0.3)
    for ax in (axes[0, 0], axes[0, 1], axes[1, 1]):
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=8)
    fig.suptitle(f"{scene}: adaptive control (eqs. 34-38)")
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=90, metadata={"Software": None})
    plt.close(fig)
    return buf.getvalue()


def write_report(out, scene: str, description: str, runs, settings: dict, *, command: str | None = None,
                 force: bool = False):
    """``control.md``, ``control.csv`` and ``control.png`` in ``out``, atomically."""
    files = {"control.md": markdown_text(scene, description, runs, settings, command),
             "control.csv": csv_text(runs), "control.png": plot_png(scene, runs)}
    return write_tree(out, files, force=force, command="symgen control")
