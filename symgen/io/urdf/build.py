"""A parsed URDF (:class:`~symgen.io.urdf.parse.UrdfRobot`) added to a symgen :class:`~symgen.scene.Scene`.

How URDF maps to the scene:

* The **root link** is welded to ``world`` at the base placement (default: the world origin).
  Its mass, and that of every link fixed to it, does not enter the dynamics of a fixed base.
* A **revolute** joint becomes a revolute joint and a **continuous** joint a revolute joint
  without limits; a **prismatic** joint stays prismatic. The child link becomes a body of the
  same name, and the joint's ``<origin>`` becomes the joint placement in its parent body. The
  ``<axis>`` is passed as written: a coordinate axis as ``x``/``-y``/..., any other axis as an
  exact vector. The scene maps every axis to the z axis of an internal joint frame by one
  constant rotation (the paper's ``Z = e3 / e6``, :mod:`symgen.tree`). The body frame stays the
  URDF link frame, so frames, inertias and the Pinocchio comparison all use the file's frames.
* A **fixed** joint merges its child link into the parent's body: mass, centre of mass and
  inertia are combined (:mod:`symgen.io.urdf.inertia`), and the child link becomes a named frame on
  that body (e.g. ``tool0``). A joint listed in ``lock`` is treated the same way, held at the
  given position.
* ``<dynamics damping>`` becomes viscous friction and ``friction`` Coulomb friction. Together they
  are the paper's ``xi = b qd + c sign(qd)`` of eq. (22). ``<limit>`` goes to
  ``scene.joint_limits``.
* A moving joint with ``<mimic joint= multiplier= offset=>`` becomes an unactuated joint tied by a
  joint coupling ``q = multiplier q_joint + offset`` (:meth:`~symgen.scene.Scene.add_coupling`,
  one row of eq. 6; the coupling is named ``<joint>_mimic``), its ``q0`` following the leader's.
  A ``<mimic>`` on a fixed joint couples nothing and is a note; a locked mimicking joint keeps no
  coupling; a leader that is locked, fixed or unknown is refused. ``mimic=False`` reads every
  mimicking joint as an independent, actuated joint (Pinocchio's default parse), with a note.
* ``floating`` and ``planar`` joints are refused.
* Inertias that no rigid body has, links welded to the world, zero-mass links with an inertia and
  a root that looks like a free body are judged by :mod:`symgen.io.urdf.physics` (option
  ``inertia="warn" | "repair" | "strict"``); what it accepts it says, as a warning and in
  ``scene.notes``, with the notes of the reading (:attr:`UrdfRobot.notes`).

A joint that moves no mass -- its child link and every link below have zero mass or no
``<inertial>``, and so do the joints that mimic it (Romeo's hands) -- would give the mass matrix a
zero row: it is locked at its ``q0`` like a fixed joint, with a
:class:`~symgen.io.urdf.physics.MasslessJointWarning`
(``inertia="strict"``: an error). A massless joint that a massive joint mimics keeps its coordinate:
the coupled row is regular. A link without ``<inertial>`` that only carries further joints is a
massless frame carrier, which the scene allows.

Names must be identifiers. Any other character becomes ``_`` (``base_link-base_fixed_joint``
becomes ``base_link_base_fixed_joint``), and ``prefix`` is put in front of every name, so one file
can be added several times.
"""
from __future__ import annotations

import dataclasses
import os
import re
import warnings
from dataclasses import dataclass, field

import sympy as sp

from ... import errors
from ...errors import SceneError
from ...scene.joint_kinds import PRISMATIC, REVOLUTE
from ...math.numbers import parse_exact
from ...scene.declaration import WORLD, Scene
from .inertia import MassProperties
from .parse import JointLimits, UrdfError, UrdfJoint, UrdfRobot, read_urdf
from .physics import (MasslessJointWarning, check_inertia_mode, free_base_finding, judged_inertials, report,
                      rounded_inertia)
from .rotations import SNAP, axis_argument, axis_rotation, quaternion_argument, rotation_from_rpy, unit_axis

#: the joint kind of each moving URDF joint type
MOVING = {"revolute": REVOLUTE, "continuous": REVOLUTE, "prismatic": PRISMATIC}


