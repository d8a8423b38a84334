"""An :class:`~symgen.scene.Scene` from a parsed MJCF model (:mod:`symgen.io.mjcf.parse`).

Frames. MJCF places a body's frame in its parent's frame and puts the body's joint at ``pos`` in
the body frame; symgen's child frame is the joint frame after the joint's motion. So each symgen
body frame is the MJCF body frame shifted by its joint's ``pos`` (``offset``, same axes): centres
of mass, sites and anchors are moved by ``-offset``; the joint's origin in the parent's symgen
frame is ``R offset + pos - offset_parent`` with the body's rotation ``R``. A body without a joint
is welded by a fixed joint ``fix_<body>``.

Coordinates. MuJoCo draws a body at ``qpos0``: a hinge or slide at its ``ref`` (0 unless given), a
ball at the identity. symgen's joint coordinate is MuJoCo's ``qpos`` itself: the joint's origin
is turned by ``-ref`` about (or moved by ``-ref`` along) its axis, and ``q0 = ref``. For a ball
joint, symgen's rotation is the matrix of MuJoCo's quaternion ``qpos`` (w, x, y, z) and its three
rates are MuJoCo's ``qvel`` (the angular velocity in the body frame).

Equalities. ``connect body1 body2 anchor`` is a ``ball`` constraint: frame ``<name>_a`` on body1 at
the anchor, frame ``<name>_b`` on body2 where the anchor is at ``qpos0``. ``weld body1 body2`` is a
``weld`` between frame ``<name>_b`` on body2 at ``anchor`` (in body2's frame, as MuJoCo reads a
weld's anchor) and frame ``<name>_a`` on body1 where it must be: at ``relpose`` (position, then
quaternion, in body1's frame -- MuJoCo's constraint puts body2's anchor point there, with body2's
axes turned by the quaternion from body1's), or where it is at ``qpos0`` when ``relpose`` is not
given (or its quaternion is zero, MuJoCo's default). Site
forms, ``connect site1 site2`` and ``weld site1 site2``, constrain the two sites' frames (their
origins for a connect, their whole frames for a weld), as MuJoCo does.

Rows. A ``connect`` closing a planar loop has a row that vanishes identically (the motion normal
to the plane), a ``weld`` three; :func:`symgen.vanishing_rows.drop_vanishing_rows` removes such rows
with a note naming them (``Scene.notes``) before the model is derived.

Motion coordinates: the actuated joints (``<actuator>``), which must number ``m`` (eq. 5). On a tree
(no loop) with fewer actuated joints than DOF -- an underactuated robot such as the acrobot, or a
file with no actuator at all -- every joint is a motion coordinate (``V_m = qd``) and the joints
without an actuator stay passive (``actuated=False``), with a note naming them: the model is the
whole robot's, and the force of a passive joint is what inverse dynamics returns for it (zero in
a passive simulation). An actuator whose transmission is a tendon, a site or a body drives no
single joint and marks none actuated (a note says so). A closed chain needs exactly ``m``
actuated joints, or ``motion=``.

Several joints in one body. MuJoCo applies a body's joints in file order, each about (or along)
its own axis through its own ``pos``, both given in the body frame already moved by the joints
before it. symgen makes that a chain: each joint but the last moves a massless body named
``<body>_<joint>`` (:func:`chain_name`) whose frame is the MJCF body frame (moved by the joints so
far) shifted to that joint's ``pos``; the last joint moves the body itself.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, replace

import sympy as sp

from ...errors import ConstraintError, SceneError
from ...scene.joint_kinds import joint_kind
from ...math.numbers import is_identifier
from ...math.rotations_snap import snap_rotation
from ...scene.declaration import WORLD, Scene
from ..urdf.build import scene_name
from .parse import MjcfError, parse_mjcf
from .records import MjcfBody, MjcfJoint, MjcfModel
from .values import axis_angle_matrix

#: the scene's name when the file's ``model`` gives no usable one
DEFAULT_NAME = "mjcf_robot"


@dataclass(frozen=True)
class MjcfSource:
    """Where a scene came from: the file and each body's frame offset (symgen frame origin in the
    MJCF body frame), for the Pinocchio cross-check."""

    path: str
    text: str
    offsets: dict


def mjcf_source(scene: Scene) -> MjcfSource | None:
    """The MJCF file ``scene`` was read from, or ``None``."""
    return next((s for s in scene.sources if isinstance(s, MjcfSource)), None)


def _scene_name(name: str) -> str:
    """The scene's name for the file's ``model``: a plain identifier (non-identifier characters
    replaced as the URDF reader replaces them, at most 64 characters)."""
    clean = scene_name("", name)[:64]
    return clean if is_identifier(clean) and re.search("[A-Za-z0-9]", clean) else DEFAULT_NAME


def _expand(m: sp.Matrix) -> list:
    """The entries of ``m``, expanded, as a list."""
    return list(m.applyfunc(sp.expand))


def _joint_origin(rot: sp.Matrix, j: MjcfJoint, element: str) -> tuple[sp.Matrix, sp.Matrix]:
    """``(translation, rotation)`` of joint ``j``'s origin, placed with rotation ``rot``, so that q =
    MuJoCo's qpos (the joint turned back by ``ref``), in the parent's frame."""
    if j.ref == 0:
        return sp.zeros(3, 1), rot
    if joint_kind(j.kind).translates:
        unit = j.axis / sp.sqrt(sum(v * v for v in j.axis))
        return -j.ref * rot * unit, rot
    turn = snap_rotation(element, axis_angle_matrix(j.axis, -float(j.ref)).tolist())
    return sp.zeros(3, 1), (rot * sp.Matrix(turn)).applyfunc(sp.expand)


def chain_name(body: str, joint: str) -> str:
    """The massless body that carries a body's joint ``joint`` when more joints follow it."""
    return f"{body}_{joint}"


