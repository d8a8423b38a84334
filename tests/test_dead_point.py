"""Near a loop's dead point the velocity terms lose cond(W)^2 u: every door refuses there, and
answers it gives are right against the 50-digit model on the constraint manifold.

The four-bar is flat on ``q = [t, -t, t - pi, pi - t]`` (``cond W ~ 21.6 / t``). The reference is
model (32) in 50 digits at the exactly closed configuration (``t`` and ``pi`` in 50 digits), not at
the double-rounded one a caller gives: the rounding of the input is what the check guards against.
"""
from __future__ import annotations

import numpy as np
import pytest

import symgen
from symgen.codegen.runtime import load_generated
from symgen.conditioning import MAX_LOOP_CONDITION
from symgen.math.configuration import Configuration
from symgen.math.fields import FloatField, make_field
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


@pytest.mark.parametrize("target", ["numpy", "c"])
def test_generated_code_refuses_and_answers_the_same(four_bar, target):
    module = load_generated(four_bar, target, ["forward_dynamics", "mass_matrix"])
    for t in REFUSED_T:
        with pytest.raises(module.SingularSolveError, match=r"T_u1, T_a1|forward_dynamics"):
            module.forward_dynamics(rounded(t), np.array([1.0]), np.array([1.0]))
        assert np.all(np.isfinite(module.mass_matrix(rounded(t))))
    for t in ANSWERED_T:
        dv = np.atleast_1d(module.forward_dynamics(rounded(t), np.array([1.0]), np.array([1.0])))
        want = on_manifold(four_bar, t)
        assert abs(dv[0] - want) <= 1e-8 * abs(want)


SWEEP_T = tuple(10.0 ** -k for k in range(1, 15))     # down to 1e-14
U = 2.0 ** -53


def _bound(model, t: float) -> float:
    """The stated bound of a returned answer: cond(W)^2 u (symgen.conditioning), plus the float
    evaluation's own rounding."""
    unlimited = FloatField(model.tree.parameters, max_condition=np.inf)
    w = np.asarray(model.evaluate(rounded(t), field=unlimited).maps.W.v, float)
    return float(np.linalg.cond(w)) ** 2 * U + 1e-13


def test_every_door_answers_within_the_bound_or_refuses_down_to_1e_minus_14(four_bar):
    """The sweep of the hardening checks: the four-bar's fold approached in steps down to t = 1e-14;
    every returned dV_m is within its bound of the 50-digit value on the manifold, every other state
    is refused with a typed error."""
    modules = {target: load_generated(four_bar, target, ["forward_dynamics"]) for target in ("numpy", "c")}
    answered = refused = 0
    for t in SWEEP_T:
        want, bound = on_manifold(four_bar, t), _bound(four_bar, t)
        doors = [("dense", lambda: four_bar.forward_dynamics(rounded(t), [1.0], [1.0])[0],
                  symgen.SingularConfigurationError)]
        doors += [(target, lambda m=m: np.atleast_1d(m.forward_dynamics(rounded(t), np.array([1.0]), np.array([1.0]))),
                   m.SingularSolveError) for target, m in modules.items()]
        for name, call, refusal in doors:
            try:
                got = call()
            except refusal:
                refused += 1
                continue
            answered += 1
            assert bound < 1, f"{name} answered at t = {t:g}, where no digit is guaranteed (bound {bound:.2g})"
            assert abs(got[0] - want) <= bound * abs(want), f"{name} at t = {t:g}"
    assert answered >= 3 * 5 and refused >= 3 * 7       # both sides of the limit are exercised
