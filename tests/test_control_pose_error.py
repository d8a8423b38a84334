"""Required task twist with rotation-log pose feedback, integrated kinematically with SciPy."""
import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import expm
from scipy.spatial.transform import Rotation

from symgen.control.errors import ControlInputError, GainMatrixError
from symgen.control.pose_error import desired_twist_in_frame, pose_error, required_twist

SEED = 36
RTOL, ATOL = 1e-10, 1e-12
#: relative agreement of the integrated error with the closed-form exponential decay
DECAY_TOL = 1e-6


def _hat(w):
    return np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


def _nearest_rotation(a):
    u, _, vt = np.linalg.svd(a)
    return u @ vt


def _frame_rhs(twist_of):
    """Free-flying frame: p' = R v, R' = R w^ with V = [v; w] in the frame's own axes. The
    controller sees the nearest rotation to the integrator's 9 numbers (trial stages of a
    rejected step may stray from SO(3))."""
    def rhs(t, y):
        p, r = y[:3], y[3:].reshape(3, 3)
        v = twist_of(t, _nearest_rotation(r), p)
        return np.concatenate([r @ v[:3], (r @ _hat(v[3:])).ravel()])
    return rhs


def _desired_pose(t, r_d0, p_d0, v_d):
    """D moving with constant body twist V_d: T_D(t) = T_D(0) exp(t V_d^), the SE(3) exponential
    in closed form: rotation exp(t w^), translation V t v with
    V = 1 + (1 - cos a)/a^2 (t w)^ + (a - sin a)/a^3 (t w)^2, a = |t w|."""
    phi = t * v_d[3:]
    a = np.linalg.norm(phi)
    k = _hat(phi)
    if a < 1e-8:
        jac = np.eye(3) + k / 2 + k @ k / 6
    else:
        jac = np.eye(3) + (1 - np.cos(a)) / a**2 * k + (a - np.sin(a)) / a**3 * k @ k
    return r_d0 @ Rotation.from_rotvec(phi).as_matrix(), p_d0 + r_d0 @ jac @ (t * v_d[:3])


def _track(r0, p0, r_d0, p_d0, v_d, gain, t_end=3.0, rtol=RTOL):
    """Integrate B with V = V_r; returns the times and the pose error e(t)."""
    def twist(t, r, p):
        r_d, p_d = _desired_pose(t, r_d0, p_d0, v_d)
        return required_twist(r, p, r_d, p_d, v_d, gain)
    times = np.linspace(0.0, t_end, 7)
    sol = solve_ivp(_frame_rhs(twist), (0.0, t_end), np.concatenate([p0, r0.ravel()]), t_eval=times,
                    rtol=rtol, atol=ATOL, method="DOP853")
    errors = [pose_error(y[3:].reshape(3, 3), y[:3], *_desired_pose(t, r_d0, p_d0, v_d))
              for t, y in zip(sol.t, sol.y.T)]
    return sol.t, np.array(errors)


def _decays_exponentially(times, errors, l_p, l_o):
    np.testing.assert_allclose(np.linalg.norm(errors[:, :3], axis=1),
                               np.exp(-l_p * times) * np.linalg.norm(errors[0, :3]), rtol=DECAY_TOL, atol=1e-9)
    np.testing.assert_allclose(np.linalg.norm(errors[:, 3:], axis=1),
                               np.exp(-l_o * times) * np.linalg.norm(errors[0, 3:]), rtol=DECAY_TOL, atol=1e-9)


def test_error_to_a_fixed_pose_decays_exponentially():
    rng = np.random.default_rng(SEED)
    r0, r_d = Rotation.random(random_state=1).as_matrix(), Rotation.random(random_state=2).as_matrix()
    times, errors = _track(r0, rng.normal(size=3), r_d, rng.normal(size=3), np.zeros(6), [2.0] * 3 + [1.5] * 3)
    assert np.linalg.norm(errors[0]) > 0.5
    _decays_exponentially(times, errors, 2.0, 1.5)


def test_error_to_a_moving_pose_decays_at_the_same_rates():
    rng = np.random.default_rng(SEED + 1)
    r0, r_d = Rotation.random(random_state=3).as_matrix(), Rotation.random(random_state=4).as_matrix()
    times, errors = _track(r0, rng.normal(size=3), r_d, rng.normal(size=3), rng.normal(size=6), [1.0] * 3 + [2.5] * 3)
    _decays_exponentially(times, errors, 1.0, 2.5)


def test_error_norm_decreases_for_a_full_spd_gain():
    """|e|^2 / 2 is a Lyapunov function for every symmetric positive definite Lambda."""
    rng = np.random.default_rng(SEED + 2)
    a = rng.normal(size=(6, 6))
    gain = 2.0 * a @ a.T / np.linalg.eigvalsh(a @ a.T).max() + 0.5 * np.eye(6)
    r0, r_d = Rotation.random(random_state=5).as_matrix(), Rotation.random(random_state=6).as_matrix()
    _, errors = _track(r0, rng.normal(size=3), r_d, rng.normal(size=3), rng.normal(size=6), gain, t_end=2.0,
                       rtol=1e-8)
    norms = np.linalg.norm(errors, axis=1)
    assert np.all(np.diff(norms) < 0) and norms[-1] < 0.5 * norms[0]


