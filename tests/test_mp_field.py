"""The extended-precision field (``MpField``, mpmath): agreement with the exact and float fields,
precision that really is extended, its pivoted solve, and its conversions."""
from __future__ import annotations

from fractions import Fraction

import mpmath
import numpy as np
import pytest
import sympy as sp

import symgen
from symgen.math.fields import ExactField, MpField, gauss_solve, make_field
from symgen.codegen.reference import reference_states
from symgen.errors import SingularConfigurationError
from symgen.proofs import random_exact_state

from .codegen_util import relative_error

#: a 50-digit evaluation agrees with exact rationals to this (relative, normwise)
EXACT_TOL = 1e-45
#: float64 model (32) against the 50-digit one, at a random loop-closed state
FLOAT_TOL = 1e-13
#: 30-digit against 60-digit evaluation
DPS30_TOL = 1e-28
#: every built-in scene family
SCENES = ("chain:n=6", "arm_on_plane", "four_bar", "five_bar", "stewart", "multi_arm:h=2")
QUANTITIES = ("M", "C", "G", "M_q", "C_q", "G_q")

_models: dict = {}


def model_of(spec):
    if spec not in _models:
        _models[spec] = symgen.derive(symgen.load(spec))
    return _models[spec]


def max_abs(a) -> float:
    return float(max((abs(v) for v in np.asarray(a, dtype=object).flat), default=0))


def max_diff(a, b) -> float:
    return float(max((abs(x - y) for x, y in zip(np.asarray(a, dtype=object).flat, np.asarray(b, dtype=object).flat)),
                     default=0))


@pytest.mark.parametrize("spec", ["four_bar", "chain:n=3"])
def test_mp_field_agrees_with_exact_field_at_rational_configuration(spec):
    model = model_of(spec)
    cfg, v_m = random_exact_state(model, np.random.default_rng(5))
    exact = ExactField(model.tree.parameters)
    want = model.evaluate(cfg, V_m=v_m, field=exact)
    got = model.evaluate(cfg, V_m=v_m, field="mp")
    assert not exact.rounded, "the exact reference must not have rounded any scene constant"
    for name in ("M", "C", "G"):
        w, g = getattr(want, name), getattr(got, name)
        assert all(isinstance(v, type(got.field.one)) for v in g.flat)
        assert max_diff(g, w) <= EXACT_TOL * max(max_abs(w), 1e-300) or max_abs(w) == max_diff(g, w) == 0, name


@pytest.mark.parametrize("spec", SCENES)
def test_mp_field_agrees_with_float_field_at_random_state(spec):
    model = model_of(spec)
    s = reference_states(model, 1, seed=11)[0]
    eta_m = s["eta_m"] if s["eta_m"].size else None
    want = model.evaluate(s["config"], V_m=s["V_m"], eta_m=eta_m, field="mp")
    got = model.evaluate(s["config"], V_m=s["V_m"], eta_m=eta_m)
    for name in QUANTITIES:
        ref = want.field.to_float(getattr(want, name))
        assert relative_error(getattr(got, name), ref) < FLOAT_TOL, name


def test_precision_increases_with_dps():
    """30 and 60 digits agree to ~1e-28 but not exactly, while float64 differs from both by its
    own rounding: the field computes in extended precision, not in floats."""
    model = model_of("arm_on_plane")
    s = reference_states(model, 1, seed=2)[0]
    args = dict(V_m=s["V_m"], eta_m=s["eta_m"])
    d30 = model.evaluate(s["config"], field="mp:30", **args)
    d60 = model.evaluate(s["config"], field="mp:60", **args)
    flt = model.evaluate(s["config"], **args)
    assert (d30.field.dps, d60.field.dps) == (30, 60)
    float_gap = 0.0
    for name in ("M", "C", "G"):
        a, b = getattr(d30, name), getattr(d60, name)
        gap = max_diff(a, b)
        assert 0 < gap < DPS30_TOL * max_abs(b), name
        float_gap = max(float_gap, max_diff(getattr(flt, name), b) / max_abs(b))
    assert float_gap > 1e-18


def test_field_precision_does_not_touch_global_mpmath():
    before = mpmath.mp.dps
    model = model_of("four_bar")
    model.evaluate(model.reference, V_m=[0.3], field="mp:80")
    assert mpmath.mp.dps == before


