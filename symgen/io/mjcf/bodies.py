"""The body tree of an MJCF file: ``<worldbody>`` sections, bodies, ``<frame>`` elements, joints,
inertials and sites, read with their default classes (:mod:`symgen.io.mjcf.defaults`).

Every ``<worldbody>`` is read, in file order, as MuJoCo reads them all. A ``<frame>`` places what it
holds (bodies, joints, sites, frames) by its pose and passes on its ``childclass``, and is then
gone, as in MuJoCo. A body holds any number of joints (``hinge``, ``slide`` or ``ball``), kept
in file order (:mod:`symgen.io.mjcf.build` makes a chain of them). Its mass properties are its
``<inertial>`` or, as ``<compiler inertiafromgeom>`` says, those of its geoms
(:mod:`symgen.io.mjcf.geoms`).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp

from .defaults import Defaults
from .geoms import FROMTO_SHAPES, GROUP_RANGE, combined, geom_inertial, in_group_range
from .records import WORLD, MjcfBody, MjcfInertial, MjcfJoint, MjcfSite, element_name
from .schema import check_neutral
from .values import Attrs, MjcfError, Values

#: MJCF joint types read, and the symgen joint kind of each
JOINT_TYPES = {"hinge": "revolute", "slide": "prismatic", "ball": "spherical", "free": "free"}
#: MuJoCo's mjMINVAL: a moving body's mass and principal inertias must exceed it
MJMINVAL = 1e-15


@dataclass(frozen=True)
class Physics:
    """The settings of ``<compiler>`` and ``<option>`` the body tree depends on."""

    springs: bool = True          # <flag spring>
    dampers: bool = True          # <flag damper>
    friction: bool = True         # <flag frictionloss>
    inertia_from_geoms: str = "auto"
    group_range: tuple = (0, 5)   # <compiler inertiagrouprange>


@dataclass(frozen=True)
class Pose:
    """A placement ``(pos, rot)`` of a frame in a body's frame, exact."""

    pos: sp.Matrix
    rot: sp.Matrix

    def compose(self, other: "Pose") -> "Pose":
        """``other`` (a pose in this frame) in the frame this pose is given in."""
        if self.rot == sp.eye(3):
            return Pose(self.pos + other.pos, other.rot)
        return Pose((self.pos + self.rot * other.pos).applyfunc(sp.expand),
                    (self.rot * other.rot).applyfunc(sp.expand))


IDENTITY = Pose(sp.zeros(3, 1), sp.eye(3))


