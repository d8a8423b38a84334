"""The constraint overlay: contact, grasps and loop closures between the frames of URDF robots.

A URDF file describes an open tree. The paper's scenes add constraints to it. Each function here
adds one, placed so that it holds at the reference configuration ``q0``: the world poses of the
frames involved are computed there in 50-digit arithmetic, and every derived placement is rounded
to the grid ``10**-20`` (as the built-in scenes do, :func:`symgen.math.numbers.to_exact`).

* :func:`add_contact` -- "this tool frame is in contact with a plane" (Section 3.2): a world
  frame ``plane`` where the tool frame is at ``q0``, and a ``plane_contact`` constraint (``vz, wx,
  wy`` for normal z). ``V_m`` is the tool's tangential twist ``(vx, vy, wz)`` with dynamic contact
  forces ``eta_m`` along it (Step 9). For a redundant arm ``V_m`` is a set of joint rates
  (``motion="joints"``).
* :func:`add_hold` -- "these tool frames hold one object" (Section 3.3): the object body on the
  first arm (fixed joint), a frame ``O{i}`` on each arm where the object frame is at ``q0``,
  ``weld`` constraints between neighbours, ``V_m`` the ``gamma = 1/H`` weighted object twist.
* :func:`add_closure` -- "close this loop between these two frames": a constraint of any kind
  between frame A and a frame on B's body that coincides with A at ``q0``.

Frames are named as in the scene. A URDF link name also works: the frame of a link merged by a
fixed joint, or a new frame at the origin of a link's body.
"""
from __future__ import annotations


from ...math.elimination import pivot_columns
from ...errors import SceneError
from ...reference_kinematics import reference_pose, reference_poses
from ...scene.declaration import WORLD, Scene
from ...math.spatial import AXIS_NAMES, pose_to_exact, relative_pose
from .build import urdf_sources


def frame_of(scene: Scene, name: str) -> str:
    """The scene frame for ``name``: a declared frame, a URDF link's frame, or a new frame named
    ``name`` at the origin of the body ``name``."""
    if name in scene.frames:
        return name
    for src in urdf_sources(scene):
        if name in src.links:
            body, frame = src.links[name]
            if frame is not None:
                return frame
            name = body
    if name in scene.frames:
        return name
    if name not in scene.bodies:
        raise SceneError(f"frame {name!r}", "is neither a frame, a URDF link, nor a body of the scene")
    scene.add_frame(name, name)
    return name


def tangential(normal: str) -> list[str]:
    """The twist components left free by a plane contact with this normal axis."""
    others = [a for a in "xyz" if a != normal]
    return [f"v{others[0]}", f"v{others[1]}", f"w{normal}"]


def choose_motion_joints(scene: Scene, *, keep_free_joints: bool = False) -> list[str]:
    """Joint rates that make good motion coordinates ``V_m`` once the constraints are declared.

    Column-pivoted QR of the constraint matrix ``T`` (eq. 6) at ``q0`` picks the ``n_c`` best
    conditioned dependent joints. The other joints, in scene order, are ``V_m``, so
    ``[J_m; J_f]`` is invertible at ``q0``.

    With ``keep_free_joints`` a floating base's free joints stay in ``V_m`` whole (their columns
    are not candidates), and their names lead the list; every other joint must be 1-DOF.
    """
    from ...math.fields import make_field
    from ...kinematics import constraint_matrix, tree_kinematics
    from ...model import reference_configuration
    from ...tree import build_tree

    tree = build_tree(scene)
    kin = tree_kinematics(tree, make_field("float", tree.parameters), reference_configuration(scene))
    t = constraint_matrix(kin, scene.constraints.values()).v
    kept = {j for f in scene.free_joints.values() for j in f.joints} if keep_free_joints else set()
    if any(not c.kind.is_one_dof and c.joint not in kept for c in tree.coordinates):
        raise SceneError("motion", "automatic motion joints need 1-DOF joints only")
    candidates = [i for i, c in enumerate(tree.coordinates) if c.joint not in kept]
    dependent = {candidates[i] for i in pivot_columns(t[:, candidates], t.shape[0])}
    rest = [c.joint for i, c in enumerate(tree.coordinates) if i not in dependent and c.joint not in kept]
    return [f for f in scene.free_joints if keep_free_joints] + rest