def scene_name(prefix: str, urdf_name: str) -> str:
    """The scene's name for a URDF link or joint: non-identifier characters replaced by ``_``."""
    name = prefix + re.sub(r"[^A-Za-z0-9_]", "_", urdf_name)
    return "_" + name if name[:1].isdigit() else name


@dataclass
class UrdfSource:
    """Where a part of a scene came from: the file, the prefix, the base placement, the locked
    joints, and the names given to its joints and links. :mod:`symgen.oracle` rebuilds the same
    robot in Pinocchio from it."""

    robot: UrdfRobot
    prefix: str
    base_rotation: sp.ImmutableMatrix
    base_translation: sp.ImmutableMatrix
    lock: dict                                      # URDF joint name -> exact position
    joints: dict = field(default_factory=dict)      # URDF joint name -> scene joint (moving joints)
    links: dict = field(default_factory=dict)       # URDF link name -> (scene body or 'world', frame or None)
    friction: bool = True
    inertia: str = "warn"                           # the option of physics.judged_inertials
    floating: str | None = None                     # the free joint above the root link, if floating
    repaired: list = field(default_factory=list)    # URDF links whose inertia inertia="repair" replaced
    mimics: dict = field(default_factory=dict)      # URDF mimicking joint -> scene coupling name

    @property
    def leading_joints(self) -> list[str]:
        """The scene joints that mimic no other (the motion coordinates of a plain robot)."""
        return [name for urdf_name, name in self.joints.items() if urdf_name not in self.mimics]


#: the name of the free joint ``floating=True`` puts above the root link (after the prefix)
FLOATING_BASE = "floating_base"


class NoMovingJointError(UrdfError):
    """A URDF robot has no revolute, continuous or prismatic joint: nothing to model."""


def urdf_sources(scene: Scene) -> list[UrdfSource]:
    """The URDF robots ``scene`` was built from, in the order they were added."""
    return [s for s in scene.sources if isinstance(s, UrdfSource)]


def _exact_map(values, robot: UrdfRobot, prefix: str, what: str) -> dict:
    """``{URDF joint name: exact value}``; keys may be URDF names or scene names."""
    by_scene = {scene_name(prefix, j): j for j in robot.joints}
    out = {}
    for key, value in (values or {}).items():
        name = key if key in robot.joints else by_scene.get(key)
        if name is None:
            raise UrdfError(f"{what} {key!r}", f"no joint of this name in robot {robot.name!r}", robot.source)
        joint = robot.joints[name]
        if joint.type not in MOVING:
            raise UrdfError(f"joint {name!r}", f"is {joint.type}; {what} applies to revolute, continuous and "
                                               "prismatic joints", robot.source, joint.line)
        try:
            out[name] = parse_exact(value)
        except ValueError as exc:
            raise UrdfError(f"joint {name!r}", f"{what}: {exc}", robot.source, joint.line) from None
    return out


def _check_supported(robot: UrdfRobot, lock: dict) -> list:
    """Refuse floating and planar joints and mimics of an unknown, fixed or locked joint or of the
    joint itself; returns the notes of ``<mimic>`` on fixed joints (no coordinate to couple, so
    nothing to read)."""
    notes = []
    for j in robot.joints.values():
        if j.type in ("floating", "planar"):
            raise UrdfError(f"joint {j.name!r}", f"type {j.type} is not supported (symgen models fixed-base "
                                                 "robots with revolute, continuous, prismatic and fixed joints)",
                            robot.source, j.line)
        if j.mimic is not None and j.type not in MOVING:
            notes.append(f"joint {j.name!r} is fixed: its <mimic> of {j.mimic.joint!r} couples no coordinate and is "
                         "not read")
        elif j.mimic is not None and j.name not in lock:
            _check_leader(robot, j, lock)
    return notes


