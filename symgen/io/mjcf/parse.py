"""Reading an MJCF (MuJoCo XML) file into exact, located records (:mod:`symgen.io.mjcf.records`); no
scene is built here.

lxml reads the XML: a syntax error reports its line, and every element keeps its ``sourceline``,
so each :class:`MjcfError` names the element *and* the line. The whole text is first held to the
shared limits of :mod:`symgen.scene.input_limits`, and every element and attribute to the allow-list of
:mod:`symgen.io.mjcf.schema` (read with MuJoCo's meaning, ignored because it does not change the
dynamics, or refused). Then, as MuJoCo does:

* every ``<compiler>`` and every ``<option>`` section is read, attribute by attribute, the last
  one written winning; they apply to the whole file wherever they stand;
* ``<default>`` classes (:mod:`symgen.io.mjcf.defaults`), then every ``<worldbody>``
  (:mod:`symgen.io.mjcf.bodies`), then every ``<equality>`` and ``<actuator>`` section;
* ``<flag gravity="disable">`` zeroes gravity; ``damper``, ``frictionloss`` and ``spring``
  disabled drop joint damping, friction loss and springs (``passive``, their flag before MuJoCo
  3.3.6, both damping and springs); ``equality`` or ``constraint`` disabled drop the equalities
  (with a note);
* ``<option density/viscosity>`` (a fluid medium) is refused, or with ``fluid="ignore"`` read
  without its forces (a note and a :class:`FluidWarning`);
* ``<compiler settotalmass>`` scales every mass and inertia so that the masses add up to it;
* a joint's ``springdamper`` sets its stiffness and damping from the mass matrix at ``qpos0``, as
  MuJoCo does (:mod:`symgen.io.mjcf.springdamper`);
* a moving body must have mass and inertia as MuJoCo requires
  (:func:`symgen.io.mjcf.bodies.check_moving_masses`), else it is refused as MuJoCo refuses it;
* an equality with ``active="false"`` is not enforced at the start of a MuJoCo simulation, so it is
  no constraint here (with a note).
"""
from __future__ import annotations

import os
import warnings

import sympy as sp

from ..textfile import read_text_file
from .bodies import BodyReader, Physics, check_moving_masses
from .defaults import Defaults
from .geoms import GROUP_RANGE
from .include import expand_includes, parse_xml
from .meshes import MeshLibrary
from .records import WORLD, MjcfEquality, MjcfModel, element_name
from .springdamper import apply_springdampers
from .schema import FLAGS_READ, check_neutral, check_schema
from .values import Attrs, MjcfError, Values, describe

__all__ = ["MjcfError", "parse_mjcf", "parse_mjcf_text"]
#: the attributes naming an actuator's transmission other than a joint
TRANSMISSIONS = ("tendon", "site", "body")
#: MuJoCo's default gravity (mjOption)
DEFAULT_GRAVITY = "0 0 -9.81"
ON_OFF = ("enable", "disable")
#: ``fluid=``: refuse a medium (``<option density/viscosity>`` nonzero), or ignore its forces (note + warning)
FLUID = ("refuse", "ignore")
FLUID_ATTRIBUTES = ("density", "viscosity")


class FluidWarning(UserWarning):
    """An MJCF model's fluid forces were left out (``fluid="ignore"``)."""


def _merged(root, tag: str, parent=None) -> Attrs:
    """The attributes of every ``<tag>`` under ``root`` (or under each ``parent`` element), later
    sections overriding earlier ones attribute by attribute."""
    values, first = {}, None
    holders = [root] if parent is None else root.findall(parent)
    for holder in holders:
        for el in holder.findall(tag):
            first = el if first is None else first
            values.update({a: (v, el) for a, v in el.attrib.items()})
    return Attrs(root if first is None else first, values)


