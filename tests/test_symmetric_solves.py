"""Solves with the library factor of a symmetric positive definite matrix, where the generated C
does not substitute row by row over panels of columns: the inverse
(:attr:`symgen.codegen.graph_solves.Solve.inverse`: a right-hand side that is the identity becomes
one call computing ``A^-1`` by panels, about a third of the substitutions' flops) and one
right-hand side (column-oriented substitutions). The generated C (whole panels of 8 columns, the
columns beyond them, the plain-C fallback; every compiler there is, with the strict flags) and NumPy
against NumPy; the inverse's flop count by hand; a general right-hand side and a non-symmetric
factor keep the substitutions."""
from __future__ import annotations

import ctypes

import numpy as np
import pytest

import symgen
from symgen.codegen import sparse_lu
from symgen.codegen.emit import lower
from symgen.codegen.functions import Argument, Function
from symgen.codegen.generate import generate
from symgen.codegen.graph import Graph
from symgen.codegen.graph_solves import inverse_flops
from symgen.codegen.runtime import load_generated

from .codegen_util import LOOP_FLAGS, loop_builds
from .test_c_products import _Cut, _SourceOnly


def _solves(kinds: tuple[str, ...], n: int = 11) -> Function:
    """A function ``solves`` of one library solve per kind, each with its own matrix (a symmetric
    one's lower triangle read, its upper one not): ``inverse`` (symmetric, the identity),
    ``vector`` (symmetric, one column), ``general`` (symmetric, three columns), ``lu`` (three
    columns), ``lu1`` (one column), ``lu-transposed`` (with ``A^T``, the factor of ``A`` shared
    with a solve whose result is dead)."""
    g = Graph()
    args, outputs = [], []
    for idx, kind in enumerate(kinds):
        a = np.array(g.input(f"a{idx}", n * n), dtype=object).reshape(n, n)
        args.append(Argument(f"a{idx}", (n * n,), "A"))
        if kind == "inverse":
            b = np.array([[g.const(int(i == j)) for j in range(n)] for i in range(n)], dtype=object)
        else:
            k = 1 if kind in ("vector", "lu1") else 3
            b = np.array(g.input(f"b{idx}", n * k), dtype=object).reshape(n, k)
            args.append(Argument(f"b{idx}", (n * k,), "B"))
        if kind in ("inverse", "vector", "general"):
            lower_a = np.array([[a[max(i, j), min(i, j)] for j in range(n)] for i in range(n)], dtype=object)
            x = g.solve_spd(lower_a, b, "test matrix")
        elif kind == "lu-transposed":
            g.solve(a, b, "test matrix")
            x = g.solve(a.T, b, "test matrix")
        else:
            x = g.solve(a, b, "test matrix")
        x = np.asarray(x, dtype=object).reshape(n, -1)
        outputs.append((Argument(f"x{idx}", x.shape, "solution"), x))
    return Function("solves", "test solves", args, outputs, g)


def _spd(n: int, seed: int) -> np.ndarray:
    """A well-conditioned symmetric positive definite matrix whose upper triangle is garbage (the
    generated code must not read it)."""
    rng = np.random.default_rng(seed)
    b = rng.normal(size=(n, n))
    a = b @ b.T + n * np.eye(n)
    return np.tril(a) + np.triu(np.full((n, n), np.nan), 1)


@pytest.fixture
def library(monkeypatch):
    """The library factor from any size (no straight-line ``LDL^T``)."""
    monkeypatch.setattr(sparse_lu, "LDLT_MAX", 0)


def test_the_flop_count_by_hand():
    """n = 1: the pivot's reciprocal, times 1. n = 2: column 0 -- Z_10 (a multiply-add), then rows
    1 and 0 each a reciprocal and a multiply, row 0 a multiply-add before it; column 1: row 1's
    reciprocal and multiply. A whole panel (n = 8): 8 columns of 8 * 7 multiply-adds, 8 rows of a
    reciprocal and 8 multiplies. n = 9: the panel's 9 rows (8 columns of 9 * 8 multiply-adds, 9
    reciprocals and 9 * 8 multiplies), then column 8's one row (a reciprocal and a multiply)."""
    assert inverse_flops(1) == 2
    assert inverse_flops(2) == 8 + 2
    assert inverse_flops(8) == 8 * 2 * 8 * 7 + 8 * (1 + 8)
    assert inverse_flops(9) == 8 * 2 * 9 * 8 + 9 + 9 * 8 + 2
    for n in (32, 64):
        assert inverse_flops(n) < 0.5 * 2 * n**3   # against substitutions on the identity's columns
    assert inverse_flops(512) < 1.1 * 2 * 512**3 / 3


@pytest.mark.usefixtures("library")
def test_only_the_identity_of_a_symmetric_factor_is_an_inverse():
    fn = _solves(("inverse",), 5)
    solves = lower(fn).ops["solves"]
    assert [s.get("inverse") for s in solves] == [True]
    assert lower(fn).ops["solve_flops"] == round(5**3 / 3) + inverse_flops(5)
    general = lower(_solves(("general",), 5)).ops["solves"]
    assert [s.get("inverse") for s in general] == [None]
    g = Graph()
    a = np.array(g.input("a", 9), dtype=object).reshape(3, 3)
    eye = np.array([[g.const(int(i == j)) for j in range(3)] for i in range(3)], dtype=object)
    g.solve(a, eye, "not symmetric")                # the LU's inverse keeps the substitutions
    assert not any(getattr(s, "inverse", False) for s in g.statements)


