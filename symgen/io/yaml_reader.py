"""The located-value reader under the YAML scene format: shape checks of mappings, lists, names,
numbers and poses, each failure a :class:`~symgen.errors.SceneError` naming the element with the
file and line (:mod:`symgen.io.scene_yaml` builds scenes on it; the URDF section reuses its
:meth:`LocatedReader.call`)."""
from __future__ import annotations

import difflib
from fractions import Fraction

import sympy as sp

from ..errors import SceneError
from ..math.numbers import IDENTIFIER_RE, parse_exact
from ..scene.declaration import Scene
from .scene_yaml_dump import rational_quat


def describe(value) -> str:
    """How a wrong value is described in an error message."""
    names = ((dict, "a mapping"), (list, "a list"), (type(None), "nothing (null)"))
    return next((text for cls, text in names if isinstance(value, cls)), f"{type(value).__name__} {value!r}")


def scalars(value):
    """The scalars in a value, nested lists and mappings included."""
    if isinstance(value, (list, dict)):
        for v in value.values() if isinstance(value, dict) else value:
            yield from scalars(v)
    else:
        yield value


def is_infinite(value) -> bool:
    """True for a number text such as ``"1/0"`` that parses to infinity."""
    if isinstance(value, bool) or not isinstance(value, (str, int, Fraction)):
        return False
    try:
        return parse_exact(value).has(sp.zoo, sp.oo, sp.nan)
    except ValueError:
        return False  # not a number: the Scene reports it with its own reason


def get_or(item, key, default):
    """``item[key]``, or ``default`` when the key is missing or null (an optional key left empty)."""
    value = item.get(key)
    return default if value is None else value


def line_of(item, key, default=None):
    """Line of ``key`` in a located mapping (``default`` for plain dicts or missing keys)."""
    return getattr(item, "lines", {}).get(key, default)


def is_name(value) -> bool:
    return isinstance(value, str) and len(value) <= 64 and IDENTIFIER_RE.fullmatch(value) is not None


def nested_3x3(value) -> bool:
    return isinstance(value, list) and len(value) == 3 and all(isinstance(r, list) and len(r) == 3 for r in value)


def float_matrix(value) -> bool:
    """A 3x3 matrix with a floating-point entry (written by another tool): snapped, not refused."""
    return nested_3x3(value) and any(isinstance(v, float) for r in value for v in r)


