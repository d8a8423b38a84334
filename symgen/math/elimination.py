"""Gaussian elimination on object arrays, for the fields of :mod:`symgen.math.fields` that NumPy's
LAPACK cannot serve: exact Gauss-Jordan on Fractions (:func:`gauss_solve`) and LU with partial
pivoting on mpmath numbers (:func:`mp_lu`, :func:`lu_solve`), both ``O(n^3)``; and the column
choice of a pivoted QR that no float library's rounding can change (:func:`pivot_columns`).
"""
from __future__ import annotations

import numpy as np
import mpmath
from mpmath.libmp import fzero, mpf_abs, mpf_cmp, mpf_div, mpf_neg, mpf_pos

from .products import Raw, exact_sum, raw_numbers
from .scalar import Scalar
from ..errors import SingularConfigurationError


#: column norms within this fraction of the largest are ties in :func:`pivot_columns`
PIVOT_TIE = 1e-9


def pivot_columns(a: np.ndarray, count: int) -> list[int]:
    """The first ``count`` pivots of a column-pivoted QR of the float matrix ``a`` (Businger-Golub:
    at each step the column of largest norm after projection off the columns already taken),
    with norms within :data:`PIVOT_TIE` of the largest counted as equal and the lowest index
    taking the tie. LAPACK's ``geqp3`` breaks exact ties by the last bits of its rounding, which
    differ between BLAS builds and processors; a robot with two identical arms has such ties, and
    Step 5's partition must not depend on the machine. ``O(count * rows * cols)``."""
    r = np.array(a, dtype=float)
    chosen: list[int] = []
    for _ in range(count):
        norms = np.sqrt(np.einsum("ij,ij->j", r, r))
        norms[chosen] = -1.0
        best = norms.max()
        if not best > 0:
            break
        j = int(np.flatnonzero(norms >= best * (1.0 - PIVOT_TIE))[0])
        chosen.append(j)
        v = r[:, j] / norms[j]
        r = r - np.outer(v, v @ r)
    return chosen


def obj_full(shape: int | tuple[int, ...], value: Scalar) -> np.ndarray:
    """An object array of ``shape`` filled with ``value``."""
    out = np.empty(shape, dtype=object)
    out.fill(value)
    return out


def mp_lu(a: np.ndarray,
          ctx: mpmath.ctx_mp.MPContext | None = None) -> tuple[np.ndarray, list[int]] | tuple[None, None]:
    """``P a = L U`` by Gaussian elimination with partial pivoting on an object array (mpf).

    Returns ``(lu, perm)`` with ``L`` (unit lower) and ``U`` packed in ``lu`` and row ``i`` of
    ``P a`` being row ``perm[i]`` of ``a``; ``(None, None)`` when a pivot column is exactly zero.
    Crout's order: column ``k`` of the remaining rows, then row ``k`` of ``U``, each entry its
    ``a`` entry minus the sum of its exact products with the factors already known, rounded once
    (an entry of ``L`` divided by the pivot after that sum, rounded once): the elimination's
    numbers without its rounding after every update, in mpmath's integer arithmetic on the raw
    numbers. The exact zeros of the factors are skipped (a robot's task matrix is mostly zeros).
    ``ctx``: the mpmath context of the arithmetic (default: that of ``a``'s first mpf entry)."""
    n = a.shape[0]
    if not n:
        return np.array(a, dtype=object), []
    if ctx is None:
        first = next((x for x in a.flat if hasattr(x, "context")), None)
        if first is None:
            raise TypeError("mp_lu needs mpmath numbers (or ctx): no entry of the matrix is one")
        ctx = first.context
    prec, rounding = ctx._prec_rounding
    rows = [raw_numbers(ctx, row) for row in a.tolist()]
    perm = list(range(n))
    lower: list[dict[int, Raw]] = [{} for _ in range(n)]     # row i of L: column -> entry (non-zero)
    upper: list[dict[int, Raw]] = [{} for _ in range(n)]     # column j of U: row -> entry (non-zero)

    def reduced(first: Raw, left: dict[int, Raw], right: dict[int, Raw], p: int) -> Raw:
        """``first`` minus the products over the keys of both (:func:`exact_sum`, ``p`` bits)."""
        return exact_sum(first, ((mpf_neg(x), right[k]) for k, x in left.items() if k in right), p, rounding)

    for k in range(n):
        column = [reduced(rows[i][k], lower[i], upper[k], 0) for i in range(k, n)]   # exact
        p = 0                                          # the first of the largest magnitudes
        for r in range(1, n - k):
            if column[r] != fzero and mpf_cmp(mpf_abs(column[r]), mpf_abs(column[p])) > 0:
                p = r
        pivot = mpf_pos(column[p], prec, rounding)
        if pivot == fzero:
            return None, None
        if p:
            i = k + p
            rows[k], rows[i] = rows[i], rows[k]
            lower[k], lower[i] = lower[i], lower[k]
            perm[k], perm[i] = perm[i], perm[k]
            column[0], column[p] = column[p], column[0]
        upper[k][k] = pivot
        for r in range(1, n - k):
            if column[r] != fzero:
                lower[k + r][k] = mpf_div(column[r], pivot, prec, rounding)
        for j in range(k + 1, n):
            u = reduced(rows[k][j], lower[k], upper[j], prec)
            if u != fzero:
                upper[j][k] = u
    make, zero = ctx.make_mpf, ctx.make_mpf(fzero)
    lu = np.empty((n, n), dtype=object)
    for i in range(n):
        for j in range(n):
            entry = lower[i].get(j) if j < i else upper[j].get(i)
            lu[i, j] = zero if entry is None else make(entry)
    return lu, perm