class _Settings:
    """``<compiler>``, ``<option>`` and ``<flag>``, merged."""

    def __init__(self, root, source: str, origins: dict):
        """Merge the sections of ``root`` (see :func:`_merged`) and read what the model needs."""
        v = Values(source, origins=origins)
        compiler, option, flags = _merged(root, "compiler"), _merged(root, "option"), _merged(root, "flag", "option")
        self.option = option
        degrees = v.keyword(compiler, "angle", ("degree", "radian"), "degree") == "degree"
        eulerseq = compiler.get("eulerseq", "xyz")
        if len(eulerseq) != 3 or any(c not in "xyzXYZ" for c in eulerseq):
            v.fail(compiler.origin("eulerseq"), f"eulerseq={eulerseq[:20]!r} must be three of x, y, z, X, Y, Z")
        self.values = Values(source, degrees, eulerseq, origins)
        on = {f: v.keyword(flags, f, ON_OFF, "enable") == "enable" for f in set(flags.values) | set(FLAGS_READ)}
        groups = v.numbers(compiler, "inertiagrouprange", 2, GROUP_RANGE, scale=False)
        self.physics = Physics(on["spring"] and on["passive"], on["damper"] and on["passive"], on["frictionloss"],
                               v.keyword(compiler, "inertiafromgeom", ("false", "true", "auto"), "auto"), groups)
        self.equalities = on["equality"] and on["constraint"]
        self.gravity = self.values.numbers(option, "gravity", 3, DEFAULT_GRAVITY) if on["gravity"] else (0, 0, 0)
        self.total_mass = self.values.numbers(compiler, "settotalmass", 1, "-1")[0]
        self.compiler = compiler

    def check_neutral(self, fluid: str) -> list:
        """The attributes of ``<compiler>`` and ``<option>`` accepted only at their neutral value
        (``density`` and ``viscosity`` of any value with ``fluid="ignore"``); returns the notes."""
        check_neutral(self.values, "compiler", self.compiler)
        if fluid not in FLUID:
            raise MjcfError("fluid", f"fluid={fluid!r} must be one of {', '.join(FLUID)}", self.values.source)
        medium = {a: self.values.scalar(self.option, a) for a in FLUID_ATTRIBUTES}
        check_neutral(self.values, "option", self.option, skip=FLUID_ATTRIBUTES if fluid == "ignore" else ())
        if not any(medium.values()):
            return []
        note = (f"MJCF: fluid forces left out (fluid='ignore'): <option {' '.join(f'{a}={v}' for a, v in medium.items())}> "
                "makes MuJoCo add velocity-dependent passive forces of the medium (qfrc_fluid), which symgen does "
                "not model; the model is the rigid-body dynamics without them (MuJoCo's mj_fullM and qfrc_bias "
                "leave them out too)")
        warnings.warn(FluidWarning(note), stacklevel=4)
        return [note]


def _scale_masses(settings: _Settings, bodies: list, source: str) -> None:
    """``<compiler settotalmass>``: every mass and inertia times ``total / sum of masses``."""
    total = sum((b.inertial.mass for b in bodies if b.inertial), sp.Integer(0))
    if total <= 0:
        raise MjcfError("<compiler>", "settotalmass needs bodies with mass to scale", source,
                        settings.compiler.origin("settotalmass").sourceline)
    k = settings.total_mass / total
    for b in bodies:
        if b.inertial is not None:
            b.inertial.mass, b.inertial.inertia = b.inertial.mass * k, b.inertial.inertia * k


def _linear_polycoef(v: Values, attrs: Attrs) -> tuple:
    """``(c0, c1)`` of ``polycoef`` (MuJoCo's default ``0 1 0 0 0``); higher terms must be 0."""
    coef = v.numbers(attrs, "polycoef", 5, "0 1 0 0 0")
    if any(c != 0 for c in coef[2:]):
        v.fail(attrs.el, f"polycoef {' '.join(str(c) for c in coef)} is not linear: only c0 + c1 (x - x_0) is a "
                         "coupling of eq. (6) (the quadratic and higher terms must be 0)")
    return tuple(coef[:2])


#: the MJCF tag of a tendon whose length is a linear function of joint positions
FIXED_TENDON = "fixed"


def fixed_tendons(root, v: Values) -> dict:
    """``{name: ((joint, coef), ...)}`` of every named ``<tendon><fixed>`` (its length is ``sum coef_i
    q_i``); a ``<spatial>`` tendon maps to None (its length is no linear function of the joints)."""
    out: dict = {}
    for section in root.findall("tendon"):
        for el in section:
            if isinstance(el.tag, str) and el.get("name"):
                out[el.get("name")] = None if el.tag != FIXED_TENDON else tuple(
                    (j.get("joint"), v.number(j, "coef", j.get("coef", "1")))
                    for j in el if isinstance(j.tag, str) and j.tag == "joint")
    return out


def _tendon_equality(v: Values, attrs: Attrs, index: int, tendons: dict) -> MjcfEquality:
    """A ``<tendon tendon1 tendon2 polycoef>`` of fixed tendons: MuJoCo's ``L1 - L1_0 = c0 + c1 (L2 -
    L2_0)``, a linear relation of joint positions; a spatial or unknown tendon is refused."""
    el = attrs.el
    paths = []
    for key in ("tendon1", "tendon2"):
        name = el.get(key)
        if name is None:
            if key == "tendon1":
                v.fail(el, "needs tendon1")
            paths.append(())
        elif name not in tendons:
            v.fail(el, f"{key} {name!r} is not a declared, named tendon")
        elif tendons[name] is None:
            v.fail(el, f"{key} {name!r} is a spatial tendon: its length is not a linear function of the joints, "
                       "so the equality is no coupling of eq. (6)")
        else:
            paths.append(tendons[name])
    coef = _linear_polycoef(v, attrs) if paths[1] else (v.numbers(attrs, "polycoef", 5, "0 1 0 0 0")[0], 0)
    return MjcfEquality("tendon", el.get("name") or f"tendon{index}", None, None, None, None, None, None,
                        el.sourceline, polycoef=coef, tendon1=paths[0], tendon2=paths[1])


