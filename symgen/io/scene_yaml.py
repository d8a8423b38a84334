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
      gear: {type: coupling, joint: j2, leader: j1, multiplier: -2, offset: 0}   # q_j2 = -2 q_j1
      # or {type: coupling, joint: j2, terms: {j1: 2, j3: -1}, offset: 0}: q_j2 + 2 q_j1 - q_j3 = 0
    motion: {joints: [j1]}                # or {frame: O, components: [...]}
                                          # or {frames: {O1: 1/2, O2: 1/2}, components: [...]}
                                          # or {frame: O, components: [...], joints: [j1]}:
                                          # mixed, the twist components first, then the rates
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

import os

import sympy as sp

from ..errors import SceneError
from ..scene.joint_kinds import JOINT_KINDS
from ..math.numbers import parse_exact
from ..scene.declaration import Scene
from .scene_yaml_dump import dump_scene, save_scene
from .textfile import read_text_file
from .yaml_exact import parse_yaml
from .yaml_reader import LocatedReader, describe, get_or, is_infinite, is_name, line_of, nested_3x3

__all__ = ["load_scene", "scene_from_dict", "dump_scene", "save_scene"]

_POSE = ("xyz", "rpy", "quat", "rotation")
KEYS = {
    "scene": ("name", "description", "gravity", "parameters", "urdf", "bodies", "joints", "frames",
              "constraints", "motion", "contact_forces", "constraint_forces"),
    "body": ("mass", "com", "inertia"),
    "joint": ("type", "parent", "child", *_POSE, "axis", "actuated", "rotor_inertia", "friction", "q0",
              "stiffness", "springref"),
    "frame": ("body", *_POSE),
    "constraint": ("type", "frames", "normal", "components"),
    "coupling": ("type", "joint", "leader", "multiplier", "offset", "terms"),
    "motion": ("joints", "frame", "frames", "components"),
    "contact_forces": ("frame", "components"),
    "friction": ("viscous", "coulomb"),
    # the urdf: section (robots from URDF files plus the constraint overlay, symgen.io.urdf.yaml_section)
    "urdf": ("file", "example", "robots", "prefix", "base", "q0", "lock", "snap", "friction", "inertia", "floating", "mimic", "stand", "contact",
             "hold", "close"),
    "urdf_robot": ("file", "example", "prefix", "base", "q0", "lock", "snap", "friction", "inertia", "floating",
                   "mimic"),
    "urdf_stand": ("frames", "kind"),
    "urdf_base": ("xyz", "rpy", "quat"),
    "urdf_contact": ("frame", "normal", "plane", "name", "motion", "friction_forces"),
    "urdf_hold": ("frames", "object", "at"),
    "urdf_object": ("name", "mass", "com", "inertia"),
    "urdf_close": ("type", "frames", "normal", "components", "place"),
}
REQUIRED = {"scene": ("name",), "body": ("mass",), "joint": ("type", "parent", "child"),
            "frame": ("body",), "constraint": ("type", "frames"), "coupling": ("type", "joint"),
            "contact_forces": ("frame", "components"), "urdf_contact": ("frame",),
            "urdf_hold": ("frames", "object"), "urdf_object": ("mass",), "urdf_close": ("type", "frames")}


