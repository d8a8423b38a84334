"""An :class:`~symgen.scene.Scene` from a parsed MJCF model (:mod:`symgen.mjcf.parse`).

Frames. MJCF places a body's frame in its parent's frame and puts the body's joint at ``pos`` in
the body frame; symgen's child frame is the joint frame after the joint's motion. So each symgen
body frame is the MJCF body frame shifted by its joint's ``pos`` (``offset``, same axes): centres
of mass, sites and anchors are moved by ``-offset``; the joint's origin in the parent's symgen
frame is ``R offset + pos - offset_parent`` with the body's rotation ``R``. A body without a joint
is welded by a fixed joint ``fix_<body>``.

Equalities. ``connect body1 body2 anchor`` is a ``ball`` constraint: frame ``<name>_a`` on body1 at
the anchor, frame ``<name>_b`` on body2 where the anchor is at ``qpos0`` (all joints at zero). A
``weld`` is a ``weld`` constraint between body1's frame at the anchor (or ``relpose``) and its
place on body2 at ``qpos0``. MuJoCo, like symgen, takes ``qpos0`` as closing every loop.

Rows. A ``connect`` closing a planar loop has a row that vanishes identically (the motion normal
to the plane), a ``weld`` three; :func:`symgen.vanishing_rows.drop_vanishing_rows` removes such rows
with a note naming them (``Scene.notes``) before the model is derived.

Motion coordinates: the actuated joints (``<actuator>``), which must number ``m`` (eq. 5); with no
actuator and no loop, every joint.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..numbers import is_identifier
from ..errors import SceneError
from ..joint_kinds import joint_kind
from ..scene import WORLD, Scene
from .parse import MjcfError, MjcfModel, parse_mjcf


@dataclass(frozen=True)
class MjcfSource:
    """Where a scene came from: the file and each body's frame offset (symgen frame origin in the
    MJCF body frame), for the Pinocchio cross-check."""

    path: str
    text: str
    offsets: dict


def _vec(values) -> sp.Matrix:
    return sp.Matrix([sp.nsimplify(v) for v in values])


def _scene_name(name: str) -> str:
    clean = "".join(c if c.isalnum() or c == "_" else "_" for c in name)
    return clean if is_identifier(clean) else "mjcf_" + clean


def _add_bodies(scene: Scene, mj: MjcfModel) -> dict:
    offsets = {WORLD: sp.zeros(3, 1)}
    for b in mj.bodies:
        j = b.joint
        offset = _vec(j.pos) if j is not None else sp.zeros(3, 1)
        offsets[b.name] = offset
        try:
            if b.inertial is not None:
                com = _vec(b.inertial.pos) - offset
                i = b.inertial.inertia
                scene.add_body(b.name, b.inertial.mass, com=list(com),
                               inertia=[i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2]])
            else:
                scene.add_body(b.name, 0)
        except SceneError as exc:
            raise MjcfError(f"<body name={b.name!r}>", exc.message, mj.source, b.line) from None
        xyz = list((b.rot * offset + _vec(b.pos) - offsets[b.parent]).applyfunc(sp.simplify))
        _add_joint(scene, mj, b, xyz)
        for name, pos, rot, _line in b.sites:
            scene.add_frame(name, b.name, xyz=list(_vec(pos) - offset), rotation=rot.tolist())
    return offsets


def _add_joint(scene: Scene, mj: MjcfModel, b, xyz) -> None:
    j = b.joint
    if j is None:
        scene.add_joint(f"fix_{b.name}", "fixed", b.parent, b.name, xyz=xyz, rotation=b.rot.tolist())
        return
    one_dof = joint_kind(j.kind).is_one_dof
    if not one_dof and j.armature != 0:
        raise MjcfError(f"<joint name={j.name!r}>", "armature on a ball joint is not read", mj.source, j.line)
    try:
        scene.add_joint(j.name, j.kind, b.parent, b.name, xyz=xyz, rotation=b.rot.tolist(),
                        axis=list(_vec(j.axis)), actuated=j.name in mj.actuated,
                        rotor_inertia=j.armature if one_dof else 0, viscous=j.damping,
                        coulomb=j.frictionloss)
    except SceneError as exc:        # keep the message, add the line
        raise MjcfError(f"<joint name={j.name!r}> in body {b.name!r}", exc.message, mj.source, j.line) from None


def _world_poses(scene: Scene) -> dict:
    """Exact world pose ``(R, p)`` of every body's symgen frame with all joints at zero (``qpos0``)."""
    poses = {WORLD: (sp.eye(3), sp.zeros(3, 1))}
    for j in scene.tree_order():
        r_p, p_p = poses[j.parent]
        r_o, p_o = sp.Matrix(j.origin.rotation), sp.Matrix(j.origin.translation)
        poses[j.child] = ((r_p * r_o).applyfunc(sp.simplify), (p_p + r_p * p_o).applyfunc(sp.simplify))
    return poses


