"""Self-tests of the independent float reference ``tests/reference/tree_dynamics.py``.

Every expected value here is derived by hand (closed forms) or from a physical law (energy,
power, finite differences of the reference's own kinematics), never from symgen's derivation.
"""
from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp
from scipy.optimize import least_squares

from symgen.scene import Scene
from symgen.math.configuration import Configuration, CosSin

try:  # `python -m pytest` from the repository root
    from tests.reference import tree_dynamics as td
except ImportError:  # pytest's rootdir-relative import (tests/ on sys.path)
    from reference import tree_dynamics as td

CLOSED_FORM_TOL = 1e-12   # algebra vs. hand-derived formula
FD_STEP = 1e-5            # central finite-difference step (s)
FD_TOL = 1e-7             # central differences: O(step^2) truncation + O(eps/step) rounding
ENERGY_TOL = 1e-8         # drift of a conserved energy under solve_ivp(rtol=1e-11)
SOLVE_TOL = 1e-10         # linear solves (KKT residuals)
G = 9.81


# ----------------------------------------------------------------------------- helpers
def advance(scene, q, qd, qdd, t):
    """Configuration and velocity at time ``t`` along ``q(t) = q + qd t + qdd t^2/2`` (spherical
    joints: ``R exp(skew(w t + wdot t^2/2))``, correct to O(t^3) for child-frame rates)."""
    out = {}
    for name, s in td.coordinate_slices(scene).items():
        step = qd[s] * t + 0.5 * qdd[s] * t * t
        if scene.joints[name].type == "spherical":
            angle = np.linalg.norm(step)
            axis = step / angle if angle > 0 else np.array([0.0, 0.0, 1.0])
            out[name] = q[name] @ td.rotation_about(axis, angle)
        else:
            out[name] = q[name] + step[0]
    return out, qd + qdd * t


def central_rate(scene, q, qd, qdd, fn):
    """d/dt fn(q(t), qd(t)) at t = 0 by central differences."""
    qp, qdp = advance(scene, q, qd, qdd, FD_STEP)
    qm, qdm = advance(scene, q, qd, qdd, -FD_STEP)
    return (np.asarray(fn(qp, qdp)) - np.asarray(fn(qm, qdm))) / (2 * FD_STEP)


def random_rotation(rng):
    quat = rng.normal(size=4)
    return td.rotation_about(quat[1:] / np.linalg.norm(quat[1:]), 2 * np.arccos(abs(quat[0]) / np.linalg.norm(quat)))


def random_state(scene, rng):
    q = {}
    for name, s in td.coordinate_slices(scene).items():
        q[name] = random_rotation(rng) if scene.joints[name].type == "spherical" else rng.uniform(-1.5, 1.5)
    n = td._n_coords(scene)
    return q, rng.normal(size=n), rng.normal(size=n)


def double_pendulum(m1=1.3, m2=0.7, l1=0.9, r1=0.4, r2=0.35, i1=0.02, i2=0.015):
    s = Scene("double_pendulum")
    s.gravity = sp.ImmutableMatrix([0, -sp.Rational("9.81"), 0])
    s.add_body("l1", mass=m1, com=[r1, 0, 0], inertia=[0.0005, i1, i1])
    s.add_body("l2", mass=m2, com=[r2, 0, 0], inertia=[0.0004, i2, i2])
    s.add_joint("j1", "revolute", "world", "l1", axis="z", actuated=True)
    s.add_joint("j2", "revolute", "l1", "l2", xyz=[l1, 0, 0], axis="z", actuated=True)
    return s