class LocatedReader:
    """Reads parsed YAML (:mod:`symgen.io.yaml_exact`: mappings that know their lines) into a
    :class:`~symgen.scene.Scene`; every error names the element and, if known, the file and line.
    A subclass gives the allowed and required keys of each kind of mapping (:attr:`keys`,
    :attr:`required`)."""

    #: kind of mapping -> the keys it may have
    keys: dict[str, tuple[str, ...]] = {}
    #: kind of mapping -> the keys it must have
    required: dict[str, tuple[str, ...]] = {}

    def __init__(self, source: str | None):
        self.source = source
        self.lines: dict[str, int | None] = {}
        self.scene: Scene | None = None

    # -------------------------------------------------------------- errors with locations
    def locate(self, exc: SceneError, line: int | None) -> SceneError:
        """The same error (same type, same element) with ``(source, line N)`` appended."""
        if getattr(exc, "located", False) or (line is None and self.source is None):
            return exc
        where = ", ".join(p for p in (self.source, f"line {line}" if line else None) if p)
        message = str(exc)[len(exc.element) + 2:]
        new = type(exc)(exc.element, f"{message} ({where})")
        new.source, new.line, new.located = self.source, line, True
        return new

    def fail(self, element: str, message: str, line: int | None = None):
        raise self.locate(SceneError(element, message), line)

    def call(self, line, fn, *args, **kwargs):
        """Call a Scene method, adding the location to any SceneError it raises."""
        try:
            return fn(*args, **kwargs)
        except SceneError as exc:
            raise self.locate(exc, line) from None

    # -------------------------------------------------------------- shape checks
    def mapping(self, value, element: str, kind: str, line=None, scan: bool = True) -> dict:
        """Check a mapping's shape: no repeated, unknown or missing keys, no infinite numbers."""
        if not isinstance(value, dict):
            self.fail(element, f"must be a mapping with keys {', '.join(self.keys[kind])}; "
                               f"got {describe(value)}", line)
        for key, first, again in getattr(value, "duplicates", ()):
            self.fail(element, f"key {key!r} is given twice (lines {first} and {again})", again)
        for key in value:
            if key not in self.keys[kind]:
                close = difflib.get_close_matches(str(key), self.keys[kind], n=1)
                hint = f"; did you mean {close[0]!r}?" if close else f"; allowed: {', '.join(self.keys[kind])}"
                self.fail(element, f"unknown key {key!r}{hint}", line_of(value, key, line))
            bad = [v for v in scalars(value[key]) if scan and is_infinite(v)]
            if bad:
                self.fail(element, f"{key}: {bad[0]!r} is not a finite number", line_of(value, key, line))
        for key in self.required.get(kind, ()):
            if key not in value:
                self.fail(element, f"missing required key {key!r}", getattr(value, "line", line))
        return value

    def section(self, data: dict, key: str, kind: str) -> list[tuple[str, object, int | None]]:
        """``(name, item, line)`` of each element of a top-level section; names checked."""
        value, line = data.get(key), line_of(data, key)
        self.lines[key] = line
        if value is None:
            return []
        if not isinstance(value, dict):
            self.fail(key, f"must be a mapping of {kind} name -> {{...}}; got {describe(value)}", line)
        for name, first, again in getattr(value, "duplicates", ()):
            self.fail(f"{kind} {name!r}", f"is declared twice (lines {first} and {again})", again)
        out = []
        for name, item in value.items():
            element = f"{kind} {name!r}"
            item_line = line_of(value, name, line)
            if not is_name(name):
                self.fail(element, "names must be plain identifiers ([A-Za-z_][A-Za-z0-9_]*, at most 64 "
                                   "characters, no spaces, quotes or newlines)", item_line)
            self.lines[element] = item_line
            out.append((name, item, item_line))
        return out

    def vector(self, value, element, what, line, lengths=(3,)):
        if value is None:
            return None
        if not isinstance(value, list) or len(value) not in lengths:
            n = " or ".join(map(str, lengths))
            self.fail(element, f"{what} must be a list of {n} numbers; got {describe(value)}", line)
        if any(isinstance(v, (list, dict)) for v in value):
            self.fail(element, f"{what} must hold numbers, not nested lists or mappings", line)
        return value

    def text(self, value, element, what, line) -> str:
        if not isinstance(value, str):
            self.fail(element, f"{what} must be a name; got {describe(value)}", line)
        return value

    def names(self, value, element, what, line) -> list[str]:
        if not isinstance(value, list) or not value:
            self.fail(element, f"{what} must be a non-empty list of names; got {describe(value)}", line)
        return [self.text(v, element, f"each entry of {what}", line) for v in value]

    def exact(self, value, element, what, line) -> sp.Expr:
        symbols = {str(s): s for s in self.scene.parameters}
        try:
            if is_infinite(value):
                raise ValueError(f"{value!r} is not a finite number")
            return parse_exact(value, symbols)
        except ValueError as exc:
            self.fail(element, f"{what}: {exc}", line)

    def rotation_quat(self, value, element, what, line) -> list:
        """A 3x3 ``rotation`` matrix, checked orthonormal with det +1, as an exact quaternion."""
        if not (isinstance(value, list) and len(value) == 3
                and all(isinstance(r, list) and len(r) == 3 for r in value)):
            self.fail(element, f"{what} must be a 3x3 matrix (a list of 3 rows of 3 numbers)", line)
        r = sp.Matrix([[self.exact(v, element, what, line) for v in row] for row in value])
        if not all(v.is_Rational for v in r):
            self.fail(element, f"{what} entries must be rational numbers (use rpy for angles like "
                               "pi/4)", line)
        if r.T * r != sp.eye(3):
            self.fail(element, f"{what} is not orthonormal (R^T R != 1)", line)
        if r.det() != 1:
            self.fail(element, f"{what} has determinant {r.det()}: a reflection, not a rotation", line)
        return rational_quat(r)

    def pose(self, item, element, line) -> dict:
        """``xyz`` and the rotation (``rpy``, ``quat``, or ``rotation`` turned into a quaternion)."""
        given = [k for k in ("rpy", "quat", "rotation") if k in item]
        if len(given) > 1:
            self.fail(element, f"give at most one of rpy, quat, rotation (got {', '.join(given)})", line)
        out = {"xyz": self.vector(item.get("xyz"), element, "xyz", line_of(item, "xyz", line))}
        for key in given:
            at = line_of(item, key, line)
            if key == "rotation" and float_matrix(item[key]):    # snapped by Scene.pose (rotations_snap)
                out["rotation"] = item[key]
                continue
            out["rpy" if key == "rpy" else "quat"] = (
                self.rotation_quat(item[key], element, key, at) if key == "rotation"
                else self.vector(item[key], element, key, at, (3,) if key == "rpy" else (4,)))
        return out
