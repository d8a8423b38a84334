"""Regressors of eq. (35) against symgen's subsystem dynamics (eqs. 21-23), exactly and symbolically."""
import random
from fractions import Fraction

import numpy as np
import pytest
import sympy as sp

from symgen.math.fields import ExactField, FloatField, SymbolicField
from symgen.control.parameters import body_inertial, body_parameters
from symgen.control.regressor import (Y_1j, Y_3i, Y_alpha, linear_coriolis, required_body_force,
                                      required_joint_force, required_spherical_moment)
from symgen.math.spatial import hat
from symgen.scene.joint_kinds import REVOLUTE, SPHERICAL
from symgen.subsystems import rigid_body_coriolis, rigid_body_gravity, rigid_body_mass

EXACT = ExactField()
SYM = SymbolicField()
SEED = 35
CASES = 10


def _q(rng):
    return Fraction(rng.randint(-90, 90), rng.randint(1, 13))


def _vec(rng, n):
    return np.array([_q(rng) for _ in range(n)], dtype=object)


def _body(rng):
    m = Fraction(rng.randint(1, 50), rng.randint(1, 7))
    a = np.array([[_q(rng) for _ in range(3)] for _ in range(3)], dtype=object)
    return m, _vec(rng, 3), a @ a.T


def _rotation(rng):
    """An exact rational rotation (Cayley transform of a rational skew matrix)."""
    k = hat(_vec(rng, 3), EXACT)
    eye = EXACT.eye(3)
    return EXACT.solve(eye + k, eye - k)


def _eq21(m, r, ic, omega, x, dx, r_bw, gravity):
    """Right-hand side with symgen's subsystem functions: M dX + C(omega) X + G."""
    mass = rigid_body_mass(m, r, ic, EXACT)
    return mass @ dx + rigid_body_coriolis(m, r, ic, omega, EXACT) @ x + rigid_body_gravity(mass, r_bw, gravity, EXACT)


def _cases():
    rng = random.Random(SEED)
    for _ in range(CASES):
        m, r, ic = _body(rng)
        x, dx, r_bw, gravity = _vec(rng, 6), _vec(rng, 6), _rotation(rng), _vec(rng, 3)
        yield m, r, ic, x, dx, r_bw, gravity, _vec(rng, 3)


def test_regressor_reproduces_eq21_exactly_for_any_actual_omega():
    """Eq. (35) with C_alpha carrying the actual angular velocity and X_r != X: exact."""
    for m, r, ic, x, dx, r_bw, gravity, omega in _cases():
        y = Y_alpha(omega, x, dx, r_bw @ gravity, EXACT)
        assert (y @ body_parameters(m, r, ic, EXACT) == _eq21(m, r, ic, omega, x, dx, r_bw, gravity)).all()


def test_linear_coriolis_is_symgens_coriolis_matrix():
    """The parameter form of C_alpha equals symgen's C_alpha(omega) built from (m, r, I_c)."""
    for m, r, ic, *_, omega in _cases():
        cbar = linear_coriolis(body_parameters(m, r, ic, EXACT), omega, EXACT)
        assert (cbar == rigid_body_coriolis(m, r, ic, omega, EXACT)).all()


def test_linear_coriolis_is_skew_symmetric():
    for m, r, ic, *_, omega in _cases():
        c = linear_coriolis(body_parameters(m, r, ic, EXACT), omega, EXACT)
        assert (c + c.T == 0).all()


def test_coriolis_force_of_two_bodies_adds_up_like_their_parameters():
    """Linearity in P_alpha: C(P1 + P2) X_r = C(P1) X_r + C(P2) X_r for any omega."""
    rng = random.Random(SEED + 1)
    (m1, r1, i1), (m2, r2, i2) = _body(rng), _body(rng)
    x, omega = _vec(rng, 6), _vec(rng, 3)
    m, r, ic_c = body_inertial(body_parameters(m1, r1, i1, EXACT) + body_parameters(m2, r2, i2, EXACT), EXACT)
    summed = rigid_body_coriolis(m1, r1, i1, omega, EXACT) @ x + rigid_body_coriolis(m2, r2, i2, omega, EXACT) @ x
    assert (rigid_body_coriolis(m, r, ic_c, omega, EXACT) @ x == summed).all()


def test_coriolis_matrix_of_design_notes_differs_by_a_block_that_annihilates_omega():
    """DESIGN.md's lower-right block -m r^ w^ r^ + I_c w^ + w^ I_c differs from symgen's
    I_o w^ + w^ I_o by m (r^ r^ w^ + w^ r^ r^ - r^ w^ r^), which maps omega to zero: both give the
    same force on the body's own velocity (hand derivation from I_c = I_o + m r^ r^)."""
    for m, r, ic, *_, omega in _cases():
        rh, wh = hat(r, EXACT), hat(omega, EXACT)
        design = -m * rh @ wh @ rh + ic @ wh + wh @ ic
        block = m * (rh @ rh @ wh + wh @ rh @ rh - rh @ wh @ rh)
        assert (design - rigid_body_coriolis(m, r, ic, omega, EXACT)[3:, 3:] == block).all()
        assert (block @ omega == 0).all()