def mixed_chain(friction=False, gravity=True):
    """A 3-D tree with every joint type, tilted origins, generic axes and full inertias."""
    s = Scene("mixed")
    if not gravity:
        s.gravity = sp.ImmutableMatrix([0, 0, 0])
    fr = dict(viscous=0.3, coulomb=0.2) if friction else {}
    s.add_body("a", mass=1.2, com=[0.1, 0.2, -0.1], inertia=[0.02, 0.03, 0.04, 0.001, -0.002, 0.003])
    s.add_body("b", mass=0.8, com=[0.3, 0, 0.05], inertia=[0.01, 0.015, 0.02, 0.0, 0.001, 0.0])
    s.add_body("c", mass=0.5, com=[0, 0.1, 0.2], inertia=[0.005, 0.006, 0.007])
    s.add_body("d", mass=0.4, com=[0.05, 0.05, 0], inertia=[0.004, 0.003, 0.005])
    s.add_body("e", mass=0.3, com=[0.0, 0.0, 0.1], inertia=[0.002, 0.002, 0.001])
    s.add_joint("ja", "revolute", "world", "a", xyz=[0.1, 0, 0.2], rpy=[0.2, -0.1, 0.4],
                axis=[1, 2, 2], rotor_inertia=0.05, **fr)
    s.add_joint("jb", "spherical", "a", "b", xyz=[0.4, 0.1, 0], rpy=[0.3, 0.5, -0.2], **fr)
    s.add_joint("jc", "prismatic", "b", "c", xyz=[0.5, 0, 0.1], axis="-y", rotor_inertia=0.1, **fr)
    s.add_joint("jd", "fixed", "c", "d", xyz=[0, 0.2, 0.1], rpy=[0.1, 0.2, 0.3])
    s.add_joint("je", "revolute", "a", "e", xyz=[0, 0.3, 0], axis="x", **fr)
    s.add_frame("tool", "d", xyz=[0.1, -0.05, 0.2], rpy=[0.4, 0.1, -0.3])
    s.add_frame("side", "e", xyz=[0, 0.2, 0.1], rpy=[-0.2, 0.3, 0.1])
    return s


def four_bar(crank=0.3, coupler=0.8, rocker=0.6, ground=0.7):
    """Planar four-bar cut at the rocker's ground pivot: a massless body after joint j4 is held
    to the ground frame by a planar_weld (vx, vy, wz)."""
    s = Scene("four_bar")
    s.gravity = sp.ImmutableMatrix([0, -sp.Rational("9.81"), 0])
    s.add_body("l1", mass=1.0, com=[crank / 2, 0, 0], inertia=[0.001, 0.01, 0.01])
    s.add_body("l2", mass=2.0, com=[coupler / 2, 0, 0], inertia=[0.001, 0.1, 0.1])
    s.add_body("l3", mass=1.5, com=[rocker / 2, 0, 0], inertia=[0.001, 0.05, 0.05])
    s.add_body("cut", mass=0)
    s.add_joint("j1", "revolute", "world", "l1", axis="z", actuated=True)
    s.add_joint("j2", "revolute", "l1", "l2", xyz=[crank, 0, 0], axis="z")
    s.add_joint("j3", "revolute", "l2", "l3", xyz=[coupler, 0, 0], axis="z")
    s.add_joint("j4", "revolute", "l3", "cut", xyz=[rocker, 0, 0], axis="z")
    s.add_frame("tip", "cut")
    s.add_frame("pivot", "world", xyz=[ground, 0, 0])
    s.add_constraint("close", "planar_weld", "tip", "pivot")
    s.set_motion(joints=["j1"])
    return s


def closed_four_bar_state(s, q1, q1_rate):
    """A configuration and velocity satisfying the closure, for crank angle q1 and rate."""
    def residual(x):
        return td.constraint_residual(s, {"j1": q1, "j2": x[0], "j3": x[1], "j4": x[2]})
    x = least_squares(residual, [1.2, -1.9, 0.0], xtol=1e-15, ftol=1e-15, gtol=1e-15).x
    q = {"j1": q1, "j2": x[0], "j3": x[1], "j4": x[2]}
    K, _ = td.constraint_rows(s, q, np.zeros(4))
    dep = np.linalg.solve(K[:, 1:], -K[:, 0] * q1_rate)
    return q, np.concatenate([[q1_rate], dep])