def _add_equalities(scene: Scene, mj: MjcfModel, offsets: dict) -> None:
    poses = _world_poses(scene)
    for eq in mj.equalities:
        if eq.relpose is not None:
            pos_a, rot_a = _vec(eq.relpose[0]) - offsets[eq.body1], eq.relpose[1]
        else:
            pos_a, rot_a = _vec(eq.anchor) - offsets[eq.body1], sp.eye(3)
        r1, p1 = poses[eq.body1]
        r2, p2 = poses[eq.body2]
        world_r, world_p = r1 * rot_a, p1 + r1 * pos_a
        pos_b = (r2.T * (world_p - p2)).applyfunc(sp.simplify)
        rot_b = (r2.T * world_r).applyfunc(sp.simplify)
        name_a, name_b = f"{eq.name}_a", f"{eq.name}_b"
        try:
            scene.add_frame(name_a, eq.body1, xyz=list(pos_a), rotation=rot_a.tolist())
            scene.add_frame(name_b, eq.body2, xyz=list(pos_b), rotation=rot_b.tolist())
            scene.add_constraint(eq.name, "ball" if eq.kind == "connect" else "weld", name_a, name_b)
        except SceneError as exc:
            raise MjcfError(f"<{eq.kind} name={eq.name!r}>", exc.message, mj.source, eq.line) from None


def _set_motion(scene: Scene, mj: MjcfModel) -> None:
    n_all = sum(j.dof for j in scene.joints.values())
    m = n_all - sum(c.dim for c in scene.constraints.values())
    chosen = mj.actuated or ([j.name for j in scene.joints.values() if j.dof] if not scene.constraints else [])
    if len(chosen) != m:
        raise MjcfError("<actuator>", f"the robot has m = {m} motion DOF (eq. 5) but {len(chosen)} actuated "
                                      "joint(s); symgen takes the actuated joints as the motion coordinates -- "
                                      f"give {m} <motor joint=...>", mj.source, None)
    scene.set_motion(joints=chosen)


def scene_from_mjcf_model(mj: MjcfModel, path: str = "") -> Scene:
    """The scene of a parsed MJCF model (see the module docstring)."""
    from ..vanishing_rows import drop_vanishing_rows

    scene = Scene(name=_scene_name(mj.name), description=f"read from MJCF {path or mj.source}")
    scene.gravity = sp.ImmutableMatrix(list(_vec(mj.gravity)))
    offsets = _add_bodies(scene, mj)
    _add_equalities(scene, mj, offsets)
    scene = drop_vanishing_rows(scene)
    _set_motion(scene, mj)
    scene.mjcf_source = MjcfSource(str(path or mj.source), mj.text, {k: tuple(v) for k, v in offsets.items()})
    return scene


def scene_from_mjcf(path) -> Scene:
    """A :class:`~symgen.scene.Scene` from an MJCF file, exact, with located typed errors."""
    return scene_from_mjcf_model(parse_mjcf(path), str(path))
