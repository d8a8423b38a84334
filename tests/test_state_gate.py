"""One state gate for the Python API: every form of a state (mapping, flat array) is checked the
same way, velocities and forces are checked for length and finiteness, functions whose meaning
needs closed loops refuse open ones, and a non-finite result is an error, never returned."""
from __future__ import annotations

import numpy as np
import pytest

import symgen
from symgen.errors import NonFiniteResultError, StateError
from symgen.model import CLOSURE_TOL


@pytest.fixture(scope="module")
def four_bar():
    return symgen.derive(symgen.load("four_bar"))


@pytest.fixture(scope="module")
def stewart():
    return symgen.derive(symgen.load("stewart"))


def _with(model, joint, value):
    pos = dict(model.reference.positions)
    pos[joint] = value
    return pos


@pytest.mark.parametrize("value, message", [(float("nan"), "joint 'j1' is nan"), (float("inf"), "joint 'j1' is inf"),
                                            ("0.3", "needs a real number, got str"),
                                            (True, "needs a real number, got bool")])
def test_a_bad_angle_in_a_mapping_is_refused_naming_the_joint(four_bar, value, message):
    with pytest.raises(StateError, match=message):
        four_bar.forward_dynamics(_with(four_bar, "j1", value), [0.5], [1.0])


def _ball(model):
    return next(name for name, v in model.reference.positions.items() if np.ndim(v) == 2)


@pytest.mark.parametrize("make, message", [
    (lambda r: np.zeros(4), "zero quaternion"),
    (lambda r: np.array([1.0, np.nan, 0, 0]), "NaN or infinity"),
    (lambda r: 2 * r, "not a rotation"),
    (lambda r: -r, "not a rotation"),
    (lambda r: r + 0.1 * np.triu(np.ones((3, 3)), 1), "not a rotation"),
    (lambda r: np.eye(2), "got shape"),
])
def test_a_bad_rotation_in_a_mapping_is_refused(stewart, make, message):
    ball = _ball(stewart)
    with pytest.raises(StateError, match=message):
        stewart.evaluate(_with(stewart, ball, make(stewart.reference[ball])))


def test_a_nearly_orthonormal_rotation_is_snapped(stewart):
    ball = _ball(stewart)
    r = stewart.reference[ball]
    noisy = r + 1e-9 * np.arange(9).reshape(3, 3)
    d_noisy = stewart.evaluate(_with(stewart, ball, noisy))
    d_exact = stewart.evaluate(_with(stewart, ball, r))
    assert np.max(np.abs(d_noisy.M - d_exact.M)) < 1e-7


def test_a_quaternion_in_a_mapping_is_the_same_state_as_its_matrix(stewart):
    from symgen.math.spatial import matrix_to_quat

    ball = _ball(stewart)
    quat = np.array(matrix_to_quat(stewart.reference[ball])) * 3.0      # not normalised: normalised here
    a = stewart.evaluate(_with(stewart, ball, quat)).M
    b = stewart.evaluate(stewart.reference).M
    assert np.max(np.abs(a - b)) < 1e-12


@pytest.mark.parametrize("kwargs, message", [
    (dict(V_m=[np.nan], tau=[1.0]), r"V_m\[0\] is nan"),
    (dict(V_m=[0.5], tau=[np.inf]), r"tau\[0\] is inf"),
    (dict(V_m=[0.5, 0.1], tau=[1.0]), r"V_m must have shape \(1,\)"),
])
def test_bad_velocities_and_forces_are_refused(four_bar, kwargs, message):
    with pytest.raises(StateError, match=message):
        four_bar.forward_dynamics(four_bar.reference, **kwargs)


def test_wrong_lengths_of_dV_m_and_eta_f_are_typed_errors():
    model = symgen.derive(symgen.load("arm_on_plane"))
    m, n = model.counts.m, model.counts.n
    with pytest.raises(StateError, match=r"dV_m must have shape"):
        model.inverse_dynamics(model.reference, np.zeros(m), np.zeros(m + 1))
    with pytest.raises(StateError, match=r"eta_f must have shape"):
        model.inverse_dynamics(model.reference, np.zeros(m), np.zeros(m), np.zeros(n - m + 2))


def test_an_overflowing_result_raises_instead_of_returning_nan(four_bar):
    with np.errstate(all="ignore"), pytest.raises(NonFiniteResultError, match="the result .* is not finite"):
        four_bar.loop_forces(four_bar.reference, [1e155], [1.0])


def test_an_open_loop_is_refused_where_the_equations_need_it_closed(four_bar):
    open_ = _with(four_bar, "j2", four_bar.reference["j2"] + 1e3 * CLOSURE_TOL)
    for call in (lambda: four_bar.forward_dynamics(open_, [0.5], [1.0]),
                 lambda: four_bar.inverse_dynamics(open_, [0.5], [0.1]),
                 lambda: four_bar.joint_accelerations(open_, [0.5], [1.0]),
                 lambda: four_bar.loop_forces(open_, [0.5], [1.0])):
        with pytest.raises(StateError, match="constraint 'closure' is open by"):
            call()
    four_bar.evaluate(open_)                                         # an identity in q: accepted
    dv, _ = four_bar.forward_dynamics(open_, [0.5], [1.0], check_closure=False)
    assert np.all(np.isfinite(dv))


def test_the_flat_array_and_the_mapping_are_one_gate(four_bar):
    from symgen.simulation import StateLayout

    flat = StateLayout(four_bar).positions(four_bar.reference)
    bad = flat.copy()
    bad[0] = np.nan
    for state in (bad, _with(four_bar, "j1", np.nan)):
        with pytest.raises(StateError, match="not finite|NaN or infinity"):
            four_bar.forward_dynamics(state, [0.5], [1.0])


def test_the_state_layout_takes_a_mapping(four_bar):
    from symgen.simulation import StateLayout

    layout = StateLayout(four_bar)
    assert np.array_equal(layout.positions(dict(four_bar.reference.positions)), layout.positions(four_bar.reference))


@pytest.mark.parametrize("spec", ["four_bar", "arm_on_plane"])
def test_one_motion_call_gives_what_the_separate_calls_give(spec):
    model = symgen.derive(symgen.load(spec))
    rng = np.random.default_rng(4)
    cfg, v_m = symgen.closure.random_consistent_states(model, 1, seed=5)[0]
    tau = rng.uniform(-1, 1, model.counts.n)
    motion = model.motion(cfg, v_m, tau)
    dv, eta_f = model.forward_dynamics(cfg, v_m, tau)
    assert np.allclose(motion.dV_m, dv, rtol=0, atol=1e-12) and np.allclose(motion.eta_f, eta_f, rtol=0, atol=1e-12)
    assert np.allclose(motion.qdd_all, model.joint_accelerations(cfg, v_m, tau), rtol=0, atol=1e-12)
    assert np.allclose(motion.lam, model.loop_forces(cfg, v_m, tau), rtol=0, atol=1e-12)
    assert np.allclose(motion.qd_all, model.joint_rates(cfg, v_m), rtol=0, atol=1e-12)
    back = model.motion(cfg, v_m, dV_m=motion.dV_m, eta_f=motion.eta_f)      # inverse: the same motion
    assert np.allclose(back.tau, tau, rtol=0, atol=1e-10)
