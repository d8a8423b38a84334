"""The banded product statement of the tracing graph (symgen.codegen.graph_products): its entries'
values against NumPy, its flop count by hand, its refusals. The generated loops are checked on the
closed form that uses them (tests/test_rnea_derivatives.py)."""
from __future__ import annotations

import numpy as np
import pytest

from symgen.codegen.derivatives import differentiate
from symgen.codegen.graph import Graph
from symgen.errors import CodegenError


def _traced(n=5, m=3, k=4, ranges=((0, 5), (2, 4), (1, 1), (4, 5))):
    g = Graph()
    a = np.array(g.input("a", n * m), dtype=object).reshape(n, m)
    b = np.array(g.input("b", m * k), dtype=object).reshape(m, k)
    rng = np.random.default_rng(2)
    g.samples = {"a": rng.normal(size=(3, n * m)), "b": rng.normal(size=(3, m * k))}
    return g, a, b, g.product(a, b, list(ranges), "test product")


def test_wanted_entries_equal_numpy_and_the_others_are_not_made():
    g, a, b, x = _traced()
    ranges = ((0, 5), (2, 4), (1, 1), (4, 5))
    want = g.samples["a"].reshape(3, 5, 3) @ g.samples["b"].reshape(3, 3, 4)
    for c, (lo, hi) in enumerate(ranges):
        for r in range(5):
            if lo <= r < hi:
                got = g.sample_values([x[r, c]])[:, 0]
                np.testing.assert_allclose(got, want[:, r, c], rtol=1e-15)
            else:
                assert x[r, c] is None


def test_the_count_is_two_flops_per_term_of_each_wanted_entry():
    g, _, _, x = _traced()
    counts = g.count(g.live([[v for v in x.flat if v is not None]]))
    assert counts["products"] == [{"rows": 5, "terms": 3, "columns": 4, "flops": 2 * 3 * (5 + 2 + 0 + 1)}]
    assert counts["product_flops"] == 48 and counts["total"] == 0


def test_no_wanted_entry_records_no_statement():
    g = Graph()
    a = np.array(g.input("a", 4), dtype=object).reshape(2, 2)
    out = g.product(a, a, [(0, 0), (1, 1)], "empty")
    assert all(v is None for v in out.flat) and not g.statements


def test_terms_zero_in_every_row_or_column_are_left_out():
    """Term 1 is zero in every row of A, term 2 in every column of B: a one-term product, whose
    entries still equal the full product; with every term zero, constant zeros and no statement."""
    g = Graph()
    a = np.array(g.input("a", 4 * 3), dtype=object).reshape(4, 3)
    b = np.array(g.input("b", 3 * 2), dtype=object).reshape(3, 2)
    a[:, 1], b[2, :] = 0, 0
    rng = np.random.default_rng(5)
    g.samples = {"a": rng.normal(size=(2, 12)), "b": rng.normal(size=(2, 6))}
    x = g.product(a, b, [(0, 4), (1, 3)], "zero terms")
    assert [p["terms"] for p in g.count(g.live([[v for v in x.flat if v is not None]]))["products"]] == [1]
    sa, sb = g.samples["a"].reshape(2, 4, 3), g.samples["b"].reshape(2, 3, 2)
    np.testing.assert_allclose(g.sample_values([x[3, 0]])[:, 0], sa[:, 3, 0] * sb[:, 0, 0], rtol=1e-15)
    zeros = Graph().product(np.zeros((4, 3), dtype=object), b, [(0, 4), (1, 3)], "no term left")
    assert all(v.is_const and v.value == 0 for v in zeros[:, 0]) and zeros[0, 1] is None


@pytest.mark.parametrize("ranges", [[(0, 6), (0, 1), (0, 1), (0, 1)], [(3, 2), (0, 1), (0, 1), (0, 1)], [(0, 1)]])
def test_a_range_outside_the_rows_or_a_missing_one_is_refused(ranges):
    with pytest.raises(ValueError):
        _traced(ranges=ranges)


def test_factors_that_are_not_matrices_are_refused():
    g = Graph()
    a = np.array(g.input("a", 4), dtype=object)
    with pytest.raises(ValueError, match="vector"):
        g.product(a.reshape(2, 2), a, [(0, 2)] * 4, "vector")


def test_the_forward_sweep_refuses_to_differentiate_through_a_product():
    """Its entries have no partials recorded; a silent zero derivative would be wrong."""
    g, a, b, x = _traced()
    with pytest.raises(CodegenError, match="test product"):
        differentiate(g, np.array([x[0, 0]], dtype=object), list(a.flat))
