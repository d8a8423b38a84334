"""Straight-line sparse elimination and LDL^T in the tracing graph (:mod:`symgen.codegen.sparse_lu`):
the static pivot order, solves against NumPy's dense LAPACK solve, the run-time pivot check, and
what the elimination buys on the built-in closed chains."""
from __future__ import annotations

import numpy as np
import pytest

import symgen
from symgen.codegen import sparse_lu
from symgen.codegen.emit import lower
from symgen.codegen.functions import Argument, Function
from symgen.codegen.generate import generate, trace_all
from symgen.codegen.graph import Graph
from symgen.codegen.graph_solves import Factor

from .codegen_util import import_file


def _matrix_graph(pattern, samples):
    """A graph whose ``n x n`` matrix has structural zeros where ``pattern`` is False and an input
    ``a[i*n + j]`` elsewhere, sampled at ``samples`` (``S x n x n``)."""
    g = Graph()
    n = pattern.shape[0]
    a_in = g.input("a", n * n)
    entries = [[a_in[i * n + j] if pattern[i, j] else 0 for j in range(n)] for i in range(n)]
    g.samples = {"a": np.asarray(samples, dtype=float).reshape(len(samples), n * n)}
    return g, entries


def _arrow(rng, blocks=4, size=3):
    """A block-arrow pattern (per-leg blocks coupled through the last block), like ``[T_u1, T_a1]``
    of a parallel robot, with values that keep it well conditioned."""
    n = blocks * size + size
    pattern = np.zeros((n, n), dtype=bool)
    for b in range(blocks + 1):
        s = slice(b * size, (b + 1) * size)
        pattern[s, s] = True
        pattern[s, -size:] = True
        pattern[-size:, s] = True
    values = np.where(pattern, rng.uniform(-1, 1, (n, n)), 0.0) + 4 * np.eye(n)
    return pattern, values


def test_static_order_keeps_an_arrow_matrix_free_of_fill():
    rng = np.random.default_rng(1)
    pattern, values = _arrow(rng)
    order = sparse_lu.plan(pattern, values[None])
    assert order is not None
    n = pattern.shape[0]
    assert sorted(order.rows) == list(range(n)) and sorted(order.cols) == list(range(n))
    assert set(order.cols[-3:]) == {n - 3, n - 2, n - 1}        # the shared block is eliminated last
    assert order.flops < 0.5 * 2 * n**3 / 3


def test_small_dense_matrix_is_eliminated_in_line_and_a_large_one_keeps_the_library_lu():
    """Up to ``SMALL`` x ``SMALL`` a dense matrix is eliminated in line (no more flops than the LU);
    above, only a sparse one that halves the dense flops is."""
    rng = np.random.default_rng(2)
    n = 6
    order = sparse_lu.plan(np.ones((n, n), dtype=bool), rng.uniform(-1, 1, (3, n, n)))
    assert order is not None and order.flops <= 2 * n**3 / 3
    n = sparse_lu.SMALL + 1
    assert sparse_lu.plan(np.ones((n, n), dtype=bool), rng.uniform(-1, 1, (3, n, n))) is None


