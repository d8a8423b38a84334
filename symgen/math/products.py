"""Faster ``a @ b`` for object arrays of one element type: the registry :mod:`symgen.math.jet` asks.

:data:`PRODUCTS` maps an element type to ``f(a, b)`` giving ``a @ b`` faster than NumPy's object
loop, or ``None`` when it does not apply. The code generator registers its traced nodes
(:mod:`symgen.codegen.node_product`), whose products are mostly structural zeros; the 50-digit
field registers :func:`sparse_product` for its numbers.
"""
from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Any, TypeAlias

import numpy as np
from mpmath.libmp import fzero, mpf_mul, mpf_sum

#: an mpmath number's raw form ``(sign, mantissa, exponent, bit count)``, what its integer
#: arithmetic (``mpmath.libmp``) works on
Raw: TypeAlias = "tuple[int, int, int, int]"

#: ``a @ b`` of two arrays, or ``None`` when the product does not apply to them
Product: TypeAlias = Callable[[np.ndarray, np.ndarray], "np.ndarray | None"]
#: element type -> its product
PRODUCTS: dict[type, Product] = {}


def sparse_product(a: np.ndarray, b: np.ndarray) -> np.ndarray | None:
    """``a @ b`` for object arrays of ``mpmath.mpf`` numbers of one context, skipping the zero
    entries of ``a`` and ``b`` (a body Jacobian's columns beyond its body's path, ``P``'s unit
    rows). Each entry is :func:`exact_sum` of its products, rounded once to the context's
    precision: no worse than NumPy's object product, which rounds after every operation, and
    without an ``mpf`` object per operation (a product of 50-digit numbers costs about a
    microsecond through them). Integer arithmetic only, so the same numbers on every machine.
    Infinities and NaN are kept (mpmath's raw zero alone is skipped).
    ``None`` (NumPy's own product) for shapes other than matrix times matrix or vector, or when
    no entry of ``a`` is an mpmath number."""
    if a.ndim != 2 or b.ndim not in (1, 2) or a.shape[1] != b.shape[0] or not a.size:
        return None
    cols = b if b.ndim == 2 else b[:, None]
    first = next((x for x in a.flat if hasattr(x, "context")), None)
    if first is None:
        return None
    ctx = first.context
    prec, rounding = ctx._prec_rounding
    make = ctx.make_mpf
    # the non-zero entries of every row of a and every column of b as raw mpmath numbers, each
    # entry looked at once; a product walks the shorter of its row's and its column's lists (a
    # body Jacobian times the identity P of a tree: one term)
    rows = [_nonzero(raw_numbers(ctx, r)) for r in a.tolist()]
    columns = [_nonzero(raw_numbers(ctx, c)) for c in cols.T.tolist()]
    out = np.empty((a.shape[0], cols.shape[1]), dtype=object)
    for i, row in enumerate(rows):
        for j, col in enumerate(columns):
            short, long = (row, col) if len(row) <= len(col) else (col, row)
            out[i, j] = make(exact_sum(fzero, ((x, long[k]) for k, x in short.items() if k in long), prec, rounding))
    return out if b.ndim == 2 else out[:, 0]


def exact_sum(first: Raw, products: Iterable[tuple[Raw, Raw]], prec: int, rounding: str) -> Raw:
    """``first + sum a b`` over the pairs ``(a, b)`` of raw mpmath numbers: each product exact, the
    sum without intermediate rounding (mpmath's ``mpf_sum``, as its ``fdot``; a term more than
    twice the precision below the running sum is dropped), rounded once to ``prec`` bits (``0``:
    not rounded)."""
    out: Raw = mpf_sum([first, *(mpf_mul(a, b) for a, b in products)], prec, rounding)
    return out


def raw_numbers(ctx: Any, entries: list[Any]) -> list[Raw]:
    """The raw forms of ``entries``: mpf numbers of the mpmath context ``ctx``, or numbers it converts."""
    try:
        return [x._mpf_ for x in entries]
    except AttributeError:
        return [ctx.convert(x)._mpf_ for x in entries]


def _nonzero(raws: list[Raw]) -> dict[int, Raw]:
    """``{index: raw number}`` of the non-zero entries."""
    return {k: r for k, r in enumerate(raws) if r != fzero}