def _add_bodies(scene: Scene, mj: MjcfModel) -> dict:
    """Bodies, joints and site frames; returns each body's offset (its last joint's ``pos``)."""
    offsets = {WORLD: sp.zeros(3, 1)}
    for b in mj.bodies:
        links = [chain_name(b.name, j.name) for j in b.joints[:-1]] + [b.name]
        parent, xyz, rot = b.parent, b.rot * (b.joints[0].pos if b.joints else sp.zeros(3, 1)) + b.pos, b.rot
        xyz -= offsets[b.parent]
        for i, (link, j) in enumerate(zip(links, b.joints or [None])):
            offsets[link] = j.pos if j is not None else sp.zeros(3, 1)
            try:
                if link == b.name and b.inertial is not None:
                    i3 = b.inertial.inertia
                    scene.add_body(link, b.inertial.mass, com=_expand(b.inertial.pos - offsets[link]),
                                   inertia=[i3[0, 0], i3[1, 1], i3[2, 2], i3[0, 1], i3[0, 2], i3[1, 2]])
                else:
                    scene.add_body(link, 0)
            except SceneError as exc:
                raise MjcfError(f"<body name={b.name!r}>", exc.message, mj.source, b.line) from None
            _add_joint(scene, mj, b, j, parent, link, xyz, rot)
            if i + 1 < len(b.joints):         # the next joint: same body frame, at its own pos
                parent, xyz, rot = link, b.joints[i + 1].pos - j.pos, sp.eye(3)
    for s in mj.sites:
        try:
            scene.add_frame(s.name, s.body, xyz=_expand(s.pos - offsets[s.body]), rotation=s.rot.tolist())
        except SceneError as exc:
            raise MjcfError(f"<site name={s.name!r}>", exc.message, mj.source, s.line) from None
    return offsets


def _add_joint(scene: Scene, mj: MjcfModel, b: MjcfBody, j: MjcfJoint | None, parent: str, child: str,
               xyz: sp.Matrix, rot: sp.Matrix) -> None:
    """Joint ``j`` of ``b`` between ``parent`` and ``child`` (a fixed one when None), placed at
    ``xyz``, ``rot`` and turned back by ``ref``."""
    if j is None:
        try:
            scene.add_joint(f"fix_{b.name}", "fixed", parent, child, xyz=_expand(xyz), rotation=rot.tolist())
        except SceneError as exc:
            raise MjcfError(f"<body name={b.name!r}>", exc.message, mj.source, b.line) from None
        return
    element = f"<joint name={j.name!r}> in body {b.name!r}"
    if j.kind == "free":
        _add_free_joint(scene, mj, j, parent, child, xyz, rot, element)
        return
    one_dof = joint_kind(j.kind).is_one_dof
    try:
        if not one_dof and j.armature != 0:
            raise SceneError(element, "armature on a ball joint is not read (symgen's rotor inertia is for "
                                      "1-DOF joints, eq. 23); put it in the body's inertia")
        shift, turned = _joint_origin(rot, j, element)
        scene.add_joint(j.name, j.kind, parent, child, xyz=_expand(xyz + shift), rotation=turned.tolist(),
                        axis=_expand(j.axis), actuated=j.name in mj.actuated,
                        rotor_inertia=j.armature if one_dof else 0, viscous=j.damping, coulomb=j.frictionloss,
                        q0=j.ref if one_dof else None, stiffness=j.stiffness if one_dof else 0,
                        springref=j.springref)
    except SceneError as exc:        # keep the message, add the line
        raise MjcfError(element, exc.message, mj.source, j.line) from None