class _Reader(LocatedReader):
    """Builds a Scene from parsed YAML; every error names the element and, if known, its line."""

    keys = KEYS
    required = REQUIRED

    # -------------------------------------------------------------- sections
    def read(self, data) -> Scene:
        if data is None:
            self.fail("scene", "the file is empty; expected a mapping with at least 'name'")
        top = self.mapping(data, "scene", "scene", scan=False)
        name = top["name"]
        if not is_name(name):
            self.fail(f"scene {name!r}", "the scene name must be a plain identifier", line_of(top, "name"))
        description = top.get("description") or ""
        if not isinstance(description, str):
            self.fail("description", f"must be text; got {describe(description)}", line_of(top, "description"))
        self.scene = scene = Scene(name, description)
        for pname, value, line in self.section(top, "parameters", "parameter"):
            if pname == "pi":
                self.fail("parameter 'pi'", "'pi' is reserved for the number pi", line)
            try:
                parse_exact(value)
            except ValueError as exc:
                self.fail(f"parameter {pname!r}", f"value: {exc}", line)
            if is_infinite(value):
                self.fail(f"parameter {pname!r}", f"value {value!r} is not a finite number", line)
            self.call(line, scene.add_parameter, pname, value)
        if top.get("gravity") is not None:
            line = line_of(top, "gravity")
            g = self.vector(top["gravity"], "gravity", "gravity", line)
            scene.gravity = sp.ImmutableMatrix([self.exact(v, "gravity", "gravity", line) for v in g])
        overlay = None
        if top.get("urdf") is not None:  # robots from URDF files; their overlay after the frames
            from .urdf.yaml_section import read_robots

            overlay = read_robots(self, top["urdf"], self.lines.setdefault("urdf", line_of(top, "urdf")))
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
            self.motion(top["motion"], line_of(top, "motion"))
        if top.get("contact_forces") is not None:
            line = self.lines["contact_forces"] = line_of(top, "contact_forces")
            item = self.mapping(top["contact_forces"], "contact_forces", "contact_forces", line)
            frame = self.text(item["frame"], "contact_forces", "frame", line)
            comps = self.names(item["components"], "contact_forces", "components", line)
            self.call(line, scene.set_contact_forces, frame, comps)
        if top.get("constraint_forces") is not None:
            line = self.lines["constraint_forces"] = line_of(top, "constraint_forces")
            if top["constraint_forces"] not in ("operational", "joint"):
                self.fail("constraint_forces", f"must be 'operational' or 'joint'; got "
                                               f"{describe(top['constraint_forces'])}", line)
            scene.constraint_forces = top["constraint_forces"]
        return scene

    def body(self, name, item, line):
        element = f"body {name!r}"
        item = self.mapping(item, element, "body", line)
        com = self.vector(get_or(item, "com", [0, 0, 0]), element, "com", line_of(item, "com", line))
        inertia = get_or(item, "inertia", [0, 0, 0])
        if not nested_3x3(inertia):    # a full 3x3 matrix goes to Scene.add_body as it is
            inertia = self.vector(inertia, element, "inertia", line_of(item, "inertia", line), (3, 6))
        self.call(line, self.scene.add_body, name, item["mass"], com, inertia)

    def joint(self, name, item, line):
        element = f"joint {name!r}"
        item = self.mapping(item, element, "joint", line)
        kw = {k: self.text(item[k], element, k, line_of(item, k, line)) for k in ("type", "parent", "child")}
        kw.update(self.pose(item, element, line))
        axis = get_or(item, "axis", "z")
        if not isinstance(axis, str):
            self.vector(axis, element, "axis", line_of(item, "axis", line))
        actuated = get_or(item, "actuated", False)
        if not isinstance(actuated, bool):
            self.fail(element, f"actuated must be true or false; got {describe(actuated)}",
                      line_of(item, "actuated", line))
        friction = self.mapping(get_or(item, "friction", {}), f"{element} friction", "friction",
                                line_of(item, "friction", line))
        q0, q0_line = item.get("q0"), line_of(item, "q0", line)
        kind = JOINT_KINDS.get(kw["type"])         # an unknown type is reported by add_joint
        if kind is not None and kind.position_is_rotation and q0 is not None:
            if isinstance(q0, list) and q0 and isinstance(q0[0], list):
                q0 = self.rotation_quat(q0, element, "q0", q0_line)
            else:
                self.vector(q0, element, "q0 (quaternion [w, x, y, z])", q0_line, (4,))
                if all(self.exact(v, element, "q0", q0_line) == 0 for v in q0):
                    self.fail(element, "q0 quaternion must not be zero", q0_line)
        self.call(line, self.scene.add_joint, name, axis=axis, actuated=actuated, q0=q0,
                  rotor_inertia=get_or(item, "rotor_inertia", 0), viscous=get_or(friction, "viscous", 0),
                  coulomb=get_or(friction, "coulomb", 0), stiffness=get_or(item, "stiffness", 0),
                  springref=get_or(item, "springref", 0), **kw)

    def constraint(self, name, item, line):
        element = f"constraint {name!r}"
        if isinstance(item, dict) and item.get("type") == "coupling":
            return self.coupling(name, item, line)
        item = self.mapping(item, element, "constraint", line)
        kind = self.text(item["type"], element, "type", line_of(item, "type", line))
        frames = self.names(item["frames"], element, "frames", line_of(item, "frames", line))
        if len(frames) > 2:
            self.fail(element, f"frames must name one or two frames; got {len(frames)}",
                      line_of(item, "frames", line))
        normal = self.text(get_or(item, "normal", "z"), element, "normal", line_of(item, "normal", line))
        comps, at = item.get("components"), line_of(item, "components", line)
        if kind == "custom":
            comps = self.names(comps, element, "components", at)
        elif comps is not None:
            self.fail(element, "components are only given for type 'custom'", at)
        self.call(line, self.scene.add_constraint, name, kind, *frames, normal=normal, components=comps)

    def coupling(self, name, item, line):
        """A joint coupling (:meth:`~symgen.scene.Scene.add_coupling`): ``joint`` with ``leader``,
        ``multiplier`` and ``offset``, or with ``terms: {joint: coefficient}``."""
        element = f"constraint {name!r}"
        item = self.mapping(item, element, "coupling", line)
        joint = self.text(item["joint"], element, "joint", line_of(item, "joint", line))
        terms = item.get("terms")
        if terms is not None and not isinstance(terms, dict):
            self.fail(element, f"terms must map joint names to coefficients; got {describe(terms)}",
                      line_of(item, "terms", line))
        if terms is not None and "multiplier" in item:
            self.fail(element, "multiplier goes with leader, not with terms", line_of(item, "multiplier", line))
        leader = item.get("leader")
        if leader is not None:
            leader = self.text(leader, element, "leader", line_of(item, "leader", line))
        self.call(line, self.scene.add_coupling, name, joint, leader, multiplier=get_or(item, "multiplier", 1),
                  offset=get_or(item, "offset", 0), terms=dict(terms) if terms is not None else None)

    def motion(self, value, line):
        self.lines["motion"] = line
        item = self.mapping(value, "motion", "motion", line)
        chosen = [k for k in ("frame", "frames") if k in item]
        if len(chosen) > 1 or not (chosen or "joints" in item):
            self.fail("motion", "give joints, or one of frame, frames (with joints too for a mixed V_m)", line)
        joints = self.names(item["joints"], "motion", "joints", line) if "joints" in item else None
        if not chosen:
            if "components" in item:
                self.fail("motion", "components go with frame/frames, not with joints alone", line)
            self.call(line, self.scene.set_motion, joints=joints)
            return
        comps = item.get("components")
        comps = None if comps is None else self.names(comps, "motion", "components", line)
        if "frame" in item:
            frame = self.text(item["frame"], "motion", "frame", line)
            self.call(line, self.scene.set_motion, frame=frame, components=comps, joints=joints)
            return
        frames = item["frames"]
        if not isinstance(frames, dict) or not frames:
            self.fail("motion", f"frames must be a mapping frame -> weight gamma; got {describe(frames)}", line)
        for key, first, again in getattr(frames, "duplicates", ()):
            self.fail("motion", f"frame {key!r} is weighted twice (lines {first} and {again})", again)
        for key in frames:
            self.text(key, "motion", "frames", line)
        self.call(line, self.scene.set_motion, frames=dict(frames), components=comps, joints=joints)

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
        raise SceneError("scene file", f"expected a path or YAML text; got {describe(text)}")
    return scene_from_dict(parse_yaml(text, source), source, validate=validate)
