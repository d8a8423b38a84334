"""Arithmetic fields: the same derivation code runs in floats, exact rationals or SymPy symbols.

Every quantity of the twelve steps is computed by one code path on NumPy arrays. The *field*
decides what the entries are:

* :class:`FloatField` -- ``float64`` arrays; fast; used for simulation references and tests.
* :class:`ExactField` -- object arrays of :class:`fractions.Fraction`; exact; used by the proofs
  at sampled points (DESIGN.md section 5). Scene constants that are not rational (``cos(0.3)``)
  are rounded to the nearest float's exact value and the field records ``rounded = True``; the
  identities proved (skew-symmetry, power balance, map consistency) do not depend on them.
* :class:`SymbolicField` -- object arrays of SymPy expressions; for inspecting small scenes.

A field converts scene constants (:meth:`const`) and solves linear systems (:meth:`solve`).
"""
from __future__ import annotations

from fractions import Fraction

import numpy as np
import sympy as sp

from .errors import SingularConfigurationError, SymbolicTooLargeError


class Field:
    """Interface shared by the three fields."""

    name = "abstract"
    dtype: object = object

    def __init__(self, params: dict[sp.Symbol, object] | None = None):
        self.params = dict(params or {})
        self.rounded = False

    def const(self, value):  # pragma: no cover - interface
        raise NotImplementedError

    def array(self, values) -> np.ndarray:
        """An array of this field from nested lists of scene constants (SymPy or Python numbers)."""
        arr = np.asarray(values, dtype=object)
        out = np.empty(arr.shape, dtype=self.dtype)
        for idx, v in np.ndenumerate(arr):
            out[idx] = self.const(v)
        return out

    def zeros(self, shape) -> np.ndarray:
        return np.zeros(shape, dtype=float) if self.dtype is float else _obj_full(shape, self.zero)

    def eye(self, n: int) -> np.ndarray:
        out = self.zeros((n, n))
        for i in range(n):
            out[i, i] = self.one
        return out

    def solve(self, a: np.ndarray, b: np.ndarray, what: str = "matrix") -> np.ndarray:  # pragma: no cover
        raise NotImplementedError


def _obj_full(shape, value) -> np.ndarray:
    out = np.empty(shape, dtype=object)
    out.fill(value)
    return out


class FloatField(Field):
    name = "float"
    dtype = float
    zero = 0.0
    one = 1.0
    #: a matrix with a larger condition number is reported singular
    max_condition = 1e12

    def const(self, value):
        if isinstance(value, sp.Basic):
            value = value.xreplace(self.params) if self.params else value
            try:
                return float(value)
            except TypeError as exc:
                raise TypeError(f"no value for parameter(s) {sorted(map(str, value.free_symbols))}") from exc
        return float(value)

    def solve(self, a, b, what="matrix"):
        if a.shape[0] == 0:
            return np.zeros((0,) + b.shape[1:])
        cond = np.linalg.cond(a)
        if not np.isfinite(cond) or cond > self.max_condition:
            raise SingularConfigurationError(what, float(cond))
        return np.linalg.solve(a, b)


class ExactField(Field):
    """Exact rational arithmetic with ``Fraction`` entries."""

    name = "exact"
    dtype = object
    zero = Fraction(0)
    one = Fraction(1)

    def const(self, value):
        if isinstance(value, Fraction):
            return value
        if isinstance(value, int):
            return Fraction(value)
        if isinstance(value, float):
            return Fraction(value)
        if isinstance(value, sp.Basic):
            if self.params:
                value = value.xreplace(self.params)
            if value.is_Rational:
                return Fraction(int(value.p), int(value.q))
            if value.free_symbols:
                raise TypeError(f"no value for parameter(s) {sorted(map(str, value.free_symbols))}")
            self.rounded = True
            return Fraction(float(value))
        return Fraction(value)

    def solve(self, a, b, what="matrix"):
        return gauss_solve(a, b, what)


class SymbolicField(Field):
    """SymPy expressions; solves are refused above :attr:`max_solve` unknowns."""

    name = "symbolic"
    dtype = object
    zero = sp.Integer(0)
    one = sp.Integer(1)
    max_solve = 6

    def const(self, value):
        return sp.sympify(value) if not isinstance(value, sp.Basic) else value

    def solve(self, a, b, what="matrix"):
        n = a.shape[0]
        if n == 0:
            return _obj_full((0,) + b.shape[1:], self.zero)
        if n > self.max_solve:
            raise SymbolicTooLargeError(
                f"symbolic inverse of the {n}x{n} {what} refused (limit {self.max_solve}); "
                "evaluate this scene in the 'exact' or 'float' field instead")
        am = sp.Matrix(a)
        det = sp.factor(am.det())
        if det == 0:
            raise SingularConfigurationError(what, float("inf"))
        sol = am.adjugate() * sp.Matrix(b) / det
        return np.array(sol.tolist(), dtype=object).reshape((n,) + b.shape[1:])


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


FIELDS = {"float": FloatField, "exact": ExactField, "symbolic": SymbolicField}


def make_field(name: str, params=None) -> Field:
    try:
        return FIELDS[name](params)
    except KeyError:
        raise ValueError(f"unknown field {name!r}; choose one of {sorted(FIELDS)}") from None
