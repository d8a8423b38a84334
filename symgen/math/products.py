"""Faster ``a @ b`` for object arrays of one element type: the registry :mod:`symgen.math.jet` asks.

:data:`PRODUCTS` maps an element type to ``f(a, b)`` giving ``a @ b`` faster than NumPy's object
loop, or ``None`` when it does not apply. The code generator registers its traced nodes
(:mod:`symgen.codegen.node_product`), whose products are mostly structural zeros; the 50-digit
field registers :func:`sparse_product` for its numbers.
"""
from __future__ import annotations

from collections.abc import Callable
from typing import TypeAlias

import numpy as np

#: ``a @ b`` of two arrays, or ``None`` when the product does not apply to them
Product: TypeAlias = Callable[[np.ndarray, np.ndarray], "np.ndarray | None"]
#: element type -> its product
PRODUCTS: dict[type, Product] = {}


def sparse_product(a: np.ndarray, b: np.ndarray) -> np.ndarray | None:
    """``a @ b`` for object arrays, skipping the zero entries of ``a`` and ``b`` (a body Jacobian's
    columns beyond its body's path, ``P``'s unit rows): each product of 50-digit numbers costs about a
    microsecond, the test for zero a fraction of that. The terms are summed in the same order as
    NumPy's product, so the result is the same number. ``None`` (NumPy's own product) for shapes
    other than matrix times matrix or vector."""
    if a.ndim != 2 or b.ndim not in (1, 2) or a.shape[1] != b.shape[0] or not a.size:
        return None
    cols = b if b.ndim == 2 else b[:, None]
    zero = a.flat[0] * 0
    out = np.empty((a.shape[0], cols.shape[1]), dtype=object)
    # the non-zero entries of every column of b and of every row of a, tested once each; a
    # product walks the shorter of its row's and its column's lists (a body Jacobian times the
    # identity P of a tree: one term), both in increasing k, so the sum keeps NumPy's order
    col_lists = [list(cols[:, j]) for j in range(cols.shape[1])]
    col_terms = [[(k, w) for k, w in enumerate(col) if w] for col in col_lists]
    col_masks = [[False] * cols.shape[0] for _ in col_terms]
    for mask, terms in zip(col_masks, col_terms):
        for k, _ in terms:
            mask[k] = True
    for i, row in enumerate(a):
        row_terms = [(k, v) for k, v in enumerate(row) if v]
        row_mask = [False] * len(row)
        for k, _ in row_terms:
            row_mask[k] = True
        for j, terms in enumerate(col_terms):
            total = zero
            if len(row_terms) <= len(terms):
                col, mask = col_lists[j], col_masks[j]
                for k, v in row_terms:
                    if mask[k]:
                        total = total + v * col[k]
            else:
                for k, w in terms:
                    if row_mask[k]:
                        total = total + row[k] * w
            out[i, j] = total
    return out if b.ndim == 2 else out[:, 0]
