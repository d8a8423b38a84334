"""States as users hold them: a Configuration, a mapping joint -> position, or a flat array in
scene order give the same dynamics; anything else is a typed error naming the argument."""
import numpy as np
import pytest

import symgen
from symgen.codegen.reference import position_vector
from symgen.errors import StateError
from symgen.simulation import SimulationInputError, StateLayout, simulate
from symgen.math.configuration import Configuration

#: the same state in three forms: quaternions and rotation matrices agree to rounding
FORM_TOL = 1e-12


@pytest.fixture(scope="module")
def stewart():
    return symgen.derive(symgen.load("stewart"))


def forms(model):
    ref = model.reference
    return {"configuration": ref, "mapping": dict(ref.positions), "flat": position_vector(model, ref),
            "list": list(position_vector(model, ref))}


@pytest.mark.parametrize("form", ["mapping", "flat", "list"])
def test_forward_dynamics_takes_every_form(stewart, form):
    want, _ = stewart.forward_dynamics(stewart.reference, [0.1] * 6, [1.0] * 6)
    got, _ = stewart.forward_dynamics(forms(stewart)[form], [0.1] * 6, [1.0] * 6)
    assert np.max(np.abs(got - want)) <= FORM_TOL * max(1.0, np.max(np.abs(want)))


@pytest.mark.parametrize("form", ["mapping", "flat"])
def test_all_joint_motion_and_loop_forces_take_every_form(stewart, form):
    state, v_m, tau = forms(stewart)[form], [0.1] * 6, [1.0] * 6
    ref = stewart.reference
    for got, want in ((stewart.joint_rates(state, v_m), stewart.joint_rates(ref, v_m)),
                      (stewart.joint_accelerations(state, v_m, tau), stewart.joint_accelerations(ref, v_m, tau)),
                      (stewart.loop_forces(state, v_m, tau), stewart.loop_forces(ref, v_m, tau))):
        assert np.max(np.abs(got - want)) <= FORM_TOL * 1e3 * max(1.0, np.max(np.abs(want)))


@pytest.mark.parametrize("form", ["mapping", "flat"])
def test_inverse_dynamics_and_evaluate_take_every_form(stewart, form):
    state = forms(stewart)[form]
    want = stewart.inverse_dynamics(stewart.reference, [0.1] * 6, [0.2] * 6)
    assert np.allclose(stewart.inverse_dynamics(state, [0.1] * 6, [0.2] * 6), want, rtol=0, atol=FORM_TOL * 1e3)
    assert np.allclose(stewart.evaluate(state).M, stewart.evaluate(stewart.reference).M, rtol=0, atol=FORM_TOL)


def test_a_mapping_may_give_a_spherical_joint_as_a_quaternion(stewart):
    positions = dict(stewart.reference.positions)
    q = position_vector(stewart, stewart.reference)
    positions["s1"] = q[3:7]            # u1a, u1b, p1, then s1's (w, x, y, z)
    got = stewart.evaluate(positions).M
    assert np.allclose(got, stewart.evaluate(stewart.reference).M, rtol=0, atol=FORM_TOL)


@pytest.mark.parametrize("bad, message", [
    ("q0", "config must be a Configuration, a mapping"),
    (3.0, "got float"),
    ([0.1, 0.2], r"config as a flat array must hold 42 real numbers .*got shape \(2,\)"),
    ({"elbow": 0.1}, "config: 'elbow' is not a moving joint"),
    (None, "got NoneType"),
])
def test_anything_else_is_a_state_error_naming_the_argument(stewart, bad, message):
    with pytest.raises(StateError, match=message):
        stewart.forward_dynamics(bad, [0.0] * 6, [0.0] * 6)


def test_a_mapping_missing_a_joint_names_it(stewart):
    positions = {k: v for k, v in stewart.reference.positions.items() if k != "p4"}
    for state in (positions, Configuration(positions)):
        with pytest.raises(StateError, match="config: joint 'p4' has no position"):
            stewart.evaluate(state)


def test_a_flat_state_with_nan_is_refused(stewart):
    q = position_vector(stewart, stewart.reference)
    q[5] = np.nan
    with pytest.raises(StateError, match="config contains NaN"):
        stewart.inverse_dynamics(q, [0.0] * 6, [0.0] * 6)


# ---------------------------------------------------------------------------- simulate
@pytest.fixture(scope="module")
def chain():
    return symgen.derive(symgen.load("chain:n=2"))


def test_simulate_takes_every_form_of_the_initial_state(chain):
    layout = StateLayout(chain)
    want = simulate(chain, 0.05, "rk4", step=0.01, x0=layout.initial_state(V_m=[0.3, -0.2])).states[-1]
    for x0 in forms(chain).values():
        got = simulate(chain, 0.05, "rk4", step=0.01, x0=x0, V_m=[0.3, -0.2]).states[-1]
        assert np.max(np.abs(got - want)) <= FORM_TOL


def test_simulate_without_gravity_keeps_a_chain_at_rest(chain):
    """No torque, no velocity, no gravity: nothing moves. With gravity the horizontal chain falls."""
    still = simulate(chain, 0.1, "rk4", step=0.01, x0=chain.reference, gravity=False)
    assert np.max(np.abs(still.states[-1] - still.states[0])) == 0.0
    falls = simulate(chain, 0.1, "rk4", step=0.01, x0=chain.reference)
    assert np.max(np.abs(falls.states[-1] - falls.states[0])) > 1e-3


@pytest.mark.parametrize("bad, message", [("start", "x0 must be a Configuration"), ({"j9": 0.0}, "x0: 'j9'"),
                                          ([0.1, 0.2, 0.3], "x0 as a flat array")])
def test_simulate_refuses_other_initial_states_naming_x0(chain, bad, message):
    with pytest.raises(SimulationInputError, match=message):
        simulate(chain, 0.05, "rk4", step=0.01, x0=bad)


def test_simulate_gravity_is_true_or_false(chain):
    with pytest.raises(SimulationInputError, match="gravity must be True or False"):
        simulate(chain, 0.05, "rk4", step=0.01, gravity=[0, 0, -1])