def _without_mimics(robot: UrdfRobot) -> UrdfRobot:
    """A copy of ``robot`` whose joints have no ``<mimic>``, with a note naming those that had one."""
    had = [j.name for j in robot.joints.values() if j.mimic is not None]
    if not had:
        return robot
    joints = {n: dataclasses.replace(j, mimic=None) for n, j in robot.joints.items()}
    note = (f"{len(had)} <mimic> element(s) not read (mimic=False): joints {', '.join(had[:4])}"
            f"{', ...' if len(had) > 4 else ''} are independent, actuated joints, as in Pinocchio's default parse")
    return dataclasses.replace(robot, joints=joints, notes=robot.notes + [note])


def _check_leader(robot: UrdfRobot, j: UrdfJoint, lock: dict) -> None:
    """The joint a moving, unlocked ``j`` mimics must be another moving joint, not locked."""
    leader = robot.joints.get(j.mimic.joint)
    problem = ("is not a joint of this robot" if leader is None else
               "is the joint itself: a joint cannot mimic itself" if leader is j else
               f"is {leader.type}: it has no coordinate to follow" if leader.type not in MOVING else
               f"is locked; lock this joint too, e.g. lock={{{j.name!r}: ...}}" if leader.name in lock else None)
    if problem:
        raise UrdfError(f"joint {j.name!r}", f"mimics joint {j.mimic.joint!r}, which {problem} (mimic=False, or "
                                             "--no-mimic, reads every mimicking joint as an independent joint)",
                        robot.source, j.line)


def _friction_notes(moving: list, friction: bool) -> list:
    """A note naming the joints whose ``<dynamics damping friction>`` is not zero: read into the
    joint friction (``friction=True``, Pinocchio's ``rnea`` leaves it out) or left out."""
    named = [j.name for j, *_ in moving if j.damping != 0 or j.friction != 0]
    if not named:
        return []
    which = f"{', '.join(named[:4])}{', ...' if len(named) > 4 else ''}"
    if friction:
        return [(None, f"{len(named)} joint(s) ({which}) have <dynamics damping friction>: read as the joint "
                       "friction xi = b qd + c sign(qd) of eq. (22), which Pinocchio's rnea leaves out; "
                       "friction=False reads none")]
    return [(None, f"{len(named)} joint(s) ({which}) have <dynamics damping friction>: left out (friction=False)")]


def _reference(j: UrdfJoint, given) -> sp.Expr:
    """``q0``: as given, else 0, or the middle of the limits when 0 is outside them."""
    lo, hi = (j.limits.lower, j.limits.upper) if j.type != "continuous" else (None, None)
    if given is None:
        if lo is not None and hi is not None and not lo <= 0 <= hi:
            return sp.Rational(lo + hi) / 2
        return sp.Integer(0)
    value = float(given)
    if lo is not None and hi is not None and not float(lo) - 1e-12 <= value <= float(hi) + 1e-12:
        raise UrdfError(f"joint {j.name!r}", f"q0 = {value:g} is outside its limits [{float(lo):g}, {float(hi):g}]")
    return given


def _locked_pose(j: UrdfJoint, rot, trans, value, snap):
    """Pose of the child link of joint ``j`` held at ``value``, from the joint frame pose."""
    if MOVING[j.type].translates:
        return rot, sp.ImmutableMatrix(sp.Matrix(trans) + sp.Matrix(rot) * sp.Matrix(unit_axis(j.axis)) * value)
    return sp.ImmutableMatrix(sp.Matrix(rot) * axis_rotation(j.axis, value, snap)), trans


def _base_pose(xyz, rpy, quat, snap):
    """Exact rational placement of the root link in the world."""
    if rpy is not None and quat is not None:
        raise SceneError("base", "give base_rpy or base_quat, not both")
    pose = Scene("base").pose("base", xyz, None, quat)   # checks and parses xyz and quat
    if rpy is None:
        return sp.ImmutableMatrix(pose.rotation), pose.translation
    try:
        angles = [parse_exact(v) for v in rpy]
    except ValueError as exc:
        raise SceneError("base", f"base_rpy: {exc}") from None
    if len(angles) != 3 or any(a.free_symbols for a in angles):
        raise SceneError("base", f"base_rpy must be 3 numbers, got {rpy!r}")
    return rotation_from_rpy(angles, snap), pose.translation


def _walk(robot: UrdfRobot):
    """Joints in depth-first order from the root (children in file order)."""
    stack = list(reversed(robot.children.get(robot.root, [])))
    while stack:
        joint = robot.joints[stack.pop()]
        yield joint
        stack.extend(reversed(robot.children.get(joint.child, [])))


