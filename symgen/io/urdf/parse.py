"""Reading a URDF file into exact, located data (:class:`UrdfRobot`); no scene is built here.

Two parsers share the work, each doing what it does well:

* **lxml** reads the XML. A syntax error reports its line, and every ``<link>``/``<joint>``
  element keeps its ``sourceline``, so each error below names the element *and* the line.
  Numbers are read from the attribute text exactly (``"0.089159"`` is the ``Fraction``
  89159/10**6), and ``<origin rpy>`` angles are kept as written. yourdfpy composes every origin
  into a float 4x4 matrix, which loses the angles the importer needs to recognise exact
  multiples of pi/2 (:mod:`symgen.io.urdf.rotations`), and it keeps no line numbers.
* **yourdfpy**, the maintained URDF reader, then parses the same element tree into its ``Robot``
  and validates it against the URDF specification (required attributes, allowed joint types,
  ``<limit>`` on revolute and prismatic joints). Its findings become :class:`UrdfError`. It runs
  after the located reading, so every problem that reading can place is reported with its line
  first.

On top of both, the kinematic tree is checked: every joint's parent and child link exist, no link
has two parent joints, there is exactly one root, and there is no cycle. Masses must not be
negative. An inertia entry below :data:`TINY` = 1e-30 kg m^2, or below 1e-30 times the
inertia's largest entry (the iCub's ``2.4e-35``: no double sum can tell it from zero), is read as
zero, with a note; so is an origin value below 1e-30 (m or rad). Whether each rotational inertia is
one of a rigid body is judged later, where the link ends up (:mod:`symgen.io.urdf.physics`). Zero
or missing inertials are allowed here; :mod:`symgen.io.urdf.build` refuses them only where they
make the mass matrix singular.

A ``<limit>`` with neither ``lower`` nor ``upper`` on a revolute or prismatic joint (written for
wheels and other joints that turn freely) is read as having no position limits, with a note; the
URDF default ``[0, 0]`` would describe a joint that cannot move. yourdfpy, which insists on both
attributes, is shown the element tree with them filled in. Limits do not enter the dynamics.
"""
from __future__ import annotations

import os
from copy import deepcopy
from dataclasses import dataclass, field
from fractions import Fraction

from ...scene import input_limits as limits
from ...errors import SceneError
from ..textfile import read_text_file
from ._deps import require
from .inertia import MassProperties
from .tree_check import check_tree

#: joint types symgen imports; ``floating`` and ``planar`` are refused by :mod:`symgen.io.urdf.build`
URDF_JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")
#: URDF types (the URDF vocabulary, not symgen's joint kinds) that need a ``<limit>``, whose lower
#: and upper limits default to 0
LIMITED_TYPES = ("revolute", "prismatic")
#: URDF types that move along or about their ``<axis>``
AXIS_TYPES = ("revolute", "continuous", "prismatic")
#: origin values and inertia entries below this magnitude (SI units: 1e-30 m, rad, kg m^2, the floor
#: of :mod:`symgen.scene.input_limits`) are read as zero, and so are inertia entries below this
#: share of the inertia's largest entry
TINY = Fraction(1, 10**limits.MAX_EXPONENT)


class UrdfError(SceneError):
    """A URDF file is malformed or describes something symgen cannot model.

    ``element`` names the link or joint (``"joint 'elbow'"``); ``source`` and ``line`` say where,
    when the parser knows it (they are also appended to the message).
    """

    def __init__(self, element: str, message: str, source: str | None = None, line: int | None = None):
        where = ", ".join(p for p in (source, f"line {line}" if line else None) if p)
        super().__init__(element, f"{message} ({where})" if where else message)
        self.source, self.line = source, line
        self.located = line is not None   # a scene file reader keeps the URDF line, adds none


@dataclass(frozen=True)
class Origin:
    """An ``<origin>``: translation ``xyz`` and fixed-axis ``rpy`` angles, exact as written."""

    xyz: tuple = (Fraction(0),) * 3
    rpy: tuple = (Fraction(0),) * 3


