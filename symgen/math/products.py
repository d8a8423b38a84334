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
    """``a @ b`` for object arrays, skipping the zero entries of ``a`` (a body Jacobian's columns
    beyond its body's path, ``P``'s unit rows): each product of 50-digit numbers costs about a
    microsecond, the test for zero a fraction of that. The terms are summed in the same order as
    NumPy's product, so the result is the same number. ``None`` (NumPy's own product) for shapes
    other than matrix times matrix or vector."""
    if a.ndim != 2 or b.ndim not in (1, 2) or a.shape[1] != b.shape[0] or not a.size:
        return None
    cols = b if b.ndim == 2 else b[:, None]
    zero = a.flat[0] * 0
    out = np.empty((a.shape[0], cols.shape[1]), dtype=object)
    columns = [list(cols[:, j]) for j in range(cols.shape[1])]
    for i, row in enumerate(a):
        terms = [(k, v) for k, v in enumerate(row) if v]
        for j, col in enumerate(columns):
            total = zero
            for k, v in terms:
                w = col[k]
                if w:
                    total = total + v * w
            out[i, j] = total
    return out if b.ndim == 2 else out[:, 0]
