"""Attribute values of an MJCF file: exact numbers within the shared input limits, booleans,
keywords and orientations, each refused with an :class:`MjcfError` naming the element and line.

Numbers. MuJoCo reads plain decimal reals (``0.3``, ``-2.5e-3``, ``5.``); symgen reads the same
text exactly (``"0.3"`` is ``3/10``) and refuses what is not a finite decimal (``pi``, ``1/3``,
``inf``, ``nan``, ``0x10``). The text is judged by :mod:`symgen.scene.input_limits` before it is
converted (so ``1e99999999`` or a 5,000-digit integer is refused at once), and every quantity with
a scale (masses, lengths, angles, damping) must lie within its magnitude bound. Directions (joint
axes, quaternions, ``axisangle`` axes, ``xyaxes``, ``zaxis``) have no scale: the bound applies to
the ratios of their components.

Orientations (MuJoCo's ``quat``, ``euler``, ``axisangle``, ``xyaxes``, ``zaxis``): a ``quat`` is
turned exactly into a rotation (``symgen.math.spatial.exact_quat``, normalised as MuJoCo does). The
others are computed in floating point exactly as MuJoCo does (``angle`` and ``eulerseq`` of
``<compiler>`` honoured, ``xyaxes`` orthogonalised by Gram-Schmidt, ``zaxis`` the smallest
rotation taking z to the vector) and snapped to an exact rotation by
:func:`symgen.math.rotations_snap.snap_rotation`: ``euler="0 0 60"`` is exactly the rotation by pi/3;
an angle that gives no recognised entries becomes an exact rotation within about 1e-12.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np
import sympy as sp

from ...errors import SceneError
from ...scene.input_limits import MAX_EXPONENT
from ...math.rotations_snap import snap_rotation
from ...scene.checks import bounded_number
from ...math.spatial import exact_quat

#: the text of one MJCF number: a plain decimal real, as MuJoCo reads it
DECIMAL = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")
#: orientation attributes; at most one may be given (MuJoCo's rule)
ORIENTATIONS = ("quat", "euler", "axisangle", "xyaxes", "zaxis")
BOOLEANS = {"true": True, "false": False}


class MjcfError(SceneError):
    """An MJCF file is malformed or holds something symgen cannot model; names the element and,
    where known, the file and line."""

    def __init__(self, element: str, message: str, source: str | None = None, line: int | None = None):
        where = ", ".join(p for p in (source, f"line {line}" if line else None) if p)
        super().__init__(element, f"{message} ({where})" if where else message)
        self.source, self.line = source, line


def describe(el) -> str:
    """``<joint name='elbow'>``: how an error names an XML element."""
    name = el.get("name")
    return f"<{el.tag}{f' name={name!r}' if name else ''}>"


@dataclass(frozen=True)
class Attrs:
    """The attributes an element takes effect with: its own, over those of its default class.
    ``values`` maps a name to ``(text, element written on)``, so an error names the element that
    wrote the value (a ``<default>`` entry or the element itself)."""

    el: object
    values: dict

    def get(self, name: str, default: str | None = None) -> str | None:
        """The text of ``name`` (or ``default``)."""
        got = self.values.get(name)
        return default if got is None else got[0]

    def origin(self, name: str):
        """The element that wrote ``name`` (the element itself when nobody did)."""
        got = self.values.get(name)
        return self.el if got is None else got[1]

    def __contains__(self, name: str) -> bool:
        return name in self.values


class Values:
    """Reads attribute values in one file's conventions (``angle``, ``eulerseq``)."""

    def __init__(self, source: str, degrees: bool = True, eulerseq: str = "xyz", origins: dict | None = None):
        """``source`` names the file in errors; ``degrees``/``eulerseq``: ``<compiler angle eulerseq>``;
        ``origins``: the file of each element brought in by ``<include>`` (:mod:`symgen.io.mjcf.include`)."""
        self.source, self.degrees, self.eulerseq = source, degrees, eulerseq
        self.origins = {} if origins is None else origins

    def source_of(self, el) -> str:
        """The file ``el`` was written in."""
        return self.origins.get(el, self.source)

    def fail(self, el, message: str):
        """Raise :class:`MjcfError` naming ``el``, its file and its line."""
        raise MjcfError(describe(el), message, self.source_of(el), el.sourceline)

    # ------------------------------------------------------------------ numbers
    def number(self, el, attr: str, text: str, scale: bool = True) -> sp.Rational:
        """The exact value of one number's ``text`` (``scale``: apply the magnitude bound)."""
        if not DECIMAL.fullmatch(text):
            self.fail(el, f"{attr}={text[:40]!r}: {text[:40]!r} is not a finite decimal number (MJCF numbers "
                          "are plain decimals such as 0.25 or -1.5e-3)")
        try:
            return bounded_number(describe(el), attr, text, magnitude=scale)
        except SceneError as exc:
            self.fail(el, exc.message)

    def numbers(self, attrs: Attrs, attr: str, count: int, default: str | None = None,
                scale: bool = True) -> tuple | None:
        """``count`` exact numbers of ``attr`` (or of ``default``; None if neither is given)."""
        text = attrs.get(attr, default)
        if text is None:
            return None
        el = attrs.origin(attr)
        parts = text.split()
        if len(parts) != count:
            self.fail(el, f"{attr}={text[:60]!r} must have {count} number{'s' if count > 1 else ''}")
        return tuple(self.number(el, attr, p, scale) for p in parts)

    def scalar(self, attrs: Attrs, attr: str, default: str = "0") -> sp.Rational:
        """One exact number (magnitude-bounded), ``default`` when not given."""
        return self.numbers(attrs, attr, 1, default)[0]

    def boolean(self, attrs: Attrs, attr: str, default: bool) -> bool:
        """``true``/``false`` (MuJoCo's spelling), ``default`` when not given."""
        text = attrs.get(attr)
        if text is None:
            return default
        if text not in BOOLEANS:
            self.fail(attrs.origin(attr), f"{attr}={text[:40]!r} must be true or false")
        return BOOLEANS[text]

    def keyword(self, attrs: Attrs, attr: str, allowed: tuple, default: str) -> str:
        """One of ``allowed``, ``default`` when not given."""
        text = attrs.get(attr, default)
        if text not in allowed:
            self.fail(attrs.origin(attr), f"{attr}={text[:40]!r} must be one of {', '.join(allowed)}")
        return text

    def angle(self, value) -> sp.Expr:
        """An exact angle in radians from a number in the file's ``angle`` unit."""
        return sp.pi * value / 180 if self.degrees else value

    def direction(self, attrs: Attrs, attr: str, count: int = 3, default: str | None = None) -> tuple | None:
        """A direction (no scale): exact numbers, not all zero, divided by the largest magnitude."""
        values = self.numbers(attrs, attr, count, default, scale=False)
        return None if values is None else self._unit(attrs.origin(attr), attr, values)

    def _unit(self, el, attr: str, values) -> tuple:
        """``values`` divided by the largest magnitude (exact); zero is refused, and so is a
        nonzero component below ``10**-MAX_EXPONENT`` of the largest (the magnitude bound of
        :mod:`symgen.scene.input_limits`, applied to the ratios)."""
        big = max(abs(v) for v in values)
        if big == 0:
            self.fail(el, f"{attr} must not be zero")
        out = tuple(v / big for v in values)
        if any(v != 0 and abs(v) * 10 ** MAX_EXPONENT < 1 for v in out):
            self.fail(el, f"{attr}: its components differ in magnitude by more than a factor 1e{MAX_EXPONENT}; "
                          "write the small ones as 0")
        return out

    # ------------------------------------------------------------------ orientations
    def rotation(self, attrs: Attrs) -> sp.Matrix:
        """The exact orientation ``attrs`` give (identity if none; see the module docstring)."""
        given = [a for a in ORIENTATIONS if a in attrs]
        if len(given) > 1:
            self.fail(attrs.el, f"gives {', '.join(given)}: at most one orientation")
        if not given:
            return sp.eye(3)
        kind, el = given[0], attrs.origin(given[0])
        if kind == "quat":
            return exact_quat(*self.direction(attrs, "quat", 4))
        if kind == "euler":
            return self._snap(el, self._euler([self.angle(v) for v in self.numbers(attrs, "euler", 3)]))
        if kind == "axisangle":
            parts = attrs.get("axisangle").split()
            if len(parts) != 4:
                self.fail(el, f"axisangle={attrs.get('axisangle')[:60]!r} must have 4 numbers")
            axis = self._unit(el, "axisangle axis", [self.number(el, "axisangle", p, scale=False) for p in parts[:3]])
            angle = self.angle(self.number(el, "axisangle", parts[3]))
            return self._snap(el, axis_angle_matrix(axis, float(angle)))
        if kind == "xyaxes":
            values = self.numbers(attrs, "xyaxes", 6, scale=False)
            return self._snap(el, self._xyaxes(el, self._unit(el, "xyaxes x", values[:3]),
                                               self._unit(el, "xyaxes y", values[3:])))
        return self._snap(el, z_to_vector(self.direction(attrs, "zaxis")))

    def segment_rotation(self, el, vector) -> sp.Matrix:
        """The exact rotation of a ``fromto`` frame along ``vector`` (not zero): MuJoCo's ``zaxis``
        rule, the smallest rotation taking z to it."""
        return self._snap(el, z_to_vector(self._unit(el, "fromto", list(vector))))

    def _euler(self, angles) -> np.ndarray:
        """MuJoCo's Euler rotation for ``<compiler eulerseq>``, in floating point."""
        r = np.eye(3)
        for name, a in zip(self.eulerseq, angles):
            step = axis_angle_matrix([1.0 if name.lower() == c else 0.0 for c in "xyz"], float(a))
            r = r @ step if name.islower() else step @ r     # lowercase: rotating (intrinsic) axes
        return r

    def _xyaxes(self, el, x_axis, y_axis) -> np.ndarray:
        """The frame whose x and y axes are given (y made orthogonal to x, as MuJoCo does)."""
        x, y = np.array([float(v) for v in x_axis]), np.array([float(v) for v in y_axis])
        x = x / np.linalg.norm(x)
        y = y - (x @ y) * x
        if np.linalg.norm(y) < 1e-10:
            self.fail(el, "xyaxes: the two axes must not be parallel")
        y = y / np.linalg.norm(y)
        return np.column_stack([x, y, np.cross(x, y)])

    def _snap(self, el, matrix: np.ndarray) -> sp.Matrix:
        """The exact rotation :func:`~symgen.math.rotations_snap.snap_rotation` makes of a float one."""
        try:
            return sp.Matrix(snap_rotation(describe(el), matrix.tolist()))
        except SceneError as exc:
            self.fail(el, exc.message)


def axis_angle_matrix(axis, angle: float) -> np.ndarray:
    """Rotation by ``angle`` (radians) about ``axis`` (any length), in floating point."""
    k = np.array([float(v) for v in axis])
    k = k / np.linalg.norm(k)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(angle) * kx + (1 - math.cos(angle)) * (kx @ kx)


def z_to_vector(vector) -> np.ndarray:
    """MuJoCo's ``zaxis`` frame: the smallest rotation taking z to ``vector`` (half a turn about x
    when it points down z)."""
    v = np.array([float(c) for c in vector])
    v = v / np.linalg.norm(v)
    axis = np.cross([0.0, 0.0, 1.0], v)
    s = np.linalg.norm(axis)
    if s < 1e-15:
        return np.eye(3) if v[2] > 0 else np.diag([1.0, -1.0, -1.0])
    return axis_angle_matrix(axis, math.atan2(s, v[2]))