@pytest.mark.parametrize("rotvec", [[0.0, np.pi / 2, 0.0], [0.0, -np.pi / 2, 0.0], [0.0, 0.0, 0.999 * np.pi]],
                         ids=["pitch+90", "pitch-90", "near-half-turn"])
def test_orientation_error_decays_from_euler_singular_and_large_errors(rotvec):
    """A pitch of +-90 deg (gimbal lock of roll-pitch-yaw angles) or a near half turn between the
    frames is an ordinary starting point for the rotation-log error."""
    r_d = Rotation.random(random_state=7).as_matrix()
    r0 = r_d @ Rotation.from_rotvec(rotvec).as_matrix()
    times, errors = _track(r0, np.zeros(3), r_d, np.ones(3), np.zeros(6), 1.0)
    _decays_exponentially(times, errors, 1.0, 1.0)


def test_orientation_error_is_the_rotation_vector_of_the_relative_rotation():
    for seed in range(5):
        r, r_d = Rotation.random(random_state=10 + seed), Rotation.random(random_state=20 + seed)
        expected = (r.inv() * r_d).as_rotvec()
        np.testing.assert_allclose(pose_error(r.as_matrix(), np.zeros(3), r_d.as_matrix(), np.zeros(3))[3:],
                                   expected, atol=1e-12)


def test_position_error_is_the_desired_origin_in_the_current_axes():
    """R = rotation by 90 deg about z, p = 0, p_d = (1, 0, 0): in B's axes D's origin is at (0, -1, 0)."""
    r = Rotation.from_rotvec([0, 0, np.pi / 2]).as_matrix()
    np.testing.assert_allclose(pose_error(r, np.zeros(3), r, np.array([1.0, 0, 0]))[:3], [0, -1, 0], atol=1e-15)


def test_errors_are_invariant_under_a_change_of_world_frame():
    """Moving the world by (Q, t) leaves e and V_d' unchanged: both live in B's own axes."""
    rng = np.random.default_rng(SEED + 3)
    r, r_d, q = (Rotation.random(random_state=k).as_matrix() for k in (30, 31, 32))
    p, p_d, t, v_d = rng.normal(size=3), rng.normal(size=3), rng.normal(size=3), rng.normal(size=6)
    moved = (q @ r, q @ p + t, q @ r_d, q @ p_d + t)
    np.testing.assert_allclose(pose_error(*moved), pose_error(r, p, r_d, p_d), atol=1e-12)
    np.testing.assert_allclose(desired_twist_in_frame(*moved, v_d), desired_twist_in_frame(r, p, r_d, p_d, v_d),
                               atol=1e-12)


def test_feedforward_alone_keeps_the_relative_pose_constant():
    """B moving with V_d' (no feedback) rides rigidly on D: its pose error stays what it was."""
    rng = np.random.default_rng(SEED + 4)
    r_d0, p_d0, v_d = Rotation.random(random_state=40).as_matrix(), rng.normal(size=3), rng.normal(size=6)
    r0, p0 = Rotation.random(random_state=41).as_matrix(), rng.normal(size=3)

    def twist(t, r, p):
        return desired_twist_in_frame(r, p, *_desired_pose(t, r_d0, p_d0, v_d), v_d)
    sol = solve_ivp(_frame_rhs(twist), (0.0, 2.0), np.concatenate([p0, r0.ravel()]), rtol=RTOL, atol=ATOL,
                    method="DOP853")
    end = sol.y[:, -1]
    np.testing.assert_allclose(pose_error(end[3:].reshape(3, 3), end[:3], *_desired_pose(2.0, r_d0, p_d0, v_d)),
                               pose_error(r0, p0, r_d0, p_d0), atol=1e-8)


def test_required_twist_without_error_is_the_desired_twist():
    r, p, v_d = Rotation.random(random_state=50).as_matrix(), np.array([1.0, 2, 3]), np.arange(6.0)
    np.testing.assert_allclose(required_twist(r, p, r, p, v_d, 3.0), v_d, atol=1e-14)


def test_bad_inputs_are_typed_errors():
    eye = np.eye(3)
    with pytest.raises(ControlInputError, match="R_d"):
        pose_error(eye, np.zeros(3), 2 * eye, np.zeros(3))
    with pytest.raises(ControlInputError, match="p"):
        pose_error(eye, np.zeros(2), eye, np.zeros(3))
    with pytest.raises(GainMatrixError, match="Lambda"):
        required_twist(eye, np.zeros(3), eye, np.zeros(3), np.zeros(6), -1.0)


def test_closed_form_desired_motion_is_scipys_matrix_exponential():
    """The test's SE(3) exponential against scipy.linalg.expm of the 4 x 4 twist matrix."""
    rng = np.random.default_rng(SEED + 5)
    v_d, r_d0, p_d0 = rng.normal(size=6), Rotation.random(random_state=60).as_matrix(), rng.normal(size=3)
    xi = np.zeros((4, 4))
    xi[:3, :3], xi[:3, 3] = _hat(v_d[3:]), v_d[:3]
    step = expm(1.7 * xi)
    r_d, p_d = _desired_pose(1.7, r_d0, p_d0, v_d)
    np.testing.assert_allclose(r_d, r_d0 @ step[:3, :3], atol=1e-12)
    np.testing.assert_allclose(p_d, p_d0 + r_d0 @ step[:3, 3], atol=1e-12)
