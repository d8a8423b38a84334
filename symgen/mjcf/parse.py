"""Reading an MJCF (MuJoCo XML) file into exact, located data; no scene is built here.

lxml reads the XML: a syntax error reports its line, and every element keeps its ``sourceline``,
so each :class:`MjcfError` names the element *and* the line. Numbers are read from the attribute
text exactly (``"0.3"`` is ``3/10``); angles in degrees (MJCF's default, ``<compiler
angle="degree">``) become exact multiples of pi.

The subset read: ``<compiler angle eulerseq>``, ``<option gravity>``, ``<worldbody>`` with nested
``<body name pos quat|euler|axisangle>``, at most one ``<joint>`` per body (``hinge``, ``slide``,
``ball``; ``pos``, ``axis``, ``damping``, ``armature``, ``frictionloss``), ``<inertial pos mass
diaginertia|fullinertia quat|euler|axisangle>``, ``<site name pos quat|euler|axisangle>``,
``<equality>`` with ``<connect body1 body2 anchor>`` and ``<weld body1 body2 anchor relpose>``,
and the actuated joints of ``<actuator>`` (``motor``, ``position``, ``velocity``, ``general``).
Everything else that changes the dynamics (``free`` joints, ``ref``, several joints in one body,
inertia from geoms, ``xyaxes``/``zaxis`` frames, ``fromto``) is a typed error, never ignored.
"""
from __future__ import annotations

from dataclasses import dataclass, field
import sympy as sp

from ..errors import SceneError
from ..numbers import parse_exact
from ..spatial import exact_quat, exact_rot
from ..textfile import read_text_file
from ..urdf._deps import require

#: MJCF joint types read, and the symgen joint kind of each
JOINT_TYPES = {"hinge": "revolute", "slide": "prismatic", "ball": "spherical"}
ACTUATORS = ("motor", "position", "velocity", "general")
#: MJCF defaults (mjModel documentation)
DEFAULT_GRAVITY = ("0", "0", "-9.81")


class MjcfError(SceneError):
    """An MJCF file is malformed or holds something symgen cannot model; names the element and,
    where known, the file and line."""

    def __init__(self, element: str, message: str, source: str | None = None, line: int | None = None):
        where = ", ".join(p for p in (source, f"line {line}" if line else None) if p)
        super().__init__(element, f"{message} ({where})" if where else message)
        self.source, self.line = source, line


@dataclass
class MjcfJoint:
    name: str
    kind: str                 # symgen joint kind
    pos: tuple
    axis: tuple
    damping: sp.Expr
    armature: sp.Expr
    frictionloss: sp.Expr
    line: int | None


@dataclass
class MjcfInertial:
    mass: sp.Expr
    pos: tuple
    inertia: sp.Matrix        # about the centre of mass, in the body frame


@dataclass
class MjcfBody:
    name: str
    parent: str
    pos: tuple
    rot: sp.Matrix
    joint: MjcfJoint | None
    inertial: MjcfInertial | None
    sites: list = field(default_factory=list)   # (name, pos, rot, line)
    line: int | None = None


@dataclass
class MjcfEquality:
    kind: str                 # connect | weld
    name: str
    body1: str
    body2: str
    anchor: tuple
    relpose: tuple | None     # weld: (pos, rot) of body2 in body1, or None (pose at qpos0)
    line: int | None


@dataclass
class MjcfModel:
    name: str
    gravity: tuple
    bodies: list              # parents first
    equalities: list
    actuated: list            # joint names
    source: str
    text: str