def _joint_equality(v: Values, attrs: Attrs, index: int) -> MjcfEquality:
    """A ``<joint joint1 joint2 polycoef>``: MuJoCo's ``q1 - q1_0 = c0 + c1 (q2 - q2_0) + c2 (q2 -
    q2_0)^2 + ...``; only the linear form (``c2 = c3 = c4 = 0``) with two joints is a coupling."""
    el = attrs.el
    if el.get("joint1") is None or el.get("joint2") is None:
        v.fail(el, "needs joint1 and joint2: a joint equality with one joint holds it fixed, which is not read "
                   "(lock the joint instead)")
    coef = _linear_polycoef(v, attrs)
    if coef[1] == 0:
        v.fail(el, "polycoef c1 = 0 holds joint1 fixed and couples nothing: lock the joint instead")
    return MjcfEquality("joint", el.get("name") or f"joint{index}", None, None, None, None, None, None,
                        el.sourceline, el.get("joint1"), el.get("joint2"), coef)


def _equality(v: Values, attrs: Attrs, index: int, tendons: dict) -> MjcfEquality:
    """A ``connect`` or ``weld`` (site or body form, MuJoCo's rules), a joint or a fixed-tendon
    coupling as an :class:`MjcfEquality`."""
    el = attrs.el
    if el.tag == "joint":
        return _joint_equality(v, attrs, index)
    if el.tag == "tendon":
        return _tendon_equality(v, attrs, index, tendons)
    sites = [element_name(el.get(a)) for a in ("site1", "site2")]
    bodies = [el.get(a) for a in ("body1", "body2", "anchor", "relpose")]
    if any(s is not None for s in sites):
        if any(b is not None for b in bodies) or None in sites:
            v.fail(el, "give site1 and site2, or body1 (with body2, anchor, relpose), not both (MuJoCo's rule)")
    elif el.get("body1") is None or (el.tag == "connect" and el.get("anchor") is None):
        v.fail(el, "needs site1 and site2, or body1" + (" and anchor" if el.tag == "connect" else ""))
    relpose = None
    if el.tag == "weld":
        torquescale = v.scalar(attrs, "torquescale", "1")
        if torquescale <= 0:
            v.fail(attrs.origin("torquescale"), "torquescale must be positive: at 0 the weld no longer holds the "
                                                "orientation, which symgen does not model")
        if el.get("relpose") is not None:
            parts = el.get("relpose").split()
            if len(parts) != 7:
                v.fail(el, "relpose must have 7 numbers (position, then quaternion w x y z)")
            quat = [v.number(el, "relpose", p, scale=False) for p in parts[3:]]
            if any(q != 0 for q in quat):
                rot = v.rotation(Attrs(el, {"quat": (" ".join(parts[3:]), el)}))
                relpose = (sp.Matrix([v.number(el, "relpose", p) for p in parts[:3]]), rot)
    anchor = v.numbers(attrs, "anchor", 3, "0 0 0")
    return MjcfEquality(el.tag, el.get("name") or f"{el.tag}{index}", element_name(el.get("body1")),
                        element_name(el.get("body2")) or (WORLD if el.get("body1") else None),
                        sp.Matrix(anchor), relpose, sites[0], sites[1], el.sourceline)


def _equalities(root, settings: _Settings, defaults: Defaults, notes: list) -> list:
    """Every equality of every ``<equality>`` section that is active and enabled (notes say which are not)."""
    out = []
    tendons = fixed_tendons(root, settings.values)
    for section in root.findall("equality"):
        for el in section:
            if not isinstance(el.tag, str):
                continue
            attrs = defaults.attrs(el)
            eq = _equality(settings.values, attrs, len(out), tendons)
            if settings.values.boolean(attrs, "active", True):
                out.append(eq)
            else:
                notes.append(f"equality {describe(el)} (line {el.sourceline}) is inactive (active=\"false\"): "
                             "MuJoCo does not enforce it at the start, so it is no constraint here")
    if out and not settings.equalities:
        notes.append("equality constraints are disabled (<flag equality|constraint=\"disable\">): none is read")
        return []
    return out


