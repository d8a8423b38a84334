"""The work-precision study, its report files, and the ``symgen simulate`` command."""
from __future__ import annotations

import csv
import dataclasses
import io
import json

import pytest

from symgen.cli import main
from symgen.io.writer import OutputError
from symgen.simulation import StateLayout, builtin_model, work_precision, write_report
from symgen.simulation.forcing import SpringTorque
from symgen.simulation.workprecision import monotonicity_violations

STEPS = (0.05, 0.025, 0.0125)
TOLERANCES = (1e-4, 1e-6, 1e-8)


@pytest.fixture(scope="module")
def study():
    model = builtin_model("five_bar")
    x0 = StateLayout(model).initial_state(V_m=[0.5, -0.5])
    return work_precision(model, 0.5, steps=STEPS, tolerances=TOLERANCES, tau=SpringTorque(model), x0=x0)


def test_study_covers_every_method_backend_and_setting(study):
    keys = {(r.backend, r.method) for r in study.rows}
    assert keys == {(b, m) for b in ("numpy", "c")
                    for m in ("rk4", "semi_implicit_euler", "RK45", "DOP853", "Radau", "BDF")}
    assert len(study.rows) == 2 * (2 * len(STEPS) + 4 * len(TOLERANCES))
    assert all(r.status == "ok" and r.rhs_calls > 0 and r.wall_time > 0 for r in study.rows)
    assert study.conservative and all(r.energy_drift is not None for r in study.rows)


def test_reference_is_checked_against_a_tighter_run(study):
    assert 0 <= study.reference_difference < 1e-11
    assert study.noise_floor >= 10 * study.reference_difference


def test_error_falls_as_steps_shrink_and_tolerances_tighten(study):
    """Monotone down to the noise floor (10x the reference's own difference, at least 1e-12)."""
    assert monotonicity_violations(study) == []
    fine = [r for r in study.rows if r.setting in (STEPS[-1], TOLERANCES[-1])]
    assert all(r.error < 1e-2 for r in fine)                    # semi-implicit Euler is first order
    assert all(r.error < 1e-6 for r in fine if r.method in ("rk4", "DOP853", "Radau"))


def test_monotonicity_check_catches_a_non_monotone_series(study):
    rows = list(study.rows)
    k = next(i for i, r in enumerate(rows) if r.method == "DOP853" and r.setting == TOLERANCES[-1])
    rows[k] = dataclasses.replace(rows[k], error=1.0)
    broken = dataclasses.replace(study, rows=rows)
    bad = monotonicity_violations(broken)
    assert len(bad) == 1 and "DOP853" in bad[0]


def test_both_backends_agree_on_every_run(study):
    errors = {(r.method, r.setting, r.backend): r.error for r in study.rows}
    for (method, setting, backend), err in errors.items():
        if backend == "c":
            assert err == pytest.approx(errors[(method, setting, "numpy")], rel=1e-3, abs=1e-11)


def test_report_files(study, tmp_path):
    out = write_report(study, tmp_path / "report", command="symgen simulate five_bar --t-end 0.5 --report r")
    table = list(csv.DictReader(io.StringIO((out / "work_precision.csv").read_text())))
    assert len(table) == len(study.rows) and float(table[0]["error"]) == study.rows[0].error
    md = (out / "work_precision.md").read_text()
    assert "| backend | method | step / tol | error |" in md and "Monotone" in md and "--t-end 0.5" in md
    assert (out / "work_precision.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    write_report(study, out)                      # its own directory is replaced
    foreign = tmp_path / "mine"
    foreign.mkdir()
    (foreign / "notes.txt").write_text("keep")
    with pytest.raises(OutputError, match="not created by symgen"):
        write_report(study, foreign)
    assert (foreign / "notes.txt").read_text() == "keep"


# ---------------------------------------------------------------------------- command line
def test_cli_single_run(capsys):
    assert main(["simulate", "four_bar", "--t-end", "0.2", "--method", "rk4", "--step", "0.01",
                 "--backend", "numpy"]) == 0
    out = capsys.readouterr().out
    assert "rk4 (numpy), stabilization projection" in out and "constraint drift" in out
    assert "relative energy drift" in out and "j4" in out


def test_cli_single_run_json_both_backends(capsys):
    assert main(["simulate", "chain:n=2", "--t-end", "0.1", "--backend", "both", "--json"]) == 0
    runs = json.loads(capsys.readouterr().out)
    assert [r["backend"] for r in runs] == ["numpy", "c"]
    assert runs[0]["final_state"]["j0"] == pytest.approx(runs[1]["final_state"]["j0"], abs=1e-12)


def test_cli_report(tmp_path, capsys):
    out = tmp_path / "wp"
    assert main(["simulate", "chain:n=2", "--t-end", "0.2", "--report", str(out), "--methods", "rk4,DOP853",
                 "--steps", "0.02,0.01", "--tolerances", "1e-6,1e-8", "--backend", "numpy"]) == 0
    assert "wrote work_precision.csv" in capsys.readouterr().out
    assert sorted(p.name for p in out.iterdir() if not p.name.startswith(".")) == \
        ["work_precision.csv", "work_precision.json", "work_precision.md", "work_precision.png"]
    assert "--methods rk4,DOP853" in (out / "work_precision.md").read_text()


@pytest.mark.parametrize("argv, message", [
    (["simulate", "four_bar", "--t-end", "-1"], "argument --t-end: -1 is out of range"),
    (["simulate", "four_bar", "--t-end", "1", "--method", "leapfrog"], "unknown method 'leapfrog'"),
    (["simulate", "four_bar", "--t-end", "1", "--method", "rk4"], "needs --step"),
    (["simulate", "four_bar", "--t-end", "1", "--method", "rk4", "--step", "0"], "argument --step: 0 is out of range"),
])
def test_cli_bad_input_exits_2_with_a_message(argv, message, capsys):
    """Refused by the parser (a bound of the option) or by the command, with status 2 either way."""
    try:
        status = main(argv)
    except SystemExit as exc:
        status = exc.code
    assert status == 2
    assert message in capsys.readouterr().err
