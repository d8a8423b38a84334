"""The one type name for a number of any field (:mod:`symgen.math.fields`).

A *field element* is a ``float`` (:class:`~symgen.math.fields.FloatField`), a
:class:`fractions.Fraction` (exact), a SymPy expression (symbolic), an ``mpmath.mpf`` of the
field's own context (mp) or a traced node of the code generator. They share no base class and
SymPy and mpmath ship no type information, so the type checker is told ``Any``; naming it
:data:`Scalar` says *which* values are field-generic, and everything else is typed precisely.
"""
from __future__ import annotations

from collections.abc import Sequence
from typing import Any, TypeAlias

import numpy as np

#: an element of a field: float, Fraction, SymPy expression, mpmath number or traced node
Scalar: TypeAlias = Any
#: a scene constant a field converts (:meth:`~symgen.math.fields.Field.const`): a SymPy number or
#: expression (parameters are substituted), a Python or NumPy number, a ``Fraction``, or already
#: an element of the field
Constant: TypeAlias = Any
#: a vector of field elements as callers hold it: a NumPy array or a sequence (read with ``np.asarray``)
FieldVector: TypeAlias = "np.ndarray | Sequence[Scalar]"

__all__ = ["Constant", "FieldVector", "Scalar"]