def ball_loop(full_weld=False):
    """A 3-D loop closed by a ball joint, plus a constraint between two moving branches: a full
    weld (over-constrained: 9 rows for 7 coordinates, fine for kinematic checks) or two of its
    components (5 rows, m = 2)."""
    s = Scene("ball_loop")
    s.add_body("a", mass=1.0, com=[0.2, 0, 0], inertia=[0.01, 0.02, 0.02])
    s.add_body("b", mass=0.7, com=[0.2, 0.05, 0], inertia=[0.01, 0.01, 0.02, 0.001, 0, 0])
    s.add_body("c", mass=0.5, com=[0, 0, 0.2], inertia=[0.01, 0.01, 0.005])
    s.add_body("d", mass=0.6, com=[0.1, 0, 0], inertia=[0.004, 0.005, 0.006])
    s.add_body("e", mass=0.2, com=[0, 0.1, 0], inertia=[0.001, 0.001, 0.001])
    s.add_joint("ja", "revolute", "world", "a", axis="z")
    s.add_joint("jb", "revolute", "a", "b", xyz=[0.4, 0, 0], rpy=[0.3, 0, 0], axis="y")
    s.add_joint("jc", "spherical", "b", "c", xyz=[0.4, 0, 0])
    s.add_joint("jd", "prismatic", "world", "d", xyz=[0, 0.5, 0], axis=[1, 1, 0])
    s.add_joint("je", "revolute", "d", "e", xyz=[0.2, 0, 0], rpy=[0, 0.4, 0], axis="z")
    s.add_frame("c_tip", "c", xyz=[0, 0, 0.4], rpy=[0.1, 0.2, 0.3])
    s.add_frame("anchor", "world", xyz=[0.5, 0.3, 0.2])
    s.add_frame("e_tip", "e", xyz=[0.1, 0.2, 0], rpy=[0.5, -0.2, 0.1])
    s.add_constraint("ball", "ball", "c_tip", "anchor")
    if full_weld:
        s.add_constraint("grip", "weld", "e_tip", "c_tip")
    else:
        s.add_constraint("grip", "custom", "e_tip", "c_tip", components=["vy", "wx"])
    return s


# ----------------------------------------------------------------------------- 1. closed form
def test_double_pendulum_mass_matrix_matches_closed_form():
    m1, m2, l1, r1, r2, i1, i2 = 1.3, 0.7, 0.9, 0.4, 0.35, 0.02, 0.015
    s = double_pendulum(m1, m2, l1, r1, r2, i1, i2)
    q1, q2 = 0.4, -1.1
    c2 = np.cos(q2)
    expected = np.array([
        [i1 + m1 * r1**2 + i2 + m2 * (l1**2 + r2**2 + 2 * l1 * r2 * c2), i2 + m2 * (r2**2 + l1 * r2 * c2)],
        [i2 + m2 * (r2**2 + l1 * r2 * c2), i2 + m2 * r2**2],
    ])
    M, _ = td.joint_space(s, {"j1": q1, "j2": q2}, np.zeros(2))
    np.testing.assert_allclose(M, expected, atol=CLOSED_FORM_TOL)


def test_double_pendulum_gravity_and_coriolis_match_closed_form():
    m1, m2, l1, r1, r2 = 1.3, 0.7, 0.9, 0.4, 0.35
    s = double_pendulum(m1, m2, l1, r1, r2)
    q1, q2, qd1, qd2 = 0.4, -1.1, 0.8, -1.7
    c1, c12, s2 = np.cos(q1), np.cos(q1 + q2), np.sin(q2)
    # V = m1 g r1 sin q1 + m2 g (l1 sin q1 + r2 sin(q1 + q2)); h_grav = dV/dq
    gravity = np.array([m1 * G * r1 * c1 + m2 * G * (l1 * c1 + r2 * c12), m2 * G * r2 * c12])
    coriolis = m2 * l1 * r2 * s2 * np.array([-(2 * qd1 * qd2 + qd2**2), qd1**2])
    q = {"j1": q1, "j2": q2}
    _, h0 = td.joint_space(s, q, np.zeros(2))
    np.testing.assert_allclose(h0, gravity, atol=CLOSED_FORM_TOL)
    _, h = td.joint_space(s, q, np.array([qd1, qd2]))
    np.testing.assert_allclose(h, gravity + coriolis, atol=CLOSED_FORM_TOL)