@pytest.mark.parametrize("seed", range(5))
def test_straight_line_solves_equal_lapack(seed):
    rng = np.random.default_rng(seed)
    pattern, values = _arrow(rng)
    n = pattern.shape[0]
    samples = values[None] + rng.uniform(-0.2, 0.2, (3, n, n)) * pattern
    g, entries = _matrix_graph(pattern, samples)
    b = g.input("b", n)
    x = g.solve(np.array(entries, dtype=object), np.array(b, dtype=object), "test")
    y = g.solve(np.array(entries, dtype=object).T, np.array(b, dtype=object), "test^T")
    assert not [s for s in g.statements if isinstance(s, Factor)]      # no library LU
    a_new = np.where(pattern, values + rng.uniform(-0.3, 0.3, (n, n)), 0.0)   # another state
    rhs = rng.uniform(-1, 1, n)
    g.samples = {"a": a_new.reshape(1, -1), "b": rhs.reshape(1, -1)}
    got_x = g.sample_values(list(x))[0]
    got_y = g.sample_values(list(y))[0]
    np.testing.assert_allclose(got_x, np.linalg.solve(a_new, rhs), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(got_y, np.linalg.solve(a_new.T, rhs), rtol=1e-12, atol=1e-12)


def test_ldlt_solves_a_spd_system_reading_the_lower_triangle_only():
    rng = np.random.default_rng(3)
    n = 7
    root = rng.uniform(-1, 1, (n, n))
    spd = root @ root.T + n * np.eye(n)
    g = Graph()
    a_in = g.input("a", n * n)
    upper_garbage = [[a_in[i * n + j] if j <= i else 123.0 for j in range(n)] for i in range(n)]
    b = g.input("b", n)
    x = g.solve_spd(np.array(upper_garbage, dtype=object), np.array(b, dtype=object), "M")
    rhs = rng.uniform(-1, 1, n)
    g.samples = {"a": spd.reshape(1, -1), "b": rhs.reshape(1, -1)}
    np.testing.assert_allclose(g.sample_values(list(x))[0], np.linalg.solve(spd, rhs), rtol=1e-12)
    counted = g.count(g.live([x]))
    assert counted["factorizations"] == [] and counted["pivot_checks"] == [n]


def _numpy_module(tmp_path, g, inputs, outputs):
    """Render a hand-made traced function with the NumPy target and import it."""
    fn = Function("solve_it", "test solve", inputs, outputs, g)
    model = symgen.derive(symgen.load("four_bar"))
    files = generate(model, "numpy", lowered=[lower(fn)]).files
    path = tmp_path / "sparse_check.py"
    path.write_text(files["four_bar.py"])
    return import_file(path, f"sparse_check_{id(g)}")


def test_a_vanishing_static_pivot_is_reported_not_divided_through(tmp_path):
    """The order is chosen where ``a00`` is large; at a state where it vanishes the matrix is still
    regular (a dense LU would pivot), and the generated code reports a singular solve instead of
    dividing by zero: the check is conservative, never silent."""
    pattern = np.array([[1, 1, 0], [1, 0, 1], [0, 1, 1]], dtype=bool)
    chosen = np.array([[5.0, 1.0, 0.0], [1.0, 0.0, 1.0], [0.0, 1.0, 2.0]])
    g, entries = _matrix_graph(pattern, np.stack([chosen, chosen * 1.1]))
    b = g.input("b", 3)
    x = g.solve(np.array(entries, dtype=object), np.array(b, dtype=object), "test matrix")
    module = _numpy_module(tmp_path, g, [Argument("a", (9,), "matrix"), Argument("b", (3,), "rhs")],
                           [(Argument("x", (3,), "solution"), np.array(x, dtype=object))])
    good = np.array([[5.0, 1.0, 0.0], [1.0, 0.0, 1.0], [0.0, 1.0, 2.0]])
    np.testing.assert_allclose(module.solve_it(good.ravel(), [1.0, 2.0, 3.0]),
                               np.linalg.solve(good, [1.0, 2.0, 3.0]), rtol=1e-13)
    bad = good.copy()
    bad[0, 0] = 0.0
    assert abs(np.linalg.det(bad)) > 0.5
    with pytest.raises(module.SingularSolveError, match="test matrix"):
        module.solve_it(bad.ravel(), [1.0, 2.0, 3.0])


def _total(ops) -> int:
    return ops["total"] + ops["solve_flops"]


def test_stewart_inverse_dynamics_has_no_dense_loop_closure_solve():
    model = symgen.derive(symgen.load("stewart"))
    (low,) = trace_all(model, ["inverse_dynamics"], None)
    assert low.ops["factorizations"] == []           # the 30 x 30 [T_u1, T_a1] is eliminated in line
    assert low.ops["pivot_checks"]                    # and its pivots are checked at run time
    assert _total(low.ops) <= 5_000                  # 3,105 (benchmarks/complexity/closed_chains.md)


def test_forward_dynamics_factors_the_mass_matrix_by_ldlt():
    model = symgen.derive(symgen.load("chain:n=6"))
    (low,) = trace_all(model, ["forward_dynamics"], {"method": "dense"})
    assert low.ops["factorizations"] == [] and low.ops["pivot_checks"] == [6]


def test_library_baseline_is_available_and_costlier():
    model = symgen.derive(symgen.load("stewart"))
    with sparse_lu.library_solves_only():
        (dense,) = trace_all(model, ["inverse_dynamics"], None)
    (sparse,) = trace_all(model, ["inverse_dynamics"], None)
    assert dense.ops["factorizations"] == [30] and not dense.ops.get("pivot_checks")
    assert _total(sparse.ops) < _total(dense.ops) / 3


def _tree_spd(rng, parents):
    """An SPD matrix with the pattern of a tree's mass matrix: entry ``(i, j)`` is nonzero when one
    of ``i, j`` is an ancestor of the other (``parents[i]``: the parent index, ``-1`` for a root)."""
    n = len(parents)

    def ancestors(i):
        out = {i}
        while parents[i] >= 0:
            i = parents[i]
            out.add(i)
        return out

    pattern = np.array([[i in ancestors(j) or j in ancestors(i) for j in range(n)] for i in range(n)])
    values = np.where(pattern, rng.uniform(-1, 1, (n, n)), 0.0)
    return pattern, (values + values.T) / 2 + n * np.eye(n)


#: a base of six coordinates and three branches of six (a humanoid's upper body on its free base)
BRANCHES = [-1, 0, 1, 2, 3, 4] + [p for b in range(3) for p in [5] + list(range(6 + 6 * b, 11 + 6 * b))]


def test_minimum_degree_takes_a_tree_mass_matrix_leaves_first_without_fill():
    rng = np.random.default_rng(4)
    pattern, _ = _tree_spd(rng, BRANCHES)
    order, flops = sparse_lu.minimum_degree(pattern)
    assert min(order[:12]) >= 6                                  # two branches before the base they share
    depth = [len(np.nonzero(pattern[i, :i])[0]) for i in range(len(BRANCHES))]
    assert flops == sum(1 + d * (d + 3) // 2 for d in depth)    # each pivot meets its ancestors only
    dense = np.ones((7, 7), dtype=bool)
    assert sparse_lu.minimum_degree(dense)[0] == tuple(range(7))   # a dense matrix keeps its order


def test_ldlt_of_a_large_tree_matrix_is_in_line_and_a_dense_one_keeps_the_library_lu():
    """24 x 24 with the pattern of a tree: eliminated in line in the minimum-degree order, equal to
    LAPACK at another state; 24 x 24 dense: the library LU."""
    rng = np.random.default_rng(5)
    pattern, spd = _tree_spd(rng, BRANCHES)
    n = len(BRANCHES)
    assert n > sparse_lu.LDLT_MAX
    g, entries = _matrix_graph(pattern, spd[None])
    b = g.input("b", n)
    x = g.solve_spd(np.array(entries, dtype=object), np.array(b, dtype=object), "M")
    counted = g.count(g.live([x]))
    assert counted["factorizations"] == [] and counted["pivot_checks"] == [n]
    _, other = _tree_spd(np.random.default_rng(6), BRANCHES)
    rhs = rng.uniform(-1, 1, n)
    g.samples = {"a": other.reshape(1, -1), "b": rhs.reshape(1, -1)}
    np.testing.assert_allclose(g.sample_values(list(x))[0], np.linalg.solve(other, rhs), rtol=1e-12)
    g, entries = _matrix_graph(np.ones((n, n), dtype=bool), spd[None])
    x = g.solve_spd(np.array(entries, dtype=object), np.array(g.input("b", n), dtype=object), "M")
    assert g.count(g.live([x]))["factorizations"] == [n]



@pytest.mark.parametrize("spec", ["chain:n=17", "arm_on_plane"])
def test_the_c_library_lu_solves_equal_numpy_on_panels_and_remainders(spec):
    """The C library LU's substitutions carry 32 right-hand-side columns at a time. With every
    solve left to the library, the forward-dynamics Jacobians of ``chain:n=17`` solve with the 17 x 17
    task matrix for 33 right-hand sides (a full panel and a remainder of 1) and with the mass matrix
    by its symmetric factor (:func:`symgen_symmetric_factor`): its inverse (the 17 identity columns
    of the right-hand side), then the 34 other columns as two library products with it, 17 columns
    each (transposed: each writes an output's rows); those of
    ``arm_on_plane`` solve with ``A^T`` (:func:`symgen_lu_solve_t`); the generated C equals the
    NumPy module, whose solves are LAPACK's."""
    from symgen.codegen.graph_products import Product
    from symgen.codegen.graph_solves import Solve
    from symgen.codegen.reference import reference_states
    from symgen.codegen.runtime import call_by_name, load_generated

    model = symgen.derive(symgen.load(spec))
    with sparse_lu.library_solves_only():
        lowered = trace_all(model, ["forward_dynamics_derivatives"], {"method": "implicit-dense"})
    statements = lowered[0].function.graph.statements
    ks = [s.k for s in statements if isinstance(s, Solve)]
    assert any(getattr(s, "transposed", False) for s in statements) == (spec == "arm_on_plane")
    assert max(ks) > (32 if spec == "chain:n=17" else 16), ks           # a full panel and a remainder
    if spec == "chain:n=17":
        symmetric = [s for s in statements if isinstance(s, Factor) and s.symmetric]
        assert [s.n for s in symmetric] == [17]
        assert sorted(s.k for s in statements if isinstance(s, Solve) and s.factor == symmetric[0].id) == [1, 17]
        assert [(s.n, s.m, s.k) for s in statements if isinstance(s, Product)] == [(17, 17, 17)] * 2
        from symgen.codegen.targets.c_products import lay_out_products

        steps = lay_out_products(lowered[0]).steps       # as the C target lays them out
        inverse = next(s for s in steps if s.kind == "solve" and s.k == 17 and s.symmetric)
        products = [s for s in steps if s.kind == "product"]
        assert [(s.into, s.shares_b) for s in products] == [("ddV_m_dq", inverse.name), ("ddV_m_dV_m", inverse.name)]
    c, numpy = (load_generated(model, t, lowered=lowered) for t in ("c", "numpy"))
    for s in reference_states(model, 2, seed=4):
        for got, want in zip(call_by_name(c, "forward_dynamics_derivatives", s),
                             call_by_name(numpy, "forward_dynamics_derivatives", s), strict=True):
            np.testing.assert_allclose(got, want, rtol=1e-10, atol=1e-10 * np.abs(want).max())


@pytest.mark.parametrize("extra, zero_row", [(5, None), (27, 3)], ids=["one-block", "two-blocks-a-zero-row"])
@pytest.mark.parametrize("target", ["c", "numpy"])
def test_the_library_symmetric_factor_reads_the_lower_triangle_and_finds_the_inverse_first(target, extra, zero_row):
    """A dense 20 x 20 symmetric positive definite matrix (beyond the straight-line LDL^T) is left to
    the library factor without row exchanges; a right-hand side holding the identity's columns gets
    the inverse by one call and its other columns by library products with it, 20 columns at a
    time (27: a block and a remainder), which read the inverse in place (the C target packs no copy
    of it) -- unless a row of those columns is a structural zero: its term is left out, and the
    inverse's columns then packed (once, for both products). Both targets
    equal LAPACK's solve with the upper triangle given as garbage (the lower one is mirrored); the C one
    reports an indefinite matrix (regular, a negative pivot) as singular."""
    from symgen.codegen.graph_products import Product
    from symgen.codegen.graph_solves import Solve, inverse_flops
    from symgen.codegen.runtime import load_generated

    n = 20
    rng = np.random.default_rng(11)
    root = rng.uniform(-1, 1, (n, n))
    spd = root @ root.T + np.eye(n)
    assert n > sparse_lu.LDLT_MAX
    g, entries = _matrix_graph(np.ones((n, n), dtype=bool), spd[None])
    b = g.input("b", n * extra)
    given_columns = np.array(b, dtype=object).reshape(n, extra)
    if zero_row is not None:
        given_columns[zero_row] = g.const(0)
    identity = np.array([[g.const(int(r == c)) for c in range(n)] for r in range(n)], dtype=object)
    rhs = np.concatenate([given_columns, identity], axis=1)           # the identity's columns last
    x = g.solve_spd(np.array(entries, dtype=object), rhs, "test mass matrix")
    counted = g.count(g.live([x.ravel()]))
    assert counted["symmetric_factorizations"] == [n] and sorted(s["rhs"] for s in counted["solves"]) == [n]
    terms = n - (zero_row is not None)
    assert [(p["rows"], p["terms"], p["columns"]) for p in counted["products"]] == [
        (min(n, extra - start), terms, n) for start in range(0, extra, n)]                          # B^T A^-T
    assert [s.get("inverse") for s in counted["solves"]] == [True]                # one call, no substitutions
    assert counted["solve_flops"] == round(n**3 / 3) + inverse_flops(n)      # LDL^T: one triangle
    assert any(isinstance(s, Product) for s in g.statements) and any(isinstance(s, Solve) for s in g.statements)
    fn = Function("solve_it", "test solve", [Argument("a", (n * n,), "matrix"), Argument("b", (n * extra,), "rhs")],
                  [(Argument("x", (n * (n + extra),), "solution"), x.ravel())], g)
    given = np.tril(spd) + np.triu(rng.uniform(-50, 50, (n, n)), 1)     # garbage above the diagonal
    b_value = rng.uniform(-1, 1, (n, extra))
    if zero_row is not None:
        b_value[zero_row] = 0.0
    want = np.linalg.solve(spd, np.concatenate([b_value, np.eye(n)], axis=1))
    fn.reference_inputs = lambda state: {"a": given.ravel(), "b": b_value.ravel()}    # the C test program's
    fn.reference = lambda state, field: {"x": want.ravel()}
    if target == "c":                 # the product reads the inverse's own array: nothing packed
        from symgen.codegen.targets.c_products import lay_out_products

        steps = lay_out_products(lower(fn)).steps
        inverse = next(s for s in steps if s.kind == "solve" and s.k == n)
        first, *later = [s for s in steps if s.kind == "product"]
        packed = f"pb{first.name[1:]}"
        expected = [inverse.name] * (1 + len(later)) if zero_row is None else ["", packed]
        assert [s.shares_b for s in [first, *later]] == expected
        assert not any(s.shares_a for s in [first, *later])
    module = load_generated(symgen.derive(symgen.load("four_bar")), target, lowered=[lower(fn)])
    got = np.asarray(module.solve_it(given.ravel(), b_value.ravel())).reshape(n, n + extra)
    np.testing.assert_allclose(got, want, rtol=1e-11, atol=1e-11 * np.abs(want).max())
    if target == "c":
        indefinite = spd - np.diag(np.r_[np.zeros(n - 1), 1e3])       # its last pivot negative
        assert np.linalg.eigvalsh(indefinite)[0] < 0 and abs(np.linalg.det(indefinite)) > 0
        with pytest.raises(module.SingularSolveError, match="singular"):
            module.solve_it(indefinite.ravel(), b_value.ravel())


@pytest.mark.parametrize("n", [17, 20, 37, 41, 48, 57])
def test_the_c_symmetric_factor_solves_as_lapack_on_every_width_of_its_rows(n):
    """The C library's symmetric factor builds row ``i`` of ``U`` from the rows above in groups of
    8 columns from the multiple of 8 at or below the diagonal: up to four groups at once, then
    three, two or one, then the columns left over. These sizes take each of those paths (17: two
    groups and one column at the first row; 37: four and five; 41: four, one, one; 48: four, two;
    57: four, three, one); the solve equals LAPACK's on a random symmetric positive definite matrix
    whose upper triangle is given as garbage, and a matrix made indefinite at its middle pivot is
    reported singular."""
    from symgen.codegen.runtime import load_generated

    rng = np.random.default_rng(n)
    root = rng.uniform(-1, 1, (n, n))
    spd = root @ root.T + 0.1 * np.eye(n)
    g, entries = _matrix_graph(np.ones((n, n), dtype=bool), spd[None])
    b = g.input("b", n)
    x = g.solve_spd(np.array(entries, dtype=object), np.array(b, dtype=object), "test mass matrix")
    counted = g.count(g.live([np.asarray(x)]))
    assert counted["symmetric_factorizations"] == [n] and counted["solve_flops"] == round(n**3 / 3) + 2 * n**2
    fn = Function("solve_it", "test solve", [Argument("a", (n * n,), "matrix"), Argument("b", (n,), "rhs")],
                  [(Argument("x", (n,), "solution"), np.asarray(x))], g)
    given = np.tril(spd) + np.triu(rng.uniform(-50, 50, (n, n)), 1)
    rhs = rng.uniform(-1, 1, n)
    want = np.linalg.solve(spd, rhs)
    fn.reference_inputs = lambda state: {"a": given.ravel(), "b": rhs}
    fn.reference = lambda state, field: {"x": want}
    module = load_generated(symgen.derive(symgen.load("four_bar")), "c", lowered=[lower(fn)])
    got = np.asarray(module.solve_it(given.ravel(), rhs))
    np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-11 * np.abs(want).max())
    indefinite = spd.copy()
    indefinite[n // 2, n // 2] -= 1e3                  # its pivot at n // 2 negative, the rest regular
    assert np.linalg.eigvalsh(indefinite)[0] < 0 and abs(np.linalg.det(indefinite)) > 0
    with pytest.raises(module.SingularSolveError, match="singular"):
        module.solve_it(np.tril(indefinite).ravel(), rhs)
