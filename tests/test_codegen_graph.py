"""The tracing graph's rules, each against a hand-written expectation: folding, shared
subexpressions, sign canonicalisation, counting, and constant solves done exactly."""
from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from symgen.codegen.graph import Graph, is_zero
from symgen.errors import SingularConfigurationError


@pytest.fixture
def g():
    return Graph()


def test_identities_fold_away(g):
    x, y = g.input("x", 2)
    assert x + 0 is x and 0 + x is x and x * 1 is x and x - 0 is x
    assert is_zero(x * 0) and is_zero(x - x)
    assert -(-x) is x
    assert (g.const(Fraction(1, 3)) * 3).value == 1          # exact constant arithmetic


def test_same_operation_is_one_node(g):
    x, y = g.input("x", 2)
    assert x * y is y * x and x + y is y + x                 # commutative operands sorted
    assert g.func("sin", x) is g.func("sin", x)
    assert x - y is not y - x


def test_signs_are_canonical(g):
    x, y = g.input("x", 2)
    assert (x + (-y)).op == "sub" and ((-x) * y).op == "neg"
    assert (x * -2.5).op == "neg"                             # negative constants pulled out
    assert (x * -2.5).args == ((x * 2.5).id,)


def test_counts_only_live_operations(g):
    x, y = g.input("x", 2)
    out = x * y + g.func("cos", x) / y
    _unused = x * x * x
    ops = g.count(g.live([[out]]))
    assert (ops["mul"], ops["div"], ops["add"], ops["trig"], ops["total"]) == (2, 1, 1, 1, 3)


def test_constant_solve_is_exact_and_singular_is_an_error(g):
    a = np.array([[2, 1], [1, 1]], dtype=object)
    x = g.solve(a, np.array([3, 2], dtype=object))
    assert [v.value for v in x] == [1, 1]
    assert g.statements == []                                  # no library call emitted
    with pytest.raises(SingularConfigurationError, match="constant"):
        g.solve(np.array([[1, 2], [2, 4]], dtype=object), np.array([1, 1], dtype=object))


def test_constant_permutation_solve_selects_rows(g, monkeypatch):
    """``a^-1 b = a^T b`` for a constant permutation ``a``: the rows of ``b``, the same nodes, no new
    operation and no exact inverse in rationals (``O(n^3)`` at generation time; what motion on joints
    gives ``[J_m; J_f]``)."""
    x = g.input("x", 6)
    inverse = g._constant_inverse
    monkeypatch.setattr(g, "_constant_inverse", lambda *a: pytest.fail("permutation inverted in rationals"))
    rhs = np.array([[x[0], x[1]], [x[2], x[3]], [x[4], x[5]]], dtype=object)
    perm = np.array([[0, 1, 0], [0, 0, 1], [1, 0, 0]], dtype=object)     # a e_1 = e_3, a e_2 = e_1
    before = len(g.nodes)
    out = g.solve(perm, rhs)
    assert [[v.id for v in row] for row in out] == [[x[4].id, x[5].id], [x[0].id, x[1].id], [x[2].id, x[3].id]]
    assert len(g.nodes) == before + 2                          # the constants 0 and 1, nothing else
    monkeypatch.setattr(g, "_constant_inverse", inverse)
    flipped = g.solve(np.array([[0, -1], [1, 0]], dtype=object), np.array([x[0], x[1]], dtype=object))
    assert flipped[0] is x[1] and flipped[1].op == "neg"       # a signed permutation: the exact inverse


def test_transposed_solve_reuses_the_factorisation(g):
    a, b, c, d = g.input("a", 4)
    x = g.solve(np.array([[a, b], [c, d]]), np.array([1, 0], dtype=object))
    y = g.solve(np.array([[a, c], [b, d]]), np.array([0, 1], dtype=object))
    ops = g.count(g.live([x, y]))
    assert ops["factorizations"] == [2]
    assert [s["transposed"] for s in ops["solves"]] == [False, True]
