"""Feet and hands on the ground: contact constraints of a floating-base robot.

A robot standing on the ground is a closed chain through the ground, exactly the paper's general
constrained robot (Section 2): each contact is a constraint of eq. (6) between a frame on the
robot and a frame fixed to the world at the contact's place,

* ``point`` (3 rows): the frame's origin does not move (a point foot that does not slip);
* ``flat`` (6 rows): the frame does not move at all (a sole flat on the ground, a weld).

The ground frame is placed where the robot's frame is at the scene's reference configuration
``q0`` (50-digit forward kinematics rounded to 1e-20, :func:`~symgen.math.spatial.pose_to_exact`),
so every contact holds at ``q0``. The constraint's rows are the robot frame's velocity components
in its own axes, so the contact force of :meth:`symgen.model.Model.loop_forces` is the force (and,
for a flat contact, the moment) the ground exerts on the robot's body, in the robot frame's axes
at its origin; :meth:`~symgen.model.Model.constraint_wrenches` gives it in world axes.

With the contacts closed, the floating base's six rates are dependent (``n_p = 6`` of eq. 10,
found by Step 5) and the legs' joint rates the independent ones; :func:`stand` chooses the base's
twist as the motion coordinates ``V_m`` and ``T_c = 1`` (``constraint_forces: joint``, eq. 12), since
``T_a1`` is not square when constraints fall on the passive base.
"""
from __future__ import annotations

from collections.abc import Sequence

from .errors import SceneError
from .math.spatial import pose_to_exact
from .reference_kinematics import reference_pose, reference_poses
from .scene.declaration import WORLD, Scene

#: contact kind -> the constraint kind it declares
CONTACT_KINDS = {"point": "point", "flat": "weld"}


def add_ground_contact(scene: Scene, frame: str, kind: str = "point", *, name: str | None = None,
                       poses: dict | None = None) -> str:
    """Declare a contact of ``frame`` with the ground (``kind`` ``"point"`` or ``"flat"``).

    The ground frame ``<name>_ground`` is fixed to the world at ``frame``'s pose at ``q0``;
    the constraint ``name`` (default ``<frame>_contact``) removes the frame's velocity relative to
    it. ``poses`` are :func:`~symgen.reference_kinematics.reference_poses` computed once for
    several contacts. Returns the constraint's name."""
    name = name or f"{frame}_contact"
    element = f"contact {name!r}"
    if kind not in CONTACT_KINDS:
        raise SceneError(element, f"unknown contact kind {kind!r}; use one of {', '.join(CONTACT_KINDS)}")
    if not isinstance(frame, str) or frame not in scene.frames:
        raise SceneError(element, f"frame {frame!r} is not declared"
                                  + (f" (a body of that name exists: declare a frame on it)" if frame in scene.bodies
                                     else ""))
    if scene.frames[frame].body == WORLD:
        raise SceneError(element, f"frame {frame!r} is fixed to the world: it cannot touch the ground")
    ground = scene.add_frame(f"{name}_ground", WORLD, **pose_to_exact(reference_pose(scene, frame, poses))).name
    scene.add_constraint(name, CONTACT_KINDS[kind], frame, ground)
    return name


def _joints_above(scene: Scene, body: str) -> list[str]:
    """The joints on the path from the world to ``body``."""
    by_child = {j.child: j for j in scene.joints.values()}
    out = []
    while body in by_child:
        joint = by_child[body]
        out.append(joint.name)
        body = joint.parent
    return out


def stand(scene: Scene, frames: Sequence[str], kind: str = "point", *, base: str | None = None) -> list[str]:
    """Put every frame of ``frames`` on the ground (:func:`add_ground_contact`), with ``T_c = 1``
    and ``V_m`` the remaining base and joint rates: the floating base's six (its free joint
    ``base``; default: the scene's only free joint), then those of every moving joint that is not
    on a path from the world to a contact (an arm or a head while the feet stand). Returns the
    constraints' names."""
    if base is None:
        if len(scene.free_joints) != 1:
            raise SceneError("motion", f"the scene has {len(scene.free_joints)} free joints: name the base")
        base = next(iter(scene.free_joints))
    if base not in scene.free_joints:
        raise SceneError("motion", f"{base!r} is not a free joint of the scene")
    poses = reference_poses(scene)
    names = [add_ground_contact(scene, f, kind, poses=poses) for f in frames]
    free = scene.free_joints[base]
    closed = {j for f in frames for j in _joints_above(scene, scene.frames[f].body)} | set(free.joints)
    others = [j.name for j in scene.joints.values() if j.dof and j.name not in closed
              and not any(j.name in fj.joints for fj in scene.free_joints.values())]
    scene.set_motion(joints=[base] + others)
    scene.constraint_forces = "joint"
    return names