def _add_free_joint(scene: Scene, mj: MjcfModel, j: MjcfJoint, parent: str, child: str, xyz: sp.Matrix,
                    rot: sp.Matrix, element: str) -> None:
    """A free joint at the world's origin whose reference position is the body's pose as drawn, so
    that its coordinates are MuJoCo's ``qpos`` (``x y z``, quaternion ``w x y z``) and ``qvel``."""
    from ...math.spatial import matrix_to_quat

    quat = [1, 0, 0, 0] if rot == sp.eye(3) else [sp.simplify(v) for v in matrix_to_quat(rot, sqrt=sp.sqrt)]
    try:
        scene.add_joint(j.name, "free", parent, child, q0=list(_expand(xyz)) + quat)
    except SceneError as exc:
        raise MjcfError(element, exc.message, mj.source, j.line) from None


def _world_poses(mj: MjcfModel) -> dict:
    """Exact world pose ``(R, p)`` of every MJCF body frame as drawn (``qpos0``)."""
    poses = {WORLD: (sp.eye(3), sp.zeros(3, 1))}
    for b in mj.bodies:
        r_p, p_p = poses[b.parent]
        poses[b.name] = ((r_p * b.rot).applyfunc(sp.expand), (p_p + r_p * b.pos).applyfunc(sp.expand))
    return poses


def _equality_frames(eq, poses: dict) -> tuple:
    """``(pos_a, rot_a), (pos_b, rot_b)`` of a body equality's frames in the MJCF frames of body1
    and body2 (see the module docstring)."""
    (r1, p1), (r2, p2) = poses[eq.body1], poses[eq.body2]
    if eq.kind == "connect":
        world = p1 + r1 * eq.anchor
        return (eq.anchor, sp.eye(3)), (r2.T * (world - p2), r2.T * r1)
    if eq.relpose is not None:       # MuJoCo: the anchor on body2 meets relpose's point on body1
        return eq.relpose, (eq.anchor, sp.eye(3))
    world = p2 + r2 * eq.anchor
    return (r1.T * (world - p1), r1.T * r2), (eq.anchor, sp.eye(3))


def _add_equalities(scene: Scene, mj: MjcfModel, offsets: dict) -> None:
    """Each equality as a ``ball`` (connect) or ``weld`` constraint between two frames, a joint
    equality as a joint coupling (:meth:`~symgen.scene.Scene.add_coupling`)."""
    poses = _world_poses(mj)
    kinds = {"connect": "ball", "weld": "weld"}
    refs = {j.name: j.ref for b in mj.bodies for j in b.joints}
    for eq in mj.equalities:
        try:
            if eq.kind == "joint":              # q1 - c1 q2 = q1_0 + c0 - c1 q2_0 (qpos0 = ref = q0)
                c0, c1 = eq.polycoef
                offset = refs.get(eq.joint1, 0) + c0 - c1 * refs.get(eq.joint2, 0)
                scene.add_coupling(eq.name, eq.joint1, eq.joint2, multiplier=c1, offset=offset)
                if c0 != 0:                     # qpos0 opens it by c0: symgen's q0 of joint1 closes it
                    j1 = scene.joints[eq.joint1]
                    scene.joints[eq.joint1] = replace(j1, q0=j1.q0 + c0)
                    scene.notes.append(f"MJCF: joint {eq.joint1!r} starts at q0 = ref + {c0} (polycoef c0 of "
                                       f"equality {eq.name!r}), where its coupling holds; MuJoCo's qpos0 leaves "
                                       "it open by that much")
                continue
            if eq.kind == "tendon":
                _add_tendon_coupling(scene, eq, refs)
                continue
            if eq.site1 is not None:
                scene.add_constraint(eq.name, kinds[eq.kind], eq.site1, eq.site2)
                continue
            frames = []
            for suffix, body, (pos, rot) in zip("ab", (eq.body1, eq.body2), _equality_frames(eq, poses)):
                frames.append(f"{eq.name}_{suffix}")
                scene.add_frame(frames[-1], body, xyz=_expand(pos - offsets[body]),
                                rotation=rot.applyfunc(sp.expand).tolist())
            scene.add_constraint(eq.name, kinds[eq.kind], *frames)
        except SceneError as exc:
            raise MjcfError(f"<{eq.kind} name={eq.name!r}>", exc.message, mj.source, eq.line) from None