def _actuated(root, settings: _Settings, defaults: Defaults, joints: set, notes: list) -> list:
    """The joints driven by ``<actuator>`` elements, each once, in file order (notes: the actuators
    with another transmission)."""
    out: list = []
    for section in root.findall("actuator"):
        for el in section:
            if not isinstance(el.tag, str):
                continue
            attrs = defaults.attrs(el)
            check_neutral(settings.values, "actuator_joint", attrs)
            joint = attrs.get("joint") or attrs.get("jointinparent")     # the same for a hinge or slide
            if joint is None:
                target = next((f"{a} {attrs.get(a)!r}" for a in TRANSMISSIONS if a in attrs), None)
                if target is None:
                    settings.values.fail(el, "needs a transmission (joint=..., tendon=..., site=... or body=...)")
                notes.append(f"actuator {describe(el)} (line {el.sourceline}) drives {target}, not one joint: symgen's "
                             "inputs are joint forces, so it marks no joint actuated")
                continue
            if joint not in joints:
                settings.values.fail(el, f"joint {joint!r} is not declared")
            if joint not in out:
                out.append(joint)
    return out


def _check_tendons(root, settings: _Settings, defaults: Defaults, notes: list) -> None:
    """Every tendon has no passive force (:data:`~symgen.io.mjcf.schema.TENDON`); a note says what
    the others do."""
    for section in root.findall("tendon"):
        for el in section:
            if isinstance(el.tag, str):
                check_neutral(settings.values, "tendon_fixed", defaults.attrs(el))
                limited = "range" in defaults.attrs(el)
                notes.append(f"tendon {describe(el)} (line {el.sourceline}) has no stiffness, damping or friction "
                             f"loss: it applies force only{' at its length limits (not modelled, like joint limits) and' if limited else ''} "
                             "through its actuators")


def _check_names(model: MjcfModel) -> None:
    """Every site and body an equality names is declared."""
    names = [b.name for b in model.bodies]       # unique and not 'world' (checked as they are read)
    sites = {s.name for s in model.sites}
    for eq in model.equalities:
        for s in (eq.site1, eq.site2):
            if s is not None and s not in sites:
                raise MjcfError(f"<{eq.kind} name={eq.name!r}>", f"site {s!r} is not declared", model.source, eq.line)
        for b in (eq.body1, eq.body2):
            if b is not None and b not in names + [WORLD]:
                raise MjcfError(f"<{eq.kind} name={eq.name!r}>", f"body {b!r} is not declared", model.source, eq.line)


def parse_mjcf_text(text: str, source: str = "<string>", directory: str | None = None, *,
                    fluid: str = "refuse") -> MjcfModel:
    """An :class:`MjcfModel` from MJCF text (``source`` names it in errors; ``directory``: where its
    ``<include>`` and mesh files are, :mod:`symgen.io.mjcf.include`, :mod:`symgen.io.mjcf.meshes`).
    ``fluid="ignore"`` reads a model with a fluid medium (``<option density/viscosity>``) without its
    fluid forces, with a note and a :class:`FluidWarning`; the default refuses it."""
    root = parse_xml(text, source)
    origins = expand_includes(root, source, directory)
    check_schema(root, Values(source, origins=origins))
    settings = _Settings(root, source, origins)
    defaults = Defaults(root, settings.values)
    meshes = MeshLibrary(root, settings.values, defaults, settings.compiler, directory)
    tree = BodyReader(settings.values, defaults, settings.physics, meshes)
    tree.read(root)                  # first: a free body is named before any other refusal
    notes: list = settings.check_neutral(fluid)
    if settings.total_mass > 0:
        _scale_masses(settings, tree.bodies, source)
    check_moving_masses(tree.bodies, settings.values)
    apply_springdampers(tree.bodies, settings.physics.springs, settings.physics.dampers)
    equalities = _equalities(root, settings, defaults, notes)
    actuated = _actuated(root, settings, defaults, {j.name for b in tree.bodies for j in b.joints}, notes)
    _check_tendons(root, settings, defaults, notes)
    model = MjcfModel(root.get("model", "mjcf_robot"), settings.gravity, tree.bodies, tree.sites, equalities,
                      actuated, source, text, notes)
    _check_names(model)
    return model


def parse_mjcf(path, *, fluid: str = "refuse") -> MjcfModel:
    """An :class:`MjcfModel` from an MJCF file (``fluid`` as in :func:`parse_mjcf_text`)."""
    text = read_text_file(path, "MJCF file", MjcfError)
    return parse_mjcf_text(text, str(path), os.path.dirname(os.path.abspath(path)), fluid=fluid)