@dataclass(frozen=True)
class UrdfLink:
    name: str
    line: int | None
    inertial: MassProperties | None   # in the inertial frame; None: no <inertial>
    inertial_origin: Origin | None
    inertia_line: int | None = None


@dataclass(frozen=True)
class JointLimits:
    """``<limit>`` of a joint (``None`` where the file gives nothing)."""

    lower: Fraction | None = None
    upper: Fraction | None = None
    velocity: Fraction | None = None
    effort: Fraction | None = None


@dataclass(frozen=True)
class UrdfJoint:
    name: str
    line: int | None
    type: str
    parent: str
    child: str
    origin: Origin
    axis: tuple                       # exact, as written (default (1, 0, 0) as the URDF spec says)
    limits: JointLimits
    damping: Fraction
    friction: Fraction
    mimic: UrdfMimic | None


@dataclass(frozen=True)
class UrdfMimic:
    """``<mimic joint= multiplier= offset=>``: this joint's position is ``multiplier * q_joint +
    offset`` (exact; the URDF defaults 1 and 0)."""

    joint: str
    multiplier: Fraction = Fraction(1)
    offset: Fraction = Fraction(0)


@dataclass
class UrdfRobot:
    """A parsed, tree-checked URDF: links and joints by name, in file order."""

    name: str
    source: str
    text: str
    links: dict = field(default_factory=dict)
    joints: dict = field(default_factory=dict)
    root: str = ""
    children: dict = field(default_factory=dict)   # link -> [joint names], file order
    notes: list = field(default_factory=list)      # what was read other than as written (tiny entries...)

    def error(self, element: str, message: str, line: int | None = None) -> UrdfError:
        return UrdfError(element, message, self.source, line)


# ----------------------------------------------------------------------------- numbers
def _mimic(el, element: str, source) -> UrdfMimic | None:
    """The ``<mimic>`` of a joint, its numbers exact; a missing ``joint`` or a number that is not
    one is a :class:`UrdfError` naming the joint."""
    if el is None:
        return None
    leader = el.get("joint")
    if not leader:
        raise UrdfError(element, "<mimic> has no joint attribute (the joint it follows)", source, el.sourceline)
    values = {key: _number(el.get(key), element, f"mimic {key}", source, el.sourceline)
              for key in ("multiplier", "offset") if el.get(key) is not None}
    return UrdfMimic(leader, **values)


def _number(text, element: str, what: str, source, line, magnitude: bool = True) -> Fraction:
    """The exact value of an attribute's number text, within :mod:`symgen.scene.input_limits` (the
    magnitude bound only if ``magnitude``)."""
    text = str(text).strip()
    problem = limits.number_text_problem(text)
    if problem is None:
        try:
            value = Fraction(text)
        except (ValueError, ZeroDivisionError):
            raise UrdfError(element, f"{what} {text[:40]!r} is not a finite number", source, line) from None
        problem = limits.magnitude_problem(value) if magnitude else None
        if problem is None:
            return value
    raise UrdfError(element, f"{what} {text[:40]!r}: {problem}", source, line)


def _vector(text, n: int, element: str, what: str, source, line, notes: list | None = None) -> tuple:
    """``n`` exact numbers; with ``notes``, those below :data:`TINY` in magnitude become 0 (noted)."""
    parts = str(text).split()
    if len(parts) != n:
        raise UrdfError(element, f"{what} must hold {n} numbers, got {text!r}", source, line)
    if notes is None:
        return tuple(_number(p, element, what, source, line) for p in parts)
    values = [_number(p, element, what, source, line, magnitude=False) for p in parts]
    return tuple(_tiny_to_zero(v, p, TINY, element, what, source, line, notes) for v, p in zip(values, parts))


