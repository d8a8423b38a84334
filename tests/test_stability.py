"""The stability suite: every case returns an accurate answer or a typed error, never NaN."""
import json
import warnings

import numpy as np
import pytest

from symgen.cli import main
from symgen.simulation import StiffnessError
from symgen.stability.cases import all_cases, get_case
from symgen.stability.runner import IllConditionedWarning, evaluate, integrate, tolerance

CASES = {c.name: c for c in all_cases()}
FAST = [c for c in CASES.values() if not c.slow]
SLOW = [c for c in CASES.values() if c.slow]


def _check_case(case, backend):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IllConditionedWarning)
        result = evaluate(case, backend)
    assert result.status == case.expect, result
    assert all(np.isfinite(v) or v == np.inf for v in result.conditions.values())
    if result.status == "accurate":
        assert np.isfinite(result.residual) and np.isfinite(result.error)
        assert result.residual <= result.tolerance and result.error <= result.tolerance
    else:
        assert "singular" in result.message and "condition" in result.message
        assert result.residual is None and result.error is None


@pytest.mark.parametrize("case", FAST, ids=lambda c: c.name)
def test_case_is_accurate_or_refused_with_a_typed_error(case):
    _check_case(case, "numpy")


@pytest.mark.slow
@pytest.mark.parametrize("case", SLOW, ids=lambda c: c.name)
def test_slow_case_is_accurate_or_refused_with_a_typed_error(case):
    _check_case(case, "numpy")


@pytest.mark.parametrize("name", ["outstretched_1e+06", "dead_point_1e+13"])
def test_c_backend_gives_the_same_verdict(name):
    _check_case(CASES[name], "c")


def test_the_suite_spans_the_conditioning_the_issue_asks_for():
    """[J_m; J_f] up to 1e12 (outstretched arm) and the four-bar's [T_u1, T_a1] past 1e12."""
    from symgen.stability.metrics import conditions

    arm = CASES["outstretched_1e+12"].setup
    assert conditions(arm.model, arm.config)["[J_m; J_f]"] == pytest.approx(1e12, rel=0.05)
    bar = CASES["dead_point_1e+13"].setup
    assert conditions(bar.model, bar.config)["[T_u1, T_a1]"] > 1e12


def test_ill_conditioned_state_warns_with_its_condition_number():
    """The warning names the worst condition number of the state (here M_mm of the dense route)."""
    from symgen.stability.metrics import conditions

    arm = CASES["outstretched_1e+08"].setup
    worst = max(conditions(arm.model, arm.config).values())
    assert worst > 1e8
    with pytest.warns(IllConditionedWarning, match=f"condition number {worst:.3g}".replace("+", r"\+")):
        evaluate(CASES["outstretched_1e+08"], "numpy")


def test_tolerance_follows_the_condition_number():
    assert tolerance(1.0) == 1e-12
    assert tolerance(1e10) == pytest.approx(100 * np.finfo(float).eps * 1e10)


def test_explicit_method_on_a_stiff_case_suggests_an_implicit_one():
    runs = {r.method: r for r in integrate(CASES["stiff_friction"], "c", methods=["RK45", "Radau"])}
    assert not runs["RK45"].ok
    assert StiffnessError.__name__ in runs["RK45"].message and "Radau" in runs["RK45"].message
    assert runs["Radau"].ok and np.isfinite(runs["Radau"].wall_time)


def test_runs_that_finish_agree_with_radau():
    runs = integrate(CASES["outstretched_1e+02"], "c", methods=["DOP853", "Radau"])
    assert all(r.ok for r in runs)
    assert runs[0].difference < 1e-6


def test_cli_json_lists_every_requested_case(capsys):
    assert main(["stability", "--cases", "length_1e+03,dead_point_1e+13", "--no-integrators", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert [d["name"] for d in data] == ["length_1e+03", "dead_point_1e+13"]
    assert [d["status"] for d in data] == ["accurate", "error"]


def test_cli_writes_the_table(tmp_path, capsys):
    out = tmp_path / "report"
    assert main(["stability", "--cases", "mass_ratio_1e+06", "--out", str(out)]) == 0
    table = (out / "stability.md").read_text()
    assert "| mass_ratio_1e+06 | extreme |" in table and "Radau" in table
    assert (out / "stability.csv").read_text().count("mass_ratio_1e+06") == 5   # one row per integrator


def test_unknown_case_is_a_clear_error(capsys):
    assert main(["stability", "--cases", "no_such_case"]) == 2
    assert "unknown stability case 'no_such_case'" in capsys.readouterr().err
    with pytest.raises(Exception, match="choose from"):
        get_case("nope")


def test_scaled_chain_is_the_benchmark_chain_and_scales_like_a_body_of_its_size():
    """Defaults give the benchmark chain; links k times longer (inertias ~ m L^2) give k^2 M_q
    and k G_q (dimensional analysis, nothing taken from the code)."""
    from symgen.io.builtin import get_scene
    from symgen.model import derive
    from symgen.stability.scenes import scaled_chain
    from symgen.math.configuration import Configuration

    cfg = Configuration({f"j{i}": v for i, v in enumerate([0.3, -0.7, 1.1])})
    base = derive(get_scene("chain:n=3")).evaluate(cfg, qd=np.zeros(3))
    same = derive(scaled_chain(3)).evaluate(cfg, qd=np.zeros(3))
    np.testing.assert_allclose(same.M_q, base.M_q, rtol=1e-14)
    np.testing.assert_allclose(same.G_q, base.G_q, rtol=1e-14, atol=1e-14)
    big = derive(scaled_chain(3, length=1000)).evaluate(cfg, qd=np.zeros(3))   # 1e4 x the 0.1 m links
    np.testing.assert_allclose(big.M_q, 1e8 * base.M_q, rtol=1e-12)
    np.testing.assert_allclose(big.G_q, 1e4 * base.G_q, rtol=1e-12, atol=1e-9)


def test_generated_codes_non_finite_error_counts_as_typed():
    """A generated module's NonFiniteOutputError (its own class, known by name) is a typed refusal."""
    from symgen.codegen.runtime import load_generated
    from symgen.model import derive
    from symgen.io.builtin import get_scene
    from symgen.stability.runner import _typed

    module = load_generated(derive(get_scene("chain:n=2")), "numpy", ["gravity"])
    assert _typed(module.NonFiniteOutputError("gravity", "G", None)) and not _typed(ValueError("other"))


def test_scaled_chain_takes_viscous_friction_joint_by_joint():
    """``viscous`` as one number per joint: the joint force of a state at rest with unit rates
    differs from the frictionless chain's by exactly ``b_i qd_i`` on each joint (eq. 22), and a
    sequence of the wrong length is refused naming the counts."""
    from symgen.math.configuration import Configuration
    from symgen.model import derive
    from symgen.stability.scenes import scaled_chain

    cfg = Configuration({f"j{i}": v for i, v in enumerate([0.3, -0.7, 1.1])})
    qd, qdd = np.array([1.0, -2.0, 0.5]), np.zeros(3)
    plain = derive(scaled_chain(3)).evaluate(cfg, qd=qd).joint_force(qdd)
    rubbed = derive(scaled_chain(3, viscous=(7, 0, 3))).evaluate(cfg, qd=qd).joint_force(qdd)
    np.testing.assert_allclose(rubbed - plain, [7 * 1.0, 0.0, 3 * 0.5], rtol=0, atol=1e-12)
    with pytest.raises(ValueError, match="viscous has 2 values for 3 joints"):
        scaled_chain(3, viscous=(1, 2))
