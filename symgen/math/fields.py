"""Arithmetic fields: the same derivation code runs in floats, exact rationals or SymPy symbols.

Every quantity of the twelve steps is computed by one code path on NumPy arrays. The *field*
decides what the entries are:

* :class:`FloatField` -- ``float64`` arrays; fast; used for simulation references and tests.
* :class:`ExactField` -- object arrays of :class:`fractions.Fraction`; exact; used by the proofs
  at sampled points (DESIGN.md section 5). Scene constants that are not rational (``cos(0.3)``)
  are rounded to the nearest float's exact value and the field records ``rounded = True``; the
  identities proved (skew-symmetry, power balance, map consistency) do not depend on them.
* :class:`SymbolicField` -- object arrays of SymPy expressions; for inspecting small scenes.
* :class:`MpField` -- object arrays of ``mpmath.mpf`` at ``dps`` decimal digits (default 50), in
  a private mpmath context; the extended-precision reference of the accuracy and stability
  reports. Irrational scene constants are evaluated by SymPy to the field's precision.

A field converts scene constants (:meth:`const`), positions (:meth:`configuration`), solves
linear systems (:meth:`solve`) and answers the few non-rational operations of the derivation
(:meth:`~Field.sign`, :meth:`~Field.sqrt`, :meth:`~Field.norm`, :meth:`~Field.cos_sin`), so no
caller ever asks which field it has. Callers never write into a field; the one exception is the
documented ``rounded`` flag, which the field itself sets.
"""
from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Mapping, Sequence
from fractions import Fraction
from typing import TYPE_CHECKING, Any, Protocol, TypeAlias

import mpmath
import numpy as np
import sympy as sp

from .elimination import gauss_solve, lu_solve, mp_lu, obj_full, one_norm_condition
from .products import PRODUCTS, sparse_product
from .scalar import Constant, Scalar
from ..errors import SingularConfigurationError, SymbolicTooLargeError

if TYPE_CHECKING:
    from .configuration import Configuration

__all__ = ["Field", "FloatField", "ExactField", "SymbolicField", "MpField", "FIELDS", "make_field",
           "gauss_solve", "lu_solve", "mp_lu", "Scalar", "JointTree"]

#: values substituted for scene parameters (SymPy symbols)
Params: TypeAlias = Mapping[sp.Symbol, Constant]


class _PositionKind(Protocol):
    def field_position(self, value: Any, field: Any) -> Any: ...


class _NamedJoint(Protocol):
    @property
    def name(self) -> str: ...

    @property
    def kind(self) -> _PositionKind: ...


class JointTree(Protocol):
    """What :meth:`Field.configuration` reads of a spanning tree (:class:`symgen.tree.Tree` is one,
    a layer up): its joints, each with a name and a kind that converts a position into a field."""

    @property
    def joints(self) -> Sequence[_NamedJoint]: ...