def lu_solve(lu: np.ndarray, perm: list[int], b: np.ndarray) -> np.ndarray:
    """Solve with the factors of :func:`mp_lu`: forward then back substitution (``b``: n, or n x k).
    Each entry of the solution is its right-hand side minus its products with the entries already
    solved (:func:`~symgen.math.products.exact_sum`), rounded once (then divided by the pivot,
    rounded once): no worse than rounding after every term. The exact zeros of the factors and
    of the partial solution are skipped (a robot's task matrix is mostly zeros; an identity
    right-hand side is mostly zeros)."""
    n = lu.shape[0]
    if not n:
        return np.array(b, dtype=object)
    ctx = lu[0, 0].context
    prec, rounding = ctx._prec_rounding
    rhs = np.asarray(b, dtype=object).reshape(n, -1)[perm]           # one column, or n x k
    y = [raw_numbers(ctx, row) for row in rhs.tolist()]
    factors = [raw_numbers(ctx, row) for row in lu.tolist()]
    width = len(y[0])
    for i in range(n):
        lower = [(k, mpf_neg(factors[i][k])) for k in range(i) if factors[i][k] != fzero]
        y[i] = [_residual(y[i][j], lower, y, j, prec, rounding) for j in range(width)]
    for i in reversed(range(n)):
        upper = [(k, mpf_neg(factors[i][k])) for k in range(i + 1, n) if factors[i][k] != fzero]
        pivot = factors[i][i]
        y[i] = [mpf_div(_residual(y[i][j], upper, y, j, 0, rounding), pivot, prec, rounding) for j in range(width)]
    make = ctx.make_mpf
    return np.array([[make(v) for v in row] for row in y], dtype=object).reshape(np.shape(b))


def _residual(first: Raw, terms: list[tuple[int, Raw]], y: list[list[Raw]], j: int, prec: int,
              rounding: str) -> Raw:
    """``first + sum_k c_k y[k][j]`` over ``terms = [(k, c_k)]`` (:func:`exact_sum`, ``prec`` bits),
    the zero ``y[k][j]`` skipped."""
    return exact_sum(first, ((c, y[k][j]) for k, c in terms if y[k][j] != fzero), prec, rounding)


def one_norm_condition(a: np.ndarray, lu: np.ndarray, perm: list[int]) -> float:
    """``|a|_1 |a^-1|_1`` with the inverse from the LU factors (``O(n^3)``, like the factoring)."""
    n = a.shape[0]
    eye = obj_full((n, n), 0)
    for i in range(n):
        eye[i, i] = 1
    inv = lu_solve(lu, perm, eye)

    def norm(m: np.ndarray) -> Scalar:
        return max(sum(abs(v) for v in m[:, j]) for j in range(n))

    return float(norm(np.asarray(a, dtype=object)) * norm(inv))


def gauss_solve(a: np.ndarray, b: np.ndarray, what: str = "matrix") -> np.ndarray:
    """Solve ``a x = b`` exactly (Gauss-Jordan elimination on object arrays of Fractions)."""
    n = a.shape[0]
    if n == 0:
        return np.empty((0,) + b.shape[1:], dtype=object)
    vector = b.ndim == 1
    rhs = b.reshape(n, -1)
    aug = np.concatenate([a.astype(object), rhs.astype(object)], axis=1)
    for col in range(n):
        pivot = next((r for r in range(col, n) if aug[r, col] != 0), None)
        if pivot is None:
            raise SingularConfigurationError(what, float("inf"))
        if pivot != col:
            aug[[col, pivot]] = aug[[pivot, col]]
        aug[col] = aug[col] / aug[col, col]
        for r in range(n):
            if r != col and aug[r, col] != 0:
                aug[r] = aug[r] - aug[r, col] * aug[col]
    x = aug[:, n:]
    return x.reshape(n) if vector else x.reshape((n,) + b.shape[1:])
