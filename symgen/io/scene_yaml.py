"""YAML scene files: read a :class:`~symgen.scene.Scene` from YAML and write it back, exactly.

The format (every section a mapping keyed by name; declaration order is kept)::

    name: four_bar                        # required, a plain identifier
    description: planar four-bar          # optional text
    gravity: [0, 0, -9.81]                # optional, default (0, 0, -9.81)
    parameters: {m_crank: 1.0}            # optional symbols with numeric values
    urdf: {file: arm.urdf, contact: {frame: tool0}}   # optional: robots from URDF files and the
                                          # constraint overlay (symgen.io.urdf.yaml_section)
    bodies:
      crank: {mass: m_crank, com: [0.05, 0, 0], inertia: [0.001, 0.002, 0.003]}
    joints:
      j1: {type: revolute, parent: world, child: crank, xyz: [0, 0, 0], rpy: [0, 0, 0],
           axis: z, actuated: true, rotor_inertia: 0, friction: {viscous: 0.1, coulomb: 0},
           q0: pi/3}
    frames:
      ground_pin: {body: world, xyz: [0.3, 0, 0]}
    constraints:
      closure: {type: planar_weld, frames: [pin_frame, ground_pin], normal: z}
    motion: {joints: [j1]}                # or {frame: O, components: [...]}
                                          # or {frames: {O1: 1/2, O2: 1/2}, components: [...]}
    contact_forces: {frame: O, components: [vx, vy, wz]}
    constraint_forces: operational        # or joint

A placement (``joints`` and ``frames``) has ``xyz`` and at most one of ``rpy`` (URDF), ``quat``
(``[w, x, y, z]``, need not be unit) or ``rotation`` (a 3x3 matrix of exact numbers, checked to be
orthonormal with determinant +1). A spherical joint's ``q0`` is a quaternion or a 3x3 matrix.

Numbers stay exact: YAML floats are read from their text (``0.1`` is exactly 1/10) and strings
such as ``"1/3"`` or ``"-pi/2"`` go through :func:`symgen.math.numbers.parse_exact`. Every problem
raises a :class:`~symgen.errors.SceneError` (or subclass) naming the element, with the file and
line where the YAML parser knows them.

:func:`dump_scene` and :func:`save_scene` (from :mod:`symgen.io.scene_yaml_dump`) write this format
back; ``scene_from_dict(yaml.safe_load(dump_scene(s)))`` equals ``s``.
"""
from __future__ import annotations

import difflib
import os
from fractions import Fraction

import sympy as sp

from ..errors import SceneError
from ..scene.joint_kinds import JOINT_KINDS
from ..math.numbers import IDENTIFIER_RE, parse_exact
from ..scene.declaration import Scene
from .scene_yaml_dump import dump_scene, rational_quat, save_scene
from .textfile import read_text_file
from .yaml_exact import parse_yaml

__all__ = ["load_scene", "scene_from_dict", "dump_scene", "save_scene"]

_POSE = ("xyz", "rpy", "quat", "rotation")
KEYS = {
    "scene": ("name", "description", "gravity", "parameters", "urdf", "bodies", "joints", "frames",
              "constraints", "motion", "contact_forces", "constraint_forces"),
    "body": ("mass", "com", "inertia"),
    "joint": ("type", "parent", "child", *_POSE, "axis", "actuated", "rotor_inertia", "friction", "q0"),
    "frame": ("body", *_POSE),
    "constraint": ("type", "frames", "normal", "components"),
    "motion": ("joints", "frame", "frames", "components"),
    "contact_forces": ("frame", "components"),
    "friction": ("viscous", "coulomb"),
    # the urdf: section (robots from URDF files plus the constraint overlay, symgen.io.urdf.yaml_section)
    "urdf": ("file", "example", "robots", "prefix", "base", "q0", "lock", "snap", "friction", "contact", "hold",
             "close"),
    "urdf_robot": ("file", "example", "prefix", "base", "q0", "lock", "snap", "friction"),
    "urdf_base": ("xyz", "rpy", "quat"),
    "urdf_contact": ("frame", "normal", "plane", "name", "motion", "friction_forces"),
    "urdf_hold": ("frames", "object", "at"),
    "urdf_object": ("name", "mass", "com", "inertia"),
    "urdf_close": ("type", "frames", "normal", "components", "place"),
}
REQUIRED = {"scene": ("name",), "body": ("mass",), "joint": ("type", "parent", "child"),
            "frame": ("body",), "constraint": ("type", "frames"),
            "contact_forces": ("frame", "components"), "urdf_contact": ("frame",),
            "urdf_hold": ("frames", "object"), "urdf_object": ("mass",), "urdf_close": ("type", "frames")}


