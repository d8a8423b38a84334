"""symgen's joint-space model of the benchmark chain against an independent exact reference.

The reference (``tests/reference/mechanics_chain.py``) rebuilds the ``chain:n=N`` robot from its
written definition with ``sympy.physics.mechanics`` (Kane's method) and evaluates it at rational
points (exact cos/sin from the tangent half-angle). symgen is evaluated in its ``exact`` field.
Every comparison is exact rational equality: no tolerance.

Convention: ``tau = M(q) qdd + C(q, qd) qd + g(q)`` (Pinocchio's ``rnea``).
"""
from __future__ import annotations

import random
from fractions import Fraction

import numpy as np
import pytest
import sympy as sp

from symgen.io.builtin import get_scene
from symgen.model import derive
from symgen.math.configuration import Configuration, CosSin

try:  # `python -m pytest` from the repository root
    from tests.reference import mechanics_chain as ref
except ImportError:  # pytest's rootdir-relative import (tests/ on sys.path)
    from reference import mechanics_chain as ref

POINTS_PER_N = 3
SIZES = [1, 2, 3, 4, pytest.param(6, marks=pytest.mark.slow)]  # n = 6: ~6 s (Kane derivation)
INVERSE_DYNAMICS_TOL = 1e-12  # float inverse_dynamics vs. the exact reference (relative to |tau|)


# ----------------------------------------------------------------------------- helpers
def random_state(n: int, rng: random.Random):
    """Exact rational (cos, sin) pairs, joint rates and accelerations."""
    cos_sin = []
    for _ in range(n):
        t = Fraction(rng.randint(-9, 9), rng.randint(1, 9))  # tan(q/2): q anywhere in (-pi, pi)
        cs = CosSin.from_half_tangent(t)
        cos_sin.append((cs.c, cs.s))
    qd = [Fraction(rng.randint(-30, 30), rng.randint(1, 10)) for _ in range(n)]
    qdd = [Fraction(rng.randint(-30, 30), rng.randint(1, 10)) for _ in range(n)]
    return cos_sin, qd, qdd


def states(n: int):
    rng = random.Random(20060 + n)  # seeded per n: the points never depend on other sizes
    return [random_state(n, rng) for _ in range(POINTS_PER_N)]


def to_sympy(values) -> sp.Matrix:
    """A NumPy object array of Fractions (or ints / SymPy Rationals) as an exact SymPy matrix."""
    arr = np.asarray(values, dtype=object)
    if arr.ndim == 1:
        arr = arr.reshape(-1, 1)

    def conv(x):
        if isinstance(x, Fraction):
            return sp.Rational(x.numerator, x.denominator)
        if isinstance(x, (int, sp.Rational)):
            return sp.Integer(x) if isinstance(x, int) else x
        raise TypeError(f"symgen returned a non-exact entry {x!r} ({type(x).__name__})")

    return sp.Matrix(arr.shape[0], arr.shape[1], [conv(x) for x in arr.flat])


_MODELS: dict = {}


def model(n: int):
    if n not in _MODELS:
        m = derive(get_scene(f"chain:n={n}"))
        # qd of symgen is ordered j0..j{n-1} (all actuated, declaration order) -- as the reference
        assert m.coordinate_names() == [f"j{i}" for i in range(n)]
        _MODELS[n] = m
    return _MODELS[n]


def symgen_exact(n: int, cos_sin, qd):
    cfg = Configuration({f"j{i}": CosSin(c, s) for i, (c, s) in enumerate(cos_sin)})
    return model(n).evaluate(cfg, qd=qd, field="exact")


def assert_exact_equal(got: sp.Matrix, want: sp.Matrix, what: str):
    assert got.shape == want.shape, f"{what}: shape {got.shape} != {want.shape}"
    diff = got - want
    assert diff.is_zero_matrix, f"{what} differs:\nsymgen    = {got}\nreference = {want}\ndiff      = {diff}"


