"""Eq. (21) for a general rigid body, proved symbolically (DESIGN.md section 3)."""
import numpy as np
import sympy as sp

from symgen.math.fields import SymbolicField
from symgen.subsystems import rigid_body_coriolis, rigid_body_gravity, rigid_body_mass

FIELD = SymbolicField()
m = sp.Symbol("m", positive=True)
r = np.array(sp.symbols("r_x r_y r_z", real=True), dtype=object)
ixx, iyy, izz, ixy, ixz, iyz = sp.symbols("I_xx I_yy I_zz I_xy I_xz I_yz", real=True)
I_C = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]], dtype=object)
v = np.array(sp.symbols("v_x v_y v_z", real=True), dtype=object)
w = np.array(sp.symbols("w_x w_y w_z", real=True), dtype=object)


def _mat(a):
    return sp.Matrix(a)


def test_mass_matrix_is_symmetric_and_depends_only_on_parameters():
    mass = _mat(rigid_body_mass(m, r, I_C, FIELD))
    assert mass == mass.T
    assert mass.free_symbols <= {m, ixx, iyy, izz, ixy, ixz, iyz, *r}


def test_coriolis_matrix_is_skew_symmetric_for_every_angular_velocity():
    c = _mat(rigid_body_coriolis(m, r, I_C, w, FIELD))
    assert sp.expand(c + c.T) == sp.zeros(6, 6)


def test_coriolis_times_velocity_is_the_newton_euler_bias_force():
    """C X = X x* (M X), with the force cross product [w x f; v x f + w x n] for X = [v; w]."""
    x = np.concatenate([v, w])
    f = rigid_body_mass(m, r, I_C, FIELD) @ x
    expected = np.concatenate([np.cross(w, f[:3]), np.cross(v, f[:3]) + np.cross(w, f[3:])])
    got = rigid_body_coriolis(m, r, I_C, w, FIELD) @ x
    assert sp.expand(_mat(got - expected)) == sp.zeros(6, 1)


def test_newton_euler_by_hand_for_a_point_mass_on_an_arm():
    """A point mass m at r = (l, 0, 0) spinning about z at rate w: the bias force is the
    centripetal force m w^2 l towards the axis, -m w^2 l along x, and no moment."""
    l, wz = sp.symbols("l w", positive=True)
    rr = np.array([l, 0, 0], dtype=object)
    zero_i = np.zeros((3, 3), dtype=object)
    x = np.array([0, 0, 0, 0, 0, wz], dtype=object)
    bias = _mat(rigid_body_coriolis(m, rr, zero_i, x[3:], FIELD) @ x)
    assert sp.simplify(bias - sp.Matrix([-m * wz**2 * l, 0, 0, 0, 0, 0])) == sp.zeros(6, 1)


def test_gravity_term_is_minus_the_weight_wrench():
    """Body frame aligned with the world, com at (l, 0, 0): weight m g along -z at the com, so
    G (left-hand side of eq. 21) = -(weight wrench about the origin) = [0, 0, m g, 0, -m g l, 0]."""
    l, g = sp.symbols("l g", positive=True)
    rr = np.array([l, 0, 0], dtype=object)
    mass = rigid_body_mass(m, rr, np.zeros((3, 3), dtype=object), FIELD)
    gvec = rigid_body_gravity(mass, np.eye(3, dtype=int).astype(object), np.array([0, 0, -g], dtype=object), FIELD)
    assert sp.simplify(_mat(gvec) - sp.Matrix([0, 0, m * g, 0, -m * g * l, 0])) == sp.zeros(6, 1)