class Field(ABC):
    """Everything the derivation asks of an arithmetic field.

    Attributes: ``name`` (for :func:`make_field` and messages only -- callers never branch on
    it), ``dtype`` (of the NumPy arrays), ``zero`` and ``one`` (the field's 0 and 1), ``params``
    (values substituted for scene parameters), ``rounds`` (whether its arithmetic rounds: then a
    product known to be symmetric may be computed on one triangle and mirrored; an exact or
    symbolic field computes both, so the proofs check the symmetry) and ``rounded`` (set by the
    field when it had to round a value: an irrational constant or square root in the exact field).
    """

    name: str = "abstract"
    dtype: type = object
    rounds: bool = True
    zero: Scalar
    one: Scalar

    def __init__(self, params: Params | None = None) -> None:
        self.params: dict[sp.Symbol, Constant] = dict(params or {})
        self.rounded = False

    @abstractmethod
    def const(self, value: Constant) -> Scalar:
        """A scene constant (SymPy or Python number) as an element of this field."""

    def array(self, values: Sequence[Any]) -> np.ndarray:
        """An array of this field from nested lists of scene constants (SymPy or Python numbers)."""
        arr = np.asarray(values, dtype=object)
        out: np.ndarray = np.empty(arr.shape, dtype=self.dtype)
        for idx, v in np.ndenumerate(arr):
            out[idx] = self.const(v)
        return out

    def zeros(self, shape: int | tuple[int, ...]) -> np.ndarray:
        return np.zeros(shape, dtype=float) if self.dtype is float else obj_full(shape, self.zero)

    def eye(self, n: int) -> np.ndarray:
        out = self.zeros((n, n))
        for i in range(n):
            out[i, i] = self.one
        return out

    @abstractmethod
    def solve(self, a: np.ndarray, b: np.ndarray, what: str = "matrix") -> np.ndarray:
        """``a^-1 b`` for a square ``a`` (n x n) and ``b`` (n or n x k); ``what`` names ``a`` in
        the :class:`SingularConfigurationError` raised when it is singular."""

    def is_zero(self, x: Scalar) -> bool:
        """Whether the scalar ``x`` is zero: the recursions of :mod:`symgen.dynamics` skip a term
        or take a structural shortcut where a scene constant is zero (the code generator's
        field answers for structural zeros only, the constant-zero node)."""
        return bool(x == 0)

    def sign(self, x: Scalar) -> Scalar:
        """``sign(x)`` (-1, 0 or 1) as a field element: the Coulomb term of eq. (22)."""
        return self.const(int(x > 0) - int(x < 0))

    @abstractmethod
    def sqrt(self, x: Scalar) -> Scalar:
        """Square root of a non-negative field element."""

    def norm(self, vector: Sequence[Scalar]) -> Scalar:
        """Euclidean norm ``sqrt(sum v^2)`` of a sequence of field elements (eq. 23)."""
        return self.sqrt(sum(v * v for v in vector))

    def cos_sin(self, angle: Scalar) -> tuple[Scalar, Scalar]:
        """``(cos, sin)`` of a revolute joint angle. Fields that cannot represent them refuse:
        their configurations give revolute positions as :class:`~symgen.math.configuration.CosSin` pairs."""
        raise TypeError("exact and symbolic fields need revolute positions as CosSin(c, s)")

    def configuration(self, config: Configuration, tree: JointTree | None = None) -> Configuration:
        """``config`` with its positions in the form this field's kinematics reads (unchanged
        by default; :class:`MpField` turns float angles into ``CosSin`` pairs at its precision)."""
        return config


class FloatField(Field):
    name = "float"
    dtype = float
    zero = 0.0
    one = 1.0
    #: a matrix with a larger condition number is reported singular (default; see ``__init__``)
    max_condition = 1e12

    def __init__(self, params: Params | None = None, max_condition: float | None = None) -> None:
        """``max_condition``: this field's singularity threshold (``inf``: never refuse a solve
        that NumPy can do), instead of the class default."""
        super().__init__(params)
        if max_condition is not None:
            self.max_condition = max_condition

    def const(self, value: Constant) -> float:
        if isinstance(value, sp.Basic):
            value = value.xreplace(self.params) if self.params else value
            try:
                return float(value)
            except TypeError as exc:
                raise TypeError(f"no value for parameter(s) {sorted(map(str, value.free_symbols))}") from exc
        return float(value)

    def sqrt(self, x: Scalar) -> float:
        return float(np.sqrt(x))

    def norm(self, vector: Sequence[Scalar]) -> float:
        return float(np.linalg.norm(vector))

    def cos_sin(self, angle: Scalar) -> tuple[Scalar, Scalar]:
        return np.cos(float(angle)), np.sin(float(angle))

    def solve(self, a: np.ndarray, b: np.ndarray, what: str = "matrix") -> np.ndarray:
        if a.shape[0] == 0:
            return np.zeros((0,) + b.shape[1:])
        cond = np.linalg.cond(a)
        if not np.isfinite(cond) or cond > self.max_condition:
            raise SingularConfigurationError(what, float(cond))
        return np.linalg.solve(a, b)