def _layout(robot: UrdfRobot, src: UrdfSource, snap: float):
    """Owner body and pose (in the owner's frame) of every link; the moving joints' placements."""
    if src.floating:      # the root link is a body of its own, placed by its free joint
        owner = {robot.root: floating_body(robot, src.prefix)}
        pose = {robot.root: (sp.ImmutableMatrix(sp.eye(3)), sp.ImmutableMatrix([0, 0, 0]))}
    else:
        owner = {robot.root: WORLD}
        pose = {robot.root: (src.base_rotation, src.base_translation)}
    moving = []
    for j in _walk(robot):
        r_p, p_p = pose[j.parent]
        rot = sp.ImmutableMatrix(sp.Matrix(r_p) * rotation_from_rpy(j.origin.rpy, snap))
        trans = sp.ImmutableMatrix(sp.Matrix(p_p) + sp.Matrix(r_p) * sp.Matrix([sp.Rational(v) for v in j.origin.xyz]))
        if j.type in MOVING and j.name not in src.lock:
            body = scene_name(src.prefix, j.child)
            owner[j.child], pose[j.child] = body, (sp.ImmutableMatrix(sp.eye(3)), sp.ImmutableMatrix([0, 0, 0]))
            moving.append((j, owner[j.parent], body, rot, trans))
        else:
            owner[j.child] = owner[j.parent]
            pose[j.child] = (_locked_pose(j, rot, trans, src.lock[j.name], snap) if j.name in src.lock
                             else (rot, trans))
    return owner, pose, moving


def _masses(robot: UrdfRobot, owner: dict, pose: dict, snap: float, inertials: dict) -> dict:
    """Merged mass properties of every body, in the body frame, from the judged ``inertials``."""
    out: dict[str, MassProperties] = {}
    for name, link in robot.links.items():
        body = owner[name]
        if body == WORLD or name not in inertials:
            continue
        origin = link.inertial_origin
        props = inertials[name].transformed(rotation_from_rpy(origin.rpy, snap), [sp.Rational(v) for v in origin.xyz])
        out[body] = out.get(body, MassProperties.zero()) + props.transformed(*pose[name])
    return out


def _subtree_masses(moving: list, masses: dict) -> dict:
    """``{URDF joint name: mass its child body and the bodies below it carry}`` of every moving joint."""
    below: dict[str, list[str]] = {}
    for j, parent, body, _, _ in moving:
        below.setdefault(parent, []).append(body)

    def subtree_mass(body):
        return masses.get(body, MassProperties.zero()).mass + sum(subtree_mass(b) for b in below.get(body, ()))

    return {j.name: subtree_mass(body) for j, _, body, _, _ in moving}


def _massless_groups(moving: list, masses: dict) -> list[list[UrdfJoint]]:
    """The groups of moving joints (a joint and the joints that mimic it) of which no member moves
    any mass: each group's coordinate has a zero row in the mass matrix (eq. 32 has no solution
    for its acceleration). A group with one massive member is kept: its coupled row is regular."""
    carried = _subtree_masses(moving, masses)
    by_name = {j.name: j for j, *_ in moving}

    def leader(j: UrdfJoint) -> str:
        return j.mimic.joint if j.mimic is not None and j.mimic.joint in by_name else j.name

    groups: dict[str, list[UrdfJoint]] = {}
    for j, *_ in moving:
        groups.setdefault(leader(j), []).append(j)
    return [g for g in groups.values() if all(carried[j.name] == 0 for j in g)]


def _massless_error(robot: UrdfRobot, owner: dict, j: UrdfJoint, why: str) -> UrdfError:
    """The error of a moving joint ``j`` that moves no mass, when it cannot be locked (``why``)."""
    links = [n for n, b in owner.items() if b == owner.get(j.child)]
    bare = [n for n in links if robot.links[n].inertial is None]
    what = ("has no <inertial>" if bare and bare[0] == j.child else
            "has zero mass" + (f" (links without <inertial>: {', '.join(bare)})" if bare else ""))
    return UrdfError(f"link {j.child!r}", f"{what}, and joint {j.name!r} moves no other mass: the mass matrix "
                                          f"would be singular; {why}", robot.source, robot.links[j.child].line)


