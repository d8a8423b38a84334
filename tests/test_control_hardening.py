"""The control Python API refuses what the plant cannot be: a non-finite estimate, a negative rotor
inertia or friction coefficient, a run that would never end; each error names the parameter or
the argument."""
from __future__ import annotations

import math

import numpy as np
import pytest

from symgen.simulation.closed_loop import MAX_T_END, ClosedLoop, check_run, run_closed_loop
from symgen.simulation.control_demo import Demo, run_demo, setup
from symgen.control.errors import ControlInputError, ParameterBoundsError
from symgen.control.parameters import Parameter, ParameterSet

SMALL = Demo("chain:n=2", {"link0": 1.3, "link1": 0.7}, amplitude=0.3, t_end=1.0)


@pytest.fixture(scope="module")
def loop():
    return setup(SMALL)


def _rebuilt(loop, p_hat0):
    lp = loop[0]
    return ClosedLoop(lp.model, lp.params, p_hat0, lp.task, lp.settings)


@pytest.mark.parametrize("bad", [math.nan, math.inf])
def test_a_non_finite_initial_estimate_is_named(loop, bad):
    p = loop[0].p_hat0.copy()
    k = loop[0].params.index("m_link1")
    p[k] = bad
    with pytest.raises(ParameterBoundsError, match=rf"parameter 'm_link1': initial estimate {bad} is not finite"):
        _rebuilt(loop, p)


def test_estimates_of_the_wrong_length_are_refused(loop):
    with pytest.raises(ControlInputError, match=r"p_hat0 has shape \(3,\); the parameter set has 26"):
        _rebuilt(loop, np.ones(3))


@pytest.mark.parametrize("quantity, value, kind", [("Ir", -0.1, "rotor inertia"), ("b", -1.0, "viscous coefficient"),
                                                   ("c", -0.5, "Coulomb coefficient")])
def test_a_known_negative_joint_coefficient_is_refused(quantity, value, kind):
    with pytest.raises(ParameterBoundsError, match=f"parameter '{quantity}_elbow': negative {kind} {value}"):
        ParameterSet([Parameter("elbow", quantity, value)])


def test_a_negative_contact_coefficient_is_refused():
    with pytest.raises(ParameterBoundsError, match="'b_vx_object': negative viscous coefficient of contact"):
        ParameterSet([Parameter("object", "b_vx", -2.0)])


def test_a_rotor_inertia_bound_allowing_negative_values_is_refused():
    with pytest.raises(ParameterBoundsError, match=r"'Ir_elbow': lower bound -1.0 allows a negative rotor inertia"):
        ParameterSet([Parameter("elbow", "Ir", 0.1, -1.0, 1.0, 1.0)])


@pytest.mark.parametrize("bad", [math.nan, math.inf, "heavy"])
def test_a_known_value_must_be_a_finite_number(bad):
    with pytest.raises(ParameterBoundsError, match="parameter 'hx_link3': value"):
        ParameterSet([Parameter("link3", "hx", bad)])


def test_new_values_with_a_nan_are_refused_by_name():
    pset = ParameterSet([Parameter("link3", "m", 2.0), Parameter("link3", "hx", 0.1)])
    with pytest.raises(ParameterBoundsError, match="'hx_link3': value nan is not finite"):
        pset.with_values([2.0, math.nan])


@pytest.mark.parametrize("t_end", [0.0, -1.0, math.inf, math.nan, MAX_T_END * 2, "long"])
def test_a_run_that_would_not_end_is_refused(t_end):
    with pytest.raises(ControlInputError, match=r"t_end = .* s: give a finite time > 0 and <= 60 s"):
        check_run(t_end, 11)


def test_run_closed_loop_checks_its_time_and_samples_before_integrating(loop):
    with pytest.raises(ControlInputError, match="t_end = -1"):
        run_closed_loop(loop[0], loop[1], -1.0)
    with pytest.raises(ControlInputError, match=r"samples = 1: give an integer >= 2"):
        run_closed_loop(loop[0], loop[1], 1.0, samples=1)
    with pytest.raises(ControlInputError, match="rtol = 0"):
        run_closed_loop(loop[0], loop[1], 1.0, rtol=0)


def test_a_zero_time_demonstration_is_refused_not_taken_as_the_default():
    with pytest.raises(ControlInputError, match="t_end = 0"):
        run_demo(SMALL, t_end=0)


def test_a_short_run_still_simulates():
    runs = run_demo(SMALL, t_end=0.05, samples=3)
    assert runs["adaptive"].times[-1] == pytest.approx(0.05)


@pytest.fixture(scope="module")
def two_link_law():
    import symgen
    from symgen.control.law import default_parameters

    model = symgen.derive(symgen.load("chain:n=2"))
    params = default_parameters(model)
    return model, model.evaluate(model.reference, V_m=[0.1, 0.2]), params, np.array(params.values, dtype=float)


@pytest.mark.parametrize("change, message", [
    (lambda p: dict(p_hat=np.where(np.arange(p.size) == 0, np.nan, p)), r"p_hat\[0\] is nan"),
    (lambda p: dict(p_hat=p[:-1]), "p_hat must have shape"),
    (lambda p: dict(v_mr=[np.inf, 0.0]), r"V_mr\[0\] is inf"),
    (lambda p: dict(dv_mr=[0.0]), r"dV_mr must have shape \(2,\)"),
])
def test_the_dense_law_refuses_non_finite_or_misshapen_inputs(two_link_law, change, message):
    from symgen.control.law import control

    model, data, params, p = two_link_law
    args = dict(p_hat=p, v_mr=[0.0, 0.0], dv_mr=[0.0, 0.0])
    control(model, data, params, **args)                        # the unchanged inputs are accepted
    args.update(change(p))
    with pytest.raises(ControlInputError, match=message):
        control(model, data, params, **args)
