"""Error against run time for every built-in scene and the UR5, then the summary table.

    python benchmarks/simulation/run_all.py                  # all scenes, then summary.md / summary.csv
    python benchmarks/simulation/run_all.py --summary-only   # the summary from the CSVs already there
    python benchmarks/simulation/run_all.py --scenes four_bar,stewart

Each scene runs ``symgen simulate SCENE --t-end T --steps ... --tolerances ... --report
benchmarks/simulation/<name>`` under ``nice``, in its own process with a time limit (a scene
that fails or times out is named in the output and left out of the summary). The summary answers,
per scene and per error threshold (1e-6, 1e-9, 1e-12), which method and backend got there fastest:
the cheapest run (wall time, then RHS calls) whose *measured* final-state error is at most the
threshold (:func:`symgen.simulation.summary.fastest_to`; no interpolation between runs).
"""
from __future__ import annotations

import argparse
import csv
import io
import pathlib
import shlex
import subprocess
import sys
import time
from dataclasses import dataclass

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from symgen.simulation.summary import (  # noqa: E402
    BELOW_FLOOR, REACHED, THRESHOLDS, fastest_to, read_csv, read_study_meta)

HERE = pathlib.Path(__file__).resolve().parent
#: fixed steps (s) and adaptive tolerances (rtol = atol): the defaults of ``symgen simulate --report``
#: and one tolerance more, 1e-12, so that an error of 1e-12 can be reached
STEPS = (0.04, 0.02, 0.01, 0.005, 0.0025, 0.00125)
TOLERANCES = (1e-4, 1e-6, 1e-8, 1e-10, 1e-12)
TIME_LIMIT = 600          # s per scene


@dataclass(frozen=True)
class Case:
    spec: str             # what `symgen simulate` loads
    name: str             # the report directory under benchmarks/simulation/ (the scene's name)
    t_end: float          # s (the spring torque's period is 1 s)
    steps: tuple = STEPS


#: t_end is cut where one right-hand side is costly, to keep the whole script near 10 minutes on
#: 2 shared cores: the contact and two-arm scenes run 0.5 s, the Stewart platform 0.2 s (its
#: constraint stabilization, 30 closure rows evaluated in NumPy, costs about 3 ms per call on either
#: backend)
CASES = (
    Case("four_bar", "four_bar", 1.0),
    Case("five_bar", "five_bar", 1.0),
    Case("stewart", "stewart", 0.2),
    Case("arm_on_plane", "arm_on_plane", 0.5),
    Case("multi_arm:h=2", "multi_arm_h2", 0.5),
    Case("chain:n=6", "chain_n6", 1.0),
    Case("ur5", "ur5", 1.0),
)


def command(case: Case) -> list[str]:
    """The ``symgen simulate`` command line of one case (run from the repository root)."""
    return ["symgen", "simulate", case.spec, "--t-end", f"{case.t_end:g}", "--steps", ",".join(f"{s:g}" for s in case.steps),
            "--tolerances", ",".join(f"{t:g}" for t in TOLERANCES), "--report", f"benchmarks/simulation/{case.name}"]


def run_case(case: Case) -> tuple[bool, float, str]:
    """Run one case in a niced subprocess; ``(succeeded, seconds, last output line)``."""
    argv = ["nice", "-n", "10", sys.executable, "-m"] + command(case)        # python -m symgen simulate ...
    env = {"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin", **_inherited_env()}
    start = time.perf_counter()
    try:
        proc = subprocess.run(argv, cwd=ROOT, env=env, capture_output=True, text=True, timeout=TIME_LIMIT)
    except subprocess.TimeoutExpired:
        return False, time.perf_counter() - start, f"timed out after {TIME_LIMIT} s"
    tail = (proc.stdout.strip().splitlines() or proc.stderr.strip().splitlines() or [""])[-1]
    if proc.returncode != 0:
        tail = (proc.stderr.strip().splitlines() or [tail])[-1]
    return proc.returncode == 0, time.perf_counter() - start, tail


def _inherited_env() -> dict:
    import os

    keep = ("PATH", "HOME", "CC", "SYMGEN_CACHE", "VIRTUAL_ENV", "LANG")
    return {k: os.environ[k] for k in keep if k in os.environ}


def _cost(run) -> str:
    return f"{run.wall_time:.3g} s, {run.rhs_calls} calls"


