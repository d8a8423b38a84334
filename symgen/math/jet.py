"""First-order jets: a value and its time derivative, carried through matrix algebra.

The Coriolis matrix of model (32) needs ``d/dt(T_S [J_m; J_f]^-1)``. Rather than deriving that
derivative by hand for every map, each quantity is computed once as a :class:`Jet` ``(v, d)``
with ``d = dv/dt`` along the current motion; products, sums and solves apply the usual rules
(``d(AB) = dA B + A dB``, ``d(A^-1 B) = A^-1 (dB - dA A^-1 B)``). This is exact in every field,
including exact rationals, so the proofs of DESIGN.md section 5 need no finite differences.
"""
from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, TypeAlias

import numpy as np

from .products import PRODUCTS
from .scalar import Scalar

if TYPE_CHECKING:
    from .fields import Field

#: an index of a jet's arrays: an integer, a slice, a list of integers, or a tuple of those
Index: TypeAlias = "int | slice | list[int] | tuple[int | slice | list[int], ...]"
#: the blocks ``(rows, cols, piece)`` that :func:`scatter` places
Pieces: TypeAlias = "Iterable[tuple[Sequence[int], Sequence[int], Jet]]"


def matmul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``a @ b``, through :data:`PRODUCTS` for object arrays of a registered element type."""
    if PRODUCTS and isinstance(a, np.ndarray) and a.dtype == object and a.size:
        product = PRODUCTS.get(type(a.flat[0]))
        if product is not None:
            out = product(a, np.asarray(b))
            if out is not None:
                return out
    result: np.ndarray = a @ b
    return result


class Jet:
    """A matrix (or vector) ``v`` with time derivative ``d`` of the same shape.

    ``v`` and ``d`` are NumPy arrays of one field. The algebra only uses ``@ + - .T``, indexing and
    ``shape``, so :func:`symgen.proofs.prove_skew_by_structure` also runs it on SymPy matrix
    symbols -- outside these types, on purpose."""

    __slots__ = ("v", "d")
    v: np.ndarray
    d: np.ndarray

    def __init__(self, v: np.ndarray, d: np.ndarray) -> None:
        self.v = v
        self.d = d

    @classmethod
    def const(cls, v: np.ndarray, field: Field) -> "Jet":
        return cls(v, field.zeros(np.shape(v)))

    @property
    def shape(self) -> tuple[int, ...]:
        return self.v.shape

    @property
    def T(self) -> "Jet":
        return Jet(self.v.T, self.d.T)

    def __getitem__(self, idx: Index) -> "Jet":
        return Jet(self.v[idx], self.d[idx])

    def __add__(self, other: "Jet | np.ndarray") -> "Jet":
        if isinstance(other, Jet):
            return Jet(self.v + other.v, self.d + other.d)
        return Jet(self.v + other, self.d)

    __radd__ = __add__

    def __sub__(self, other: "Jet | np.ndarray") -> "Jet":
        if isinstance(other, Jet):
            return Jet(self.v - other.v, self.d - other.d)
        return Jet(self.v - other, self.d)

    def __neg__(self) -> "Jet":
        return Jet(-self.v, -self.d)

    def __matmul__(self, other: "Jet | np.ndarray") -> "Jet":
        if isinstance(other, Jet):
            return Jet(matmul(self.v, other.v), matmul(self.d, other.v) + matmul(self.v, other.d))
        return Jet(matmul(self.v, other), matmul(self.d, other))

    def __rmatmul__(self, other: np.ndarray) -> "Jet":
        return Jet(matmul(other, self.v), matmul(other, self.d))

    def scale(self, factor: Scalar) -> "Jet":
        """Multiply by a constant scalar."""
        return Jet(self.v * factor, self.d * factor)


def solve(field: Field, a: Jet, b: Jet, what: str = "matrix") -> Jet:
    """``x = a^-1 b`` with ``dx = a^-1 (db - da x)``; nothing to solve for an empty ``a``."""
    if a.shape[0] == 0:
        return Jet.const(field.zeros(b.shape), field)
    x = field.solve(a.v, b.v, what)
    dx = field.solve(a.v, b.d - matmul(a.d, x), what)
    return Jet(x, dx)


def block(rows: Sequence[Sequence[Jet]]) -> Jet:
    """Assemble a block matrix of jets (like ``numpy.block``)."""
    return Jet(np.block([[j.v for j in row] for row in rows]),
               np.block([[j.d for j in row] for row in rows]))


def vstack(parts: Sequence[Jet], ncols: int, field: Field) -> Jet:
    """Stack jets vertically; an empty list gives a ``0 x ncols`` jet."""
    if not parts:
        z = field.zeros((0, ncols))
        return Jet(z, z.copy())
    return Jet(np.vstack([p.v for p in parts]), np.vstack([p.d for p in parts]))


def hstack(parts: Sequence[Jet], nrows: int, field: Field) -> Jet:
    if not parts:
        z = field.zeros((nrows, 0))
        return Jet(z, z.copy())
    return Jet(np.hstack([p.v for p in parts]), np.hstack([p.d for p in parts]))


def scatter(field: Field, shape: tuple[int, int], pieces: Pieces) -> Jet:
    """A ``shape`` jet that is zero except for each ``(rows, cols, piece)`` of ``pieces``, whose
    jet ``piece`` is placed at ``rows x cols`` (lists of indices; like ``out[ix_(rows, cols)] =``)."""
    v, d = field.zeros(shape), field.zeros(shape)
    for rows, cols, piece in pieces:
        if len(rows) and len(cols):
            v[np.ix_(list(rows), list(cols))] = piece.v
            d[np.ix_(list(rows), list(cols))] = piece.d
    return Jet(v, d)


def identity(field: Field, n: int) -> Jet:
    """The constant ``n x n`` identity."""
    return Jet.const(field.eye(n), field)