class _Reader:
    def __init__(self, source: str, degrees: bool = True, eulerseq: str = "xyz"):
        self.source, self.degrees, self.eulerseq = source, degrees, eulerseq

    def fail(self, el, message: str):
        name = el.get("name")
        element = f"<{el.tag}{f' name={name!r}' if name else ''}>"
        raise MjcfError(element, message, self.source, el.sourceline)

    def numbers(self, el, attr: str, count: int, default=None) -> tuple | None:
        text = el.get(attr)
        if text is None:
            return None if default is None else tuple(parse_exact(v) for v in default)
        parts = text.split()
        if len(parts) != count:
            self.fail(el, f"{attr}={text!r} must have {count} numbers")
        try:
            values = tuple(parse_exact(p) for p in parts)
        except ValueError:
            values = None
        if values is None or not all(v.is_number for v in values):
            self.fail(el, f"{attr}={text!r} is not a list of numbers")
        return values

    def angle(self, value):
        return sp.pi * sp.nsimplify(value) / 180 if self.degrees else sp.nsimplify(value)

    def rotation(self, el) -> sp.Matrix:
        """The orientation of ``el`` (``quat``, ``euler`` or ``axisangle``; identity if none)."""
        given = [a for a in ("quat", "euler", "axisangle", "xyaxes", "zaxis") if el.get(a) is not None]
        if len(given) > 1:
            self.fail(el, f"gives {', '.join(given)}: at most one orientation")
        if not given:
            return sp.eye(3)
        if given[0] in ("xyaxes", "zaxis"):
            self.fail(el, f"{given[0]} orientations are not read; use quat, euler or axisangle")
        if given[0] == "quat":
            q = self.numbers(el, "quat", 4)
            if all(v == 0 for v in q):
                self.fail(el, "quat must not be zero")
            return sp.Matrix(exact_quat(*(sp.nsimplify(v) for v in q))).applyfunc(sp.simplify)
        if given[0] == "axisangle":
            *axis, a = self.numbers(el, "axisangle", 4)
            axis = sp.Matrix([sp.nsimplify(v) for v in axis])
            if axis.norm() == 0:
                self.fail(el, "axisangle axis must not be zero")
            k = axis / axis.norm()
            half = self.angle(a) / 2
            return sp.Matrix(exact_quat(sp.cos(half), *(sp.sin(half) * k))).applyfunc(sp.simplify)
        angles = self.numbers(el, "euler", 3)
        r = sp.eye(3)
        for axis_name, a in zip(self.eulerseq, angles):
            step = exact_rot("xyz".index(axis_name.lower()), self.angle(a))
            r = r * step if axis_name.islower() else step * r     # lowercase: rotating axes
        return r.applyfunc(sp.simplify)