def _tiny_to_zero(value: Fraction, text: str, below, element: str, what: str, source, line, notes: list) -> Fraction:
    """0 (and a note) when ``0 < |value| < below``; else ``value`` within the magnitude bound."""
    if value and abs(value) < below:
        notes.append(f"{element}: {what} {float(value):.3g} is below {float(below):.3g}: read as 0 (line {line})")
        return Fraction(0)
    problem = limits.magnitude_problem(value)
    if problem is not None:
        raise UrdfError(element, f"{what} {text[:40]!r}: {problem}", source, line)
    return value


def _origin(el, element: str, source, notes: list) -> Origin:
    if el is None:
        return Origin()
    line = el.sourceline
    return Origin(_vector(el.get("xyz", "0 0 0"), 3, element, "origin xyz", source, line, notes),
                  _vector(el.get("rpy", "0 0 0"), 3, element, "origin rpy", source, line, notes))


# ----------------------------------------------------------------------------- XML
def _load_xml(path_or_text):
    """``(root element, source name, text)``; a path, or a string holding the XML itself."""
    etree = require("lxml.etree", "reading URDF files")
    is_text = isinstance(path_or_text, str) and path_or_text.lstrip().startswith("<")
    source = "<string>" if is_text else str(path_or_text)
    if is_text:
        text = path_or_text
    else:
        text = read_text_file(path_or_text, f"URDF file {source!r}", UrdfError)
    problem = limits.text_problem(text)
    if problem is not None:
        raise UrdfError(f"URDF file {os.path.basename(source)!r}", problem[1], source, problem[0])
    parser = etree.XMLParser(remove_comments=True, resolve_entities=False, no_network=True)
    try:
        root = etree.fromstring(text.encode("utf-8"), parser)
    except etree.XMLSyntaxError as exc:
        raise UrdfError(f"URDF file {os.path.basename(source)!r}", f"malformed XML: {exc.msg}",
                        source, exc.lineno) from None
    if root.tag != "robot":
        raise UrdfError(f"URDF file {os.path.basename(source)!r}",
                        f"the root element is <{root.tag}>, expected <robot>", source, root.sourceline)
    return root, source, text


def _named(elements, kind: str, source) -> dict:
    """``name -> element``; a missing or repeated name is an error at its line."""
    out = {}
    for el in elements:
        name = el.get("name")
        if not name:
            raise UrdfError(f"<{kind}>", "has no name attribute", source, el.sourceline)
        if name in out:
            raise UrdfError(f"{kind} {name!r}", f"is declared twice (lines {out[name].sourceline} and "
                                                f"{el.sourceline})", source, el.sourceline)
        out[name] = el
    return out


def _joint_structure(el, source) -> tuple[str, str, str]:
    """``(type, parent, child)`` of a ``<joint>``, checked at its line."""
    element = f"joint {el.get('name')!r}"
    kind = el.get("type")
    if kind not in URDF_JOINT_TYPES:
        raise UrdfError(element, f"type {kind!r} is not a URDF joint type ({', '.join(URDF_JOINT_TYPES)})",
                        source, el.sourceline)
    links = []
    for role in ("parent", "child"):
        sub = el.find(role)
        if sub is None or not sub.get("link"):
            raise UrdfError(element, f"has no <{role} link=...>", source, el.sourceline)
        links.append(sub.get("link"))
    if kind in LIMITED_TYPES and el.find("limit") is None:
        raise UrdfError(element, f"a {kind} joint needs a <limit> (URDF specification)", source, el.sourceline)
    return kind, links[0], links[1]