def _kind(value) -> str:
    """How a wrong value is described in an error message."""
    names = ((dict, "a mapping"), (list, "a list"), (type(None), "nothing (null)"))
    return next((text for cls, text in names if isinstance(value, cls)), f"{type(value).__name__} {value!r}")


def _scalars(value):
    """The scalars in a value, nested lists and mappings included."""
    if isinstance(value, (list, dict)):
        for v in value.values() if isinstance(value, dict) else value:
            yield from _scalars(v)
    else:
        yield value


def _infinite(value) -> bool:
    """True for a number text such as ``"1/0"`` that parses to infinity."""
    if isinstance(value, bool) or not isinstance(value, (str, int, Fraction)):
        return False
    try:
        return parse_exact(value).has(sp.zoo, sp.oo, sp.nan)
    except ValueError:
        return False  # not a number: the Scene reports it with its own reason


def _get(item, key, default):
    """``item[key]``, or ``default`` when the key is missing or null (an optional key left empty)."""
    value = item.get(key)
    return default if value is None else value


def _at(item, key, default=None):
    """Line of ``key`` in a located mapping (``default`` for plain dicts or missing keys)."""
    return getattr(item, "lines", {}).get(key, default)


def _is_name(value) -> bool:
    return isinstance(value, str) and len(value) <= 64 and IDENTIFIER_RE.fullmatch(value) is not None


