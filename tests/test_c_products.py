"""How the C target lays out banded products (symgen.codegen.targets.c_products): written straight
into an output where that is provably safe, refused where it is not, repeated factors packed once.
The compiled result is checked against NumPy on hand-made products whose ranges leave partial
groups of rows next to another product's rows in the same output; the closed form that relies on
it is checked against Pinocchio and 50-digit differences in tests/test_rnea_derivatives.py."""
from __future__ import annotations

import ctypes
import os
import shutil
import subprocess

import numpy as np
import pytest

import symgen
from symgen.codegen.emit import lower
from symgen.codegen.functions import Argument, Function
from symgen.codegen.generate import generate
from symgen.codegen.graph import Graph
from symgen.codegen.targets.c import CTarget
from symgen.codegen.targets.c_products import lay_out_products

N, M = 13, 3                 # 13 rows: a full group of 8, an overlapping tail and partial groups


def _inputs(g, k=N):
    a = np.array(g.input("a", N * M), dtype=object).reshape(N, M)
    b = np.array(g.input("b", M * k), dtype=object).reshape(M, k)
    return a, b


def _function(g, outputs) -> Function:
    return Function("products", "test products", [Argument("a", (N * M,), "A"), Argument("b", (M * N,), "B")],
                    outputs, g)


def _split_output(g, a, b, zero_row=None, computed=False):
    """``O[c, r] = (A B)[r, c]`` for rows ``r <= c`` from one product, ``-(A B)[r, c]`` for ``r > c``
    from another (a row one of them wrote beyond its range would hold the other's sign), into one
    output; ``zero_row``: that row of every column assigned 0 instead (a row a range covers but
    does not own), or with ``computed`` ``A[0, 0] B[0, c]``, statements of their own traced before
    the products (stored only after them, which write over that row). The second output copies the first product's entries to the transposed
    positions (as ``M``'s upper triangle is made), except those of the zeroed row (which it does
    not own there)."""
    filler = [a[0, 0] * b[0, c] if computed else g.const(0) for c in range(N)]
    low = g.product(a, b, [(0, c + 1) for c in range(N)], "at and above")
    high = g.product(-a, b, [(c + 1, N) for c in range(N)], "below")
    out = np.empty((N, N), dtype=object)
    for c in range(N):
        for r in range(N):
            if r == zero_row:
                out[c, r] = filler[c]
            else:
                out[c, r] = (low if r <= c else high)[r, c]
    mirror = np.array([[low[c, r] if c <= r and c != zero_row else g.const(0) for r in range(N)] for c in range(N)],
                      dtype=object)
    return out, mirror


class _SourceOnly(CTarget):
    def files(self, module, python_extension=False):
        return super().files(module)[:2]


class _Cut(_SourceOnly):
    """Cut into blocks of 20 statements: the factors' entries computed in blocks and stored in place."""

    split_statements = 10
    block_statements = 20


def _compiled(tmp_path, fn: Function, flags=(), target=None):
    cc = os.environ.get("CC", "cc")
    if shutil.which(cc) is None:
        pytest.skip(f"no C compiler ({cc})")
    gen = generate(symgen.derive(symgen.load("four_bar")), target or _SourceOnly(), lowered=[lower(fn)])
    for name, text in gen.files.items():
        (tmp_path / name).write_text(text)
    lib = tmp_path / f"products{len(flags)}.so"
    subprocess.run([cc, "-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic", "-O2", "-fPIC", "-shared",
                    "-march=native", *flags, "-o", str(lib), str(tmp_path / f"{gen.module}.c"), "-lm"], check=True)
    return ctypes.CDLL(str(lib)), gen.files[f"{gen.module}.c"]


def _call(lib, a, b, sizes):
    """The single-state function on ``a``, ``b``: its outputs (filled with NaN before the call)."""
    outs = [np.full(s, np.nan) for s in sizes]
    ptr = [np.ascontiguousarray(x, dtype=float).ctypes.data_as(ctypes.c_void_p) for x in (a, b)]
    status = lib.symgen_four_bar_products(*ptr, *[o.ctypes.data_as(ctypes.c_void_p) for o in outs], None)
    assert status == 0
    return outs


def _batch_agrees(lib, a_val, b_val, sizes, states=5):
    """The ``_batch`` entry (the lane kernel where the build has lanes) on ``states`` states, the
    first two those of ``a_val``, ``b_val`` scaled, equals the single-state function state by state."""
    a_all = np.stack([a_val * (1 + 0.1 * s) for s in range(states)])
    b_all = np.stack([b_val * (1 - 0.1 * s) for s in range(states)])
    outs = [np.full((states, size), np.nan) for size in sizes]
    ptr = [np.ascontiguousarray(x).ctypes.data_as(ctypes.c_void_p) for x in (a_all, b_all)]
    status = lib.symgen_four_bar_products_batch(states, *ptr, *[o.ctypes.data_as(ctypes.c_void_p) for o in outs], None)
    assert status == 0
    for s in range(states):
        for got, want in zip(outs, _call(lib, a_all[s], b_all[s], sizes)):
            np.testing.assert_allclose(got[s], want, rtol=1e-14, atol=1e-14)


@pytest.mark.parametrize("zero_row, computed", [(None, False), (5, False), (0, True)],
                         ids=["all-rows", "zero-row", "computed-row"])