def _yourdfpy_check(root, source) -> None:
    """yourdfpy's parse and validation of the element tree (meshes are never loaded)."""
    yourdfpy = require("yourdfpy", "reading URDF files")
    root = _limits_filled(root)
    errors: list = []
    try:
        robot = yourdfpy.URDF._parse_robot(root)
        urdf = yourdfpy.URDF(robot=robot, build_scene_graph=False, build_collision_scene_graph=False,
                             load_meshes=False, load_collision_meshes=False)
        urdf.validate(validation_fn=lambda errs: (errors.extend(errs), not errs)[1])
    except Exception as exc:  # noqa: BLE001 - a third-party reader: whatever it raises, it cannot read the file
        element, line = _yourdfpy_culprit(yourdfpy, root) or (f"URDF file {os.path.basename(source)!r}", None)
        raise UrdfError(element, f"yourdfpy cannot read it ({type(exc).__name__}: {exc})", source, line) from None
    if errors:
        raise UrdfError(f"robot {robot.name!r}", f"invalid URDF (yourdfpy): {errors[0].msg}", source)


def _limits_filled(root):
    """A copy of the element tree in which every ``<limit>`` of a revolute or prismatic joint has
    ``lower`` and ``upper`` (0 where missing, the URDF default); yourdfpy requires both."""
    copy = None
    for index, joint in enumerate(root.findall("joint")):
        limit = joint.find("limit")
        bounds = (limit.get("lower"), limit.get("upper")) if limit is not None else ()
        if joint.get("type") in LIMITED_TYPES and None in bounds:
            if copy is None:
                copy = deepcopy(root)
            filled = copy.findall("joint")[index].find("limit")
            for key in ("lower", "upper"):
                filled.set(key, filled.get(key) or "0")
    return root if copy is None else copy


def _yourdfpy_culprit(yourdfpy, root) -> tuple[str, int] | None:
    """``(element, line)`` of the first ``<link>``, ``<joint>`` or ``<material>`` yourdfpy cannot
    parse on its own (it indexes sub-elements without checking them), or None."""
    parsers = (("link", yourdfpy.URDF._parse_link), ("joint", yourdfpy.URDF._parse_joint),
               ("material", yourdfpy.URDF._parse_material))
    for kind, parse in parsers:
        for el in root.findall(kind):
            try:
                parse(el)
            except Exception:  # noqa: BLE001 - locating the failure reported by the caller
                return f"{kind} {el.get('name')!r}", el.sourceline
    return None


# ----------------------------------------------------------------------------- elements
def _link(el, source, notes: list) -> UrdfLink:
    name, element = el.get("name"), f"link {el.get('name')!r}"
    inertial = el.find("inertial")
    if inertial is None:
        return UrdfLink(name, el.sourceline, None, None)
    mass_el, inertia_el = inertial.find("mass"), inertial.find("inertia")
    if mass_el is None or mass_el.get("value") is None:
        raise UrdfError(element, "<inertial> has no <mass value=...>", source, inertial.sourceline)
    mass = _number(mass_el.get("value"), element, "mass", source, mass_el.sourceline)
    if mass < 0:
        raise UrdfError(element, f"mass {float(mass):g} is negative", source, mass_el.sourceline)
    if inertia_el is None:
        raise UrdfError(element, "<inertial> has no <inertia .../>", source, inertial.sourceline)
    values = _inertia_values(inertia_el, element, source, notes)
    origin = _origin(inertial.find("origin"), element, source, notes)
    return UrdfLink(name, el.sourceline, MassProperties.from_urdf(mass, values), origin, inertia_el.sourceline)


def _inertia_values(inertia_el, element: str, source, notes: list) -> dict:
    """``ixx .. iyz`` exactly; entries below :data:`TINY` (kg m^2) or below :data:`TINY` times the
    largest entry become 0 (noted)."""
    line, values = inertia_el.sourceline, {}
    for key in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz"):
        text = inertia_el.get(key)
        if text is None and key in ("ixx", "iyy", "izz"):
            raise UrdfError(element, f"<inertia> has no {key}", source, line)
        values[key] = _number(text or 0, element, f"inertia {key}", source, line, magnitude=False)
    below = TINY * max(1, *(abs(v) for v in values.values()))
    return {key: _tiny_to_zero(value, inertia_el.get(key) or "0", below, element, f"inertia {key}", source, line,
                               notes) for key, value in values.items()}