def test_irrational_scene_constant_is_converted_at_field_precision():
    fld = MpField(dps=50)
    got = fld.const(sp.cos(sp.Rational(3, 10)) * sp.sqrt(2))
    with mpmath.workdps(80):
        want = mpmath.cos(mpmath.mpf(3) / 10) * mpmath.sqrt(2)
        assert abs(got - want) < mpmath.mpf(10) ** -49
        assert abs(mpmath.mpf(float(want)) - want) > mpmath.mpf(10) ** -20   # a float would be visible
    assert fld.const(Fraction(1, 3)) * 3 == 1
    assert fld.const(0.1) == mpmath.mpf(0.1)          # a float at its exact binary value


def test_solve_pivots_and_matches_exact_on_hilbert_matrix():
    """The 12x12 Hilbert matrix (condition ~1.7e16, hopeless in float64) solved at 50 digits
    agrees with the exact rational solution to ~1e-30; a zero leading entry needs pivoting."""
    n = 12
    exact = np.array([[Fraction(1, i + j + 1) for j in range(n)] for i in range(n)], dtype=object)
    rhs = np.array([Fraction(k + 1) for k in range(n)], dtype=object)
    want = gauss_solve(exact, rhs)
    fld = MpField(dps=50)
    got = fld.solve(fld.array(exact.tolist()), fld.array(rhs.tolist()))
    assert max_diff(got, want) < 1e-30 * max_abs(want)
    swap = fld.array([[0, 1], [1, 0]])
    assert list(fld.solve(swap, fld.array([2, 3]))) == [3, 2]


def test_singular_and_ill_conditioned_solves_are_typed_errors():
    fld = MpField(dps=30)
    with pytest.raises(SingularConfigurationError, match="my matrix"):
        fld.solve(fld.array([[1, 2], [2, 4]]), fld.array([1, 1]), "my matrix")
    eps = Fraction(1, 10**25)                     # condition ~4e25 > 10^(30 - 10)
    with pytest.raises(SingularConfigurationError) as info:
        fld.solve(fld.array([[1, 1], [1, 1 + eps]]), fld.array([1, 1]))
    assert info.value.condition > fld.max_condition


def test_make_field_names_and_bad_digits():
    assert make_field("mp").dps == MpField.default_dps == 50
    assert make_field("mp:64").dps == 64
    with pytest.raises(ValueError, match="mp:D"):
        make_field("mp:many")
    with pytest.raises(ValueError, match="dps"):
        MpField(dps=12)


def test_spherical_rotations_become_mpf_matrices():
    model = model_of("stewart")
    fld = MpField(model.tree.parameters, dps=40)
    cfg = fld.configuration(model.reference, model.tree)
    leg = next(j.name for j in model.scene.joints.values() if j.type == "spherical")
    r = cfg[leg]
    assert r.shape == (3, 3) and all(isinstance(v, type(fld.one)) for v in r.flat)
    assert np.array_equal(fld.to_float(r), np.asarray(model.reference[leg], dtype=float))


def test_50_digit_products_skip_zeros_and_agree_with_numpys():
    """The registered product of 50-digit arrays (zeros skipped, each sum rounded once) has NumPy's
    shapes and agrees with its object product (rounded at every term) to the last digits, for
    matrices and vectors with zero entries and rows; a zero row gives exact zeros."""
    from symgen.math.fields import MpField
    from symgen.math.jet import matmul

    fld = MpField()
    rng = np.random.default_rng(8)
    a = rng.normal(size=(5, 7)) * (rng.random((5, 7)) < 0.5)
    a[2] = 0.0
    b = rng.normal(size=(7, 4)) * (rng.random((7, 4)) < 0.6)
    big_a = np.array([[fld.const(v) / 3 for v in row] for row in a], dtype=object)
    big_b = np.array([[fld.const(v) / 7 for v in row] for row in b], dtype=object)
    for right in (big_b, big_b[:, 0]):
        got, want = matmul(big_a, right), np.dot(big_a, right)
        assert got.shape == want.shape
        scale = max(abs(w) for w in want.ravel())
        assert all(abs(g - w) <= mpmath.mpf(10) ** -48 * scale for g, w in zip(got.ravel(), want.ravel()))
        assert all(g == 0 for g in np.atleast_1d(got[2]))


def _sparse_mp(rng, shape, density):
    values = rng.standard_normal(shape) * (rng.random(shape) < density)
    return np.vectorize(lambda v: mpmath.mpf(float(v)), otypes=[object])(values)