@pytest.mark.parametrize("flags", [(), ("-DSYMGEN_NO_VECTOR",)], ids=["vector", "plain-loops"])
def test_two_products_share_an_output_and_a_copy_reads_the_owned_rows(tmp_path, flags, zero_row, computed):
    g = Graph()
    a, b = _inputs(g)
    out, mirror = _split_output(g, a, b, zero_row, computed)
    fn = _function(g, [(Argument("o", (N, N), "split"), out), (Argument("m", (N, N), "mirror"), mirror)])
    laid = lay_out_products(lower(fn))
    products = [s for s in laid.steps if s.kind == "product"]
    assert [s.into for s in products] == ["o", "o"]
    assert not products[1].shares_a and products[1].shares_b == "pb" + products[0].name[1:]
    lib, source = _compiled(tmp_path, fn, flags)
    assert "symgen_product(13, 3, 13, pa" in source
    assert ("o[0] = " in source.split("int symgen_four_bar_products(")[1]) == computed   # row 0 is the product's
    rng = np.random.default_rng(4)
    a_val, b_val = rng.normal(size=(N, M)), rng.normal(size=(M, N))
    got, mirrored = _call(lib, a_val, b_val, [N * N, N * N])
    want = np.where(np.tril(np.ones((N, N))) > 0, (a_val @ b_val).T, -(a_val @ b_val).T)
    if zero_row is not None:
        want[:, zero_row] = a_val[0, 0] * b_val[0] if computed else 0.0
    np.testing.assert_allclose(got.reshape(N, N), want, rtol=1e-14, atol=1e-14)
    full = a_val @ b_val
    upper = np.triu(full)
    if zero_row is not None:
        upper[zero_row] = 0.0
    np.testing.assert_allclose(mirrored.reshape(N, N), upper, rtol=1e-14, atol=1e-14)
    _batch_agrees(lib, a_val, b_val, [N * N, N * N])


def test_factors_computed_in_blocks_are_stored_in_place_and_the_rest_copied(tmp_path):
    """A function cut into blocks: ``A``'s entries are computed (``2 a``, ``a * a``), so its
    blocks store them straight into the product's packed array; ``B``'s are inputs (copied) and
    one entry of ``A`` repeats (copied from where it was stored)."""
    g = Graph()
    a, b = _inputs(g)
    a2 = np.array([[2 * v for v in row] for row in a], dtype=object)
    a2[0, 1] = a2[3, 2]                              # a repeat
    a2[1, 0] = a[1, 0] * a[1, 0]
    x = g.product(a2, b, [(0, N)] * N, "computed factor")
    fn = _function(g, [(Argument("o", (N, N), "product"), np.array([[x[r, c] for r in range(N)] for c in range(N)]))])
    lib, source = _compiled(tmp_path, fn, target=_Cut())
    body = source.split("int symgen_four_bar_products(")[1].split("#if SYMGEN_LANES > 1")[0]
    assert "double *pa" in body and body.count("pb") > N * M and body.count("] = work[") == 1
    rng = np.random.default_rng(6)
    a_val, b_val = rng.normal(size=(N, M)), rng.normal(size=(M, N))
    want_a = 2 * a_val
    want_a[0, 1] = want_a[3, 2]
    want_a[1, 0] = a_val[1, 0] ** 2
    got, = _call(lib, a_val, b_val, [N * N])
    np.testing.assert_allclose(got.reshape(N, N), (want_a @ b_val).T, rtol=1e-14)
    _batch_agrees(lib, a_val, b_val, [N * N])


def test_a_product_is_kept_apart_where_a_copy_would_read_a_row_it_does_not_own():
    """Its entries assigned at their transposed positions: only the diagonal at its own flat index."""
    g = Graph()
    a, b = _inputs(g)
    whole = g.product(a, b, [(0, N)] * N, "whole")
    transposed = np.array([[whole[c, r] for r in range(N)] for c in range(N)], dtype=object)
    fn = _function(g, [(Argument("t", (N, N), "entries at other positions"), transposed)])
    assert [s.into for s in lay_out_products(lower(fn)).steps if s.kind == "product"] == [""]


def test_of_two_products_whose_ranges_meet_in_one_output_one_is_written_there():
    g = Graph()
    a, b = _inputs(g)
    whole = g.product(a, b, [(0, N)] * N, "whole")
    other = g.product(a, b, [(0, 2)] * N, "overlapping")
    both = np.array([[whole[r, c] if r >= 2 else other[r, c] for r in range(N)] for c in range(N)], dtype=object)
    fn = _function(g, [(Argument("o", (N, N), "two products' ranges meet"), both)])
    into = {s.what: s.into for s in lay_out_products(lower(fn)).steps if s.kind == "product"}
    assert into == {"whole": "o", "overlapping": ""}


def test_a_product_before_a_pivot_check_stays_in_the_workspace():
    """A singular return after it would leave the outputs half written."""
    g = Graph()
    a, b = _inputs(g)
    x = g.product(a, b, [(0, N)] * N, "before a check")
    mat = np.array([[x[i, j] for j in range(3)] for i in range(3)], dtype=object)
    sol = g.solve_spd(mat, np.array([1, 2, 3], dtype=object), "a check after it")
    out = np.array([[x[r, c] for r in range(N)] for c in range(N)], dtype=object)
    fn = _function(g, [(Argument("o", (N, N), "product"), out), (Argument("s", (3,), "solution"), np.array(sol))])
    laid = lay_out_products(lower(fn))
    assert any(s.kind == "check" for s in laid.steps)
    assert [s.into for s in laid.steps if s.kind == "product"] == [""]
