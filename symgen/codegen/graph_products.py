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

A :class:`ScanProduct` is the same kind of statement for ``D^T W`` where ``D`` is given by two
low-rank triangles (the closed-form partials of a serial chain): its loop keeps running sums over
the terms instead of forming ``D``, so the Jacobians of forward dynamics multiply the mass matrix's
inverse by ``d tau/dq`` without the ``n x n`` product
(:func:`~symgen.codegen.dynamics_derivatives.scanned_inverse_products`).

:class:`Products` is the part of :class:`~symgen.codegen.graph.Graph` that records them; an entry
is a ``library_out`` node (as a solve's), a statement counts its loop's multiply-adds, two flops
each (``2 m`` per wanted entry of a banded product).
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

    @property
    def operands(self) -> tuple:
        """Every node id the statement reads: ``A^T`` then ``B^T``."""
        return self.a + self.b

    def values(self, vals: dict[int, np.ndarray], count: int) -> np.ndarray:
        """The full ``count x n x k`` result at sampled values ``vals`` (node id -> array)."""
        a_t = np.stack([vals[i] for i in self.a], axis=-1).reshape(count, self.m, self.n)
        b_t = np.stack([vals[i] for i in self.b], axis=-1).reshape(count, self.k, self.m)
        return np.swapaxes(a_t, 1, 2) @ np.swapaxes(b_t, 1, 2)


#: the most terms a side of a scan product (``SYMGEN_SCAN_TERMS`` of the C library loop, which holds
#: one running sum per term in registers): the closed form's triangles have nine and six
SCAN_TERMS = 12


@dataclass
class ScanProduct:
    """``X = (W^T D)^T``-shaped product with a matrix ``D`` given by two low-rank triangles (library
    call): with ``W`` an ``n x k`` matrix and, for ``i, j < n``,

        D[j, i] = rl_j . cl_i  (j >= i),        D[j, i] = ru_j . cu_i  (j < i),

    the result is ``X[i, c] = sum_j D[j, i] W[j, c]`` (``n x k``, column ``c`` at ``c * n`` as a
    :class:`Product`'s). The library loop runs the sums over ``j`` as running sums -- a suffix
    ``sum_{j >= i} W[j, c] rl_j`` and a prefix ``sum_{j < i} W[j, c] ru_j`` per row ``c`` -- so ``D``
    is never formed: ``O(n k (p_l + p_u))`` multiply-adds where forming ``D`` and multiplying costs
    ``O(n^2 k)``. The closed-form partials of a serial chain have this form (``d tau_j / dq_i``, torque
    ``j``, coordinate moved ``i``: :mod:`symgen.dynamics.rnea_derivatives`), and ``W`` the mass
    matrix's inverse gives the forward-dynamics Jacobians ``M^-1 d tau / dq`` without the ``n x n``
    product (:func:`symgen.codegen.dynamics_derivatives.scanned_inverse_products`).

    ``w`` holds ``W`` row-major (``n x k``: row ``j``'s ``k`` entries contiguous), ``rl``/``cl``
    the ``n x p_l`` factors and ``ru``/``cu`` the ``n x p_u`` ones, row-major."""

    id: int
    n: int
    k: int
    pl: int
    pu: int
    w: tuple                  # node ids, n x k
    rl: tuple                 # n x pl
    cl: tuple                 # n x pl
    ru: tuple                 # n x pu
    cu: tuple                 # n x pu
    what: str

    @property
    def m(self) -> int:
        """The number of terms ``j`` (the rows of ``W``)."""
        return self.n

    @property
    def lo(self) -> tuple:
        return (0,) * self.k

    @property
    def hi(self) -> tuple:
        return (self.n,) * self.k

    @property
    def flops(self) -> int:
        """The library loop's multiply-adds, two flops each: per row ``c`` of the result, the prefix's
        total ``sum_j W[j, c] ru_j`` (``n p_u``), then per ``i`` the two running sums' updates
        (``p_l + p_u``) and the entry's dot products (``p_l + p_u``)."""
        return 2 * self.n * self.k * (2 * self.pl + 3 * self.pu)

    @property
    def operands(self) -> tuple:
        """Every node id the statement reads: ``W``, then ``rl, cl, ru, cu``."""
        return self.w + self.rl + self.cl + self.ru + self.cu

    def values(self, vals: dict[int, np.ndarray], count: int) -> np.ndarray:
        """The full ``count x n x k`` result at sampled values ``vals`` (node id -> array), by
        forming ``D``."""
        def block(ids, cols):
            if not ids:
                return np.zeros((count, self.n, cols))
            return np.stack([vals[i] for i in ids], axis=-1).reshape(count, self.n, cols)

        w = block(self.w, self.k)
        lower = block(self.rl, self.pl) @ np.swapaxes(block(self.cl, self.pl), 1, 2)     # [j, i]
        upper = block(self.ru, self.pu) @ np.swapaxes(block(self.cu, self.pu), 1, 2)
        j, i = np.indices((self.n, self.n))
        d = np.where(j >= i, lower, upper)
        return np.swapaxes(d, 1, 2) @ w


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

    def scan_product(self, w, rl, cl, ru, cu, what: str) -> np.ndarray:
        """``X[i, c] = sum_{j >= i} (rl_j . cl_i) W[j, c] + sum_{j < i} (ru_j . cu_i) W[j, c]``
        (:class:`ScanProduct`) for an ``n x k`` array ``w`` and ``n x p`` arrays of factors: an
        ``n x k`` object array of new nodes. One library statement; terms that are structural zeros
        in every row of a factor pair are left out, and with no term left on either side the result
        is the constant 0 and no statement is made."""
        w, rl, cl, ru, cu = (np.asarray(x, dtype=object) for x in (w, rl, cl, ru, cu))
        n, k = w.shape
        if any(x.ndim != 2 or x.shape[0] != n for x in (rl, cl, ru, cu)) or rl.shape != cl.shape or ru.shape != cu.shape:
            raise ValueError(f"scan product {what}: factors of shapes {[x.shape for x in (w, rl, cl, ru, cu)]}")
        lower = [t for t in range(rl.shape[1]) if not (self._zeros(rl[:, t]) or self._zeros(cl[:, t]))]
        upper = [t for t in range(ru.shape[1]) if not (self._zeros(ru[:, t]) or self._zeros(cu[:, t]))]
        if max(len(lower), len(upper)) > SCAN_TERMS:
            raise ValueError(f"scan product {what}: {len(lower)} and {len(upper)} terms, at most {SCAN_TERMS} a side")
        rl, cl, ru, cu = rl[:, lower], cl[:, lower], ru[:, upper], cu[:, upper]
        if not lower and not upper:
            return np.full((n, k), self.const(0), dtype=object)
        ids = [tuple(self._node(x).id for x in m.flat) for m in (w, rl, cl, ru, cu)]     # may make constants
        statement = ScanProduct(len(self.nodes), n, k, len(lower), len(upper), *ids, what)
        self.statements.append(statement)
        self._statement_node("product", statement)
        out = np.empty((n, k), dtype=object)
        for c in range(k):
            for r in range(n):
                out[r, c] = self._make("library_out", (statement.id, r, c))
        return out

    def _zeros(self, entries) -> bool:
        """Every entry the constant 0."""
        return all(node.is_const and node.value == 0 for node in map(self._node, entries))