def _massless_locks(robot: UrdfRobot, owner: dict, moving: list, masses: dict, q0: dict,
                    strict: bool, floating: bool) -> tuple[dict, list]:
    """``({URDF joint: position}, findings)``: the joints of every group that moves no mass
    (:func:`_massless_groups`, e.g. a hand whose finger links all have zero mass), to be locked at
    their reference position like a fixed joint, each group with a warning; ``strict``, or when no
    other joint would move (on a fixed base): an error."""
    groups = _massless_groups(moving, masses)
    if not groups:
        return {}, []
    if strict:
        raise _massless_error(robot, owner, groups[0][0], "inertia='strict' refuses it, the other modes lock it")
    if sum(len(g) for g in groups) == len(moving) and not floating:
        raise _massless_error(robot, owner, groups[0][0], "no other joint moves, so it cannot be locked: give "
                                                          "the link a positive mass")
    references = _references(moving, q0)
    locks, findings = {}, []
    for group in groups:
        names = [j.name for j in group]
        locks.update({name: references[name] for name in names})
        others = f" and {len(names) - 1} joint(s) that mimic it ({', '.join(names[1:4])}{', ...' if len(names) > 4 else ''})" \
            if len(names) > 1 else ""
        one = len(names) == 1
        findings.append((MasslessJointWarning,
                         f"joint {names[0]!r}{others} {'moves' if one else 'move'} no mass (link {group[0].child!r} "
                         "and every link below have zero mass or no <inertial>): the mass matrix would have a zero "
                         f"row, so {'it is locked like a fixed joint' if one else 'they are locked like fixed joints'} at q0 "
                         f"({names[0]} = {references[names[0]]}); give the links mass to model "
                         f"{'it' if one else 'them'}, or lock= to choose the position"))
    return locks, findings


def _add_link_frames(scene: Scene, robot: UrdfRobot, src: UrdfSource, owner: dict, pose: dict) -> None:
    """A named frame for every link merged into another body (``tool0`` ...); ``src.links`` records
    where each link went."""
    prefix = src.prefix
    for link in robot.links:
        body = owner[link]
        frame = None
        if body != scene_name(prefix, link) and scene_name(prefix, link) != WORLD:
            frame = scene_name(prefix, link)
            rot, trans = pose[link]
            try:
                scene.add_frame(frame, body, xyz=list(trans), quat=quaternion_argument(rot))
            except SceneError as exc:
                raise UrdfError(exc.element, f"{exc.message} (from URDF link {link!r})", robot.source,
                                robot.links[link].line) from None
        src.links[link] = (body, frame)


