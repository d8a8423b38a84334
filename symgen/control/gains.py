"""Feedback gain matrices: ``K_A`` of eq. (34) and the pose-feedback ``Lambda`` must be symmetric
positive definite for the virtual-power argument of Section 4.

:func:`gain_matrix` turns a scalar, a diagonal or a full matrix into an ``n x n`` array;
:func:`check_positive_definite` proves symmetry and definiteness -- by Cholesky in floats, by an
exact ``L D L^T`` factorization (Sylvester: every pivot ``d_i > 0``) for Fractions, mpmath
numbers and SymPy numbers -- and otherwise raises :class:`GainMatrixError` naming the gain and
its smallest eigenvalue.
"""
from __future__ import annotations

import numpy as np

from .errors import ControlInputError, GainMatrixError

#: relative asymmetry ``max|K - K^T| / max|K|`` accepted for a float gain
SYMMETRY_TOLERANCE = 1e-12


def gain_matrix(value, n: int, name: str = "K") -> np.ndarray:
    """``k 1_n`` for a scalar, ``diag(d)`` for a length-``n`` vector, the matrix itself for
    ``n x n``; the entries keep their type (float, Fraction, mpmath number, ...)."""
    arr = np.asarray(value)
    if arr.dtype.kind not in "fiuO":
        raise ControlInputError(f"gain {name!r}: entries must be numbers, got dtype {arr.dtype}")
    if arr.shape == (n, n):
        return np.array(arr, dtype=float if arr.dtype.kind in "fiu" else object)
    if arr.shape not in ((), (n,)):
        raise ControlInputError(f"gain {name!r} has shape {arr.shape}; expected a scalar, ({n},) or ({n}, {n})")
    diagonal = np.broadcast_to(arr, (n,))
    if arr.dtype.kind in "fiu":
        return np.diag(diagonal.astype(float))
    out = np.full((n, n), 0 * diagonal[0] if n else 0, dtype=object)
    for i in range(n):
        out[i, i] = diagonal[i]
    return out


def smallest_eigenvalue(k) -> float:
    """Smallest eigenvalue of the symmetric part of ``k``, in floats (for messages)."""
    try:
        a = np.array(k, dtype=float)
    except (TypeError, ValueError):
        return float("nan")
    if not np.all(np.isfinite(a)):
        return float("nan")
    return float(np.linalg.eigvalsh((a + a.T) / 2).min()) if a.size else float("nan")


def ldlt_pivots(k) -> list:
    """The pivots ``d_i`` of ``K = L D L^T`` without pivoting, exact in the entries' arithmetic.

    For a symmetric ``K`` they are all ``> 0`` exactly when ``K`` is positive definite (the
    leading principal minors are their running products). Stops after the first pivot that is
    not ``> 0`` (it is returned last)."""
    a = np.array(k, dtype=object)
    n = a.shape[0]
    pivots = []
    for i in range(n):
        d = a[i, i]
        pivots.append(d)
        if not d > 0:
            break
        col = a[i + 1:, i] / d
        a[i + 1:, i + 1:] = a[i + 1:, i + 1:] - np.outer(col, a[i, i + 1:])
    return pivots


def check_positive_definite(k, name: str = "K") -> np.ndarray:
    """Return ``k`` (square) if it is symmetric positive definite, else raise
    :class:`GainMatrixError` naming ``name`` and the smallest eigenvalue."""
    k = np.asarray(k)
    if k.ndim != 2 or k.shape[0] != k.shape[1]:
        raise ControlInputError(f"gain {name!r} must be a square matrix, got shape {k.shape}")
    if k.dtype.kind in "fiu":
        return _check_float(np.asarray(k, dtype=float), name)
    return _check_exact(k, name)


def _check_float(k: np.ndarray, name: str) -> np.ndarray:
    if not np.all(np.isfinite(k)):
        raise GainMatrixError(name, float("nan"), "has entries that are not finite")
    scale = float(np.abs(k).max()) if k.size else 0.0
    if float(np.abs(k - k.T).max(initial=0.0)) > SYMMETRY_TOLERANCE * scale:
        raise GainMatrixError(name, smallest_eigenvalue(k), "is not symmetric")
    try:
        np.linalg.cholesky(k)
    except np.linalg.LinAlgError:
        raise GainMatrixError(name, smallest_eigenvalue(k), "is not positive definite") from None
    return k


def _check_exact(k: np.ndarray, name: str) -> np.ndarray:
    n = k.shape[0]
    if any(k[i, j] != k[j, i] for i in range(n) for j in range(i)):
        raise GainMatrixError(name, smallest_eigenvalue(k), "is not symmetric")
    try:
        pivots = ldlt_pivots(k)
        positive = len(pivots) == n and all(bool(d > 0) for d in pivots)
    except TypeError:     # a SymPy relational that cannot be decided
        raise GainMatrixError(name, float("nan"), "has entries whose sign cannot be decided") from None
    if not positive:
        raise GainMatrixError(name, smallest_eigenvalue(k), "is not positive definite")
    return k
