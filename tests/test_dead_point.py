"""Near a loop's dead point the velocity terms lose cond(W)^2 u: every door refuses there, and
answers it gives are right against the 50-digit model on the constraint manifold. The same for
every built-in with loops (symgen.accuracy.dead_points): the five-bar's fold, the Stewart
platform's singular yaw, and two arms holding an object with one wrist singular, where
[J_m; J_f] -- not W -- is what goes singular.

The four-bar is flat on ``q = [t, -t, t - pi, pi - t]`` (``cond W ~ 21.6 / t``). The reference is
model (32) in 50 digits at the exactly closed configuration (``t`` and ``pi`` in 50 digits), not at
the double-rounded one a caller gives: the rounding of the input is what the check guards against.
"""
from __future__ import annotations

import numpy as np
import pytest

import symgen
from symgen.accuracy.dead_points import FAMILIES, conditions, exact_configuration, float_positions, sweep_point
from symgen.closure import closure_residual
from symgen.codegen.runtime import load_generated
from symgen.conditioning import MAX_LOOP_CONDITION
from symgen.math.configuration import Configuration, as_configuration
from symgen.math.fields import make_field
from symgen.model_solves import solve_forward

REFUSED_T = (1e-8, 1e-10)            # cond W ~ 2e9, 2e11
ANSWERED_T = (1e-2, 1e-4)            # cond W ~ 2e3, 2e5


@pytest.fixture(scope="module")
def four_bar():
    return symgen.derive(symgen.load("four_bar"))


def on_manifold(model, t: float) -> float:
    """``dV_m`` at ``V_m = 1``, ``tau = 1`` in 50 digits at the exact configuration of the family."""
    fld = make_field("mp", model.tree.parameters)
    mp = fld.ctx
    t_mp = mp.mpf(t)
    config = Configuration({"j1": t_mp, "j2": -t_mp, "j3": t_mp - mp.pi, "j4": mp.pi - t_mp})
    dv, _ = solve_forward(model.evaluate(config, V_m=[fld.one], field=fld), [fld.one])
    return float(dv[0])


def rounded(t: float) -> np.ndarray:
    return np.array([t, -t, t - np.pi, np.pi - t])


def test_the_family_is_near_the_dead_point_as_stated(four_bar):
    for t in REFUSED_T:
        w = four_bar.evaluate(rounded(t), field="float").maps.W.v
        assert np.linalg.cond(np.asarray(w, float)) > MAX_LOOP_CONDITION


@pytest.mark.parametrize("t", REFUSED_T)
def test_dense_model_refuses_within_the_rounding_of_the_dead_point(four_bar, t):
    with pytest.raises(symgen.SingularConfigurationError, match=r"\[T_u1, T_a1\].*dead point"):
        four_bar.forward_dynamics(rounded(t), [1.0], [1.0])
    with pytest.raises(symgen.SingularConfigurationError):
        four_bar.loop_forces(rounded(t), [1.0], [1.0])


def test_functions_without_the_maps_rates_keep_answering(four_bar):
    """M, G and the joint rates lose only cond u: still answered at cond W ~ 2e9."""
    q = rounded(1e-8)
    assert np.all(np.isfinite(four_bar.joint_rates(q, [1.0])))
    assert np.all(np.isfinite(four_bar.evaluate(q).M))


@pytest.mark.parametrize("t", ANSWERED_T)
def test_dense_answers_are_right_on_the_manifold(four_bar, t):
    dv, _ = four_bar.forward_dynamics(rounded(t), [1.0], [1.0])
    want = on_manifold(four_bar, t)
    assert abs(dv[0] - want) <= 1e-8 * abs(want)


@pytest.mark.parametrize("target", ["numpy", "c", "c-extension"])
def test_generated_code_refuses_and_answers_the_same(four_bar, target):
    """Every target refuses the states near the dead point, naming the matrix ([T_u1, T_a1] of
    eq. 9; the C ones name each matrix the function factors, not knowing which one failed)."""
    module = load_generated(four_bar, target.removesuffix("-extension"), ["forward_dynamics", "mass_matrix"],
                            python_extension=target.endswith("-extension"))
    for t in REFUSED_T:
        with pytest.raises(module.SingularSolveError, match=r"\[T_u1, T_a1\] \(eq\. 9\)"):
            module.forward_dynamics(rounded(t), np.array([1.0]), np.array([1.0]))
        assert np.all(np.isfinite(module.mass_matrix(rounded(t))))
    for t in ANSWERED_T:
        dv = np.atleast_1d(module.forward_dynamics(rounded(t), np.array([1.0]), np.array([1.0])))
        want = on_manifold(four_bar, t)
        assert abs(dv[0] - want) <= 1e-8 * abs(want)


SWEEP_T = tuple(10.0 ** -k for k in range(1, 15))     # down to 1e-14
U = 2.0 ** -53
#: the scene spec of each family of symgen.accuracy.dead_points
SPECS = {"four_bar": "four_bar", "five_bar": "five_bar", "stewart": "stewart", "multi_arm": "multi_arm:h=2"}
#: slack for the float evaluation's own rounding next to cond^2 u (a few ulps of a well-conditioned solve)
EVALUATION_SLACK = 1e-13


