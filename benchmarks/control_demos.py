"""Closed-loop demonstrations of the adaptive controller (Section 4), measured in one run.

For every demonstration of ``symgen.simulation.control_demo.DEMOS`` (or the ones named on the command line)
this runs the closed loop with adaptation and with the estimates frozen at their wrong start,
writes the report into ``benchmarks/control/<scene>/`` (control.md, control.csv, control.png) and
a summary table ``benchmarks/control/summary.md`` and ``.csv``.

    python benchmarks/control_demos.py                 # all
    python benchmarks/control_demos.py arm_on_plane    # one
"""
import csv
import dataclasses
import sys
from pathlib import Path

from symgen.simulation.control_demo import DEMOS, run_demo
from symgen.simulation.control_report import FINAL_SHARE, summary, write_report

HERE = Path(__file__).parent / "control"
COLUMNS = ("scene", "final_task_error_adaptive", "final_task_error_frozen", "ratio", "final_force_error_adaptive",
           "final_force_error_frozen", "lyapunov_largest_increase", "estimates_inside_bounds", "rhs_calls",
           "wall_time")


def folder(scene: str) -> str:
    return scene.replace(":", "_").replace("=", "")


def run(names) -> list[dict]:
    rows = []
    for name in names:
        demo = DEMOS[name]
        print(f"  {name} ...", flush=True)
        runs = run_demo(demo)
        settings = {f.name: getattr(demo, f.name) for f in dataclasses.fields(demo) if f.name != "description"}
        write_report(HERE / folder(name), name, demo.description, runs, settings,
                     command=f"python benchmarks/control_demos.py {name}", force=True)
        rows.append({"scene": name, **summary(runs)})
    return rows


def merge(rows: list[dict]) -> list[dict]:
    """The new rows over the ones of an earlier run (one row per scene, DEMOS order)."""
    old = {}
    path = HERE / "summary.csv"
    if path.exists():
        with path.open() as fh:
            old = {r["scene"]: r for r in csv.DictReader(fh)}
    old.update({r["scene"]: r for r in rows})
    return [old[name] for name in DEMOS if name in old]


def write(rows: list[dict]) -> None:
    with (HERE / "summary.csv").open("w", newline="") as fh:
        w = csv.DictWriter(fh, COLUMNS, extrasaction="ignore", lineterminator="\n")
        w.writeheader()
        w.writerows(rows)
    lines = ["# Adaptive control: closed-loop demonstrations", "",
             "`python benchmarks/control_demos.py`. Task error (m and rad as the task's components are) and "
             f"constraint-force error (N, N m): the largest value over the last {FINAL_SHARE:.0%} of the run. "
             "Frozen: the same controller with its estimates held at their wrong start.", "",
             "| scene | task error, adaptive | task error, frozen | adaptive / frozen | force error, adaptive "
             "| force error, frozen | V: largest rise | estimates in bounds | RHS calls | time (s) |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        f = {k: float(r[k]) for k in COLUMNS[1:7]}
        lines.append(f"| {r['scene']} | {f['final_task_error_adaptive']:.2g} | {f['final_task_error_frozen']:.2g} | "
                     f"{f['ratio']:.2g} | {f['final_force_error_adaptive']:.2g} | {f['final_force_error_frozen']:.2g} "
                     f"| {f['lyapunov_largest_increase']:.1g} | {r['estimates_inside_bounds']} | {r['rhs_calls']} | "
                     f"{float(r['wall_time']):.0f} |")
    (HERE / "summary.md").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    HERE.mkdir(parents=True, exist_ok=True)
    write(merge(run(sys.argv[1:] or list(DEMOS))))
