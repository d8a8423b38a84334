"""Gaussian elimination on object arrays, for the fields of :mod:`symgen.math.fields` that NumPy's
LAPACK cannot serve: exact Gauss-Jordan on Fractions (:func:`gauss_solve`) and LU with partial
pivoting on mpmath numbers (:func:`mp_lu`, :func:`lu_solve`), both ``O(n^3)``; and the column
choice of a pivoted QR that no float library's rounding can change (:func:`pivot_columns`).
"""
from __future__ import annotations

import numpy as np

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


def mp_lu(a: np.ndarray) -> tuple[np.ndarray, list[int]] | tuple[None, None]:
    """``P a = L U`` by Gaussian elimination with partial pivoting on an object array (mpf).

    Returns ``(lu, perm)`` with ``L`` (unit lower) and ``U`` packed in ``lu`` and row ``i`` of
    ``P a`` being row ``perm[i]`` of ``a``; ``(None, None)`` when a pivot column is exactly zero."""
    lu = np.array(a, dtype=object)
    n = lu.shape[0]
    perm = list(range(n))
    for k in range(n):
        p = max(range(k, n), key=lambda r: abs(lu[r, k]))
        if lu[p, k] == 0:
            return None, None
        if p != k:
            lu[[k, p]] = lu[[p, k]]
            perm[k], perm[p] = perm[p], perm[k]
        lu[k + 1:, k] = lu[k + 1:, k] / lu[k, k]
        rows = [r for r in range(k + 1, n) if lu[r, k] != 0]      # exact zeros change nothing
        if rows:
            lu[rows, k + 1:] = lu[rows, k + 1:] - np.outer(lu[rows, k], lu[k, k + 1:])
    return lu, perm


def lu_solve(lu: np.ndarray, perm: list[int], b: np.ndarray) -> np.ndarray:
    """Solve with the factors of :func:`mp_lu`: forward then back substitution (``b``: n x k).
    The exact zeros of the factors are skipped (a robot's task matrix is mostly zeros); the
    remaining terms are summed in the same order, so the result is the same number."""
    n = lu.shape[0]
    y = np.array(b[perm], dtype=object)
    for i in range(1, n):
        cols = [k for k in range(i) if lu[i, k] != 0]
        if cols:
            y[i] = y[i] - lu[i, cols] @ y[cols]
    for i in reversed(range(n)):
        cols = [k for k in range(i + 1, n) if lu[i, k] != 0]
        if cols:
            y[i] = y[i] - lu[i, cols] @ y[cols]
        y[i] = y[i] / lu[i, i]
    return y


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