def summary_rows(cases=CASES) -> list[dict]:
    """One row per scene and threshold, from ``benchmarks/simulation/<name>/work_precision.{csv,json}``."""
    rows = []
    for case in cases:
        folder = HERE / case.name
        if not (folder / "work_precision.csv").exists():
            continue
        runs = read_csv(folder / "work_precision.csv")
        meta = read_study_meta(folder / "work_precision.json")
        for threshold in THRESHOLDS:
            best = fastest_to(runs, threshold, meta["noise_floor"])
            run = best.run
            rows.append({"scene": case.spec, "t_end": meta["t_end"], "noise_floor": meta["noise_floor"],
                         "threshold": threshold, "verdict": best.verdict,
                         "method": run.method if run else "", "backend": run.backend if run else "",
                         "setting": f"{run.kind} {run.setting:g}" if run else "",
                         "error": repr(run.error) if run else "", "wall_time": repr(run.wall_time) if run else "",
                         "rhs_calls": run.rhs_calls if run else ""})
    return rows


def summary_csv(rows: list[dict]) -> str:
    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=list(rows[0]), lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    return buf.getvalue()


def _cell(row: dict) -> str:
    if row["verdict"] == REACHED:
        return (f"{row['method']} ({row['backend']}), {row['setting']}: {float(row['wall_time']):.3g} s, "
                f"{row['rhs_calls']} calls")
    if row["verdict"] == BELOW_FLOOR:
        return f"below the noise floor ({row['noise_floor']:.3g})"
    return "not reached"


def summary_md(rows: list[dict]) -> str:
    lines = ["# Fastest run to a final-state error, per scene", "",
             "Command: `python benchmarks/simulation/run_all.py` (the per-scene reports, then this table; "
             "`--summary-only` recomputes this table from the CSVs).", "",
             "For each scene and threshold: the run of least wall time (ties: fewer RHS calls) whose *measured* "
             "final-state error is at most the threshold, among all methods, backends and steps or tolerances of "
             "the scene's `work_precision.csv` (no interpolation). `not reached`: no run got there. `below the noise "
             "floor`: the threshold is smaller than ten times the difference between the reference and a tighter "
             "run, so the reference cannot resolve it. Wall time is integration only, on a shared 2-core machine "
             "(noise of tens of per cent); RHS calls do not depend on the machine.", "",
             "| scene | t_end (s) | error <= 1e-6 | error <= 1e-9 | error <= 1e-12 |", "|---|---|---|---|---|"]
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    for scene in scenes:
        mine = {r["threshold"]: r for r in rows if r["scene"] == scene}
        t_end = mine[THRESHOLDS[0]]["t_end"]
        lines.append(f"| `{scene}` | {t_end:g} | " + " | ".join(_cell(mine[t]) for t in THRESHOLDS) + " |")
    return "\n".join(lines) + "\n"


def write_summary(cases=CASES) -> list[dict]:
    rows = summary_rows(cases)
    if not rows:
        raise SystemExit("no work_precision.csv found under benchmarks/simulation/")
    (HERE / "summary.csv").write_text(summary_csv(rows), encoding="utf-8")
    (HERE / "summary.md").write_text(summary_md(rows), encoding="utf-8")
    return rows


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", help="comma-separated specs (default: all)")
    parser.add_argument("--summary-only", action="store_true", help="only rebuild summary.md / summary.csv")
    args = parser.parse_args(argv)
    cases = CASES
    if args.scenes:
        wanted = [s.strip() for s in args.scenes.split(",")]
        unknown = [s for s in wanted if s not in {c.spec for c in CASES}]
        if unknown:
            parser.error(f"unknown scene(s) {unknown}; choose from {[c.spec for c in CASES]}")
        cases = tuple(c for c in CASES if c.spec in wanted)
    failed = []
    if not args.summary_only:
        total = time.perf_counter()
        for case in cases:
            print(f"$ {shlex.join(command(case))}", flush=True)
            ok, seconds, tail = run_case(case)
            print(f"  {'ok' if ok else 'FAILED'} in {seconds:.0f} s: {tail}", flush=True)
            if not ok:
                failed.append(case.spec)
        print(f"all scenes: {time.perf_counter() - total:.0f} s", flush=True)
    write_summary(CASES)
    print(f"wrote {HERE / 'summary.md'} and summary.csv")
    if failed:
        print(f"FAILED: {', '.join(failed)}", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