def test_cos_sin_configuration_is_accepted():
    s = double_pendulum()
    t = 0.25
    cs = CosSin.from_half_tangent(t)
    angle = 2 * np.arctan(t)
    M_cs, _ = td.joint_space(s, Configuration({"j1": cs, "j2": cs}), np.zeros(2))
    M_f, _ = td.joint_space(s, {"j1": angle, "j2": angle}, np.zeros(2))
    np.testing.assert_allclose(M_cs, M_f, atol=CLOSED_FORM_TOL)


# ----------------------------------------------------------------------------- 2. M, KE, power
def test_coordinate_slices_follow_declaration_order_and_skip_fixed():
    sl = td.coordinate_slices(mixed_chain())
    assert sl == {"ja": slice(0, 1), "jb": slice(1, 4), "jc": slice(4, 5), "je": slice(5, 6)}


def test_mass_matrix_is_symmetric_positive_definite():
    s, rng = mixed_chain(), np.random.default_rng(1)
    for _ in range(5):
        q, qd, _ = random_state(s, rng)
        M, _ = td.joint_space(s, q, qd)
        np.testing.assert_allclose(M, M.T, atol=SOLVE_TOL)
        assert np.linalg.eigvalsh(M).min() > 0


def test_kinetic_energy_equals_half_qd_M_qd():
    s, rng = mixed_chain(), np.random.default_rng(2)
    q, qd, _ = random_state(s, rng)
    M, _ = td.joint_space(s, q, qd)
    assert td.kinetic_energy(s, q, qd) == pytest.approx(0.5 * qd @ M @ qd, rel=SOLVE_TOL)


def test_newton_euler_is_affine_in_qdd_with_slope_M():
    s, rng = mixed_chain(friction=True), np.random.default_rng(3)
    q, qd, qdd = random_state(s, rng)
    M, h = td.joint_space(s, q, qd)
    np.testing.assert_allclose(td.inverse_dynamics(s, q, qd, qdd), M @ qdd + h, atol=SOLVE_TOL)


@pytest.mark.parametrize("friction", [False, True])
def test_power_balance_without_gravity(friction):
    """d/dt KE = qd^T (tau - friction) along the motion that tau produces."""
    s, rng = mixed_chain(friction=friction, gravity=False), np.random.default_rng(4)
    q, qd, _ = random_state(s, rng)
    tau = rng.normal(size=len(qd))
    qdd, lam = td.kkt(s, q, qd, tau)
    assert lam.size == 0
    rate = central_rate(s, q, qd, qdd, lambda qq, vv: td.kinetic_energy(s, qq, vv))
    friction_force = td._friction(s, qd)
    assert friction == bool(np.any(friction_force))
    assert rate == pytest.approx(qd @ (tau - friction_force), abs=FD_TOL)


def test_friction_enters_h_with_positive_sign():
    """h(friction) - h(no friction) = b qd + c sign(qd) per 1-DOF joint, b w + c w/|w| for a
    spherical joint (b = 0.3, c = 0.2 on every moving joint of mixed_chain)."""
    rng = np.random.default_rng(14)
    q, qd, _ = random_state(mixed_chain(), rng)
    qd[5] = 0.0   # Coulomb friction of a joint at rest is zero
    _, h_plain = td.joint_space(mixed_chain(), q, qd)
    _, h_fric = td.joint_space(mixed_chain(friction=True), q, qd)
    w = qd[1:4]
    expected = 0.3 * qd + 0.2 * np.concatenate([np.sign(qd[:1]), w / np.linalg.norm(w), np.sign(qd[4:])])
    np.testing.assert_allclose(h_fric - h_plain, expected, atol=CLOSED_FORM_TOL)


