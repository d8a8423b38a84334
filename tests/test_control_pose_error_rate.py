"""The exact time derivative of the required twist (``dV_r`` of eqs. 34-36) against a finite
difference of ``V_r`` along frames moving in closed form (SciPy's matrix exponential)."""
import mpmath
import numpy as np
import pytest
from scipy.linalg import expm
from scipy.spatial.transform import Rotation

from symgen.control.errors import ControlInputError
from symgen.control.pose_error import (SMALL_ANGLE, desired_twist_in_frame, log_rate_matrix, pose_error,
                                       required_twist, required_twist_rate)

SEED = 52
#: step of the fourth-order central difference (s) and its agreement with the exact derivative
STEP, FD_TOL = 1e-3, 1e-8


def _hat(w):
    return np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


def _pose(t0_pose, twist, s):
    """``T_0 expm(s V^)``: the pose after moving for ``s`` with constant body twist ``V``."""
    xi = np.zeros((4, 4))
    xi[:3, :3], xi[:3, 3] = _hat(twist[3:]), twist[:3]
    t = t0_pose @ expm(s * xi)
    return t[:3, :3], t[:3, 3]


def _homogeneous(r, p):
    t = np.eye(4)
    t[:3, :3], t[:3, 3] = r, p
    return t


def _scenario(seed, error_angle):
    """B moves with a constant body twist; D with the body twist ``sdot(t) V_d0``, ``s = t + t^2``
    (so ``dV_d = 2 V_d0``), starting ``error_angle`` rad away from B."""
    rng = np.random.default_rng(seed)
    r_b = Rotation.random(random_state=seed).as_matrix()
    axis = rng.normal(size=3)
    r_d = r_b @ Rotation.from_rotvec(error_angle * axis / np.linalg.norm(axis)).as_matrix()
    t_b, t_d = _homogeneous(r_b, rng.normal(size=3)), _homogeneous(r_d, rng.normal(size=3))
    v_b, v_d0 = rng.normal(size=6), rng.normal(size=6)

    def at(t):
        r, p = _pose(t_b, v_b, t)
        rd, pd = _pose(t_d, v_d0, t + t * t)
        return r, p, rd, pd, (1 + 2 * t) * v_d0
    return at, v_b, 2 * v_d0


def _central_difference(f, t, h=STEP):
    return (-f(t + 2 * h) + 8 * f(t + h) - 8 * f(t - h) + f(t - 2 * h)) / (12 * h)


@pytest.mark.parametrize("error_angle", [0.0, 0.3, 2.5], ids=["on-path", "small-error", "large-error"])
def test_required_acceleration_is_the_time_derivative_of_the_required_twist(error_angle):
    at, v_b, dv_d = _scenario(SEED, error_angle)
    gain = [1.5, 2.0, 2.5, 0.7, 1.1, 3.0]
    t = 0.4
    v_r, dv_r = required_twist_rate(*at(t)[:4], v_b, at(t)[4], dv_d, gain)
    np.testing.assert_allclose(v_r, required_twist(*at(t), gain), atol=1e-14)
    reference = _central_difference(lambda s: required_twist(*at(s), gain), t)
    np.testing.assert_allclose(dv_r, reference, rtol=0, atol=FD_TOL * max(1.0, np.abs(reference).max()))


def test_first_order_derivative_misses_the_finite_difference():
    """The replaced approximation, ``dV_d + Lambda (V_d' - V)``: the check above would catch it."""
    at, v_b, dv_d = _scenario(SEED, 2.5)
    t, gain = 0.4, 2.0
    r, p, rd, pd, v_d = at(t)
    first_order = dv_d + gain * (desired_twist_in_frame(r, p, rd, pd, v_d) - v_b)
    reference = _central_difference(lambda s: required_twist(*at(s), gain), t)
    assert np.abs(first_order - reference).max() > 1e3 * FD_TOL * np.abs(reference).max()


def test_orientation_error_rate_is_the_inverse_left_jacobian_times_the_relative_velocity():
    """``d/dt log(R_BD)`` by a central difference of SciPy's rotation vector for ``R_BD(t) =
    expm(t u^) R_BD(0)`` (left velocity u), far from and near zero."""
    rng = np.random.default_rng(SEED + 1)
    for angle in (2.9, 1.0, 1e-3, 0.5 * SMALL_ANGLE):
        axis = rng.normal(size=3)
        phi, u = angle * axis / np.linalg.norm(axis), rng.normal(size=3)
        r0 = Rotation.from_rotvec(phi).as_matrix()
        log = lambda s: Rotation.from_matrix(expm(s * _hat(u)) @ r0).as_rotvec()
        h = min(STEP, angle / 10)
        np.testing.assert_allclose(log_rate_matrix(phi) @ u, _central_difference(log, 0.0, h), atol=1e-8)


@pytest.mark.parametrize("scale", [0.5, 0.999, 1.001, 100.0])
def test_log_rate_matrix_is_the_closed_form_in_50_digits_near_the_series_switch(scale):
    """Series below :data:`SMALL_ANGLE` and closed form above it against the closed form in
    50-digit arithmetic (mpmath), where cancellation cannot hide."""
    mpmath.mp.dps = 50
    w = np.array([0.3, -0.4, 0.5]) / np.linalg.norm([0.3, -0.4, 0.5])
    phi = scale * SMALL_ANGLE * w
    a = mpmath.sqrt(sum(mpmath.mpf(float(x)) ** 2 for x in phi))
    c = 1 / a**2 - (1 + mpmath.cos(a)) / (2 * a * mpmath.sin(a))
    k = _hat(phi)
    expected = np.eye(3) - 0.5 * k + float(c) * (k @ k)
    np.testing.assert_allclose(log_rate_matrix(phi), expected, rtol=0, atol=1e-15)


def test_required_twist_rate_rejects_a_short_twist():
    eye = np.eye(3)
    with pytest.raises(ControlInputError, match="V"):
        required_twist_rate(eye, np.zeros(3), eye, np.zeros(3), np.zeros(5), np.zeros(6), np.zeros(6), 1.0)
    assert pose_error(eye, np.zeros(3), eye, np.zeros(3)).shape == (6,)
