"""P_r of eq. (35): standard inertial parameters, names, and the validated ParameterSet."""
import math
import random
from fractions import Fraction

import mpmath
import numpy as np
import pytest
import sympy as sp

from symgen.math.fields import ExactField, FloatField, MpField, SymbolicField
from symgen.control.errors import (ControlError, ControlInputError, ParameterBoundsError,
                                   UnknownParameterError, UpdateGainError)
from symgen.control.parameters import (BODY_QUANTITIES, Parameter, ParameterSet, body_inertial,
                                       body_mass_matrix, body_parameter_set, body_parameters,
                                       tree_parameters)
from symgen.errors import SymgenError
from symgen.scene import Scene
from symgen.subsystems import rigid_body_mass
from symgen.tree import build_tree

EXACT = ExactField()
SEED = 20060304


def _rational(rng):
    return Fraction(rng.randint(-60, 60), rng.randint(1, 17))


def _random_body(rng):
    """A random (m, r, I_c) with rational entries (I_c = A A^T + 1, symmetric positive)."""
    m = Fraction(rng.randint(1, 40), rng.randint(1, 9))
    r = np.array([_rational(rng) for _ in range(3)], dtype=object)
    a = np.array([[_rational(rng) for _ in range(3)] for _ in range(3)], dtype=object)
    return m, r, a @ a.T + np.eye(3, dtype=int).astype(object)


def test_body_parameters_are_mass_first_moment_and_origin_inertia_by_hand():
    """m = 2, r = (1, 0, 0), I_c = diag(1, 2, 3): h = (2, 0, 0); parallel-axis theorem about the
    origin adds m (r.r 1 - r r^T) = diag(0, 2, 2), no products of inertia."""
    ic = np.diag([Fraction(1), Fraction(2), Fraction(3)]).astype(object)
    p = body_parameters(Fraction(2), np.array([Fraction(1), 0, 0], dtype=object), ic, EXACT)
    assert list(p) == [2, 2, 0, 0, 1, 4, 5, 0, 0, 0]


def test_product_of_inertia_follows_the_parallel_axis_theorem():
    """Origin inertia I_xy = I_c,xy - m r_x r_y (hand formula)."""
    m, r = Fraction(3), np.array([Fraction(1, 2), Fraction(-2), Fraction(5)], dtype=object)
    p = body_parameters(m, r, np.zeros((3, 3), dtype=object), EXACT)
    names = dict(zip(BODY_QUANTITIES, p))
    assert names["Ixy"] == -m * r[0] * r[1] and names["Ixz"] == -m * r[0] * r[2]
    assert names["Iyz"] == -m * r[1] * r[2]
    assert names["Izz"] == m * (r[0] ** 2 + r[1] ** 2)


def test_conversion_round_trips_exactly_with_fractions():
    rng = random.Random(SEED)
    for _ in range(20):
        m, r, ic = _random_body(rng)
        m2, r2, ic2 = body_inertial(body_parameters(m, r, ic, EXACT), EXACT)
        assert m2 == m and list(r2) == list(r) and (ic2 == ic).all()


def test_inverse_conversion_round_trips_exactly_with_fractions():
    rng = random.Random(SEED + 1)
    m, r, ic = _random_body(rng)
    p = body_parameters(m, r, ic, EXACT)
    assert list(body_parameters(*body_inertial(p, EXACT), EXACT)) == list(p)


def test_conversion_round_trips_symbolically():
    m = sp.Symbol("m", positive=True)
    r = np.array(sp.symbols("r_x r_y r_z", real=True), dtype=object)
    c = sp.symbols("c0:6", real=True)
    ic = np.array([[c[0], c[3], c[4]], [c[3], c[1], c[5]], [c[4], c[5], c[2]]], dtype=object)
    field = SymbolicField()
    m2, r2, ic2 = body_inertial(body_parameters(m, r, ic, field), field)
    assert sp.simplify(m2 - m) == 0
    assert sp.simplify(sp.Matrix(r2 - r)) == sp.zeros(3, 1)
    assert sp.simplify(sp.Matrix(ic2 - ic)) == sp.zeros(3, 3)


def test_conversion_round_trips_in_mpmath_to_its_precision():
    field = MpField(dps=40)
    rng = random.Random(SEED + 2)
    m, r, ic = _random_body(rng)
    conv = lambda a: np.array([field.const(v) for v in np.ravel(a)], dtype=object).reshape(np.shape(a))  # noqa: E731
    m2, r2, ic2 = body_inertial(body_parameters(field.const(m), conv(r), conv(ic), field), field)
    tol = mpmath.mpf(10) ** -35
    assert abs(m2 - m) < tol and max(abs(x - field.const(y)) for x, y in zip(r2, r)) < tol
    assert max(abs(x - field.const(y)) for x, y in zip(ic2.flat, ic.flat)) < tol


def test_mass_matrix_from_parameters_equals_symgens_eq21_mass_matrix():
    rng = random.Random(SEED + 3)
    m, r, ic = _random_body(rng)
    p = body_parameters(m, r, ic, EXACT)
    assert (body_mass_matrix(p, EXACT) == rigid_body_mass(m, r, ic, EXACT)).all()


def test_zero_mass_has_no_centre_of_mass():
    with pytest.raises(ParameterBoundsError, match="m_tool"):
        body_inertial(np.array([Fraction(0)] * 10, dtype=object), EXACT, owner="tool")


