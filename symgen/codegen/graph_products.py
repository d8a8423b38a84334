"""Banded matrix products on the tracing graph: a library loop instead of one dot product per entry.

``X = A B`` for an ``n x m`` matrix ``A`` and an ``m x k`` matrix ``B`` of nodes, of which only the
rows ``lo[c] <= r < hi[c]`` of each column ``c`` are wanted (the other entries are never read).
Straight-line code spends one six- or twelve-term dot product per entry, every term a workspace
load once the function is long; the library loop (``symgen_product`` in the C target,
``np.matmul`` in the NumPy one) runs the same multiply-adds over contiguous rows, vectorised, in a
few hundred bytes of machine code. :mod:`symgen.codegen.dynamics_derivatives` uses it for the
closed-form Jacobians' ancestor-pair entries (:mod:`symgen.dynamics.rnea_derivatives`), the
library's symmetric solve for the columns it multiplies by a large mass matrix's inverse
(:meth:`~symgen.codegen.graph_solves.LinearSolves.solve_spd`).

:class:`Products` is the part of :class:`~symgen.codegen.graph.Graph` that records them; an entry
is a ``library_out`` node (as a solve's), the statement counts ``2 m`` flops per wanted entry.
"""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np


@dataclass
class Product:
    """``X = A B`` on the rows ``lo[c]..hi[c]-1`` of each column ``c`` of the ``n x k`` result
    (library call): ``a`` holds ``A^T`` row-major (``m x n``: term ``t`` of row ``r`` at
    ``t * n + r``), ``b`` holds ``B^T`` row-major (``k x m``: term ``t`` of column ``c`` at ``c * m + t``),
    so that each term's rows and each column's terms are contiguous."""

    id: int
    n: int
    m: int
    k: int
    a: tuple                  # node ids of A^T, m x n
    b: tuple                  # node ids of B^T, k x m
    lo: tuple
    hi: tuple
    what: str

    @property
    def flops(self) -> int:
        """``2 m`` per wanted entry (one multiply and one add per term), as the library LU's flops are
        counted from the textbook: the C loop also computes the rows a group of columns shares beyond
        one column's range and recomputes a column's last rows, which this leaves out."""
        return 2 * self.m * sum(h - lo for lo, h in zip(self.lo, self.hi))


class Products:
    """The product method of :class:`~symgen.codegen.graph.Graph` (which provides ``nodes``,
    ``statements``, ``_node``, ``_make`` and ``_statement_node``)."""

    def product(self, a, b, ranges: Sequence[tuple[int, int]], what: str) -> np.ndarray:
        """``a @ b`` (``n x m`` and ``m x k`` arrays of nodes and numbers) on the rows
        ``ranges[c] = (lo, hi)`` of each column ``c``: an ``n x k`` object array whose wanted
        entries are new nodes and the others ``None``. One library statement; nothing when no
        entry is wanted. Terms that are structural zeros (the constant 0 in every row of ``a`` or
        every column of ``b``) are left out."""
        a = np.asarray(a, dtype=object)
        b = np.asarray(b, dtype=object)
        if a.ndim != 2 or b.ndim != 2:
            raise ValueError(f"product {what}: factors of shapes {a.shape} and {b.shape}")
        n, m = a.shape
        k = b.shape[1]
        if b.shape[0] != m or len(ranges) != k:
            raise ValueError(f"product of {a.shape} and {b.shape} with {len(ranges)} column ranges")
        if any(not 0 <= lo <= hi <= n for lo, hi in ranges):
            raise ValueError(f"product {what}: a row range outside 0..{n}")
        out = np.full((n, k), None, dtype=object)
        if all(lo == hi for lo, hi in ranges):
            return out
        terms = [t for t in range(m) if not (self._zeros(a[:, t]) or self._zeros(b[t, :]))]
        if len(terms) < m:                  # a term that is zero in every row or column adds nothing
            a, b, m = a[:, terms], b[terms, :], len(terms)
        if not terms:
            for c, (lo, hi) in enumerate(ranges):
                out[lo:hi, c] = [self.const(0)] * (hi - lo)
            return out
        a_ids = tuple(self._node(a[r, t]).id for t in range(m) for r in range(n))   # may make constants
        b_ids = tuple(self._node(b[t, c]).id for c in range(k) for t in range(m))
        statement = Product(len(self.nodes), n, m, k, a_ids, b_ids, tuple(lo for lo, _ in ranges),
                            tuple(hi for _, hi in ranges), what)
        self.statements.append(statement)
        self._statement_node("product", statement)
        for c, (lo, hi) in enumerate(ranges):
            for r in range(lo, hi):
                out[r, c] = self._make("library_out", (statement.id, r, c))
        return out

    def _zeros(self, entries) -> bool:
        """Every entry the constant 0."""
        return all(node.is_const and node.value == 0 for node in map(self._node, entries))


def product_values(statement: Product, vals: dict[int, np.ndarray], count: int) -> np.ndarray:
    """The statement's full ``count x n x k`` result at sampled values ``vals`` (node id -> array)."""
    a_t = np.stack([vals[i] for i in statement.a], axis=-1).reshape(count, statement.m, statement.n)
    b_t = np.stack([vals[i] for i in statement.b], axis=-1).reshape(count, statement.k, statement.m)
    return np.swapaxes(a_t, 1, 2) @ np.swapaxes(b_t, 1, 2)