class BodyReader:
    """Reads the body tree under every ``<worldbody>`` of ``root``."""

    def __init__(self, values: Values, defaults: Defaults, physics: Physics, meshes=None):
        """Readers of values and classes, the settings the bodies depend on, and the file's meshes
        (a :class:`~symgen.io.mjcf.meshes.MeshLibrary`, for mesh geoms)."""
        self.values, self.defaults, self.physics, self.meshes = values, defaults, physics, meshes
        self.bodies: list = []
        self.sites: list = []
        self.names: set = set()

    def read(self, root) -> None:
        """Read every ``<worldbody>`` of ``root`` into :attr:`bodies` and :attr:`sites`."""
        for world in root.findall("worldbody"):
            self._tree(world)

    def _pose(self, attrs: Attrs) -> Pose:
        """``pos`` and the orientation ``attrs`` give."""
        pos = self.values.numbers(attrs, "pos", 3, "0 0 0")
        return Pose(sp.Matrix(pos), self.values.rotation(attrs))

    def _items(self, el, pose: Pose, childclass: str | None, out: list) -> None:
        """``(element, pose in the body, childclass)`` of everything ``el`` holds, frames opened."""
        for child in el:
            if not isinstance(child.tag, str):
                continue
            if child.tag == "frame":
                cls = child.get("childclass")
                if cls is not None:
                    self.defaults.check_class(child, cls)
                attrs = Attrs(child, {a: (v, child) for a, v in child.attrib.items()})
                self._items(child, pose.compose(self._pose(attrs)), cls or childclass, out)
            else:
                out.append((child, pose, childclass))

    def _tree(self, world) -> None:
        """Read the bodies under ``world`` depth first, parents before children (MuJoCo's order)."""
        pending = [(world, IDENTITY, WORLD, None)]     # element, pose in its parent, parent, inherited class
        while pending:
            el, pose, parent, childclass = pending.pop()
            body = None if el is world else self._body(el, pose, parent)
            name = WORLD if body is None else body.name
            own = None if body is None else el.get("childclass")
            if own is not None:
                self.defaults.check_class(el, own)
            items: list = []
            self._items(el, IDENTITY, own or childclass, items)
            self.sites += [self._site(c, p, k, name) for c, p, k in items if c.tag == "site" and c.get("name")]
            if body is None:
                for c, _, _ in items:
                    if c.tag == "joint":
                        self.values.fail(c, "is not read: the world cannot move (a joint belongs in a body)")
            else:
                self._body_content(el, body, items)
            pending += reversed([(c, p, name, k) for c, p, k in items if c.tag == "body"])

    def _body(self, el, pose: Pose, parent: str) -> MjcfBody:
        """The body ``el`` (placed in ``parent`` by ``pose``, its enclosing frames), contents to come."""
        attrs = Attrs(el, {a: (v, el) for a, v in el.attrib.items()})
        check_neutral(self.values, "body", attrs)
        name = element_name(el.get("name"))
        if name is None:
            self.values.fail(el, "needs a name")
        if name == WORLD or name in self.names:
            self.values.fail(el, "body names must be unique and not 'world'")
        self.names.add(name)
        placed = pose.compose(self._pose(attrs))
        body = MjcfBody(name, parent, placed.pos, placed.rot, [], None, line=el.sourceline)
        self.bodies.append(body)
        return body

    def _body_content(self, el, body: MjcfBody, items: list) -> None:
        """The joints (in file order) and the inertial of ``body`` from its items: the ``<inertial>``,
        or the geoms' (:mod:`symgen.io.mjcf.geoms`) as ``<compiler inertiafromgeom>`` says."""
        inertials = [c for c, _, _ in items if c.tag == "inertial"]
        geoms = [(c, p, k) for c, p, k in items if c.tag == "geom"]
        mode = self.physics.inertia_from_geoms
        if geoms and (mode == "true" or (mode == "auto" and not inertials)):
            parts = []
            for c, p, k in geoms:
                attrs = self.defaults.attrs(c, k)
                if in_group_range(self.values, attrs, self.physics.group_range):
                    parts.append(geom_inertial(self.values, attrs, p, self.meshes))
            body.inertial = combined(parts)
        elif inertials:
            body.inertial = self._inertial(inertials[0])
        body.joints = [self._joint(*j) for j in items if j[0].tag in ("joint", "freejoint")]
        free = [j for j in body.joints if j.kind == "free"]
        if free and (len(body.joints) > 1 or body.parent != WORLD):
            self.values.fail(next(c for c, _, _ in items if c.tag in ("joint", "freejoint")),
                             "a free joint must be its body's only joint, and the body a child of the world "
                             "(as MuJoCo requires)")

    def _joint(self, el, pose: Pose, childclass: str | None) -> MjcfJoint:
        """A joint with its class, placed in its body by ``pose`` (its enclosing frames)."""
        v = self.values
        attrs = self.defaults.attrs(el, childclass)
        check_neutral(v, "joint", attrs, skip=("springdamper",))
        if el.tag == "freejoint":
            return self._free_joint(el)
        kind = v.keyword(attrs, "type", tuple(JOINT_TYPES), "hinge")
        if el.get("name") is None:
            v.fail(el, "needs a name")
        if kind == "free":
            return self._free_joint(el, attrs)
        ref = v.scalar(attrs, "ref") if kind != "ball" else sp.Integer(0)
        gains = {a: v.scalar(attrs, a) if on else sp.Integer(0) for a, on in
                 (("damping", self.physics.dampers), ("armature", True), ("frictionloss", self.physics.friction),
                  ("stiffness", self.physics.springs))}
        spring_ref = v.scalar(attrs, "springref")
        if kind == "ball" and gains["stiffness"] != 0:
            v.fail(attrs.origin("stiffness"), "a ball joint's spring (MuJoCo's rotational spring toward "
                                              "qpos_spring) is not modelled: give it stiffness='0'")
        springdamper = self._springdamper(attrs, kind)
        return MjcfJoint(el.get("name"), JOINT_TYPES[kind],
                         (pose.pos + pose.rot * sp.Matrix(v.numbers(attrs, "pos", 3, "0 0 0"))).applyfunc(sp.expand),
                         (pose.rot * sp.Matrix(v.direction(attrs, "axis", 3, "0 0 1"))).applyfunc(sp.expand),
                         v.angle(ref) if kind == "hinge" else ref, line=el.sourceline,
                         springref={"hinge": v.angle(spring_ref), "slide": spring_ref}.get(kind, sp.Integer(0)),
                         springdamper=springdamper, **gains)

    def _springdamper(self, attrs: Attrs, kind: str) -> tuple | None:
        """``(timeconst, dampratio)`` of ``springdamper`` (None for ``0 0`` or not given): both
        positive (MuJoCo's rule), on a hinge or slide (:mod:`symgen.io.mjcf.springdamper`)."""
        v = self.values
        pair = v.numbers(attrs, "springdamper", 2, "0 0")
        if pair == (0, 0):
            return None
        if min(pair) <= 0:
            v.fail(attrs.origin("springdamper"), "springdamper: both numbers must be positive (MuJoCo's rule)")
        if kind not in ("hinge", "slide"):
            v.fail(attrs.origin("springdamper"), f"springdamper on a {kind} joint is not read (only a hinge's or "
                                                 "slide's): give stiffness and damping")
        return pair

    def _free_joint(self, el, attrs=None) -> MjcfJoint:
        """A free joint (``<freejoint>`` or ``type="free"``): a floating base, at the body frame; no
        damping, armature or friction loss (symgen's free joint has none)."""
        v, zero = self.values, sp.Integer(0)
        if attrs is None:
            check_neutral(v, "freejoint", Attrs(el, {a: (t, el) for a, t in el.attrib.items()}))
        else:
            for a in ("damping", "armature", "frictionloss", "stiffness"):
                if v.scalar(attrs, a) != 0:
                    v.fail(attrs.origin(a), f"{a} on a free joint is not read (a floating base has none)")
        name = el.get("name") or f"{element_name(el.getparent().get('name'))}_free"
        return MjcfJoint(name, "free", sp.zeros(3, 1), sp.Matrix([0, 0, 1]), zero, line=el.sourceline,
                         damping=zero, armature=zero, frictionloss=zero)

    def _inertial(self, el) -> MjcfInertial:
        """An ``<inertial>``: mass, centre of mass and inertia in the body frame (no classes)."""
        v = self.values
        attrs = Attrs(el, {a: (t, el) for a, t in el.attrib.items()})
        mass, pos = v.numbers(attrs, "mass", 1), v.numbers(attrs, "pos", 3)
        if mass is None or pos is None:
            v.fail(el, "needs mass and pos (the centre of mass)")
        diag, full = v.numbers(attrs, "diaginertia", 3), v.numbers(attrs, "fullinertia", 6)
        if (diag is None) == (full is None):
            v.fail(el, "give exactly one of diaginertia and fullinertia")
        if full is not None:
            if any(a in el.attrib for a in ("quat", "euler", "axisangle", "xyaxes", "zaxis")):
                v.fail(el, "fullinertia is in the body frame: it takes no orientation (as in MuJoCo)")
            ixx, iyy, izz, ixy, ixz, iyz = full
            return MjcfInertial(mass[0], sp.Matrix(pos), sp.Matrix([[ixx, ixy, ixz], [ixy, iyy, iyz],
                                                                    [ixz, iyz, izz]]))
        r = v.rotation(attrs)
        return MjcfInertial(mass[0], sp.Matrix(pos), (r * sp.diag(*diag) * r.T).applyfunc(sp.expand))

    def _site(self, el, pose: Pose, childclass: str | None, body: str) -> MjcfSite:
        """A named site with its class, placed in its body by ``pose``: by its ``pos`` and
        orientation, or by ``fromto`` (MuJoCo's rule, checked against its compiled ``site_quat``: the
        frame halfway between the two points, its z axis along ``from - to`` -- pointing back to
        ``from`` -- by the smallest rotation, as for ``zaxis``; the orientation attributes are then
        not used, and ``pos`` with ``fromto`` is an error)."""
        attrs = self.defaults.attrs(el, childclass)
        v = self.values
        if "fromto" in attrs:
            shape = v.keyword(attrs, "type", ("sphere", "capsule", "ellipsoid", "cylinder", "box"), "sphere")
            if shape not in FROMTO_SHAPES:
                v.fail(attrs.origin("fromto"), f"fromto needs a site of type {', '.join(FROMTO_SHAPES)} "
                                               f"(MuJoCo's rule), not {shape}")
            if el.get("pos") is not None:
                v.fail(el, "gives both pos and fromto (MuJoCo refuses this)")
            ends = v.numbers(attrs, "fromto", 6)
            start, end = sp.Matrix(ends[:3]), sp.Matrix(ends[3:])
            if start == end:
                v.fail(attrs.origin("fromto"), "fromto: the two points must differ")
            placed = pose.compose(Pose((start + end) / 2, v.segment_rotation(attrs.origin("fromto"), start - end)))
            return MjcfSite(element_name(el.get("name")), body, placed.pos, placed.rot, el.sourceline)
        placed = pose.compose(self._pose(attrs))
        return MjcfSite(element_name(el.get("name")), body, placed.pos, placed.rot, el.sourceline)