def test_gravity_term_is_gradient_of_potential():
    s, rng = mixed_chain(), np.random.default_rng(5)
    q, _, _ = random_state(s, rng)
    zero = np.zeros(td._n_coords(s))
    _, h = td.joint_space(s, q, zero)
    for k in range(len(zero)):   # directional derivative along each coordinate
        e = np.eye(len(zero))[k]
        dV = central_rate(s, q, e, zero, lambda qq, vv: td.potential_energy(s, qq))
        assert dV == pytest.approx(h[k], abs=FD_TOL)


def test_frame_jacobian_matches_pose_derivative():
    """[v; w] of a frame in its own axes: v = R^T dp/dt, skew(w) = R^T dR/dt."""
    s, rng = mixed_chain(), np.random.default_rng(6)
    q, qd, qdd = random_state(s, rng)
    for frame in ("tool", "side"):
        R, _ = td.frame_pose(s, q, frame)
        dR = central_rate(s, q, qd, qdd, lambda qq, vv: td.frame_pose(s, qq, frame)[0])
        dp = central_rate(s, q, qd, qdd, lambda qq, vv: td.frame_pose(s, qq, frame)[1])
        w_hat = R.T @ dR
        X = td.frame_jacobian(s, q, frame) @ qd
        np.testing.assert_allclose(X[:3], R.T @ dp, atol=FD_TOL)
        np.testing.assert_allclose(X[3:], [w_hat[2, 1], w_hat[0, 2], w_hat[1, 0]], atol=FD_TOL)


def test_body_poses_follow_joint_conventions():
    s = Scene("poses")
    s.add_body("a", mass=1)
    s.add_body("b", mass=1)
    s.add_joint("ja", "prismatic", "world", "a", xyz=[1, 0, 0], rpy=[0, 0, np.pi / 2], axis="x")
    s.add_joint("jb", "revolute", "a", "b", xyz=[0, 2, 0], axis="z")
    poses = td.body_poses(s, {"ja": 0.5, "jb": np.pi / 2})
    np.testing.assert_allclose(poses["world"][0], np.eye(3))
    np.testing.assert_allclose(poses["a"][1], [1, 0.5, 0], atol=CLOSED_FORM_TOL)
    np.testing.assert_allclose(poses["b"][1], [-1, 0.5, 0], atol=CLOSED_FORM_TOL)
    np.testing.assert_allclose(poses["b"][0], [[-1, 0, 0], [0, -1, 0], [0, 0, 1]], atol=CLOSED_FORM_TOL)


