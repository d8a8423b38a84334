"""Y_alpha against Pinocchio's body regressor (an independent implementation of Newton-Euler).

Pinocchio: ``I a + v x* I v = bodyRegressor(v, a) @ I.toDynamicParameters()`` with motions and
forces ordered [linear; angular] (as symgen's [v; w], [f; n]) and dynamic parameters
``[m, m c_x, m c_y, m c_z, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz]`` about the frame origin.
symgen: ``[m, hx, hy, hz, Ixx, Iyy, Izz, Ixy, Ixz, Iyz]``. Gravity is folded into the
acceleration: ``a = dX - [g_body; 0]``; the actual angular velocity is the required one.
"""
import numpy as np
import pytest

from symgen.math.fields import FloatField
from symgen.control.parameters import body_parameters
from symgen.control.regressor import Y_alpha, required_body_force

pin = pytest.importorskip("pinocchio")

FIELD = FloatField()
#: symgen's index of Pinocchio's k-th dynamic parameter
PIN_ORDER = [0, 1, 2, 3, 4, 7, 5, 8, 9, 6]
TOL = 1e-12
SEED = 38


def _random_inertia(rng):
    a = rng.normal(size=(3, 3))
    return 0.5 + rng.random(), rng.normal(size=3), a @ a.T + 0.1 * np.eye(3)


def test_pinocchio_dynamic_parameters_are_symgens_parameters_reordered():
    rng = np.random.default_rng(SEED)
    for _ in range(5):
        m, c, ic = _random_inertia(rng)
        ours = body_parameters(m, c, ic, FIELD)
        theirs = pin.Inertia(m, c, ic).toDynamicParameters()
        np.testing.assert_allclose(theirs, ours[PIN_ORDER], rtol=TOL, atol=TOL)


def test_regressor_matches_pinocchio_body_regressor():
    rng = np.random.default_rng(SEED + 1)
    for _ in range(10):
        x, dx, g = rng.normal(size=6), rng.normal(size=6), rng.normal(size=3)
        a = dx - np.concatenate([g, np.zeros(3)])
        theirs = pin.bodyRegressor(pin.Motion(x[:3], x[3:]), pin.Motion(a[:3], a[3:]))
        ours = Y_alpha(x[3:], x, dx, g, FIELD)
        np.testing.assert_allclose(ours[:, PIN_ORDER], theirs, rtol=TOL, atol=TOL)


def test_applied_form_matches_pinocchio_newton_euler_force():
    rng = np.random.default_rng(SEED + 2)
    for _ in range(10):
        m, c, ic = _random_inertia(rng)
        x, dx, g = rng.normal(size=6), rng.normal(size=6), rng.normal(size=3)
        inertia = pin.Inertia(m, c, ic)
        v, a = pin.Motion(x[:3], x[3:]), pin.Motion(*np.split(dx - np.concatenate([g, np.zeros(3)]), 2))
        force = inertia * a + v.cross(inertia * v)
        ours = required_body_force(body_parameters(m, c, ic, FIELD), x[3:], x, dx, g, FIELD)
        np.testing.assert_allclose(ours, force.vector, rtol=TOL, atol=TOL)