def _generated(tmp_path, fn, target=_SourceOnly):
    gen = generate(symgen.derive(symgen.load("four_bar")), target(), lowered=[lower(fn)])
    for name, text in gen.files.items():
        (tmp_path / name).write_text(text)
    return gen


@pytest.mark.usefixtures("library")
@pytest.mark.parametrize("n", [1, 3, 8, 11, 16, 21, 32])
def test_the_c_loop_equals_numpy_s_inverse(n, tmp_path):
    """Columns one at a time only (n < 8), one and several whole panels, whole panels and columns
    beyond them; vector extensions for this processor and for the baseline instruction set, plain
    loops; every compiler there is, with the strict flags. The identity is never written out."""
    gen = _generated(tmp_path, _solves(("inverse",), n))
    source = gen.files[f"{gen.module}.c"]
    assert f"symgen_symmetric_inverse({n}, " in source and "symgen_symmetric_solve(" not in source
    assert "] = 1.0;" not in source
    a = _spd(n, n)
    want = np.linalg.inv(np.tril(a) + np.tril(a, -1).T)
    for label, lib in loop_builds(tmp_path / f"{gen.module}.c", "inverse"):
        out = np.full(n * n, np.nan)
        status = lib.symgen_four_bar_solves(np.ascontiguousarray(a).ctypes.data_as(ctypes.c_void_p),
                                             out.ctypes.data_as(ctypes.c_void_p), None)
        assert status == 0
        np.testing.assert_allclose(out.reshape(n, n), want, rtol=1e-12, atol=1e-14, err_msg=label)
        np.testing.assert_array_equal(out.reshape(n, n), out.reshape(n, n).T, err_msg=label)   # exactly


@pytest.mark.usefixtures("library")
@pytest.mark.parametrize("n", [1, 3, 8, 11, 32])
def test_one_right_hand_side_equals_numpy_s_solve(n, tmp_path):
    gen = _generated(tmp_path, _solves(("vector",), n))
    assert f"symgen_symmetric_solve({n}, 1, " in gen.files[f"{gen.module}.c"]
    a = _spd(n, n + 1)
    b = np.random.default_rng(n).normal(size=n)
    want = np.linalg.solve(np.tril(a) + np.tril(a, -1).T, b)
    for label, lib in loop_builds(tmp_path / f"{gen.module}.c", "vector"):
        out = np.full(n, np.nan)
        status = lib.symgen_four_bar_solves(np.ascontiguousarray(a).ctypes.data_as(ctypes.c_void_p),
                                             b.ctypes.data_as(ctypes.c_void_p), out.ctypes.data_as(ctypes.c_void_p), None)
        assert status == 0
        np.testing.assert_allclose(out, want, rtol=1e-12, atol=1e-14, err_msg=label)


@pytest.mark.usefixtures("library")
def test_a_matrix_not_positive_definite_is_refused(tmp_path):
    """The factor's pivot check runs before the inverse: a negative pivot is a singular status."""
    n = 11
    gen = _generated(tmp_path, _solves(("inverse",), n))
    a = _spd(n, 4)
    a[6, 6] = -1.0                                    # pivot 6 is at most -1
    for label, lib in loop_builds(tmp_path / f"{gen.module}.c", "refused"):
        out = np.full(n * n, np.nan)
        status = lib.symgen_four_bar_solves(np.ascontiguousarray(a).ctypes.data_as(ctypes.c_void_p),
                                            out.ctypes.data_as(ctypes.c_void_p), None)
        assert status == 1, label                     # SYMGEN_SINGULAR


@pytest.mark.usefixtures("library")
def test_the_numpy_target_equals_numpy_s_inverse():
    n = 11
    module = load_generated(symgen.derive(symgen.load("four_bar")), "numpy", lowered=[lower(_solves(("inverse",), n))])
    a = np.stack([np.nan_to_num(_spd(n, s), nan=0.0) for s in range(3)])
    got = module.solves(a.reshape(3, -1))
    want = np.linalg.inv(a + np.swapaxes(np.tril(a, -1), 1, 2))
    np.testing.assert_allclose(got.reshape(3, n, n), want, rtol=1e-12)



@pytest.mark.usefixtures("library")
@pytest.mark.parametrize("kinds", [("inverse",), ("vector",), ("general", "inverse"), ("lu1", "inverse"),
                                   ("lu-transposed",), ("lu", "vector")], ids="+".join)
@pytest.mark.parametrize("target", [_SourceOnly, _Cut], ids=["whole", "blocks"])
def test_each_mix_of_library_solves_compiles_with_the_strict_flags(kinds, target, tmp_path):
    """Only the library loops a function calls are emitted (an unused static function is a warning,
    an error under ``-Werror``), whole or cut into blocks, with vectors or without."""
    gen = _generated(tmp_path, _solves(kinds), target)
    assert len(list(loop_builds(tmp_path / f"{gen.module}.c", "solves"))) >= len(LOOP_FLAGS)   # each built