def add_urdf(scene: Scene, urdf, *, prefix: str = "", base_xyz=None, base_rpy=None, base_quat=None, q0=None,
             lock=None, snap: float = SNAP, friction: bool = True, inertia: str = "warn",
             floating: bool = False, mimic: bool = True) -> UrdfSource:
    """Add the robot of a URDF file (path, URDF text or :class:`UrdfRobot`) to ``scene``.

    Args:
        prefix: put in front of every body, joint and frame name (several copies of one file).
        base_xyz, base_rpy, base_quat: placement of the root link in the world (rpy as URDF,
            or a quaternion ``[w, x, y, z]``).
        q0: reference positions ``{joint: value}`` (URDF or scene names; numbers or text such as
            ``"-pi/2"``); default 0, or the middle of the limits when 0 is outside them.
        lock: ``{joint: position}`` joints held fixed (merged like fixed joints), e.g. fingers.
        snap: angles within ``snap`` rad of a multiple of pi/2 are taken as exact (see
            :mod:`symgen.io.urdf.rotations`); 0 keeps every angle as written.
        friction: carry ``<dynamics damping friction>`` into the joints (``False``: none).
        inertia: ``"warn"`` (default), ``"repair"`` or ``"strict"``: what to do with inertias no rigid
            body has (:mod:`symgen.io.urdf.physics`).
        floating: put a free joint (:mod:`symgen.scene.free_joint`) named ``<prefix>floating_base``
            between the world and the root link instead of welding the root to the world; the
            base placement is then the free joint's reference position ``q0``.
        mimic: read ``<mimic>`` as joint couplings (default); ``False`` reads every mimicking
            joint as an independent, actuated joint, as Pinocchio's default parse does (with a
            note): for files whose ``<mimic>`` names a joint they lack.

    Returns:
        the :class:`UrdfSource` (also appended to ``scene.sources``).
    """
    robot = urdf if isinstance(urdf, UrdfRobot) else read_urdf(urdf)
    if not mimic:
        robot = _without_mimics(robot)
    lock_v = _exact_map(lock, robot, prefix, "lock")
    q0_v = _exact_map(q0, robot, prefix, "q0")
    mimic_notes = _check_supported(robot, lock_v)
    locked_q0 = sorted(set(lock_v) & set(q0_v))
    if locked_q0:
        raise UrdfError(f"joint {locked_q0[0]!r}", "is both locked and given a q0")
    base_rot, base_trans = _base_pose(base_xyz, base_rpy, base_quat, snap)
    src = UrdfSource(robot, prefix, base_rot, base_trans, lock_v, friction=friction,
                     inertia=check_inertia_mode(inertia),
                     floating=scene_name(prefix, FLOATING_BASE) if floating else None)
    owner, pose, moving = _layout(robot, src, snap)
    inertials, findings = judged_inertials(robot, owner, inertia)
    masses = _masses(robot, owner, pose, snap, inertials)
    locks, massless = _massless_locks(robot, owner, moving, masses, q0_v, strict=src.inertia == "strict",
                                      floating=bool(src.floating))
    if locks:                      # laid out again with the massless joints welded
        src.lock.update(locks)
        q0_v = {k: v for k, v in q0_v.items() if k not in locks}
        owner, pose, moving = _layout(robot, src, snap)
        inertials, findings = judged_inertials(robot, owner, inertia)
        masses = _masses(robot, owner, pose, snap, inertials)
    findings += massless
    src.repaired = [n for n, props in inertials.items()      # noise rounded to zero is no repair
                    if props.inertia != rounded_inertia(robot.links[n].inertial.inertia)]
    if floating:
        _add_floating_base(scene, robot, src, masses)
    else:
        findings += [f for f in [free_base_finding(robot, owner, moving)] if f is not None]
    findings += _friction_notes(moving, friction)
    limits = scene.joint_limits
    references = _references(moving, q0_v)
    for j, parent, body, rot, trans in moving:
        name = scene_name(prefix, j.name)
        try:
            with warnings.catch_warnings():        # judged above, and reported naming the URDF link
                warnings.simplefilter("ignore", errors.InertiaWarning)
                scene.add_body(body, **masses.get(body, MassProperties.zero()).scene_arguments())
            scene.add_joint(name, MOVING[j.type].name, parent, body, xyz=list(trans), quat=quaternion_argument(rot),
                            axis=axis_argument(j.axis), actuated=j.mimic is None, q0=references[j.name],
                            viscous=j.damping if friction else 0, coulomb=j.friction if friction else 0)
        except SceneError as exc:
            if isinstance(exc, UrdfError):
                raise
            raise UrdfError(exc.element, f"{exc.message} (from URDF joint {j.name!r})", robot.source, j.line) from None
        src.joints[j.name] = name
        limits[name] = j.limits if j.type != "continuous" else JointLimits(velocity=j.limits.velocity,
                                                                            effort=j.limits.effort)
    _add_couplings(scene, robot, src, moving)
    _add_link_frames(scene, robot, src, owner, pose)
    scene.sources.append(src)
    report(scene, [(None, note) for note in robot.notes + mimic_notes] + findings, f"robot {robot.name!r}")
    return src


def _references(moving: list, q0: dict) -> dict:
    """``q0`` of every moving joint (:func:`_reference`); a mimicking joint's follows its leader's,
    ``multiplier q0_leader + offset``, unless given."""
    by_name = {j.name: j for j, *_ in moving}
    out: dict = {}

    def reference(j: UrdfJoint):
        if j.name not in out:
            follows = j.mimic is not None and j.name not in q0 and j.mimic.joint in by_name
            out[j.name] = (sp.Rational(j.mimic.multiplier) * reference(by_name[j.mimic.joint])
                           + sp.Rational(j.mimic.offset)) if follows else _reference(j, q0.get(j.name))
        return out[j.name]

    for j in by_name.values():
        reference(j)
    return out


