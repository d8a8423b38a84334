"""The implicit integrators' Jacobian from the generated ``state_derivative_jacobian``
(``simulate(..., jacobian="generated")``): the chain rule through state-dependent torques and
contact forces and through the Baumgarte correction, against central differences of the counted
right-hand side itself; the runs it gives; its refusals. (The generated Jacobian alone is checked
against 50-digit differences in ``tests/test_codegen_forward_derivatives.py``; here the whole
right-hand side is a float function of ``x``, so its differences are float ones, step 1e-6.)"""
from __future__ import annotations

import pathlib
from types import SimpleNamespace

import numpy as np
import pytest

import symgen
from symgen.simulation import SpringTorque, simulate
from symgen.simulation.dynamics import Dynamics
from symgen.simulation.errors import SimulationInputError
from symgen.simulation.jacobian import StateJacobian, force_jacobian
from symgen.simulation.state import StateLayout
from symgen.simulation.forcing import CheckedForce
from symgen.stability.cases import get_case

#: float central differences of the right-hand side (step 1e-6 relative): truncation and rounding
#: both about 1e-10 of its scale
FLOAT_FD_TOL = 1e-6
STEP = 1e-6
#: a chain with a ball wrist (q holds its quaternion at entries 3-6)
WRIST = str(pathlib.Path(__file__).parent / "data" / "derivatives" / "spherical_wrist.yaml")


def _differences(dyn, x, t=0.0):
    cols = []
    for k in range(x.size):
        h = STEP * max(1.0, abs(x[k]))
        e = np.zeros(x.size)
        e[k] = h
        cols.append((dyn(t, x + e) - dyn(t, x - e)) / (2 * h))
    return np.array(cols).T


def _relative(got, want):
    return float(np.max(np.abs(got - want)) / max(1.0, np.max(np.abs(want))))


def _state(model, seed):
    from symgen.codegen.reference import reference_states
    from symgen.simulation.state import StateLayout

    s = reference_states(model, 1, seed=seed)[0]
    return StateLayout(model).join(s["q"], s["V_m"])


@pytest.mark.parametrize("spec", ["chain:n=3", "five_bar"])
def test_equals_differences_of_the_right_hand_side_with_a_spring_and_baumgarte(spec):
    model = symgen.derive(symgen.load(spec))
    dyn = Dynamics(model, "numpy", tau=SpringTorque(model), baumgarte=True)
    x = _state(model, 3)
    assert _relative(StateJacobian(dyn)(0.0, x), _differences(dyn, x)) < FLOAT_FD_TOL


def test_equals_differences_with_a_state_dependent_contact_force():
    case = get_case("stiff_contact_K1e+04")
    st = case.setup
    dyn = Dynamics(st.model, "numpy", tau=lambda t, q, v: st.tau, eta_m=st.eta_m, baumgarte=True)
    x = _state(st.model, 5)
    assert _relative(StateJacobian(dyn)(0.0, x), _differences(dyn, x)) < FLOAT_FD_TOL


def test_a_forgotten_chain_rule_is_caught():
    """Leaving out the torque's own dependence on the state fails the same comparison."""
    model = symgen.derive(symgen.load("chain:n=3"))
    dyn = Dynamics(model, "numpy", tau=SpringTorque(model, period=0.1))
    x = _state(model, 3)
    jac = StateJacobian(dyn)
    d_x, _ = jac.module.state_derivative_jacobian(*dyn.layout.split(x), dyn.tau(0.0, *dyn.layout.split(x)))
    assert _relative(d_x, _differences(dyn, x)) > 1e3 * FLOAT_FD_TOL


def test_a_spring_s_own_jacobian_equals_its_differences():
    model = symgen.derive(symgen.load("four_bar"))
    spring = SpringTorque(model)
    x = _state(model, 2)
    q, v = x[:4], x[4:]
    own = force_jacobian(CheckedForce(spring, model.counts.n, "tau"), 0.0, q, v)
    plain = force_jacobian(CheckedForce(lambda t, q, v: spring(t, q, v), model.counts.n, "tau"), 0.0, q, v)
    np.testing.assert_allclose(own, plain, rtol=1e-8, atol=1e-8)


@pytest.mark.parametrize("method", ["Radau", "BDF"])
def test_a_stiff_run_ends_where_the_finite_difference_run_ends(method):
    case = get_case("stiff_friction")
    st = case.setup
    runs = {jac: simulate(st.model, case.t_end, method, rtol=1e-9, x0=st.config, V_m=st.V_m,
                          tau=lambda t, q, v: st.tau, jacobian=jac, energy=False)
            for jac in ("finite-difference", "generated")}
    assert runs["generated"].settings["jacobian"] == "generated"
    assert runs["generated"].settings["jacobian_calls"] >= 1
    np.testing.assert_allclose(runs["generated"].states[-1], runs["finite-difference"].states[-1], atol=1e-7)


def test_refusals():
    model = symgen.derive(symgen.load("chain:n=2"))
    with pytest.raises(SimulationInputError, match="implicit methods"):
        simulate(model, 0.01, "DOP853", jacobian="generated")
    with pytest.raises(SimulationInputError, match="unknown jacobian"):
        simulate(model, 0.01, "Radau", jacobian="exact")
    stewart = symgen.derive(symgen.load("stewart"))
    baumgarte = SimpleNamespace(baumgarte=True, layout=StateLayout(stewart))
    with pytest.raises(SimulationInputError, match="joint 's1' \\(spherical\\).*Baumgarte"):
        StateJacobian(baumgarte)


def test_with_a_ball_joint_it_equals_differences_of_the_right_hand_side_off_the_unit_sphere():
    """The wrist's quaternion scaled by 1.3: the right-hand side normalises it, and the four
    quaternion columns carry the normalisation's derivative ``(1 - n n^T) / |p|``."""
    model = symgen.derive(symgen.load(WRIST))
    dyn = Dynamics(model, "numpy", tau=SpringTorque(model))
    x = _state(model, 3)
    x[3:7] *= 1.3
    assert _relative(StateJacobian(dyn)(0.0, x), _differences(dyn, x)) < FLOAT_FD_TOL


def test_with_a_ball_joint_a_radau_run_ends_where_the_finite_difference_run_ends():
    model = symgen.derive(symgen.load(WRIST))
    runs = {jac: simulate(model, 0.1, "Radau", rtol=1e-9, jacobian=jac, energy=False)
            for jac in ("finite-difference", "generated")}
    assert runs["generated"].settings["jacobian_calls"] >= 1
    np.testing.assert_allclose(runs["generated"].states[-1], runs["finite-difference"].states[-1], atol=1e-7)