# ----------------------------------------------------------------------------- 3. spherical energy
def test_spherical_pendulum_conserves_energy():
    s = Scene("spherical_pendulum")
    s.add_body("bob", mass=1.5, com=[0.1, 0.05, -0.4], inertia=[0.03, 0.04, 0.02, 0.002, 0.001, -0.003])
    s.add_body("arm", mass=0.5, com=[0.1, 0, 0], inertia=[0.001, 0.004, 0.004])
    s.add_joint("ball", "spherical", "world", "bob", xyz=[0, 0, 1], rpy=[0.2, 0.1, 0])
    s.add_joint("hinge", "revolute", "bob", "arm", xyz=[0, 0.1, -0.4], axis=[0, 1, 1])

    def unpack(y):
        quat = y[:4] / np.linalg.norm(y[:4])
        w, x, yy, z = quat
        R = np.array([[1 - 2 * (yy * yy + z * z), 2 * (x * yy - w * z), 2 * (x * z + w * yy)],
                      [2 * (x * yy + w * z), 1 - 2 * (x * x + z * z), 2 * (yy * z - w * x)],
                      [2 * (x * z - w * yy), 2 * (yy * z + w * x), 1 - 2 * (x * x + yy * yy)]])
        return {"ball": R, "hinge": y[4]}, y[5:]

    def rhs(_, y):
        q, qd = unpack(y)
        qdd, _ = td.kkt(s, q, qd, np.zeros(4))
        w, x, yy, z = y[:4]
        ox, oy, oz = qd[:3]   # child-frame rate: dquat/dt = quat (x) [0, omega] / 2
        dquat = 0.5 * np.array([-x * ox - yy * oy - z * oz, w * ox + yy * oz - z * oy,
                                w * oy + z * ox - x * oz, w * oz + x * oy - yy * ox])
        return np.concatenate([dquat, [qd[3]], qdd])

    def energy(y):
        q, qd = unpack(y)
        return td.kinetic_energy(s, q, qd) + td.potential_energy(s, q)

    y0 = np.array([0.9, 0.3, -0.2, 0.25, 0.4, 1.0, -0.5, 2.0, 1.5])
    y0[:4] /= np.linalg.norm(y0[:4])
    sol = solve_ivp(rhs, (0, 0.6), y0, method="DOP853", rtol=1e-11, atol=1e-12)
    assert sol.success
    e = np.array([energy(y) for y in sol.y.T])
    assert np.ptp(e) < ENERGY_TOL * max(1.0, abs(e[0]))
    # the motion is not trivial: the rotation and the hinge both moved
    assert abs(sol.y[4, -1] - y0[4]) > 0.1 and np.linalg.norm(sol.y[:4, -1] - y0[:4]) > 0.1


# ----------------------------------------------------------------------------- 4. kbias by FD
def _check_kbias(s, q, qd, qdd):
    K, kbias = td.constraint_rows(s, q, qd)
    rate = central_rate(s, q, qd, qdd, lambda qq, vv: td.constraint_rows(s, qq, vv)[0] @ vv)
    np.testing.assert_allclose(rate, K @ qdd + kbias, atol=FD_TOL * max(1.0, np.abs(rate).max()))


def test_kbias_planar_weld_four_bar():
    s, rng = four_bar(), np.random.default_rng(7)
    for _ in range(3):
        q, qd, qdd = random_state(s, rng)   # the identity holds on and off the closure
        _check_kbias(s, q, qd, qdd)
    q, qd = closed_four_bar_state(s, 0.7, 1.3)
    _check_kbias(s, q, qd, rng.normal(size=4))


def test_kbias_ball_and_weld_between_moving_bodies():
    s, rng = ball_loop(full_weld=True), np.random.default_rng(8)
    for _ in range(3):
        q, qd, qdd = random_state(s, rng)
        K, _ = td.constraint_rows(s, q, qd)
        assert K.shape == (9, td._n_coords(s))
        _check_kbias(s, q, qd, qdd)


def test_constraint_residual_rate_is_minus_K_qd_on_the_closure():
    """At a closed configuration ^A p_B = 0, ^A R_B = 1, so d/dt residual = -(rel. twist of a)."""
    s = four_bar()
    q, _ = closed_four_bar_state(s, 0.7, 1.3)
    assert np.abs(td.constraint_residual(s, q)).max() < SOLVE_TOL
    qd = np.random.default_rng(9).normal(size=4)   # any velocity, not only admissible ones
    K, _ = td.constraint_rows(s, q, qd)
    rate = central_rate(s, q, qd, np.zeros(4), lambda qq, vv: td.constraint_residual(s, qq))
    np.testing.assert_allclose(rate, -K @ qd, atol=FD_TOL)


def test_task_acceleration_is_derivative_of_task_velocity():
    s, rng = mixed_chain(), np.random.default_rng(10)
    s.set_motion(frames={"tool": sp.Rational(1, 3), "side": sp.Rational(2, 3)}, components=["vx", "wy", "wz"])
    q, qd, qdd = random_state(s, rng)
    rate = central_rate(s, q, qd, qdd, lambda qq, vv: td.task_velocity(s, qq, vv))
    np.testing.assert_allclose(td.task_acceleration(s, q, qd, qdd), rate, atol=FD_TOL)
    X = td.frame_jacobian(s, q, "tool") @ qd / 3 + td.frame_jacobian(s, q, "side") @ qd * 2 / 3
    np.testing.assert_allclose(td.task_velocity(s, q, qd), X[[0, 4, 5]], atol=SOLVE_TOL)