def _add_couplings(scene: Scene, robot: UrdfRobot, src: UrdfSource, moving: list) -> None:
    """The coupling ``q = multiplier q_leader + offset`` of every moving mimicking joint."""
    for j, *_ in moving:
        if j.mimic is None:
            continue
        name = scene_name(src.prefix, j.name)
        try:
            scene.add_coupling(f"{name}_mimic", name, src.joints[j.mimic.joint],
                               multiplier=sp.Rational(j.mimic.multiplier), offset=sp.Rational(j.mimic.offset))
        except SceneError as exc:
            raise UrdfError(exc.element, f"{exc.message} (from the <mimic> of URDF joint {j.name!r})", robot.source,
                            j.line) from None
        src.mimics[j.name] = f"{name}_mimic"


def floating_body(robot: UrdfRobot, prefix: str) -> str:
    """The scene body of a floating robot's root link (a root link named ``world``, as ROS files
    often have, becomes ``world_link``)."""
    name = scene_name(prefix, robot.root)
    return name if name != WORLD else scene_name(prefix, "world_link")


def _add_floating_base(scene: Scene, robot: UrdfRobot, src: UrdfSource, masses: dict) -> None:
    """The root link as a body on a free joint from the world, at the base placement."""
    body = floating_body(robot, src.prefix)
    quat = quaternion_argument(src.base_rotation) or [1, 0, 0, 0]
    try:
        scene.add_body(body, **masses.get(body, MassProperties.zero()).scene_arguments())
        scene.add_joint(src.floating, "free", WORLD, body, q0=list(src.base_translation) + list(quat))
    except SceneError as exc:
        if isinstance(exc, UrdfError):
            raise
        raise UrdfError(exc.element, f"{exc.message} (the floating base of URDF link {robot.root!r})",
                        robot.source, robot.links[robot.root].line) from None


def scene_from_urdf(path, *, name: str | None = None, validate: bool = True, **options) -> Scene:
    """A :class:`~symgen.scene.Scene` of one URDF robot on a fixed base, every moving joint
    actuated and a motion coordinate (``V_m = qd``).

    ``options`` are those of :func:`add_urdf` (``prefix``, ``base_xyz``, ``base_rpy``,
    ``base_quat``, ``q0``, ``lock``, ``snap``, ``friction``, ``inertia``).

    Raises:
        NoMovingJointError: the robot has no revolute, continuous or prismatic joint (or all are locked).
        UrdfError: anything else the file holds that symgen cannot model, named.

    >>> from symgen.io.urdf.examples import example_path
    >>> scene = scene_from_urdf(example_path("ur5"))               # doctest: +SKIP
    >>> list(scene.joints)[:2]                                     # doctest: +SKIP
    ['shoulder_pan_joint', 'shoulder_lift_joint']
    """
    robot = path if isinstance(path, UrdfRobot) else read_urdf(path)
    scene = Scene(name or scene_name("", robot.name),
                  description=f"URDF robot {robot.name!r} from {os.path.basename(robot.source)}")
    src = add_urdf(scene, robot, **options)
    if not src.joints and not src.floating:       # a free body alone (a quadrotor) moves by its free joint
        raise no_moving_joint(robot)
    scene.set_motion(joints=([src.floating] if src.floating else []) + src.leading_joints)
    if validate:
        scene.validate()
    return scene


def no_moving_joint(robot: UrdfRobot) -> NoMovingJointError:
    kinds = sorted({j.type for j in robot.joints.values()})
    return NoMovingJointError(f"robot {robot.name!r}", "has no moving joint (no revolute, continuous or prismatic "
                              f"joint that is not locked; joint types in the file: {', '.join(kinds) or 'none'}): "
                              "with nothing that moves there is no dynamics to model (a free body, e.g. a drone: "
                              "floating=True)", robot.source)
