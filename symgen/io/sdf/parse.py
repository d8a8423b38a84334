"""Reading an SDF file (SDFormat 1.5 to 1.7, one ``<model>``) into exact, located records; no scene
is built here (:mod:`symgen.io.sdf.build` does that).

What SDF says and how it is read (``sdformat.org/spec``, versions 1.5-1.7):

* A ``<link>``'s ``<pose>`` (x y z roll pitch yaw, fixed axes as URDF's ``rpy``) is its frame in
  the model frame; its ``<inertial><pose>`` is the inertial frame in the link frame, in which
  ``<inertia>`` (``ixx .. iyz``, about the centre of mass) is written.
* A ``<joint>``'s ``<pose>`` is the joint frame **in its child link's frame** (the SDF default; a
  ``relative_to`` or non-empty ``frame`` attribute is refused). Its ``<axis><xyz>`` is in the joint
  frame, unless ``<use_parent_model_frame>`` is true (1.5, 1.6) or ``expressed_in="__model__"``
  (1.7): then it is in the model frame.
* ``<axis><dynamics>``: ``damping`` (viscous, N m s/rad), ``friction`` (Coulomb), ``spring_stiffness``
  and ``spring_reference`` are all read (:mod:`symgen.io.sdf.build` says where each goes).
  ``<limit>`` is kept aside like the URDF reader's: limits act only at the limit.

Every element is on an allow-list (:data:`SCHEMA`): read, ignored with a reason (appearance,
collision shapes, simulator settings), or refused. An element or attribute that is not listed is an
:class:`SdfError` naming it and its line, so nothing is silently dropped. Numbers are read exactly
(``"0.045"`` is 9/200).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction

from ...errors import SceneError
from ..textfile import read_text_file
from ..urdf._deps import require
from ..urdf.inertia import MassProperties
from ..urdf.parse import JointLimits

#: SDFormat versions whose frame conventions this reader implements
VERSIONS = ("1.5", "1.6", "1.7")
#: SDF joint types read: moving ones become scene joints, ``ball`` and ``fixed`` may close loops
#: SDF's own joint type vocabulary (the scene's kinds are asked of ``joint.kind``, not spelled)
SDF_REVOLUTE, SDF_PRISMATIC, SDF_BALL, SDF_FIXED = "revolute", "prismatic", "ball", "fixed"
JOINT_TYPES = (SDF_REVOLUTE, SDF_PRISMATIC, SDF_BALL, SDF_FIXED)
#: the types with one axis
AXIAL = (SDF_REVOLUTE, SDF_PRISMATIC)
INERTIA_KEYS = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")


class SdfError(SceneError):
    """An SDF file is malformed or holds something symgen does not model; names the element and line."""

    def __init__(self, element: str, message: str, source: str | None = None, line: int | None = None):
        where = ", ".join(p for p in (source, f"line {line}" if line else None) if p)
        super().__init__(element, f"{message} ({where})" if where else message)
        self.source, self.line = source, line


#: a subtree accepted and not read, with why the dynamics do not depend on it
IGNORED = {
    "visual": "appearance only", "collision": "contact geometry: contacts act only on touch",
    "sensor": "measurements, no forces", "self_collide": "contacts act only on touch",
    "physics": "the simulator's constraint-solver settings, not the ideal joint",
    "material": "appearance only", "allow_auto_disable": "simulator setting",
    "enable_wind": "no wind in the model", "velocity_decay": "simulator damping, not the robot's",
}
#: element -> (attributes allowed, children read); children in IGNORED are skipped whole
SCHEMA = {
    "sdf": ({"version"}, {"model"}),
    "model": ({"name"}, {"link", "joint", "pose", "static", "plugin"}),
    "link": ({"name"}, {"pose", "inertial"}),
    "inertial": (set(), {"pose", "mass", "inertia"}),
    "inertia": (set(), set(INERTIA_KEYS)),
    "joint": ({"name", "type"}, {"parent", "child", "pose", "axis"}),
    "axis": (set(), {"xyz", "use_parent_model_frame", "limit", "dynamics"}),
    "xyz": ({"expressed_in"}, set()),
    "limit": (set(), {"lower", "upper", "effort", "velocity", "stiffness", "dissipation"}),
    "dynamics": (set(), {"damping", "friction", "spring_reference", "spring_stiffness"}),
    "pose": ({"frame", "relative_to"}, set()),
    "plugin": ({"name", "filename"}, None),        # None: any content (noted, see read_sdf)
}
LEAVES = {"mass", "static", "use_parent_model_frame", "parent", "child", "lower", "upper", "effort", "velocity",
          "stiffness", "dissipation", "damping", "friction", "spring_reference", "spring_stiffness", *INERTIA_KEYS}


@dataclass(frozen=True)
class SdfPose:
    """``x y z roll pitch yaw``, exact as written."""

    xyz: tuple = (Fraction(0),) * 3
    rpy: tuple = (Fraction(0),) * 3


@dataclass(frozen=True)
class SdfLink:
    name: str
    line: int | None
    pose: SdfPose                       # in the model frame
    inertial: MassProperties | None     # in the inertial frame; None: no <inertial>
    inertial_pose: SdfPose              # in the link frame


@dataclass(frozen=True)
class SdfJoint:
    name: str
    line: int | None
    type: str
    parent: str
    child: str
    pose: SdfPose                       # in the child link's frame
    axis: tuple                         # exact, as written (default (0, 0, 1))
    axis_in_model: bool                 # the axis is in the model frame, not the joint frame
    limits: JointLimits
    damping: Fraction = Fraction(0)
    friction: Fraction = Fraction(0)
    stiffness: Fraction = Fraction(0)
    springref: Fraction = Fraction(0)


@dataclass
class SdfModel:
    name: str
    source: str | None
    version: str
    pose: SdfPose
    links: dict = field(default_factory=dict)       # name -> SdfLink, file order
    joints: dict = field(default_factory=dict)      # name -> SdfJoint, file order
    notes: list = field(default_factory=list)


class _Reader:
    def __init__(self, source: str | None):
        self.source = source

    def error(self, node, message: str, element: str | None = None) -> SdfError:
        name = node.get("name")
        what = element or (f"<{node.tag}> {name!r}" if name else f"<{node.tag}>")
        return SdfError(what, message, self.source, node.sourceline)

    def check(self, node) -> None:
        """Attributes and children of ``node`` against :data:`SCHEMA` (recursively)."""
        attrs, children = SCHEMA.get(node.tag, (set(), set()))
        for key in node.attrib:
            if key not in attrs:
                raise self.error(node, f"attribute {key!r} is not supported (allowed: {sorted(attrs) or 'none'})")
        if children is None:
            return
        for child in node:
            if not isinstance(child.tag, str):
                continue
            if child.tag in IGNORED:
                continue
            if child.tag not in children:
                raise self.error(child, f"element <{child.tag}> inside <{node.tag}> is not supported by symgen's "
                                        f"SDF reader (read: {', '.join(sorted(children)) or 'nothing'})")
            if child.tag in LEAVES:
                if len(child) or child.attrib:
                    raise self.error(child, "must be a plain value")
            else:
                self.check(child)

    def number(self, node, default=None) -> Fraction:
        if node is None:
            if default is None:
                raise SdfError("value", "missing", self.source)
            return Fraction(default)
        return self.numbers(node, 1)[0]

    def numbers(self, node, count: int) -> tuple:
        text = (node.text or "").split()
        if len(text) != count:
            raise self.error(node, f"needs {count} number(s), got {len(text)}: {(node.text or '').strip()!r}")
        try:
            values = tuple(Fraction(v) for v in text)
        except (ValueError, ZeroDivisionError):
            raise self.error(node, f"is not a list of numbers: {(node.text or '').strip()!r}") from None
        if any(abs(v) > 10**30 for v in values):
            raise self.error(node, "holds a number beyond 1e30")
        return values

    def pose(self, parent) -> SdfPose:
        node = parent.find("pose")
        if node is None:
            return SdfPose()
        for key in ("frame", "relative_to"):
            if node.get(key):
                raise self.error(node, f"{key}={node.get(key)!r}: only poses in the SDF default frame are read")
        v = self.numbers(node, 6)
        return SdfPose(v[:3], v[3:])

    def flag(self, node) -> bool:
        text = (node.text or "").strip().lower()
        if text not in ("0", "1", "true", "false"):
            raise self.error(node, f"must be true, false, 1 or 0, got {text!r}")
        return text in ("1", "true")

    def link(self, node) -> SdfLink:
        inertial = node.find("inertial")
        props, ipose = None, SdfPose()
        if inertial is not None:
            mass = self.number(inertial.find("mass"), 1)
            if mass < 0:
                raise self.error(inertial.find("mass"), "mass must not be negative", f"link {node.get('name')!r}")
            box = inertial.find("inertia")
            values = {k: self.number(box.find(k) if box is not None else None, 1 if k in ("ixx", "iyy", "izz") else 0)
                      for k in INERTIA_KEYS}
            props, ipose = MassProperties.from_urdf(mass, values), self.pose(inertial)
        return SdfLink(node.get("name"), node.sourceline, self.pose(node), props, ipose)

    def joint(self, node, version: str) -> SdfJoint:
        name, jtype = node.get("name"), node.get("type")
        element = f"joint {name!r}"
        if jtype not in JOINT_TYPES:
            raise self.error(node, f"type {jtype!r} is not supported (symgen reads {', '.join(JOINT_TYPES)})", element)
        ends = {}
        for key in ("parent", "child"):
            found = node.find(key)
            if found is None or not (found.text or "").strip():
                raise self.error(node, f"has no <{key}>", element)
            ends[key] = found.text.strip()
        axis_node = node.find("axis")
        axis, in_model, limits, dyn = (Fraction(0), Fraction(0), Fraction(1)), False, JointLimits(), {}
        if axis_node is not None:
            xyz = axis_node.find("xyz")
            if xyz is not None:
                axis = self.numbers(xyz, 3)
                expressed = xyz.get("expressed_in")
                if expressed not in (None, "", "__model__"):
                    raise self.error(xyz, f"expressed_in={expressed!r}: only the joint frame or __model__ is read",
                                     element)
                in_model = expressed == "__model__"
            upmf = axis_node.find("use_parent_model_frame")
            if upmf is not None:
                if version == "1.7":
                    raise self.error(upmf, "is not part of SDF 1.7 (use expressed_in)", element)
                in_model = self.flag(upmf)
            lim = axis_node.find("limit")
            if lim is not None:
                get = {k: (self.number(lim.find(k)) if lim.find(k) is not None else None)
                       for k in ("lower", "upper", "velocity", "effort")}
                limits = JointLimits(**get)
            d = axis_node.find("dynamics")
            if d is not None:
                dyn = {key: self.number(d.find(tag)) for key, tag in (("damping", "damping"), ("friction", "friction"),
                                                                      ("stiffness", "spring_stiffness"),
                                                                      ("springref", "spring_reference"))
                       if d.find(tag) is not None}
        if jtype in AXIAL and all(v == 0 for v in axis):
            raise self.error(node, "axis must not be zero", element)
        return SdfJoint(name, node.sourceline, jtype, ends["parent"], ends["child"], self.pose(node), axis, in_model,
                        limits, **dyn)


def read_sdf(path_or_text, source: str | None = None) -> SdfModel:
    """The one ``<model>`` of an SDF file (a path, or the file's text starting with ``<``)."""
    etree = require("lxml.etree", "reading SDF files")
    text = str(path_or_text)
    if not text.lstrip().startswith("<"):
        source = source or text
        text = read_text_file(path_or_text, f"SDF file {text!r}", SdfError)
    reader = _Reader(source)
    parser = etree.XMLParser(remove_comments=True, resolve_entities=False, no_network=True)
    try:
        root = etree.fromstring(text.encode("utf-8"), parser)
    except etree.XMLSyntaxError as exc:
        raise SdfError("SDF file", f"is not well-formed XML: {exc}", source) from None
    if root.tag != "sdf":
        raise SdfError(f"<{root.tag}>", "the root element must be <sdf>", source, root.sourceline)
    version = (root.get("version") or "").strip()
    if version not in VERSIONS:
        raise reader.error(root, f"version {version!r} is not read (SDF versions {', '.join(VERSIONS)})", "<sdf>")
    reader.check(root)
    models = root.findall("model")
    if len(models) != 1:
        raise reader.error(root, f"must hold exactly one <model>, found {len(models)}", "<sdf>")
    node = models[0]
    static = node.find("static")
    if static is not None and reader.flag(static):
        raise reader.error(static, "a static model does not move: there is no dynamics to model",
                           f"model {node.get('name')!r}")
    model = SdfModel(node.get("name") or "model", source, version, reader.pose(node))
    for plugin in node.findall("plugin"):
        model.notes.append(f"<plugin> {plugin.get('name')!r} ({plugin.get('filename')}) is simulator code, not read: "
                           "any force it applies is an input tau of the model (line "
                           f"{plugin.sourceline})")
    for child in node:
        if child.tag not in ("link", "joint"):
            continue
        name = child.get("name")
        if not name:
            raise reader.error(child, "has no name")
        table = model.links if child.tag == "link" else model.joints
        if name in table:
            raise reader.error(child, f"a second {child.tag} named {name!r}")
        table[name] = reader.link(child) if child.tag == "link" else reader.joint(child, version)
    for j in model.joints.values():
        for end in (j.parent, j.child):
            if end not in model.links and not (end == "world" and end == j.parent):
                raise SdfError(f"joint {j.name!r}", f"names link {end!r}, which the model does not have", source,
                               j.line)
    return model