def add_contact(scene: Scene, frame: str, *, plane: str = "plane", name: str = "contact", normal: str = "z",
                motion: str | None = "frame", friction_forces: bool = True) -> str:
    """``frame`` slides on a plane through its pose at ``q0``, normal to its axis ``normal``.

    Args:
        motion: ``"frame"`` (``V_m`` = the tangential twist of ``frame``), ``"joints"``
            (:func:`choose_motion_joints`) or ``None`` (leave ``V_m`` to the caller).
        friction_forces: declare ``eta_m`` along the tangential twist (only with ``"frame"``).

    Returns:
        the name of the contact frame.
    """
    if normal not in AXIS_NAMES:
        raise SceneError(f"constraint {name!r}", f"normal {normal!r} must be x, y or z")
    f = frame_of(scene, frame)
    scene.add_frame(plane, WORLD, **pose_to_exact(reference_pose(scene, f)))
    scene.add_constraint(name, "plane_contact", f, plane, normal=normal)
    if motion == "frame":
        scene.set_motion(frame=f, components=tangential(normal))
        if friction_forces:
            scene.set_contact_forces(f, tangential(normal))
    elif motion == "joints":
        scene.set_motion(joints=choose_motion_joints(scene))
    elif motion is not None:
        raise SceneError("motion", f"must be 'frame', 'joints' or None, got {motion!r}")
    scene.constraint_forces = "operational"
    return f


def add_hold(scene: Scene, frames, *, mass, com=(0, 0, 0), inertia=(0, 0, 0), name: str = "object",
             at_xyz=None, at_rpy=None, at_quat=None, motion: bool = True) -> list[str]:
    """The tool ``frames`` (one per arm) rigidly hold one object (paper, Section 3.3).

    The object frame is ``frames[0]`` moved by ``at_xyz``/``at_rpy``/``at_quat`` (in that frame's
    axes), at ``q0``. The object body (``mass``, ``com``, ``inertia`` about its centre of mass,
    in the object frame) hangs on the first arm by the fixed joint ``{name}_grip``. Arm ``i``
    gets the frame ``{name}_O{i}``, which coincides with the object frame at ``q0``, and welds
    tie neighbours: ``{name}_grasp{i}_{i+1}``.

    Returns:
        the names of the grasp frames ``O_i``.
    """
    tools = [frame_of(scene, f) for f in frames]
    if not tools:
        raise SceneError(f"body {name!r}", "hold needs at least one frame")
    offset = scene.pose(f"body {name!r}", at_xyz, at_rpy, at_quat)
    probe = f"{name}_at"
    scene.add_frame(probe, scene.frames[tools[0]].body, **_compose(scene, tools[0], offset))
    poses = reference_poses(scene)
    object_pose = reference_pose(scene, probe, poses)
    del scene.frames[probe]
    grasps = []
    for i, tool in enumerate(tools, 1):
        body = scene.frames[tool].body
        placement = pose_to_exact(relative_pose(poses[body], object_pose))
        grasps.append(f"{name}_O{i}")
        scene.add_frame(grasps[-1], body, **placement)
        if i == 1:
            scene.add_body(name, mass, com=com, inertia=inertia)
            scene.add_joint(f"{name}_grip", "fixed", body, name, **placement)
    for i in range(1, len(grasps)):
        scene.add_constraint(f"{name}_grasp{i}_{i + 1}", "weld", grasps[i - 1], grasps[i])
    if motion:
        scene.set_motion(frames={g: f"1/{len(grasps)}" for g in grasps})
    scene.constraint_forces = "operational"
    return grasps


def _compose(scene: Scene, frame: str, offset) -> dict:
    """``xyz``/``quat`` on ``frame``'s body of the pose ``frame * offset`` (exact when rational)."""
    from ..scene_yaml_dump import rational_quat

    pose = scene.frames[frame].pose
    rot = pose.rotation * offset.rotation
    trans = pose.translation + pose.rotation * offset.translation
    if all(v.is_Rational for v in rot):
        return dict(xyz=list(trans), quat=rational_quat(rot))
    from ...math.numbers import mp_matrix

    return pose_to_exact((mp_matrix(rot), mp_matrix(trans)))


def add_closure(scene: Scene, name: str, kind: str, frame_a: str, frame_b: str, *, normal: str = "z",
                components=None, place: bool = True) -> str:
    """Close a loop: constraint ``kind`` (``weld``, ``ball``, ``planar_weld``, ``plane_contact``,
    ``custom``) between ``frame_a`` and ``frame_b``.

    With ``place`` (default) the constraint ties ``frame_a`` to a new frame ``{name}_b`` on
    ``frame_b``'s body that coincides with ``frame_a`` at ``q0``, so the loop is closed there.
    Without it, the two frames are used as given and must already meet at ``q0``.

    Returns:
        the name of the frame used on B's side.
    """
    a, b = frame_of(scene, frame_a), frame_of(scene, frame_b) if frame_b != WORLD else WORLD
    if place:
        body_b = scene.frames[b].body if b != WORLD else WORLD
        poses = reference_poses(scene)
        placement = pose_to_exact(relative_pose(poses[body_b], reference_pose(scene, a, poses)))
        b = f"{name}_b"
        scene.add_frame(b, body_b, **placement)
    scene.add_constraint(name, kind, a, b, normal=normal, components=components)
    return b


__all__ = ["add_closure", "add_contact", "add_hold", "choose_motion_joints", "frame_of", "tangential"]