# ----------------------------------------------------------------------------- names, sets
def _scene():
    s = Scene("named")
    s.add_body("base", 1, com=(0, 0, 0), inertia=(1, 1, 1))
    s.add_body("link3", 2, com=(1, 0, 0), inertia=(1, 2, 3))
    s.add_body("ball", 1, inertia=(1, 1, 1))
    s.add_joint("mount", "fixed", "world", "base")
    s.add_joint("elbow", "revolute", "base", "link3", rotor_inertia="1/10", viscous="1/5", coulomb="1/2")
    s.add_joint("wrist", "spherical", "link3", "ball", viscous="1/3")
    return s


def test_tree_parameters_are_named_after_their_owners_in_eq35_order():
    pset = tree_parameters(build_tree(_scene()), EXACT)
    assert pset.names[:5] == ("Ir_elbow", "b_elbow", "c_elbow", "b_wrist", "c_wrist")
    assert pset.names[5:15] == tuple(f"{q}_base" for q in BODY_QUANTITIES)
    assert "m_link3" in pset.names and "hx_link3" in pset.names and "Ixx_link3" in pset.names
    assert len(pset) == 5 + 3 * 10


def test_tree_parameters_carry_the_scene_values():
    pset = tree_parameters(build_tree(_scene()), EXACT)
    assert pset.values[pset.index("Ir_elbow")] == Fraction(1, 10)
    assert pset.values[pset.index("c_elbow")] == Fraction(1, 2)
    assert pset.values[pset.index("b_wrist")] == Fraction(1, 3)
    assert not pset.uncertain.any() and (pset.rho == 0).all()


def test_symbols_are_named_after_the_parameters():
    pset = ParameterSet(body_parameter_set("link3", 2.0, np.zeros(3), np.eye(3), FloatField()))
    syms = pset.symbols()
    assert [str(s) for s in syms] == [f"{q}_link3" for q in BODY_QUANTITIES]
    assert syms[0].is_positive


def _uncertain_set(**kw):
    spec = {"value": 2.0, "lower": 1.0, "upper": 3.0, "rho": 0.5}
    spec.update(kw)
    return ParameterSet([Parameter("link3", "m", spec["value"], spec["lower"], spec["upper"], spec["rho"]),
                         Parameter("elbow", "b", 0.1)])


def test_valid_set_exposes_its_adaptation_arrays():
    pset = _uncertain_set()
    assert list(pset.uncertain) == [True, False]
    assert list(pset.lower) == [1.0, 0.1] and list(pset.upper) == [3.0, 0.1]
    assert list(pset.rho) == [0.5, 0.0]


def test_unknown_name_is_a_typed_error_naming_it():
    with pytest.raises(UnknownParameterError, match="m_link4") as info:
        _uncertain_set().with_uncertainty({"m_link4": (0, 1, 1)})
    assert info.value.parameter == "m_link4"


def test_lower_bound_above_upper_bound_is_rejected():
    with pytest.raises(ParameterBoundsError, match="m_link3.*lower bound 3.0 > upper bound 1.0"):
        _uncertain_set(lower=3.0, upper=1.0)


def test_initial_estimate_outside_its_bounds_is_rejected():
    with pytest.raises(ParameterBoundsError, match="m_link3.*outside"):
        _uncertain_set(value=4.0)


@pytest.mark.parametrize("rho", [0.0, -1.0, math.inf, math.nan, "fast"])
def test_update_gain_must_be_finite_and_positive(rho):
    with pytest.raises(UpdateGainError, match="m_link3"):
        _uncertain_set(rho=rho)


def test_mass_bound_allowing_negative_mass_is_rejected():
    with pytest.raises(ParameterBoundsError, match="m_link3.*negative mass"):
        _uncertain_set(value=0.5, lower=-1.0)


def test_known_negative_mass_is_rejected():
    with pytest.raises(ParameterBoundsError, match="m_link3"):
        ParameterSet([Parameter("link3", "m", Fraction(-1))])


def test_other_parameters_may_have_negative_bounds():
    """Only the mass must stay >= 0: first moments and products of inertia take either sign."""
    pset = ParameterSet([Parameter("link3", "hx", -0.5, -1.0, 1.0, 2.0)])
    assert pset.lower[0] == -1.0


def test_infinite_bounds_are_allowed_but_nan_is_not():
    assert ParameterSet([Parameter("l", "hx", 0.0, -math.inf, math.inf, 1.0)]).upper[0] == math.inf
    with pytest.raises(ParameterBoundsError, match="hx_l.*not finite"):
        ParameterSet([Parameter("l", "hx", 0.0, math.nan, 1.0, 1.0)])


def test_duplicate_names_are_rejected():
    with pytest.raises(ParameterBoundsError, match="b_elbow.*twice"):
        ParameterSet([Parameter("elbow", "b", 0.1), Parameter("elbow", "b", 0.2)])


def test_new_estimates_are_checked_against_the_bounds():
    with pytest.raises(ParameterBoundsError, match="m_link3"):
        _uncertain_set().with_values([5.0, 0.1])
    with pytest.raises(ControlInputError):
        _uncertain_set().with_values([2.0])


def test_control_errors_are_symgen_errors():
    assert issubclass(UnknownParameterError, ControlError) and issubclass(ControlError, SymgenError)
