"""The fastest run to an error threshold, read back from work-precision rows (no interpolation)."""
from __future__ import annotations

import math

import pytest

from symgen.simulation.errors import SimulationInputError
from symgen.simulation.summary import BELOW_FLOOR, NOT_REACHED, REACHED, Run, fastest_to, read_rows


def run(method, error, wall_time, rhs_calls=100, backend="c", status="ok", setting=1e-6):
    return Run(backend, method, "tol", setting, error, wall_time, rhs_calls, status)


RUNS = [run("rk4", 5e-7, 0.20, 800), run("DOP853", 2e-7, 0.05, 170), run("Radau", 3e-10, 0.40, 550),
        run("BDF", 1e-10, 0.30, 400, status="failed: StiffnessError"), run("RK45", math.nan, math.nan, 0)]


def test_cheapest_run_at_or_below_the_threshold():
    best = fastest_to(RUNS, 1e-6)
    assert best.verdict == REACHED and best.run.method == "DOP853"
    assert fastest_to(RUNS, 2e-7).run.method == "DOP853"           # at the threshold counts
    assert fastest_to(RUNS, 1.9e-7).run.method == "Radau"          # the cheaper runs miss it: no interpolation


def test_failed_runs_never_count():
    assert fastest_to(RUNS, 2e-10).verdict == NOT_REACHED            # only the failed BDF row is below
    assert fastest_to(RUNS, 2e-10).run is None


def test_threshold_below_the_noise_floor_is_not_claimed():
    assert fastest_to(RUNS, 1e-6, noise_floor=1e-12).verdict == REACHED
    assert fastest_to(RUNS, 1e-12, noise_floor=2e-12).verdict == BELOW_FLOOR


def test_ties_go_to_fewer_rhs_calls():
    runs = [run("a", 1e-8, 0.1, 300), run("b", 1e-8, 0.1, 200)]
    assert fastest_to(runs, 1e-6).run.method == "b"


def test_rows_from_csv_dicts():
    rows = [dict(backend="numpy", method="rk4", kind="step", setting="0.01", error="", wall_time="",
                 rhs_calls="0", status="failed: x"),
            dict(backend="c", method="DOP853", kind="tol", setting="1e-08", error="4e-09", wall_time="0.1",
                 rhs_calls="266", status="ok")]
    runs = read_rows(rows)
    assert math.isnan(runs[0].error) and runs[1].error == 4e-9 and runs[1].rhs_calls == 266
    with pytest.raises(SimulationInputError, match="row 1"):
        read_rows([dict(backend="c", method="rk4")])


def test_committed_summary_is_what_the_csvs_give():
    """benchmarks/simulation/summary.md and .csv equal the summary recomputed from the per-scene
    work_precision.csv files (a stale or hand-edited summary fails)."""
    import importlib.util
    import sys
    from pathlib import Path

    path = Path(__file__).resolve().parents[1] / "benchmarks" / "simulation" / "run_all.py"
    spec = importlib.util.spec_from_file_location("run_all", path)
    run_all = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = run_all                      # dataclasses look their module up
    try:
        spec.loader.exec_module(run_all)
    finally:
        del sys.modules[spec.name]
    rows = run_all.summary_rows()
    assert len(rows) == len(run_all.CASES) * 3
    assert (path.parent / "summary.md").read_text() == run_all.summary_md(rows)
    assert (path.parent / "summary.csv").read_text() == run_all.summary_csv(rows)