def check_moving_masses(bodies: list, values: Values) -> None:
    """MuJoCo's rule for the bodies that move: each body with a joint, together with the bodies
    welded to it (its jointless descendants), has mass above :data:`MJMINVAL`, and each of them
    that has mass has principal moments of inertia above it. MuJoCo refuses other models ("mass
    and inertia of moving bodies must be larger than mjMINVAL"); symgen's mass matrix would be
    singular or its bodies point masses."""
    children: dict = {}
    for b in bodies:
        children.setdefault(b.parent, []).append(b)
    for body in bodies:
        if not body.joints:
            continue
        group, mass = [body], 0.0
        for b in group:                       # grows while it is walked: the weld group
            group += [k for k in children.get(b.name, []) if not k.joints]
            if b.inertial is not None and b.inertial.mass != 0:
                mass += float(b.inertial.mass)
                if np.min(np.linalg.eigvalsh(np.array(b.inertial.inertia, dtype=float))) <= MJMINVAL:
                    _fail_mass(b, "its rotational inertia about some axis is not above", values)
        if mass <= MJMINVAL:
            _fail_mass(body, "it moves, with the bodies welded to it, with a mass not above", values)


def _fail_mass(body, why: str, values: Values) -> None:
    """Refuse ``body`` for MuJoCo's moving-mass rule."""
    raise MjcfError(f"<body name={body.name!r}>", f"{why} {MJMINVAL:g} (MuJoCo's mjMINVAL): MuJoCo refuses such a "
                    "moving body too", values.source, body.line)