class _Reader:
    """Builds a Scene from parsed YAML; every error names the element and, if known, its line."""

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
            self.fail(element, f"must be a mapping with keys {', '.join(KEYS[kind])}; "
                               f"got {_kind(value)}", line)
        for key, first, again in getattr(value, "duplicates", ()):
            self.fail(element, f"key {key!r} is given twice (lines {first} and {again})", again)
        for key in value:
            if key not in KEYS[kind]:
                close = difflib.get_close_matches(str(key), KEYS[kind], n=1)
                hint = f"; did you mean {close[0]!r}?" if close else f"; allowed: {', '.join(KEYS[kind])}"
                self.fail(element, f"unknown key {key!r}{hint}", _at(value, key, line))
            bad = [v for v in _scalars(value[key]) if scan and _infinite(v)]
            if bad:
                self.fail(element, f"{key}: {bad[0]!r} is not a finite number", _at(value, key, line))
        for key in REQUIRED.get(kind, ()):
            if key not in value:
                self.fail(element, f"missing required key {key!r}", getattr(value, "line", line))
        return value

    def section(self, data: dict, key: str, kind: str) -> list[tuple[str, object, int | None]]:
        """``(name, item, line)`` of each element of a top-level section; names checked."""
        value, line = data.get(key), _at(data, key)
        self.lines[key] = line
        if value is None:
            return []
        if not isinstance(value, dict):
            self.fail(key, f"must be a mapping of {kind} name -> {{...}}; got {_kind(value)}", line)
        for name, first, again in getattr(value, "duplicates", ()):
            self.fail(f"{kind} {name!r}", f"is declared twice (lines {first} and {again})", again)
        out = []
        for name, item in value.items():
            element = f"{kind} {name!r}"
            item_line = _at(value, name, line)
            if not _is_name(name):
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
            self.fail(element, f"{what} must be a list of {n} numbers; got {_kind(value)}", line)
        if any(isinstance(v, (list, dict)) for v in value):
            self.fail(element, f"{what} must hold numbers, not nested lists or mappings", line)
        return value

    def text(self, value, element, what, line) -> str:
        if not isinstance(value, str):
            self.fail(element, f"{what} must be a name; got {_kind(value)}", line)
        return value

    def names(self, value, element, what, line) -> list[str]:
        if not isinstance(value, list) or not value:
            self.fail(element, f"{what} must be a non-empty list of names; got {_kind(value)}", line)
        return [self.text(v, element, f"each entry of {what}", line) for v in value]

    def exact(self, value, element, what, line) -> sp.Expr:
        symbols = {str(s): s for s in self.scene.parameters}
        try:
            if _infinite(value):
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
        out = {"xyz": self.vector(item.get("xyz"), element, "xyz", _at(item, "xyz", line))}
        for key in given:
            at = _at(item, key, line)
            if key == "rotation" and _float_matrix(item[key]):    # snapped by Scene.pose (rotations_snap)
                out["rotation"] = item[key]
                continue
            out["rpy" if key == "rpy" else "quat"] = (
                self.rotation_quat(item[key], element, key, at) if key == "rotation"
                else self.vector(item[key], element, key, at, (3,) if key == "rpy" else (4,)))
        return out

    # -------------------------------------------------------------- sections
    def read(self, data) -> Scene:
        if data is None:
            self.fail("scene", "the file is empty; expected a mapping with at least 'name'")
        top = self.mapping(data, "scene", "scene", scan=False)
        name = top["name"]
        if not _is_name(name):
            self.fail(f"scene {name!r}", "the scene name must be a plain identifier", _at(top, "name"))
        description = top.get("description") or ""
        if not isinstance(description, str):
            self.fail("description", f"must be text; got {_kind(description)}", _at(top, "description"))
        self.scene = scene = Scene(name, description)
        for pname, value, line in self.section(top, "parameters", "parameter"):
            if pname == "pi":
                self.fail("parameter 'pi'", "'pi' is reserved for the number pi", line)
            try:
                parse_exact(value)
            except ValueError as exc:
                self.fail(f"parameter {pname!r}", f"value: {exc}", line)
            if _infinite(value):
                self.fail(f"parameter {pname!r}", f"value {value!r} is not a finite number", line)
            self.call(line, scene.add_parameter, pname, value)
        if top.get("gravity") is not None:
            line = _at(top, "gravity")
            g = self.vector(top["gravity"], "gravity", "gravity", line)
            scene.gravity = sp.ImmutableMatrix([self.exact(v, "gravity", "gravity", line) for v in g])
        overlay = None
        if top.get("urdf") is not None:  # robots from URDF files; their overlay after the frames
            from .urdf.yaml_section import read_robots

            overlay = read_robots(self, top["urdf"], self.lines.setdefault("urdf", _at(top, "urdf")))
        for name, item, line in self.section(top, "bodies", "body"):
            self.body(name, item, line)
        for name, item, line in self.section(top, "joints", "joint"):
            self.joint(name, item, line)
        for name, item, line in self.section(top, "frames", "frame"):
            element = f"frame {name!r}"
            item = self.mapping(item, element, "frame", line)
            body = self.text(item["body"], element, "body", line)
            self.call(line, scene.add_frame, name, body, **self.pose(item, element, line))
        if overlay is not None:
            overlay()
        for name, item, line in self.section(top, "constraints", "constraint"):
            self.constraint(name, item, line)
        if top.get("motion") is not None:
            self.motion(top["motion"], _at(top, "motion"))
        if top.get("contact_forces") is not None:
            line = self.lines["contact_forces"] = _at(top, "contact_forces")
            item = self.mapping(top["contact_forces"], "contact_forces", "contact_forces", line)
            frame = self.text(item["frame"], "contact_forces", "frame", line)
            comps = self.names(item["components"], "contact_forces", "components", line)
            self.call(line, scene.set_contact_forces, frame, comps)
        if top.get("constraint_forces") is not None:
            line = self.lines["constraint_forces"] = _at(top, "constraint_forces")
            if top["constraint_forces"] not in ("operational", "joint"):
                self.fail("constraint_forces", f"must be 'operational' or 'joint'; got "
                                               f"{_kind(top['constraint_forces'])}", line)
            scene.constraint_forces = top["constraint_forces"]
        return scene

    def body(self, name, item, line):
        element = f"body {name!r}"
        item = self.mapping(item, element, "body", line)
        com = self.vector(_get(item, "com", [0, 0, 0]), element, "com", _at(item, "com", line))
        inertia = _get(item, "inertia", [0, 0, 0])
        if not _nested_3x3(inertia):    # a full 3x3 matrix goes to Scene.add_body as it is
            inertia = self.vector(inertia, element, "inertia", _at(item, "inertia", line), (3, 6))
        self.call(line, self.scene.add_body, name, item["mass"], com, inertia)

    def joint(self, name, item, line):
        element = f"joint {name!r}"
        item = self.mapping(item, element, "joint", line)
        kw = {k: self.text(item[k], element, k, _at(item, k, line)) for k in ("type", "parent", "child")}
        kw.update(self.pose(item, element, line))
        axis = _get(item, "axis", "z")
        if not isinstance(axis, str):
            self.vector(axis, element, "axis", _at(item, "axis", line))
        actuated = _get(item, "actuated", False)
        if not isinstance(actuated, bool):
            self.fail(element, f"actuated must be true or false; got {_kind(actuated)}",
                      _at(item, "actuated", line))
        friction = self.mapping(_get(item, "friction", {}), f"{element} friction", "friction",
                                _at(item, "friction", line))
        q0, q0_line = item.get("q0"), _at(item, "q0", line)
        kind = JOINT_KINDS.get(kw["type"])         # an unknown type is reported by add_joint
        if kind is not None and kind.position_is_rotation and q0 is not None:
            if isinstance(q0, list) and q0 and isinstance(q0[0], list):
                q0 = self.rotation_quat(q0, element, "q0", q0_line)
            else:
                self.vector(q0, element, "q0 (quaternion [w, x, y, z])", q0_line, (4,))
                if all(self.exact(v, element, "q0", q0_line) == 0 for v in q0):
                    self.fail(element, "q0 quaternion must not be zero", q0_line)
        self.call(line, self.scene.add_joint, name, axis=axis, actuated=actuated, q0=q0,
                  rotor_inertia=_get(item, "rotor_inertia", 0), viscous=_get(friction, "viscous", 0),
                  coulomb=_get(friction, "coulomb", 0), **kw)

    def constraint(self, name, item, line):
        element = f"constraint {name!r}"
        item = self.mapping(item, element, "constraint", line)
        kind = self.text(item["type"], element, "type", _at(item, "type", line))
        frames = self.names(item["frames"], element, "frames", _at(item, "frames", line))
        if len(frames) > 2:
            self.fail(element, f"frames must name one or two frames; got {len(frames)}",
                      _at(item, "frames", line))
        normal = self.text(_get(item, "normal", "z"), element, "normal", _at(item, "normal", line))
        comps, at = item.get("components"), _at(item, "components", line)
        if kind == "custom":
            comps = self.names(comps, element, "components", at)
        elif comps is not None:
            self.fail(element, "components are only given for type 'custom'", at)
        self.call(line, self.scene.add_constraint, name, kind, *frames, normal=normal, components=comps)

    def motion(self, value, line):
        self.lines["motion"] = line
        item = self.mapping(value, "motion", "motion", line)
        chosen = [k for k in ("joints", "frame", "frames") if k in item]
        if len(chosen) != 1:
            self.fail("motion", "give exactly one of joints, frame, frames", line)
        if "joints" in item:
            if "components" in item:
                self.fail("motion", "components go with frame/frames, not with joints", line)
            joints = self.names(item["joints"], "motion", "joints", line)
            self.call(line, self.scene.set_motion, joints=joints)
            return
        comps = item.get("components")
        comps = None if comps is None else self.names(comps, "motion", "components", line)
        if "frame" in item:
            frame = self.text(item["frame"], "motion", "frame", line)
            self.call(line, self.scene.set_motion, frame=frame, components=comps)
            return
        frames = item["frames"]
        if not isinstance(frames, dict) or not frames:
            self.fail("motion", f"frames must be a mapping frame -> weight gamma; got {_kind(frames)}", line)
        for key, first, again in getattr(frames, "duplicates", ()):
            self.fail("motion", f"frame {key!r} is weighted twice (lines {first} and {again})", again)
        for key in frames:
            self.text(key, "motion", "frames", line)
        self.call(line, self.scene.set_motion, frames=dict(frames), components=comps)

    def validate(self):
        try:
            self.scene.validate()
        except SceneError as exc:
            element = exc.element
            line = self.lines.get(element, self.lines.get(element.split(" ")[0]))
            raise self.locate(exc, line) from None