def _add_tendon_coupling(scene: Scene, eq, refs: dict) -> None:
    """A fixed-tendon equality ``L1 - L1_0 = c0 + c1 (L2 - L2_0)``, ``L = sum coef_i q_i``, as the
    joint coupling ``sum_i k_i q_i = sum_i k_i q_i_0 + c0`` with ``k = coef(L1) - c1 coef(L2)``,
    divided by its first joint's ``k``; a ``c0`` moves that joint's ``q0`` onto the coupling."""
    c0, c1 = eq.polycoef
    k: dict = {}
    for path, scale in ((eq.tendon1, 1), (eq.tendon2, -c1)):
        for joint, coef in path:
            k[joint] = k.get(joint, 0) + scale * coef
    k = {j: c for j, c in k.items() if c != 0}
    if len(k) < 2:
        raise SceneError(f"constraint {eq.name!r}", f"the tendons' joints combine to {len(k)} joint(s) with a "
                                                    "nonzero coefficient: that holds a joint fixed or nothing, "
                                                    "not a coupling (lock the joint instead)")
    (first, k0), *others = k.items()
    for j in k:
        if j not in refs:
            raise SceneError(f"constraint {eq.name!r}", f"joint {j!r} of its tendon is not declared")
    offset = sum(c * refs[j] for j, c in k.items()) / k0 + c0 / k0
    scene.add_coupling(eq.name, first, terms={j: c / k0 for j, c in others}, offset=offset)
    if c0 != 0:
        j1 = scene.joints[first]
        scene.joints[first] = replace(j1, q0=j1.q0 + c0 / k0)
        scene.notes.append(f"MJCF: joint {first!r} starts at q0 = ref + {c0 / k0} (polycoef c0 of equality "
                           f"{eq.name!r}), where its coupling holds; MuJoCo's qpos0 leaves it open by that much")


def _check_closed(scene: Scene, mj: MjcfModel) -> None:
    """Every equality holds at ``qpos0`` (symgen's ``q0``), else the loop is open as drawn: an
    error at the equality's line, before the rows are examined (which needs closed loops)."""
    from ...model import check_closed, reference_configuration
    from ...tree import build_tree

    if not scene.constraints:
        return
    try:
        check_closed(scene, build_tree(scene), reference_configuration(scene))
    except ConstraintError as exc:
        line = next((eq.line for eq in mj.equalities if exc.element == f"constraint {eq.name!r}"), None)
        raise MjcfError(exc.element, exc.message + " (MuJoCo's efc_pos is not zero at qpos0 either)", mj.source,
                        line) from None