def _inertial(rd: _Reader, el) -> MjcfInertial:
    mass = rd.numbers(el, "mass", 1)
    if mass is None:
        rd.fail(el, "needs mass")
    pos = rd.numbers(el, "pos", 3)
    if pos is None:
        rd.fail(el, "needs pos (the centre of mass)")
    diag, full = rd.numbers(el, "diaginertia", 3), rd.numbers(el, "fullinertia", 6)
    if (diag is None) == (full is None):
        rd.fail(el, "give exactly one of diaginertia and fullinertia")
    if diag is not None:
        inertia = sp.diag(*diag)
    else:
        ixx, iyy, izz, ixy, ixz, iyz = full
        inertia = sp.Matrix([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
    r = rd.rotation(el)
    return MjcfInertial(mass[0], pos, (r * inertia * r.T).applyfunc(sp.simplify))


def _joint(rd: _Reader, el) -> MjcfJoint:
    kind = el.get("type", "hinge")
    if kind not in JOINT_TYPES:
        rd.fail(el, f"type {kind!r} is not read; use hinge, slide or ball (a free joint is a floating base)")
    if el.get("name") is None:
        rd.fail(el, "needs a name")
    ref = rd.numbers(el, "ref", 1, default=("0",))
    if ref[0] != 0:
        rd.fail(el, "ref must be 0: the body placement is the joint's zero")
    values = {a: rd.numbers(el, a, 1, default=("0",))[0] for a in ("damping", "armature", "frictionloss")}
    return MjcfJoint(el.get("name"), JOINT_TYPES[kind], rd.numbers(el, "pos", 3, ("0", "0", "0")),
                     rd.numbers(el, "axis", 3, ("0", "0", "1")), line=el.sourceline, **values)


def _body(rd: _Reader, el, parent: str, out: list) -> None:
    name = el.get("name")
    if name is None:
        rd.fail(el, "needs a name")
    joints = el.findall("joint") + el.findall("freejoint")
    if len(joints) > 1:
        rd.fail(el, f"has {len(joints)} joints; one joint per body is read (put the others in massless child bodies)")
    inertials = el.findall("inertial")
    if not inertials and el.findall("geom"):
        rd.fail(el, "has geoms but no <inertial>: inertia from geoms is not read; give <inertial>")
    body = MjcfBody(name, parent, rd.numbers(el, "pos", 3, ("0", "0", "0")), rd.rotation(el),
                    _joint(rd, joints[0]) if joints else None, _inertial(rd, inertials[0]) if inertials else None,
                    line=el.sourceline)
    for site in el.findall("site"):
        if site.get("name") is None:
            rd.fail(site, "needs a name")
        body.sites.append((site.get("name"), rd.numbers(site, "pos", 3, ("0", "0", "0")), rd.rotation(site),
                           site.sourceline))
    out.append(body)
    for child in el.findall("body"):
        _body(rd, child, name, out)


def _equalities(rd: _Reader, root) -> list:
    out = []
    for eq in root.iter("equality"):
        for k, el in enumerate(eq):
            if not isinstance(el.tag, str):
                continue
            if el.tag not in ("connect", "weld"):
                rd.fail(el, "only connect and weld equalities are read")
            if el.get("body1") is None or el.get("site1") is not None:
                rd.fail(el, "needs body1 (site-based equalities are not read)")
            relpose = None
            if el.tag == "weld" and el.get("relpose") is not None:
                values = rd.numbers(el, "relpose", 7)
                if any(v != 0 for v in values[3:]):
                    relpose = (values[:3], sp.Matrix(exact_quat(*(sp.nsimplify(v) for v in values[3:]))))
            anchor = rd.numbers(el, "anchor", 3, ("0", "0", "0"))
            if el.tag == "connect" and el.get("anchor") is None:
                rd.fail(el, "needs anchor")
            out.append(MjcfEquality(el.tag, el.get("name") or f"{el.tag}{len(out)}", el.get("body1"),
                                    el.get("body2", "world"), anchor, relpose, el.sourceline))
    return out


def parse_mjcf_text(text: str, source: str = "<string>") -> MjcfModel:
    """An :class:`MjcfModel` from MJCF text (``source`` names it in errors)."""
    etree = require("lxml.etree", "the MJCF reader")
    try:
        root = etree.fromstring(text.encode("utf-8"), etree.XMLParser(remove_comments=True, resolve_entities=False))
    except etree.XMLSyntaxError as exc:
        raise MjcfError("MJCF file", f"is not well-formed XML: {exc.msg}", source, exc.lineno) from None
    if root.tag != "mujoco":
        raise MjcfError(f"<{root.tag}>", "the root element must be <mujoco>", source, root.sourceline)
    compiler = root.find("compiler")
    angle = compiler.get("angle", "degree") if compiler is not None else "degree"
    rd = _Reader(source, angle == "degree", compiler.get("eulerseq", "xyz") if compiler is not None else "xyz")
    if angle not in ("degree", "radian") or len(rd.eulerseq) != 3 or any(c not in "xyzXYZ" for c in rd.eulerseq):
        rd.fail(compiler, "angle must be degree or radian and eulerseq three of x, y, z, X, Y, Z")
    option = root.find("option")
    gravity = rd.numbers(option, "gravity", 3, DEFAULT_GRAVITY) if option is not None else \
        tuple(parse_exact(v) for v in DEFAULT_GRAVITY)
    world = root.find("worldbody")
    if world is None:
        raise MjcfError("<mujoco>", "has no <worldbody>", source, root.sourceline)
    bodies: list = []
    for el in world.findall("body"):
        _body(rd, el, "world", bodies)
    names = {b.name for b in bodies} | {"world"}
    if len(names) != len(bodies) + 1:
        raise MjcfError("<worldbody>", "body names must be unique and not 'world'", source, world.sourceline)
    equalities = _equalities(rd, root)
    for eq in equalities:
        for b in (eq.body1, eq.body2):
            if b not in names:
                raise MjcfError(f"<{eq.kind} name={eq.name!r}>", f"body {b!r} is not declared", source, eq.line)
    joints = {b.joint.name for b in bodies if b.joint}
    actuated = []
    for act in root.iter("actuator"):
        for el in act:
            if isinstance(el.tag, str) and el.tag in ACTUATORS:
                if el.get("joint") not in joints:
                    rd.fail(el, f"joint {el.get('joint')!r} is not declared")
                actuated.append(el.get("joint"))
    name = root.get("model", "mjcf_robot")
    return MjcfModel(name, gravity, bodies, equalities, actuated, source, text)


def parse_mjcf(path) -> MjcfModel:
    """An :class:`MjcfModel` from an MJCF file."""
    text = read_text_file(path, "MJCF file", MjcfError)
    return parse_mjcf_text(text, str(path))