# ----------------------------------------------------------------------------- the reference itself
def test_reference_one_link_by_hand():
    """One link about the world z axis, gravity along -z: M = Izz + m (L/2)^2, no C, no g."""
    m, cqd, g = ref.chain_equations(1)
    assert m == sp.Matrix([[sp.Rational(3, 100) + 1 * sp.Rational(1, 20) ** 2]])
    assert cqd == sp.Matrix([[0]]) and g == sp.Matrix([[0]])


def test_reference_two_link_gravity_and_inertia_by_hand():
    """Link 1 turns about y of link 0: its com height is -(L/2) sin q1, so
    g_1 = dV/dq1 = -m1 g (L/2) cos q1 and M_11 = Iyy1 + m1 (L/2)^2."""
    q, qd = ref.symbols(2)
    m, cqd, g = ref.chain_equations(2)
    m1, g0, half = sp.Rational(11, 10), sp.Rational(981, 100), sp.Rational(1, 20)
    assert sp.simplify(g[1] - (-m1 * g0 * half * sp.cos(q[1]))) == 0
    assert g[0] == 0
    assert sp.simplify(m[1, 1] - (sp.Rational(2, 100) * sp.Rational(11, 10) + m1 * half ** 2)) == 0
    assert m[0, 1] == 0 and m[1, 0] == 0   # y-axis joint is orthogonal to the z-axis joint


# ----------------------------------------------------------------------------- symgen vs. reference
@pytest.mark.parametrize("n", SIZES)
def test_joint_space_terms_exact(n):
    """M_q, C_q qd and G_q equal Kane's M, velocity-product and gravity terms exactly."""
    for k, (cos_sin, qd, _) in enumerate(states(n)):
        m_ref, cqd_ref, g_ref = ref.evaluate_exact(n, cos_sin, qd)
        data = symgen_exact(n, cos_sin, qd)
        assert [Fraction(v) for v in data.qd] == qd
        assert_exact_equal(to_sympy(data.M_q), m_ref, f"n={n} point {k}: M_q")
        assert_exact_equal(to_sympy(data.C_q @ data.qd), cqd_ref, f"n={n} point {k}: C_q qd")
        assert_exact_equal(to_sympy(data.G_q), g_ref, f"n={n} point {k}: G_q")


@pytest.mark.parametrize("n", SIZES)
def test_inverse_dynamics_exact(n):
    """tau = M qdd + C qd + G, from symgen's joint-space form and from its model (32)
    (``tau = A^T (M dV_m + C V_m + G)``, ``V_m = qd`` here), equals Kane's ``-(Fr + Fr*)`` taken
    without the M / forcing split; symgen's float ``inverse_dynamics`` agrees to rounding."""
    for k, (cos_sin, qd, qdd) in enumerate(states(n)):
        tau_ref = ref.inverse_dynamics_exact(n, cos_sin, qd, qdd)
        data = symgen_exact(n, cos_sin, qd)
        qdd_arr = np.array(qdd, dtype=object)
        tau_q = data.M_q @ qdd_arr + data.C_q @ data.qd + data.G_q
        assert_exact_equal(to_sympy(tau_q), tau_ref, f"n={n} point {k}: M_q qdd + C_q qd + G_q")

        m = model(n).counts.m
        assert m == n
        tau_32 = data.maps.A.v.T @ (data.M[:, :m] @ qdd_arr + data.C[:, :m] @ data.V_m + data.G)
        assert_exact_equal(to_sympy(tau_32), tau_ref, f"n={n} point {k}: A^T (M dV_m + C V_m + G)")

        cfg = Configuration({f"j{i}": CosSin(c, s) for i, (c, s) in enumerate(cos_sin)}).as_float()
        tau_f = model(n).inverse_dynamics(cfg, [float(v) for v in qd], [float(v) for v in qdd])
        want = np.array([float(v) for v in tau_ref], dtype=float)
        scale = max(1.0, float(np.max(np.abs(want))))
        assert np.max(np.abs(np.asarray(tau_f, float) - want)) <= INVERSE_DYNAMICS_TOL * scale, \
            f"n={n} point {k}: float inverse_dynamics {tau_f} vs exact {want}"