def _set_motion(scene: Scene, mj: MjcfModel, motion: dict | None) -> None:
    """``V_m``: the caller's ``motion``, else the actuated joints (every joint of a tree without them)."""
    if motion is not None:
        try:
            scene.set_motion(**motion)
        except (SceneError, TypeError) as exc:
            raise MjcfError("motion", getattr(exc, "message", str(exc)), mj.source, None) from None
        return
    n_all = sum(j.dof for j in scene.joints.values())
    moving = [j.name for j in scene.joints.values() if j.dof]
    if not moving:
        raise MjcfError("<worldbody>", "has no joint: with nothing that moves there is no dynamics to model",
                        mj.source, None)
    m = n_all - sum(c.dim for c in scene.constraints.values())
    chosen = mj.actuated
    if not scene.constraints and len(chosen) != m:      # a tree: V_m = qd, the passive joints included
        free_parts = {j: f.name for f in scene.free_joints.values() for j in f.joints}
        passive = list(dict.fromkeys(free_parts.get(n, n) for n in moving if n not in mj.actuated))
        shown = list(dict.fromkeys(free_parts.get(n, n) for n in moving))
        scene.notes.append(f"MJCF: {'no joint has' if not mj.actuated else f'{len(passive)} of {len(shown)} joints have no'} "
                           f"actuator ({', '.join(passive[:6])}{', ...' if len(passive) > 6 else ''}): on a tree every "
                           "joint is a motion coordinate (V_m = qd) and the joints without actuator are passive "
                           "(their force is an output of inverse dynamics, zero in a passive simulation)")
        chosen = moving
        if n_all == m:
            _set_rates(scene, mj, chosen)
            return
    if len(chosen) != m and _coupled_tree_motion(scene, mj, moving):
        return
    if len(chosen) != m:
        raise MjcfError("<actuator>", f"the robot has m = {m} motion DOF (eq. 5) but {len(chosen)} actuated "
                                      "joint(s); symgen takes the actuated joints as the motion coordinates of a "
                                      f"closed chain -- give {m} <motor joint=...>, or motion=...", mj.source, None)
    try:
        scene.set_motion(joints=chosen)
    except SceneError as exc:
        raise MjcfError("<actuator>", exc.message, mj.source, None) from None


def _coupled_tree_motion(scene: Scene, mj: MjcfModel, moving: list) -> bool:
    """A tree whose only constraints are joint couplings, without one actuator per motion DOF:
    ``V_m`` = every joint's rates but the first joint of each coupling (its ``joint1``, or the
    first joint of its tendon), which the coupling makes dependent (eq. 10), as a URDF mimic joint.
    ``False`` (nothing set) when there are loops between frames or two couplings share that joint."""
    couplings = [c for c in scene.constraints.values() if c.is_coupling]
    dependent = [c.terms[0][0] for c in couplings]
    if len(couplings) != len(scene.constraints) or len(set(dependent)) != len(dependent):
        return False
    free_parts = {j: f.name for f in scene.free_joints.values() for j in f.joints}
    chosen = list(dict.fromkeys(free_parts.get(n, n) for n in moving if n not in dependent))
    scene.notes.append(f"MJCF: {len(mj.actuated)} actuated joint(s) for a tree with {len(couplings)} joint "
                       f"coupling(s): every joint is a motion coordinate but the coupled ones "
                       f"({', '.join(dependent[:6])}{', ...' if len(dependent) > 6 else ''}), whose rates the "
                       "couplings give (eq. 10); the joints without actuator are passive")
    _set_rates(scene, mj, chosen)
    return True


def _set_rates(scene: Scene, mj: MjcfModel, joints: list) -> None:
    """``V_m`` = every rate of ``joints`` (a ball or free joint's several)."""
    try:
        scene.set_motion(joints=joints)
    except SceneError as exc:
        raise MjcfError("<actuator>", exc.message, mj.source, None) from None


def scene_from_mjcf_model(mj: MjcfModel, path: str = "", *, motion: dict | None = None) -> Scene:
    """The scene of a parsed MJCF model (see the module docstring). ``motion``: keywords of
    :meth:`~symgen.scene.Scene.set_motion` to use instead of the actuated joints (a tree with ball
    joints, whose rates no list of 1-DOF joints names, needs frames here)."""
    from ...vanishing_rows import drop_vanishing_rows

    scene = Scene(name=_scene_name(mj.name), description=f"read from MJCF {path or mj.source}")
    scene.gravity = sp.ImmutableMatrix(list(mj.gravity))
    scene.notes.extend(mj.notes)
    offsets = _add_bodies(scene, mj)
    _add_equalities(scene, mj, offsets)
    _check_closed(scene, mj)
    scene = drop_vanishing_rows(scene)
    _set_motion(scene, mj, motion)
    scene.sources.append(MjcfSource(str(path or mj.source), mj.text, {k: tuple(v) for k, v in offsets.items()}))
    return scene


def scene_from_mjcf(path, *, motion: dict | None = None, fluid: str = "refuse") -> Scene:
    """A :class:`~symgen.scene.Scene` from an MJCF file, exact, with located typed errors
    (``motion`` as in :func:`scene_from_mjcf_model`; ``fluid="ignore"``: a model in a fluid medium
    read without its fluid forces, with a note and a warning, :func:`symgen.io.mjcf.parse.parse_mjcf_text`)."""
    return scene_from_mjcf_model(parse_mjcf(path, fluid=fluid), str(path), motion=motion)