def test_applied_form_equals_regressor_times_parameters_exactly():
    for m, r, ic, x, dx, r_bw, gravity, omega in _cases():
        p = body_parameters(m, r, ic, EXACT)
        g = r_bw @ gravity
        assert (required_body_force(p, omega, x, dx, g, EXACT) == Y_alpha(omega, x, dx, g, EXACT) @ p).all()


def test_applied_form_equals_regressor_in_floats():
    rng = np.random.default_rng(SEED)
    f = FloatField()
    p, omega, g = rng.normal(size=10), rng.normal(size=3), rng.normal(size=3)
    x, dx = rng.normal(size=6), rng.normal(size=6)
    np.testing.assert_allclose(required_body_force(p, omega, x, dx, g, f), Y_alpha(omega, x, dx, g, f) @ p,
                               rtol=1e-13, atol=1e-13)


def _symbolic_body():
    m = sp.Symbol("m", positive=True)
    r = np.array(sp.symbols("r_x r_y r_z", real=True), dtype=object)
    c = sp.symbols("I_xx I_yy I_zz I_xy I_xz I_yz", real=True)
    ic = np.array([[c[0], c[3], c[4]], [c[3], c[1], c[5]], [c[4], c[5], c[2]]], dtype=object)
    return m, r, ic


def _symbols(name, n):
    return np.array(sp.symbols(f"{name}0:{n}", real=True), dtype=object)


def test_regressor_reproduces_eq21_symbolically():
    m, r, ic = _symbolic_body()
    x, dx, g, omega = _symbols("x", 6), _symbols("dx", 6), _symbols("g", 3), _symbols("w", 3)
    mass = rigid_body_mass(m, r, ic, SYM)
    expected = mass @ dx + rigid_body_coriolis(m, r, ic, omega, SYM) @ x \
        + rigid_body_gravity(mass, np.eye(3, dtype=int).astype(object), g, SYM)
    got = Y_alpha(omega, x, dx, g, SYM) @ body_parameters(m, r, ic, SYM)
    assert sp.simplify(sp.Matrix(got - expected)) == sp.zeros(6, 1)


def test_regressor_is_linear_coriolis_form_symbolically_for_any_omega():
    m, r, ic = _symbolic_body()
    x, dx, g, omega = _symbols("x", 6), _symbols("dx", 6), _symbols("g", 3), _symbols("w", 3)
    p = body_parameters(m, r, ic, SYM)
    mass = rigid_body_mass(m, r, ic, SYM)
    expected = mass @ dx + linear_coriolis(p, omega, SYM) @ x + mass @ np.concatenate([-g, SYM.zeros((3,))])
    got = Y_alpha(omega, x, dx, g, SYM) @ p
    assert sp.simplify(sp.Matrix(got - expected)) == sp.zeros(6, 1)


# ------------------------------------------------------------------------------------ joints


@pytest.mark.parametrize("qd", [Fraction(3, 7), Fraction(-2, 5), Fraction(0)])
def test_one_dof_regressor_is_rotor_inertia_plus_symgens_friction_at_the_actual_rate(qd):
    ir, b, c, qdd_r = Fraction(1, 9), Fraction(2, 3), Fraction(5, 4), Fraction(-7, 2)
    expected = ir * qdd_r + REVOLUTE.friction(np.array([qd], dtype=object), EXACT, b, c)[0]
    assert (Y_1j(qdd_r, qd, EXACT) @ np.array([ir, b, c], dtype=object))[0] == expected
    assert required_joint_force([ir, b, c], qdd_r, qd, EXACT) == expected


def test_one_dof_regressor_by_hand():
    """I* = 2, b = 3, c = 5, qdd_r = 1, qd = -4: 2 - 12 - 5 = -15."""
    assert required_joint_force([2, 3, 5], 1, -4, FloatField()) == -15


def test_spherical_regressor_is_symgens_friction_moment():
    f = FloatField()
    w = np.array([0.3, -1.2, 0.4])
    expected = SPHERICAL.friction(w, f, 0.7, 0.25)
    np.testing.assert_allclose(Y_3i(w, f) @ np.array([0.7, 0.25]), expected, rtol=1e-15)
    np.testing.assert_allclose(required_spherical_moment([0.7, 0.25], w, f), expected, rtol=1e-15)


def test_spherical_regressor_by_hand_and_at_rest():
    """w = (3, 0, 4), |w| = 5: b w + c w/|w| = (3b + 3c/5, 0, 4b + 4c/5); zero at rest."""
    got = required_spherical_moment([2, 5], np.array([3.0, 0.0, 4.0]), FloatField())
    np.testing.assert_allclose(got, [9.0, 0.0, 12.0], rtol=1e-15)
    assert not required_spherical_moment([2, 5], np.zeros(3), FloatField()).any()


def test_spherical_regressor_symbolic_matches_symgens_friction():
    w = _symbols("w", 3)
    b, c = sp.symbols("b c", positive=True)
    expected = SPHERICAL.friction(w, SYM, b, c)
    assert sp.simplify(sp.Matrix(Y_3i(w, SYM) @ np.array([b, c], dtype=object) - expected)) == sp.zeros(3, 1)