def test_task_velocity_of_joints_is_joint_rates():
    s = mixed_chain()
    s.set_motion(joints=["jc", "ja"])
    q, qd, qdd = random_state(s, np.random.default_rng(11))
    np.testing.assert_allclose(td.task_velocity(s, q, qd), qd[[4, 0]])
    np.testing.assert_allclose(td.task_acceleration(s, q, qd, qdd), qdd[[4, 0]])


# ----------------------------------------------------------------------------- 5. KKT
@pytest.mark.parametrize("make", [four_bar, ball_loop])
def test_kkt_solution_satisfies_constraints_and_equations_of_motion(make):
    s, rng = make(), np.random.default_rng(12)
    q, qd, _ = random_state(s, rng)
    tau = rng.normal(size=len(qd))
    qdd, lam = td.kkt(s, q, qd, tau)
    M, h = td.joint_space(s, q, qd)
    K, kbias = td.constraint_rows(s, q, qd)
    np.testing.assert_allclose(K @ qdd + kbias, 0, atol=SOLVE_TOL)
    np.testing.assert_allclose(M @ qdd + h, tau + K.T @ lam, atol=SOLVE_TOL)


def test_lambda_is_the_constraint_force_on_the_robot():
    """A slider along world z held by a vz constraint: lam = +m g (the support pushes up)."""
    s = Scene("slider")
    s.add_body("box", mass=2)
    s.add_joint("lift", "prismatic", "world", "box", axis="z")
    s.add_frame("base", "box")
    s.add_constraint("hold", "custom", "base", components=["vz"])
    qdd, lam = td.kkt(s, {"lift": 0.3}, np.zeros(1), np.zeros(1))
    assert qdd == pytest.approx([0.0], abs=SOLVE_TOL)
    assert lam == pytest.approx([2 * G], rel=SOLVE_TOL)


def test_contact_force_enters_as_minus_D_transpose_eta():
    s = mixed_chain()
    s.set_contact_forces("tool", ["vx", "vz", "wy"])
    q, qd, _ = random_state(s, np.random.default_rng(13))
    eta = np.array([1.0, -2.0, 0.5])
    D = td.contact_map(s, q)
    np.testing.assert_allclose(D, td.frame_jacobian(s, q, "tool")[[0, 2, 4]], atol=SOLVE_TOL)
    qdd_eta, _ = td.kkt(s, q, qd, np.zeros(len(qd)), eta)
    qdd_tau, _ = td.kkt(s, q, qd, -D.T @ eta)
    np.testing.assert_allclose(qdd_eta, qdd_tau, atol=SOLVE_TOL)


def test_constrained_four_bar_conserves_energy_and_stays_closed():
    s = four_bar()
    q0, qd0 = closed_four_bar_state(s, 0.7, 2.0)
    names = ["j1", "j2", "j3", "j4"]

    def rhs(_, y):
        qdd, _ = td.kkt(s, dict(zip(names, y[:4])), y[4:], np.zeros(4))
        return np.concatenate([y[4:], qdd])

    y0 = np.concatenate([[q0[n] for n in names], qd0])
    sol = solve_ivp(rhs, (0, 0.4), y0, method="DOP853", rtol=1e-11, atol=1e-12)
    assert sol.success
    e = [td.kinetic_energy(s, dict(zip(names, y[:4])), y[4:]) + td.potential_energy(s, dict(zip(names, y[:4])))
         for y in sol.y.T]
    assert np.ptp(e) < ENERGY_TOL * max(1.0, abs(e[0]))
    assert np.abs(td.constraint_residual(s, dict(zip(names, sol.y[:4, -1])))).max() < 1e-8
    assert abs(sol.y[0, -1] - y0[0]) > 0.3