class ExactField(Field):
    """Exact rational arithmetic with ``Fraction`` entries."""

    name = "exact"
    rounds = False
    dtype = object
    zero = Fraction(0)
    one = Fraction(1)

    def const(self, value: Constant) -> Fraction:
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

    def sqrt(self, x: Scalar) -> Fraction:
        """The square root rounded through a float (the result is not exact: sets ``rounded``)."""
        self.rounded = True
        return Fraction(float(np.sqrt(float(x))))

    def solve(self, a: np.ndarray, b: np.ndarray, what: str = "matrix") -> np.ndarray:
        return gauss_solve(a, b, what)


class SymbolicField(Field):
    """SymPy expressions; solves are refused above :attr:`max_solve` unknowns."""

    name = "symbolic"
    rounds = False
    dtype = object
    zero = sp.Integer(0)
    one = sp.Integer(1)
    max_solve = 6

    def const(self, value: Constant) -> sp.Basic:
        return sp.sympify(value) if not isinstance(value, sp.Basic) else value

    def sign(self, x: Scalar) -> sp.Basic:
        return sp.sign(x)

    def sqrt(self, x: Scalar) -> sp.Basic:
        return sp.sqrt(x)

    def solve(self, a: np.ndarray, b: np.ndarray, what: str = "matrix") -> np.ndarray:
        n = a.shape[0]
        if n == 0:
            return obj_full((0,) + b.shape[1:], self.zero)
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


