"""A joint placed by a Denavit-Hartenberg twist keeps ``R_PC`` as two factors: the same rotation
(exactly), fewer operations where the recursions rotate vectors through it."""
from fractions import Fraction

import sympy as sp

from symgen.dynamics import transforms
from symgen.dynamics.algebra import FactoredRotation, matmul3, rotate, rotate_t
from symgen.io.builtin import get_scene
from symgen.model import derive


def _turn(axis: int, c, s) -> sp.Matrix:
    m = sp.eye(3)
    i, j = [k for k in range(3) if k != axis]
    m[i, i], m[i, j], m[j, i], m[j, j] = c, -s if axis != 1 else s, s if axis != 1 else -s, c
    return m


def test_only_a_turn_about_x_or_y_through_a_general_angle_is_a_twist():
    c, s = sp.Rational(3, 5), sp.Rational(4, 5)
    assert transforms.is_twist(_turn(0, c, s)) and transforms.is_twist(_turn(1, c, s))
    assert not transforms.is_twist(_turn(2, c, s))                  # commutes with the joint's own turn
    assert not transforms.is_twist(_turn(0, 0, 1))                  # 90 degrees: a signed permutation
    assert not transforms.is_twist(sp.eye(3))
    assert not transforms.is_twist(_turn(0, c, s) * _turn(2, c, s))  # general: the product is cheaper


def test_the_factored_rotation_is_the_product_exactly():
    a = [[Fraction(int(x.p), int(x.q)) for x in row] for row in _turn(0, sp.Rational(5, 13), sp.Rational(12, 13)).tolist()]
    b = [[Fraction(3, 5), Fraction(-4, 5), 0], [Fraction(4, 5), Fraction(3, 5), 0], [0, 0, 1]]
    r = FactoredRotation(a, b)
    assert [list(row) for row in r] == matmul3(a, b)
    v = (Fraction(1, 3), Fraction(-2, 7), Fraction(5, 11))
    assert rotate(r, v) == rotate(matmul3(a, b), v) and rotate_t(r, v) == rotate_t(matmul3(a, b), v)


def test_the_general_chain_costs_fewer_operations_with_its_twists_apart(monkeypatch):
    from symgen.codegen.generate import operation_counts

    functions = ["inverse_dynamics", "inverse_dynamics_derivatives"]
    apart = operation_counts(derive(get_scene("general_chain:n=4")), functions)
    monkeypatch.setattr(transforms, "is_twist", lambda rotation: False)
    whole = operation_counts(derive(get_scene("general_chain:n=4")), functions)
    for name in functions:
        assert apart[name]["total"] < whole[name]["total"] - 20, name