@pytest.fixture(scope="module")
def doors():
    """Per family: the model and its generated NumPy and C forward dynamics, made once."""
    made = {}

    def get(name):
        if name not in made:
            model = symgen.derive(symgen.load(SPECS[name]))
            made[name] = model, {t: load_generated(model, t, ["forward_dynamics"]) for t in ("numpy", "c")}
        return made[name]
    return get


def _check_point(model, family, t, modules) -> tuple[int, int]:
    """Every door at ``t``: an answer within ``max(cond W, cond A)^2 u`` (and only where that is
    below 1), or a typed refusal. Returns (answered, refused)."""
    point = sweep_point(model, family, t, modules)
    bound = point.bound + EVALUATION_SLACK
    answered = refused = 0
    for door, answer in point.answers.items():
        if isinstance(answer, str):
            assert answer in ("SingularConfigurationError", "SingularSolveError"), (door, t, answer)
            refused += 1
            continue
        answered += 1
        assert point.bound < 1, f"{door} answered at t = {t:g}, where no digit is guaranteed (bound {point.bound:.2g})"
        assert answer <= bound, f"{door} at t = {t:g}: error {answer:.2g} above the bound {bound:.2g}"
    return answered, refused


@pytest.mark.parametrize("name", ["four_bar", "five_bar"])
def test_every_door_answers_within_the_bound_or_refuses_down_to_1e_minus_14(doors, name):
    """The sweep of the hardening checks: the fold approached in steps down to t = 1e-14; every
    returned dV_m is within its bound of the 50-digit value on the manifold, every other state is
    refused with a typed error."""
    model, modules = doors(name)
    counts = np.array([_check_point(model, FAMILIES[name], t, modules) for t in SWEEP_T]).sum(axis=0)
    assert counts[0] >= 3 * 5 and counts[1] >= 3 * 7       # both sides of the limit are exercised


@pytest.mark.slow
@pytest.mark.parametrize("name", ["stewart", "multi_arm"])
def test_every_door_answers_within_the_bound_or_refuses_on_the_large_loops(doors, name):
    """The same sweep on the Stewart platform (W singular at a yaw of the platform) and on two arms
    holding an object (arm 1's wrist singular: [J_m; J_f] singular, W well conditioned)."""
    model, modules = doors(name)
    counts = np.array([_check_point(model, FAMILIES[name], t, modules) for t in SWEEP_T]).sum(axis=0)
    assert counts[0] >= 3 * 4 and counts[1] >= 3 * 7


@pytest.mark.parametrize("name", ["stewart", "multi_arm"])
def test_the_large_loops_refuse_where_the_estimate_ran_low_and_answer_away_from_it(doors, name):
    """At t = 1e-7 the 2-norm condition is 3.6e8 (Stewart's W) and 1.1e8 (the arms' [J_m; J_f]):
    every door refuses (the generated pivot-ratio estimates are 3.0e7 and 2.8e7 there, below the
    2-norm limit, hence the estimate's margin); at t = 1e-3 every door answers within its bound."""
    model, modules = doors(name)
    assert _check_point(model, FAMILIES[name], 1e-7, modules) == (0, 3)
    assert _check_point(model, FAMILIES[name], 1e-3, modules) == (3, 0)


def test_the_arms_limit_comes_from_the_task_matrix_not_the_loop_block(doors):
    """Two arms, arm 1's wrist at 1e-7 from its singularity: W is well conditioned, [J_m; J_f] is
    not, and the dense model's refusal names [J_m; J_f]."""
    model, _ = doors("multi_arm")
    fld = make_field("mp", model.tree.parameters)
    q = float_positions(model, exact_configuration(model, FAMILIES["multi_arm"], fld, 1e-7))
    cond_w, cond_a = conditions(model, q)
    assert cond_w < 10 and cond_a > MAX_LOOP_CONDITION
    with pytest.raises(symgen.SingularConfigurationError, match=r"\[J_m; J_f\]"):
        model.forward_dynamics(q, np.array(FAMILIES["multi_arm"].V_m), np.array(FAMILIES["multi_arm"].tau))
    assert np.all(np.isfinite(model.joint_rates(q, np.array(FAMILIES["multi_arm"].V_m))))


@pytest.mark.parametrize("name", list(SPECS))
def test_each_family_is_closed_and_its_condition_grows_like_one_over_t(doors, name):
    """The rounded states are closed to double precision, and the singular matrix's condition
    grows 1000-fold from t = 1e-3 to 1e-6 (a simple fold: smallest singular value ~ t)."""
    model, _ = doors(name)
    family = FAMILIES[name]
    fld = make_field("mp", model.tree.parameters)
    conds = []
    for t in (1e-3, 1e-6):
        q = float_positions(model, exact_configuration(model, family, fld, t))
        assert np.max(np.abs(closure_residual(model, as_configuration(q, model.scene)))) < 1e-14
        conds.append(max(conditions(model, q)))
    assert 900 < conds[1] / conds[0] < 1100
