"""Matrix products of traced :class:`~symgen.codegen.graph.Node` arrays that skip structural zeros.

The kinematics (body Jacobians ``6 x N_all``, eq. 6), the task map ``J_m = J_m_all P`` (eq. 17)
and the projection ``P^T tau`` (eq. 10) multiply matrices whose entries are mostly the constant
0: a Jacobian's columns beyond its body's depth, the unit rows of the motion joints, an identity
``P``. NumPy's object ``@`` calls ``*`` and ``+`` on every pair (``O(n m k)`` Python calls);
:func:`node_matmul` visits only the pairs whose two factors are not the graph's constant 0, in
the same order as NumPy (``sum = p_0; sum = sum + p_1; ...``), so the recorded graph is the one
``@`` records (``x + 0`` and ``x * 0`` fold away there too) and the generated code is unchanged.

It is registered with :data:`symgen.math.products.PRODUCTS` by :mod:`symgen.codegen.trace_field`.
"""
from __future__ import annotations

import numpy as np

from .graph import Node


def _rows(a: np.ndarray):
    """Per row of the 2-D array ``a``: ``[(column, node), ...]`` of the entries that are not the
    constant 0, or ``None`` when an entry is not a :class:`Node`."""
    rows = []
    for row in a.tolist():
        entries = []
        for j, x in enumerate(row):
            if x.__class__ is not Node:
                return None
            if x is not x.graph._zero:
                entries.append((j, x))
        rows.append(entries)
    return rows


def node_matmul(a: np.ndarray, b: np.ndarray):
    """``a @ b`` for object arrays of nodes (1-D or 2-D), or ``None`` when it does not apply
    (other entries, other dimensions, an empty inner axis): the caller then uses ``@``."""
    if a.dtype != object or b.dtype != object or not 1 <= a.ndim <= 2 or not 1 <= b.ndim <= 2:
        return None
    a2 = a.reshape(1, -1) if a.ndim == 1 else a
    b2 = b.reshape(-1, 1) if b.ndim == 1 else b
    n, k = a2.shape
    k2, m = b2.shape
    if k != k2 or k == 0 or n == 0 or m == 0:
        return None
    rows_a, rows_b = _rows(a2), _rows(b2)
    if rows_a is None or rows_b is None:
        return None
    cols_b = [[] for _ in range(m)]
    for j, entries in enumerate(rows_b):
        for c, y in entries:
            cols_b[c].append((j, y))
    maps_a = [dict(entries) for entries in rows_a]
    maps_b = [dict(entries) for entries in cols_b]
    zero = a2[0, 0].graph._zero
    out = np.empty((n, m), dtype=object)
    for i, row in enumerate(rows_a):           # NumPy's order: entry by entry, j increasing inside
        for c, col in enumerate(cols_b):
            s = None
            if len(row) <= len(col):
                other = maps_b[c]
                pairs = ((x, other.get(j)) for j, x in row)
            else:
                other = maps_a[i]
                pairs = ((other.get(j), y) for j, y in col)
            for x, y in pairs:
                if x is None or y is None:
                    continue
                term = x * y
                s = term if s is None else s + term
            out[i, c] = zero if s is None else s     # an empty sum: there was a zero factor
    if a.ndim == 1 and b.ndim == 1:
        return out[0, 0]
    if a.ndim == 1:
        return out[0]
    if b.ndim == 1:
        return out[:, 0]
    return out