class MpField(Field):
    """``mpmath.mpf`` entries at ``dps`` decimal digits: the extended-precision reference.

    The field owns a private :class:`mpmath.MPContext`, so its precision does not depend on (or
    change) the global ``mpmath.mp.dps``: every operation between two of its numbers rounds to
    ``dps`` digits, and a Python float meeting one of them is taken at its exact binary value.
    Scene constants are converted exactly when rational and through SymPy's ``evalf`` at
    ``dps + 10`` digits otherwise (never through a float), so ``rounded`` stays ``False``.
    Solves use Gaussian elimination with partial pivoting (:func:`mp_lu`), ``O(n^3)``; a matrix
    whose 1-norm condition number exceeds :attr:`max_condition` is reported singular.
    """

    name = "mp"
    dtype = object
    default_dps = 50
    #: fewer digits than this would not be a reference for float64 results
    min_dps = 20

    def __init__(self, params: Params | None = None, dps: int = default_dps) -> None:
        super().__init__(params)
        if not isinstance(dps, int) or dps < self.min_dps:
            raise ValueError(f"MpField needs an integer dps >= {self.min_dps}, got {dps!r}")
        self.dps = dps
        self.ctx = mpmath.MPContext()
        self.ctx.dps = dps
        self.zero = self.ctx.mpf(0)
        self.one = self.ctx.mpf(1)
        PRODUCTS.setdefault(type(self.zero), sparse_product)
        self._lu_cache: tuple[np.ndarray, np.ndarray | None, list[int] | None, float] | None = None

    @property
    def max_condition(self) -> float:
        """Solves keep at least 10 correct digits: condition numbers up to ``10^(dps - 10)``."""
        return 10.0 ** (self.dps - 10)

    def const(self, value: Constant) -> mpmath.mpf:
        ctx = self.ctx
        if isinstance(value, ctx.mpf):
            return value
        if isinstance(value, (bool, np.bool_)):
            raise TypeError(f"expected a number, got {value!r}")
        if isinstance(value, (int, float, np.integer, np.floating)):
            return ctx.mpf(int(value) if isinstance(value, np.integer) else float(value)
                           if isinstance(value, np.floating) else value)
        if isinstance(value, Fraction):
            return ctx.mpf(value.numerator) / value.denominator
        if isinstance(value, sp.Basic):
            if self.params:
                value = value.xreplace(self.params)
            if value.free_symbols:
                raise TypeError(f"no value for parameter(s) {sorted(map(str, value.free_symbols))}")
            if value.is_Rational:
                return ctx.mpf(int(value.p)) / int(value.q)
            num = sp.N(value, self.dps + 10)
            if not isinstance(num, sp.Float):
                raise TypeError(f"scene constant {value} is not a real number")
            return ctx.mpf(num._mpf_)
        return ctx.mpf(value)      # an mpf of another context, a decimal string

    def sqrt(self, x: Scalar) -> mpmath.mpf:
        return self.ctx.sqrt(self.const(x))

    def cos_sin(self, angle: Scalar) -> tuple[mpmath.mpf, mpmath.mpf]:
        """``(cos, sin)`` of an angle given as a float (its exact binary value) or an mpf."""
        a = self.const(angle)
        return self.ctx.cos(a), self.ctx.sin(a)

    def to_float(self, values: np.ndarray | Sequence[Scalar]) -> np.ndarray:
        """Round an array of this field to ``float64`` (nearest)."""
        arr = np.asarray(values, dtype=object)
        return np.array([float(v) for v in arr.flat], dtype=float).reshape(arr.shape)

    def configuration(self, config: Configuration, tree: JointTree | None = None) -> Configuration:
        """Positions as field numbers: revolute angles as ``CosSin`` (cosine and sine computed at
        ``dps`` digits from the angle's exact value), displacements and rotation matrices
        converted entrywise. ``tree`` tells revolute from prismatic joints."""
        from .configuration import Configuration, CosSin

        kinds = {j.name: j.kind for j in tree.joints} if tree is not None else {}
        out: dict[str, Any] = {}
        for name, value in config.positions.items():
            if name in kinds:
                out[name] = kinds[name].field_position(value, self)
            elif isinstance(value, CosSin):
                out[name] = CosSin(self.const(value.c), self.const(value.s),
                                   None if value.angle is None else self.const(value.angle))
            elif np.ndim(value) == 2:
                out[name] = np.array([[self.const(v) for v in row] for row in np.asarray(value, dtype=object)],
                                     dtype=object)
            else:
                out[name] = self.const(value)
        return Configuration(out)

    def solve(self, a: np.ndarray, b: np.ndarray, what: str = "matrix") -> np.ndarray:
        n = a.shape[0]
        if n == 0:
            return obj_full((0,) + b.shape[1:], self.zero)
        lu, perm, cond = self._factor(a, what)
        vector = b.ndim == 1
        x = lu_solve(lu, perm, np.asarray(b, dtype=object).reshape(n, -1))
        return x.reshape(n) if vector else x.reshape((n,) + b.shape[1:])

    def _factor(self, a: np.ndarray, what: str) -> tuple[np.ndarray, list[int], float]:
        """LU factors of ``a`` with its condition number; the last factorization is reused
        when the same values come again (a jet solves twice with one matrix)."""
        cached = self._lu_cache
        if cached is not None and cached[0].shape == a.shape and all(
                x == y for x, y in zip(cached[0].flat, a.flat)):
            lu, perm, cond = cached[1:]
        else:
            lu, perm = mp_lu(a, self.ctx)
            cond = float("inf") if lu is None or perm is None else one_norm_condition(a, lu, perm)
            self._lu_cache = (np.array(a, dtype=object), lu, perm, cond)
        if lu is None or perm is None or not cond <= self.max_condition:   # no factors: cond is inf
            raise SingularConfigurationError(what, cond)
        return lu, perm, cond


FIELDS: dict[str, type[Field]] = {"float": FloatField, "exact": ExactField, "symbolic": SymbolicField,
                                  "mp": MpField}


def make_field(name: str, params: Params | None = None) -> Field:
    """A field by name: ``float``, ``exact``, ``symbolic``, ``mp`` (50 digits) or ``mp:D``
    (``D`` decimal digits, ``D >= MpField.min_dps``)."""
    if name == "mp" or name.startswith("mp:"):
        digits = name[3:]
        if digits and not digits.isdigit():
            raise ValueError(f"unknown field {name!r}: write mp:D with D the decimal digits, e.g. mp:60")
        return MpField(params, dps=int(digits) if digits else MpField.default_dps)
    try:
        return FIELDS[name](params)
    except KeyError:
        raise ValueError(f"unknown field {name!r}; choose one of {sorted(FIELDS)} (or mp:D)") from None