@pytest.mark.parametrize("shapes", [((6, 35), (35, 35)), ((40, 30), (30, 20)), ((5, 7), (7,)), ((3, 4), (4, 1))])
def test_sparse_product_is_the_exact_product_rounded_once(shapes):
    """The 50-digit product that skips the zeros of both sides: every entry is the exact dot
    product rounded once to 50 digits (the reference: the same terms summed at 300 digits, then
    rounded), whichever side is sparser. Full 50-digit entries, so that NumPy's object product,
    rounding after every term, is not that number everywhere: the test tells the two apart."""
    from symgen.math.products import sparse_product

    fld = MpField()
    rng = np.random.default_rng(4)

    def draw(shape, density):
        out = np.empty(shape, dtype=object)
        for idx in np.ndindex(shape):
            keep = rng.random() < density
            out[idx] = fld.ctx.mpf(str(rng.standard_normal())) / 7 if keep else fld.zero
        return out

    differs = 0
    for density in (0.1, 0.5, 1.0):
        a, b = draw(shapes[0], density), draw(shapes[1], 1.1 - density)
        got = sparse_product(a, b)
        b2 = b if b.ndim == 2 else b[:, None]
        with mpmath.workdps(300):
            exact = [[mpmath.fsum(mpmath.mpf(a[i, k]) * mpmath.mpf(b2[k, j]) for k in range(a.shape[1]))
                      for j in range(b2.shape[1])] for i in range(a.shape[0])]
        want = np.array([[fld.ctx.mpf(v) for v in row] for row in exact], dtype=object)
        assert all(type(g) is type(fld.zero) for g in np.ravel(got))
        assert all(g == w for g, w in zip(np.ravel(got), np.ravel(want)))
        differs += sum(x != y for x, y in zip(np.ravel(a @ b), np.ravel(got)))
    if shapes[0][1] >= 30:
        assert differs > 0        # sequential rounding and one rounding do differ on these numbers


def test_mp_lu_skipping_zeros_solves_like_mpmath():
    """The LU that skips exact zeros against mpmath's own solver, on a sparse, pivoting matrix."""
    from symgen.math.elimination import lu_solve, mp_lu

    rng = np.random.default_rng(5)
    with mpmath.workdps(50):
        a = (_sparse_mp(rng, (12, 12), 0.3) + np.diag([mpmath.mpf(3 + k % 3) for k in range(12)]))[::-1]
        b = _sparse_mp(rng, (12, 3), 1.0)
        lu, perm = mp_lu(a)
        x = lu_solve(lu, perm, b)
        for j in range(3):
            want = mpmath.lu_solve(mpmath.matrix(a.tolist()), mpmath.matrix(list(b[:, j])))
            assert max(abs(x[i, j] - want[i]) for i in range(12)) < mpmath.mpf(10) ** -40


def test_mp_lu_factors_and_solves_edge_cases():
    """The 50-digit LU: ``P a = L U`` to the last digits (``perm`` read as documented), a 1-D
    right-hand side solved as the column it is, a zero right-hand side giving exact zeros, an
    exactly zero pivot column reported (``None``), and a NaN carried through the product and the
    solve instead of being skipped as a zero."""
    from symgen.math.elimination import lu_solve, mp_lu
    from symgen.math.products import sparse_product

    fld = MpField()
    rng = np.random.default_rng(6)
    a = np.array([[fld.ctx.mpf(str(v)) for v in row] for row in rng.standard_normal((7, 7))], dtype=object)
    a[0, 0] = fld.zero                                              # the first column must pivot
    lu, perm = mp_lu(a, fld.ctx)
    unit_lower = np.array([[lu[i, j] if j < i else (fld.one if i == j else fld.zero) for j in range(7)]
                           for i in range(7)], dtype=object)
    upper = np.array([[lu[i, j] if j >= i else fld.zero for j in range(7)] for i in range(7)], dtype=object)
    assert perm[0] != 0
    assert max(abs(v) for v in np.ravel(unit_lower @ upper - a[perm])) < mpmath.mpf(10) ** -45
    b = np.array([fld.ctx.mpf(str(v)) for v in rng.standard_normal(7)], dtype=object)
    x1 = lu_solve(lu, perm, b)
    assert x1.shape == (7,)
    assert all(p == q for p, q in zip(x1, lu_solve(lu, perm, b[:, None])[:, 0]))
    assert max(abs(v) for v in a @ x1 - b) < mpmath.mpf(10) ** -45
    assert all(v == 0 for v in lu_solve(lu, perm, np.array([fld.zero] * 7, dtype=object)))
    singular = a.copy()
    singular[:, 3] = fld.zero
    assert mp_lu(singular, fld.ctx) == (None, None)
    with pytest.raises(TypeError, match="mpmath numbers"):
        mp_lu(np.array([[1, 0], [0, 1]], dtype=object))
    b[2] = fld.ctx.nan
    assert all(mpmath.isnan(v) for v in sparse_product(a, b[:, None])[:, 0])
    assert any(mpmath.isnan(v) for v in lu_solve(lu, perm, b))
