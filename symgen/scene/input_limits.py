"""Limits on what a scene file, a URDF or a scene value may hold, checked before any heavy work.

The readers (:mod:`symgen.io.yaml_exact`, :mod:`symgen.io.urdf.parse`) and :class:`symgen.scene.Scene`
apply these bounds to the *text* of the input first, so no parser, exact-arithmetic constructor or
SymPy conversion ever sees a number it would spend minutes on, and a pathological input becomes a
:class:`~symgen.errors.SceneError` naming the element and the line:

* a file of at most :data:`MAX_FILE_CHARS` characters, with no NUL or other control character
  (tab, newline and carriage return excepted) and no lone surrogate;
* YAML nested at most :data:`MAX_DEPTH` levels, and at most :data:`MAX_NODES` values once every
  alias (``*name``) is expanded -- an alias bomb is refused while it is parsed, not walked;
* a number written with at most :data:`MAX_DIGITS` digits in a row (integer, mantissa, numerator or
  denominator) and a decimal exponent of at most :data:`MAX_EXPONENT_DIGITS` digits (checked on
  the text, before any conversion);
* a physical quantity (mass, inertia, length, gravity, friction, parameter value, reference
  position) that is zero or of magnitude between ``10**-MAX_EXPONENT`` and ``10**MAX_EXPONENT``
  (checked by :class:`~symgen.scene.Scene` on the exact value). Directions -- axes and
  quaternions -- have no scale and are exempt.

The magnitude bound keeps every product the derivation forms (a mass times two lengths squared,
an inertia matrix's eigenvalues) far inside double precision, whose range ends near ``1e308``.

>>> number_text_problem("1e99999999")
'the exponent 99999999 has more than 3 digits'
>>> number_text_problem("2.5e-3") is None
True
>>> magnitude_problem(Fraction(10) ** 31)
'magnitude 1e+31 is outside the range 1e-30 .. 1e30 symgen accepts for a nonzero number'

"""
from __future__ import annotations

import math
import re
from fractions import Fraction

#: characters of one scene or URDF file
MAX_FILE_CHARS = 4_000_000
#: nesting levels of a YAML document (mappings and lists)
MAX_DEPTH = 32
#: values of a YAML document with every alias expanded
MAX_NODES = 20_000
#: digits in a row in a number's text: far below Python's own 4300-digit conversion limit, and above
#: the exact rationals symgen itself writes (merged URDF links reach about 160 digits)
MAX_DIGITS = 1000
#: digits of a written decimal exponent (``1e1234`` has 4)
MAX_EXPONENT_DIGITS = 3
#: nonzero numbers lie between 10**-MAX_EXPONENT and 10**MAX_EXPONENT in magnitude
MAX_EXPONENT = 30

_BAD_CHAR = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\x7f\ud800-\udfff]")
_DIGIT_RUN = re.compile(r"[0-9][0-9_]*")
#: text that may be read as a number (YAML int/float forms, fractions, multiples of pi)
_NUMBERISH = re.compile(r"[0-9a-fA-FxXoObBpPiI_.:/*+\- ]*[0-9][0-9a-fA-FxXoObBpPiI_.:/*+\- ]*")
_DECIMAL = re.compile(r"(?P<mant>[+-]?(?:[0-9_]+\.?[0-9_]*|\.[0-9_]+))(?:[eE](?P<exp>[+-]?[0-9_]+))?")


def bad_character(text: str) -> tuple[int, str] | None:
    """``(line, description)`` of the first character no scene or URDF file may hold, else None."""
    match = _BAD_CHAR.search(text)
    if match is None:
        return None
    code = ord(match.group())
    what = "a NUL byte" if code == 0 else (f"a lone surrogate U+{code:04X}" if 0xD800 <= code <= 0xDFFF
                                            else f"the control character U+{code:04X}")
    return text.count("\n", 0, match.start()) + 1, what


def text_problem(text: str) -> tuple[int | None, str] | None:
    """``(line, reason)`` when a whole file's text breaks a limit, else None."""
    if len(text) > MAX_FILE_CHARS:
        return None, f"is {len(text)} characters long; the limit is {MAX_FILE_CHARS}"
    bad = bad_character(text)
    if bad is not None:
        return bad[0], f"contains {bad[1]}; scene and URDF files are plain text"
    return None


def number_text_problem(text: str) -> str | None:
    """Why the text of a (possible) number breaks the limits, or None. Text that cannot be a
    number (a name, a sentence) is never refused here."""
    if not isinstance(text, str) or not _NUMBERISH.fullmatch(text):
        return None
    compact = text.replace(" ", "")
    for run in _DIGIT_RUN.findall(compact):
        digits = len(run.replace("_", ""))
        if digits > MAX_DIGITS:
            return f"a number written with {digits} digits in a row; the limit is {MAX_DIGITS}"
    for part in re.split(r"[/*]", compact):
        match = _DECIMAL.fullmatch(part)
        if match and match["exp"]:
            exp = match["exp"].replace("_", "").lstrip("+-").lstrip("0")
            if len(exp) > MAX_EXPONENT_DIGITS:
                return f"the exponent {exp} has more than {MAX_EXPONENT_DIGITS} digits"
    return None


def magnitude_problem(value) -> str | None:
    """Why an exact number (``int``, ``Fraction``, SymPy number) is out of range, or None.
    Symbols (parameters) and non-numbers are not judged here."""
    try:
        if getattr(value, "free_symbols", None):
            return None
        size = abs(value)
        if size == 0:
            return None
        big = bool(size > 10 ** MAX_EXPONENT)
        small = bool(size * 10 ** MAX_EXPONENT < 1)
    except (TypeError, ValueError, ArithmeticError):
        return None
    if big or small:
        return (f"magnitude {_magnitude_text(size)} is outside the range "
                f"1e-{MAX_EXPONENT} .. 1e{MAX_EXPONENT} symgen accepts for a nonzero number")
    return None


def _magnitude_text(size) -> str:
    """``size`` (> 0) to 3 digits where a float holds it, else its order of magnitude, ``~1e+400``.

    >>> _magnitude_text(Fraction(10) ** 31), _magnitude_text(10 ** 400), _magnitude_text(Fraction(1, 10 ** 400))
    ('1e+31', '~1e+400', '~1e-400')
    """
    try:
        value = float(size)
    except (OverflowError, TypeError, ValueError):
        value = float("inf")
    if value != 0 and value != float("inf"):
        return f"{value:.3g}"
    try:
        if hasattr(size, "p") and hasattr(size, "q"):          # a SymPy Integer or Rational
            size = Fraction(int(size.p), int(size.q))
        if isinstance(size, (int, Fraction)):
            frac = Fraction(size)
            exponent = math.floor(math.log10(frac.numerator) - math.log10(frac.denominator))
        else:                                                  # a SymPy Float, an mpmath number
            import mpmath

            exponent = int(mpmath.floor(mpmath.log10(mpmath.mpf(size))))
    except (TypeError, ValueError, OverflowError, AttributeError):
        return "beyond double precision" if value else "below double precision"
    return f"~1e{exponent:+d}"