def scene_from_dict(data, source: str | None = None, *, validate: bool = True) -> Scene:
    """Build a :class:`Scene` from parsed YAML (a mapping laid out as in this module's docstring).

    Args:
        data: the parsed document (from :func:`yaml.safe_load` or :func:`symgen.io.yaml_exact.parse_yaml`).
        source: file name used in error messages (``None``: no location).
        validate: run :meth:`Scene.validate` (topology, counts, task space) before returning.

    Raises:
        SceneError: (or a subclass) naming the offending element.
    """
    reader = _Reader(source)
    reader.read(data)
    if validate:
        reader.validate()
    return reader.scene


def load_scene(path_or_text, *, validate: bool = True) -> Scene:
    """Read a scene from a YAML file or from YAML text.

    ``path_or_text`` is a path when it is a :class:`pathlib.Path`, or a one-line string that names
    an existing file, ends in ``.yaml``/``.yml``, or holds no ``:``; any other string is YAML text.

    >>> s = load_scene("name: p\\nbodies: {b: {mass: 0.1}}\\njoints: {j: {type: revolute, "
    ...                "parent: world, child: b}}\\nmotion: {joints: [j]}")
    >>> s.bodies["b"].mass
    1/10
    """
    text, source = path_or_text, "<string>"
    is_path = isinstance(path_or_text, os.PathLike) or (
        isinstance(path_or_text, str) and "\n" not in path_or_text
        and (path_or_text.endswith((".yaml", ".yml")) or ":" not in path_or_text
             or os.path.isfile(path_or_text)))
    if is_path:
        source = str(path_or_text)
        text = read_text_file(path_or_text, f"scene file {source!r}")
    elif not isinstance(text, str):
        raise SceneError("scene file", f"expected a path or YAML text; got {_kind(text)}")
    return scene_from_dict(parse_yaml(text, source), source, validate=validate)


def _nested_3x3(value) -> bool:
    return isinstance(value, list) and len(value) == 3 and all(isinstance(r, list) and len(r) == 3 for r in value)


def _float_matrix(value) -> bool:
    """A 3x3 matrix with a floating-point entry (written by another tool): snapped, not refused."""
    return _nested_3x3(value) and any(isinstance(v, float) for r in value for v in r)
