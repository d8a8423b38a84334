"""Exact numbers from scene files, parsed without ``eval``.

Scene values are kept exact (SymPy ``Rational``, multiples of ``pi``) so that derivations and
proofs can run in exact arithmetic. A value may be

* a YAML number (``0.1`` is read as its decimal string, so it becomes exactly 1/10);
* a string: a decimal or fraction (``"1/3"``, ``"-2.5e-3"``), optionally times ``pi``
  (``"pi/2"``, ``"-3*pi/4"``);
* a parameter name (a plain identifier declared in the scene's ``parameters``), which becomes a
  SymPy symbol.

Nothing else is accepted: strings never reach ``sympify``/``eval``.

Numbers *derived* from a scene (a placement found by forward or inverse kinematics at ``q0``) are
computed in 50-digit arithmetic (:func:`mp`, :func:`mp_matrix`, ``DPS`` digits) and handed back
exact: :func:`to_exact` rounds them to the grid ``10**-GRID_DIGITS``, so built-in scenes are exact
rational data, identical on every platform, whose closures hold at ``q0`` to about ``1e-20``.
"""
from __future__ import annotations

import re
from collections.abc import Sequence
from fractions import Fraction

import mpmath
import sympy as sp

_DECIMAL = r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?"
_NUMBER_RE = re.compile(rf"^(?P<num>{_DECIMAL})(?:/(?P<den>\d+))?$")
_PI_RE = re.compile(rf"^(?:(?P<coef>{_DECIMAL})\*)?(?P<sign>-)?pi(?:/(?P<den>\d+))?$")
IDENTIFIER_RE = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
#: working precision of numbers derived from a scene, such as reference kinematics (decimal digits)
DPS = 50
#: derived placements and reference positions are rounded to multiples of 10**-GRID_DIGITS
GRID_DIGITS = 20


def is_identifier(name: object) -> bool:
    """True for a plain ASCII identifier (safe as a symbol and as a name in generated code)."""
    return isinstance(name, str) and bool(IDENTIFIER_RE.fullmatch(name)) and len(name) <= 64


def parse_exact(value: object, symbols: dict[str, sp.Symbol] | None = None) -> sp.Expr:
    """Turn a scene value into an exact SymPy number (or a declared parameter symbol).

    Raises ``ValueError`` with a short reason; callers wrap it in a ``SceneError`` that names
    the element.

    >>> parse_exact(0.1)
    1/10
    >>> parse_exact("-pi/2")
    -pi/2
    """
    if isinstance(value, bool):
        raise ValueError(f"expected a number, got {value!r}")
    if isinstance(value, sp.Expr):
        return value
    if isinstance(value, int):
        return sp.Integer(value)
    if isinstance(value, float):
        if value != value or value in (float("inf"), float("-inf")):
            raise ValueError(f"expected a finite number, got {value!r}")
        return sp.Rational(repr(value))
    if isinstance(value, Fraction):
        return sp.Rational(value.numerator, value.denominator)
    if isinstance(value, str):
        text = value.strip().replace(" ", "")
        match = _NUMBER_RE.fullmatch(text)
        if match:
            num = sp.Rational(match["num"])
            if match["den"] and int(match["den"]) == 0:
                raise ValueError(f"division by zero in {value!r}")
            return num / int(match["den"]) if match["den"] else num
        match = _PI_RE.fullmatch(text)
        if match:
            if match["den"] and int(match["den"]) == 0:
                raise ValueError(f"division by zero in {value!r}")
            coef = sp.Rational(match["coef"]) if match["coef"] else sp.Integer(1)
            if match["sign"]:
                coef = -coef
            den = int(match["den"]) if match["den"] else 1
            return coef * sp.pi / den
        if symbols is not None and text in symbols:
            return symbols[text]
        if is_identifier(text):
            raise ValueError(f"unknown parameter {text!r} (declare it under 'parameters')")
        raise ValueError(f"cannot read {value!r} as a number")
    raise ValueError(f"expected a number, got {type(value).__name__} {value!r}")


# ------------------------------------------------------------ 50-digit derived numbers (mpmath)
def mp(value: sp.Expr | float | Fraction | str) -> mpmath.mpf:
    """An exact scene number as a 50-digit mpmath float."""
    return mpmath.mpf(sp.Float(sp.N(sp.sympify(value), DPS + 10), DPS + 10)._mpf_)


def mp_matrix(m: sp.Matrix | Sequence[Sequence[sp.Expr]]) -> mpmath.matrix:
    """An exact SymPy matrix (or nested list) as an mpmath matrix."""
    m = sp.Matrix(m)
    return mpmath.matrix([[mp(m[i, j]) for j in range(m.cols)] for i in range(m.rows)])


def to_exact(x: mpmath.mpf | float) -> Fraction:
    """Round a 50-digit number to the grid ``10**-GRID_DIGITS`` (an exact ``Fraction``)."""
    scale = 10 ** GRID_DIGITS
    with mpmath.workdps(DPS):
        return Fraction(int(mpmath.nint(x * scale)), scale)