def _joint(el, source, notes: list) -> UrdfJoint:
    name, element, line = el.get("name"), f"joint {el.get('name')!r}", el.sourceline
    kind, parent, child = _joint_structure(el, source)
    axis_el, limit_el, dyn_el = el.find("axis"), el.find("limit"), el.find("dynamics")
    axis = (_vector(axis_el.get("xyz", "1 0 0"), 3, element, "axis xyz", source, axis_el.sourceline)
            if axis_el is not None else (Fraction(1), Fraction(0), Fraction(0)))
    if kind in AXIS_TYPES and not any(axis):
        raise UrdfError(element, "axis is the zero vector", source, axis_el.sourceline if axis_el is not None else line)
    limits = JointLimits()
    if limit_el is not None:
        at = limit_el.sourceline
        get = lambda key: (None if limit_el.get(key) is None  # noqa: E731
                           else _number(limit_el.get(key), element, f"limit {key}", source, at))
        limits = JointLimits(get("lower"), get("upper"), get("velocity"), get("effort"))
        if kind in LIMITED_TYPES and limits.lower is None and limits.upper is None:
            notes.append(f"{element}: <limit> gives neither lower nor upper: read as no position limits "
                         f"(line {at})")
        elif kind in LIMITED_TYPES:  # the URDF spec: lower and upper default to 0
            limits = JointLimits(limits.lower or Fraction(0), limits.upper or Fraction(0), limits.velocity,
                                 limits.effort)
            if limits.lower > limits.upper:
                raise UrdfError(element, f"limit lower {float(limits.lower):g} > upper {float(limits.upper):g}",
                                source, at)
    friction = {}
    for key in ("damping", "friction"):
        text = dyn_el.get(key) if dyn_el is not None else None
        friction[key] = Fraction(0) if text is None else _number(text, element, f"dynamics {key}", source,
                                                                 dyn_el.sourceline)
        if friction[key] < 0:
            raise UrdfError(element, f"dynamics {key} {float(friction[key]):g} is negative", source,
                            dyn_el.sourceline)
    mimic = _mimic(el.find("mimic"), element, source)
    return UrdfJoint(name, line, kind, parent, child, _origin(el.find("origin"), element, source, notes),
                     axis, limits, friction["damping"], friction["friction"], mimic)


def read_urdf(path_or_text) -> UrdfRobot:
    """Parse a URDF file (or URDF text) into a :class:`UrdfRobot` with exact numbers.

    Raises:
        UrdfError: malformed XML, a missing or bad attribute, a negative mass, a joint whose
            parent or child link does not exist, two roots, or a cycle;
            the message names the link or joint and gives the file and line.
        MissingExtraError: yourdfpy (extra ``urdf``) is not installed.
    """
    root, source, text = _load_xml(path_or_text)
    if root.find("link") is None:
        raise UrdfError("<robot>" if not root.get("name") else f"robot {root.get('name')!r}",
                        "has no <link>: the description is empty, there is nothing to model", source, root.sourceline)
    unnamed = not root.get("name")
    if unnamed:       # required by the URDF specification; Pinocchio refuses such a file
        if source == "<string>":
            raise UrdfError("<robot>", "has no name attribute", source, root.sourceline)
        root.set("name", os.path.splitext(os.path.basename(source))[0])
    robot = UrdfRobot(root.get("name"), source, text)
    if unnamed:
        robot.notes.append(f"<robot> has no name attribute (the URDF specification requires one): named "
                           f"{robot.name!r} after the file")
    for name, el in _named(root.findall("link"), "link", source).items():
        robot.links[name] = _link(el, source, robot.notes)
    for name, el in _named(root.findall("joint"), "joint", source).items():
        robot.joints[name] = _joint(el, source, robot.notes)
    _yourdfpy_check(root, source)
    check_tree(robot)
    return robot
