"""What symgen does with each element and attribute of MuJoCo's MJCF schema: an explicit allow-list.

Every element symgen meets is one of

* **read** -- an :class:`Element` below: each of its attributes is read with MuJoCo's meaning
  (``READ``), accepted and ignored because it does not change the equations of motion
  (:class:`Ignored`, with the reason), or accepted only at the value that leaves the dynamics
  unchanged (:class:`Neutral`, e.g. a joint's ``stiffness="0"``). Any other attribute is an
  :class:`~symgen.io.mjcf.values.MjcfError` naming the element and the line;
* **ignored** with its whole content (:class:`Ignored`): rendering, sensors, stored states, contacts;
* **refused** (:class:`Refused`): it changes the dynamics in a way symgen does not model.

An element of MJCF that is not listed is refused too, so nothing new is silently accepted.

symgen models the smooth dynamics of the robot between contacts and inside its joint limits:
contacts and joint limits are inequality constraints that act only on touch or at a limit, so their
data (geoms' collision properties, ``<contact>``, ``range``) are accepted and not used -- as the
URDF reader keeps ``<limit>`` aside. MuJoCo's softening of constraints (``solref``, ``solimp``) and
its integrator settings shape how a simulation approximates the ideal constraint, not the ideal
constraint itself, which is what symgen derives.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from .values import DECIMAL, Attrs, MjcfError, Values, describe

READ = "read"


@dataclass(frozen=True)
class Ignored:
    """Accepted and not read; ``reason`` says why the dynamics do not depend on it."""

    reason: str


@dataclass(frozen=True)
class Neutral:
    """Accepted only at ``value`` (numbers compared exactly); ``reason`` says what any other value does."""

    value: str
    reason: str


@dataclass(frozen=True)
class Refused:
    """An element symgen refuses wherever it appears; ``reason`` says what it would change."""

    reason: str


@dataclass(frozen=True)
class Element:
    attributes: dict
    children: dict = field(default_factory=dict)   # tag -> element key | Ignored | Refused


# ------------------------------------------------------------------ reasons
LOOKS = Ignored("rendering only")
LABEL = Ignored("a label or a group for the viewer")
USER = Ignored("user data, read by user code only")
LIMIT = Ignored("a joint limit acts only at the limit; symgen models the motion inside the range")
SOFT = Ignored("how MuJoCo's solver softens the constraint, not the ideal constraint symgen derives")
NUMERICS = Ignored("the simulator's numerical method or tolerances, not the equations of motion")
CONTACT = Ignored("contacts are not part of symgen's model (the dynamics between contacts)")
INPUT = Ignored("how the control signal becomes the joint's force; symgen takes that force as the input tau")
FILES = Ignored("where texture and height-field files are found; they give no mass")
FIT = Ignored("fits a primitive geom to a mesh, which symgen refuses where the geom gives mass")
REFUSED_PLUGIN = Refused("a plugin computes forces symgen cannot see")
REFUSED_INCLUDE = Refused("an <include> is expanded when the file is read from a path (parse_mjcf); from "
                          "text there is no directory to find the included file in")
REFUSED_MACRO = Refused("model-building macros (replicate, attach, composite, flexcomp) are not expanded: "
                        "write the bodies out")

ORIENTATION = {"quat": READ, "euler": READ, "axisangle": READ, "xyaxes": READ, "zaxis": READ}
POSE = {"pos": READ, **ORIENTATION}

JOINT = {
    "class": READ, "type": READ, "pos": READ, "axis": READ, "ref": READ,
    "damping": READ, "armature": READ, "frictionloss": READ,
    "stiffness": READ, "springref": READ,
    "springdamper": READ,
    "limited": LIMIT, "range": LIMIT, "margin": LIMIT, "solreflimit": LIMIT, "solimplimit": LIMIT,
    "solreffriction": SOFT, "solimpfriction": SOFT,
    "actuatorfrcrange": INPUT, "actuatorfrclimited": INPUT,
    "actuatorgravcomp": Ignored("routes gravity compensation, which must be 0 (body gravcomp)"),
    "group": LABEL, "user": USER,
}
GEOM = {
    "class": READ, "type": READ, "size": READ, **POSE, "fromto": READ, "mass": READ, "density": READ, "group": READ,
    "shellinertia": READ, "mesh": READ, "hfield": READ,
    "fitscale": FIT, "contype": CONTACT, "conaffinity": CONTACT, "condim": CONTACT, "priority": CONTACT,
    "friction": CONTACT, "solmix": CONTACT, "solref": CONTACT, "solimp": CONTACT, "margin": CONTACT, "gap": CONTACT,
    "rgba": LOOKS, "material": LOOKS, "user": USER,
    "fluidshape": Ignored("shapes the fluid forces, which act only in a medium of nonzero <option density> or "
                          "viscosity (refused unless fluid='ignore', which leaves them out)"),
    "fluidcoef": Ignored("coefficients of the fluid forces (see fluidshape)"),
}
#: a tendon applies force only through its limits (ignored, like joint limits), its actuators (not joint
#: inputs: noted) and its passive terms, which must be neutral
TENDON_PATH = Ignored("the tendon's path; a tendon without stiffness, damping or friction loss applies force "
                      "only at its length limits and through its actuators")
TENDON = {
    "class": READ, "limited": LIMIT, "range": LIMIT, "margin": LIMIT, "solreflimit": LIMIT, "solimplimit": LIMIT,
    "solreffriction": SOFT, "solimpfriction": SOFT, "springlength": Ignored("the rest length of a spring whose "
                                                                          "stiffness must be 0"),
    "stiffness": Neutral("0", "a tendon spring is not modelled"),
    "damping": Neutral("0", "tendon damping is not modelled"),
    "frictionloss": Neutral("0", "tendon friction loss is not modelled"),
    "armature": Neutral("0", "a tendon's armature adds inertia along its path, which is not modelled"),
    "actuatorfrcrange": INPUT, "actuatorfrclimited": INPUT,
    "width": LOOKS, "rgba": LOOKS, "material": LOOKS, "group": LABEL, "user": USER,
}
#: an ``<asset><mesh>``: read when a geom takes mass from it (:mod:`symgen.io.mjcf.meshes`), where a
#: mesh not given by an STL file is refused
MESH = {
    "name": READ, "class": READ, "file": READ, "scale": READ, "inertia": READ,
    **{a: Ignored("read for a geom's mass only from a file (refused there otherwise)")
       for a in ("vertex", "face", "builtin", "params", "content_type")},
    "normal": LOOKS, "texcoord": LOOKS, "smoothnormal": LOOKS, "material": LOOKS,
    "refpos": Neutral("0 0 0", "a mesh moved by refpos is not read where it gives mass"),
    "refquat": Neutral("1 0 0 0", "a mesh turned by refquat is not read where it gives mass"),
    "maxhullvert": Neutral("-1", "a convex hull with fewer vertices is not read where the mesh gives mass"),
}
SITE = {"class": READ, **POSE, "fromto": READ, "type": READ, "size": LOOKS, "rgba": LOOKS, "material": LOOKS, "mesh": LOOKS,
        "group": LABEL, "user": USER}
EQUALITY = {"class": READ, "active": READ, "solref": SOFT, "solimp": SOFT}
ACTUATOR = {
    "class": READ, "joint": READ,
    **{a: READ for a in ("tendon", "site", "body", "jointinparent", "refsite", "cranksite", "slidersite")}, "name": LABEL, "group": LABEL, "user": USER,
    **{a: INPUT for a in ("gear", "ctrlrange", "ctrllimited", "forcerange", "forcelimited", "actrange",
                          "actlimited", "actdim", "actearly", "dyntype", "gaintype", "biastype", "dynprm",
                          "gainprm", "biasprm", "kp", "kv", "dampratio", "timeconst", "inheritrange",
                          "lengthrange", "cranklength", "delay", "nsample", "interp")},
    "armature": Neutral("0", "MuJoCo adds an actuator's armature to its joint's inertia: give it as the "
                             "joint's armature"),
    "damping": Neutral("0", "MuJoCo adds an actuator's damping to its joint: give it as the joint's damping"),
}
#: parameters of actuator kinds symgen refuses; in a <default> they shape only those kinds' forces
OTHER_ACTUATOR_PARAMETERS = ("area", "diameter", "bias", "force", "scale", "lmin", "lmax", "vmax", "fpmax",
                             "fvmax", "range", "tausmooth", "gain", "ki", "imax", "slewmax", "ffrange", "velrange",
                             "posrange", "input", "cogging", "controller", "inductance", "lugre", "motorconst",
                             "nominal", "resistance", "saturation", "thermal")
READ_ACTUATORS = ("motor", "position", "velocity", "general")
REFUSED_ACTUATORS = {
    "damper": "a damper's force opposes the joint's velocity (a dissipation, not an input)",
    "intvelocity": "an integrated-velocity actuator has its own state",
    "cylinder": "a cylinder has its own activation state", "muscle": "a muscle has its own state and a tendon",
    "adhesion": "adhesion acts through contacts", "pid": "a PID actuator has its own state",
    "dcmotor": "a DC motor has its own electrical state", "orientation": "an orientation actuator acts on a site",
    "plugin": REFUSED_PLUGIN.reason,
}

BODY_CHILDREN = {
    "body": "body", "frame": "frame", "site": "site", "geom": "geom", "camera": LOOKS, "light": LOOKS,
    "inertial": "inertial", "joint": "joint",
    "freejoint": "freejoint",
    "include": REFUSED_INCLUDE, "replicate": REFUSED_MACRO, "attach": REFUSED_MACRO, "composite": REFUSED_MACRO,
    "flexcomp": REFUSED_MACRO, "plugin": REFUSED_PLUGIN,
}
#: ``passive`` is MuJoCo's flag before 3.3.6 for springs and dampers together (split into ``spring``
#: and ``damper`` since)
FLAGS_READ = ("gravity", "damper", "frictionloss", "equality", "constraint", "spring", "passive")
FLAGS_IGNORED = {
    "contact": CONTACT, "limit": LIMIT, "filterparent": CONTACT, "override": CONTACT, "midphase": CONTACT,
    "multiccd": CONTACT, "nativeccd": CONTACT, "warmstart": NUMERICS, "refsafe": NUMERICS, "eulerdamp": NUMERICS,
    "island": NUMERICS, "clampctrl": INPUT, "actuation": INPUT, "sensor": Ignored("sensors apply no force"),
    "energy": Ignored("energy is reported, not applied"), "fwdinv": Ignored("a diagnostic"),
    "invdiscrete": Ignored("inverse dynamics of the discrete-time integrator, a diagnostic"),
    "autoreset": Ignored("resets a diverged simulation"),
}

ELEMENTS = {
    "mujoco": Element({"model": READ}, {
        "compiler": "compiler", "option": "option", "default": "default", "worldbody": "worldbody",
        "equality": "equality", "actuator": "actuator",
        "size": Ignored("memory sizes"), "statistic": Ignored("scales of the viewer and of solver tolerances"),
        "visual": LOOKS, "asset": "asset",
        "custom": USER, "keyframe": Ignored("stored states; they do not change the model"),
        "sensor": Ignored("sensors measure; they apply no force"), "contact": CONTACT,
        "tendon": "tendon",
        "extension": REFUSED_PLUGIN, "deformable": Refused("flexible bodies are not modelled"),
        "include": REFUSED_INCLUDE,
    }),
    "compiler": Element({
        "angle": READ, "eulerseq": READ, "settotalmass": READ, "inertiafromgeom": READ,
        "boundmass": Neutral("0", "MuJoCo raises smaller masses to this bound"),
        "boundinertia": Neutral("0", "MuJoCo raises smaller inertias to this bound"),
        "coordinate": Neutral("local", "global coordinates are not read (MuJoCo 3 refuses them too)"),
        "autolimits": LIMIT, "meshdir": READ, "texturedir": FILES, "assetdir": READ, "strippath": READ,
        "discardvisual": Ignored("removes geoms used only for looks"),
        "fusestatic": Ignored("merging a jointless body into its parent keeps the dynamics"),
        "balanceinertia": Ignored("changes only inertias that break the triangle inequality, which symgen refuses"),
        "inertiagrouprange": READ, "fitaabb": FIT,
        "exactmeshinertia": Neutral("false", "the pre-3.0 switch of every mesh to exact inertia is not read: "
                                             "give each <mesh inertia='exact'>"),
        "alignfree": Neutral("false", "aligned free joints move the body frame to its inertia's principal axes"), "usethread": NUMERICS,
        "saveinertial": Ignored("writes a file"),
    }, {"lengthrange": Ignored("computes actuator length ranges, used by muscles (refused)")}),
    "option": Element({
        "gravity": READ,
        "density": Neutral("0", "fluid forces (a medium of nonzero density) are not modelled; load with "
                                "fluid='ignore' (CLI --fluid ignore) for the rigid-body dynamics without them"),
        "viscosity": Neutral("0", "fluid forces (a viscous medium) are not modelled; load with fluid='ignore' "
                                  "(CLI --fluid ignore) for the rigid-body dynamics without them"),
        "wind": Ignored("acts through fluid forces, which need density or viscosity (refused unless "
                        "fluid='ignore', which leaves them out)"),
        "magnetic": Ignored("read by magnetometer sensors only"),
        **{a: NUMERICS for a in ("timestep", "integrator", "solver", "iterations", "tolerance", "ls_iterations",
                                 "ls_tolerance", "noslip_iterations", "noslip_tolerance", "ccd_iterations",
                                 "ccd_tolerance", "mpr_iterations", "mpr_tolerance", "sdf_iterations",
                                 "sdf_initpoints", "jacobian", "apirate")},
        **{a: CONTACT for a in ("impratio", "cone", "o_margin", "o_solref", "o_solimp", "o_friction")},
    }, {"flag": "flag"}),
    "flag": Element({**{f: READ for f in FLAGS_READ}, **FLAGS_IGNORED}),
    "default": Element({"class": READ}, {
        "default": "default", "joint": "default_joint", "site": "default_site", "equality": "default_equality",
        **{a: "default_actuator" for a in READ_ACTUATORS + tuple(REFUSED_ACTUATORS)},
        "geom": "default_geom", "camera": LOOKS, "light": LOOKS, "mesh": "default_mesh", "material": LOOKS,
        "texture": LOOKS,
        "pair": CONTACT, "tendon": "default_tendon",
    }),
    "default_joint": Element(JOINT),
    "default_site": Element(SITE),
    "default_tendon": Element(TENDON),
    "default_geom": Element(GEOM),
    "default_mesh": Element({a: r for a, r in MESH.items() if a != "name"}),
    "asset": Element({}, {"mesh": "mesh", "texture": LOOKS, "material": LOOKS, "skin": LOOKS,
                          "hfield": Ignored("a height field gives no mass (a geom taking mass from it is refused)"),
                          "model": Ignored("a model for <attach>, which is refused"), "plugin": REFUSED_PLUGIN}),
    "mesh": Element(MESH),
    "default_equality": Element(EQUALITY),
    "default_actuator": Element({**ACTUATOR, **{a: Ignored("a parameter of an actuator kind symgen refuses")
                                                 for a in OTHER_ACTUATOR_PARAMETERS}}),
    "worldbody": Element({}, {k: v for k, v in BODY_CHILDREN.items() if k not in ("inertial", "joint")}
                         | {"joint": Refused("the world cannot move")}),
    "body": Element({
        "name": READ, "childclass": READ, **POSE,
        "mocap": Neutral("false", "a mocap body is moved by the user, not by the dynamics"),
        "gravcomp": Neutral("0", "gravity compensation forces are not modelled"), "user": USER,
    }, BODY_CHILDREN),
    "frame": Element({"name": LABEL, "childclass": READ, **POSE},
                     {k: v for k, v in BODY_CHILDREN.items() if k != "inertial"}),
    "inertial": Element({"mass": READ, "pos": READ, "diaginertia": READ, "fullinertia": READ, **ORIENTATION}),
    "joint": Element({"name": READ, **JOINT}),
    "freejoint": Element({"name": READ, "group": LABEL,
                          "align": Neutral("false", "an aligned free joint moves the body frame to its inertia's "
                                                    "principal axes (write align=\"false\")")}),
    "site": Element({"name": READ, **SITE}),
    "geom": Element({"name": LABEL, **GEOM}),
    "equality": Element({}, {
        "connect": "connect", "weld": "weld",
        "joint": "joint_equality", "tendon": "tendon_equality",
        **{k: Refused("couplings of flexes are not read (a joint coupling is <joint joint1 joint2 polycoef>, "
                      "a fixed tendon's <tendon tendon1 tendon2 polycoef>)") for k in ("flex", "flexstrain", "distance")},
    }),
    "joint_equality": Element({"name": READ, "joint1": READ, "joint2": READ, "polycoef": READ, **EQUALITY}),
    "tendon_equality": Element({"name": READ, "tendon1": READ, "tendon2": READ, "polycoef": READ, **EQUALITY}),
    "connect": Element({"name": READ, "body1": READ, "body2": READ, "anchor": READ, "site1": READ,
                        "site2": READ, **EQUALITY}),
    "weld": Element({"name": READ, "body1": READ, "body2": READ, "anchor": READ, "relpose": READ,
                     "site1": READ, "site2": READ, "torquescale": READ, **EQUALITY}),
    "actuator": Element({}, {**{a: "actuator_joint" for a in READ_ACTUATORS},
                             **{a: Refused(r) for a, r in REFUSED_ACTUATORS.items()}}),
    "actuator_joint": Element(ACTUATOR),
    "tendon": Element({}, {"fixed": "tendon_fixed", "spatial": "tendon_spatial"}),
    "tendon_fixed": Element({"name": LABEL, **TENDON}, {"joint": "tendon_joint"}),
    "tendon_spatial": Element({"name": LABEL, **TENDON}, {"site": "tendon_point", "geom": "tendon_point",
                                                          "pulley": "tendon_point"}),
    "tendon_joint": Element({"joint": TENDON_PATH, "coef": TENDON_PATH}),
    "tendon_point": Element({"site": TENDON_PATH, "geom": TENDON_PATH, "sidesite": TENDON_PATH,
                             "divisor": TENDON_PATH}),
}


def check_schema(root, values: Values) -> None:
    """Every element and attribute of the tree under ``root`` (a ``<mujoco>``) is on the allow-list,
    else :class:`MjcfError` at its line (see the module docstring)."""
    if root.tag != "mujoco":
        raise MjcfError(f"<{root.tag}>", "the root element must be <mujoco>", values.source, root.sourceline)
    stack = [(root, "mujoco")]
    while stack:
        el, key = stack.pop()
        spec = ELEMENTS[key]
        for name in el.attrib:
            if name not in spec.attributes:
                values.fail(el, f"attribute {name!r} is not read by symgen (it is not on the MJCF allow-list "
                                f"of <{el.tag}>, symgen/io/mjcf/schema.py)")
        inner = []
        for child in el:
            if not isinstance(child.tag, str):
                continue                                  # comments, processing instructions
            rule = spec.children.get(child.tag)
            if rule is None:
                values.fail(child, f"<{child.tag}> inside <{el.tag}> is not an element symgen reads")
            if isinstance(rule, Refused):
                values.fail(child, f"is not read: {rule.reason}")
            if isinstance(rule, str):
                inner.append((child, rule))
        stack += reversed(inner)                          # depth first, in file order


def check_neutral(values: Values, key: str, attrs: Attrs, skip: tuple = ()) -> None:
    """Every :class:`Neutral` attribute of element ``key`` that ``attrs`` give has its neutral value."""
    for name, rule in ELEMENTS[key].attributes.items():
        if isinstance(rule, Neutral) and name in attrs and name not in skip:
            el, text, want = attrs.origin(name), attrs.get(name).split(), rule.value.split()
            if len(text) != len(want) or not all(_same(values, el, name, a, b) for a, b in zip(text, want)):
                values.fail(el, f"{name}={attrs.get(name)[:40]!r} is not read: {rule.reason} "
                                f"(only {name}={rule.value!r} is accepted, in {describe(attrs.el)})")


def _same(values: Values, el, name: str, text: str, neutral: str) -> bool:
    """Whether one word of an attribute equals the neutral word (numbers compared exactly)."""
    if DECIMAL.fullmatch(neutral):
        return values.number(el, name, text, scale=False) == values.number(el, name, neutral)
    return text == neutral
