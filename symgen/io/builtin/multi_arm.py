"""``multi_arm:h=H`` -- coordinated manipulators holding one object: the paper's Section 3.3.

``H`` identical six-revolute arms (:func:`symgen.io.builtin._arm.add_arm`; arm ``i`` has bodies
``a{i}_link1..6`` and joints ``a{i}_j1..6``, all actuated, no friction) stand on a circle around a
shared object and grasp it from all sides.

* Arm ``i``'s base is at angle ``2 pi (i - 1) / H`` on a circle about the world z axis, turned so
  that, at the reference configuration, its gripper points at the object's centre.
* Each arm's last link carries a frame ``O{i}`` that coincides with the object frame at ``q0``;
  its placement is ``FK_i(q0)^-1 * O``, computed in 50-digit arithmetic and rounded to 1e-20.
* The object (a 0.2 m cube of 2 kg) hangs on arm 1: fixed joint ``grip`` from ``a1_link6`` placed
  at ``O1``, so the object's frame is ``O1``.
* Constraints ``grasp{i}{i+1}`` (``weld``, ``O{i}`` to ``O{i+1}``, i = 1..H-1) give
  ``T_a = T_f diag(J_1, ..., J_H)`` with the paper's ``T_f = [1 -1 0 ..; 0 1 -1 ..]`` (Step 4);
  ``eta_f`` are the internal forces between neighbouring end-effectors (Step 7).
* Motion coordinates: the ``gamma``-weighted twist of the ``O{i}`` with ``gamma_i = 1/H``
  (all six components).

Counts: ``n_1a = 6H``, ``m = 6``, ``n_c = 6(H - 1)``, ``n_p = 0``, ``n = 6H``. ``H = 1`` is a
single free arm carrying the object (no constraint).

Reference configuration (every arm): ``q0 = (0, -pi/3, 2 pi/3, pi/6, -pi/3, pi/4)``; each
``J_i`` (6 x 6, in ``O{i}``) has condition number about 10.
"""
from __future__ import annotations

from fractions import Fraction

import mpmath

from ...math.numbers import DPS, to_exact
from ...reference_kinematics import reference_pose, reference_poses
from ...scene.declaration import Scene
from ...math.spatial import box_inertia, pose_to_exact, relative_pose
from ._arm import FLANGE, add_arm

Q0 = (0, "-pi/3", "2*pi/3", "pi/6", "-pi/3", "pi/4")
#: the object's centre lies this far beyond the flange, along the last link's x axis
REACH = FLANGE + Fraction(1, 10)
OBJECT_MASS = 2
OBJECT_SIZE = "0.2"


def _grip_point():
    """The point the gripper aims at, in the arm's base frame at ``q0`` (mpmath 3-vector)."""
    probe = Scene(name="probe")
    last = add_arm(probe, q0=Q0)
    probe.add_frame("aim", last, xyz=(REACH, 0, 0))
    return reference_pose(probe, "aim")[1]


def _base_placement(i: int, h: int, aim) -> dict:
    """Base of arm ``i`` (1-based): on the circle of radius |aim_xy| at angle 2 pi (i-1)/h, yawed
    so that the aim point lands on the world z axis."""
    with mpmath.workdps(DPS):
        radius = mpmath.hypot(aim[0], aim[1])
        theta = 2 * mpmath.pi * (i - 1) / h
        yaw = theta + mpmath.pi - mpmath.atan2(aim[1], aim[0])
        return dict(base_xyz=[to_exact(radius * mpmath.cos(theta)), to_exact(radius * mpmath.sin(theta)), 0],
                    base_quat=[to_exact(mpmath.cos(yaw / 2)), 0, 0, to_exact(mpmath.sin(yaw / 2))])


def multi_arm(h: int = 2) -> Scene:
    """``h`` 6R arms rigidly grasping one object (paper, Section 3.3)."""
    scene = Scene(name=f"multi_arm_h{h}",
                  description=f"{h} coordinated 6R arms holding one object (paper Section 3.3): "
                              f"m = 6, n_c = {6 * (h - 1)}")
    aim = _grip_point()
    lasts = [add_arm(scene, f"a{i}_", q0=Q0, **_base_placement(i, h, aim)) for i in range(1, h + 1)]

    # the object frame O at q0: world-aligned, centred on the world z axis at the aim height
    with mpmath.workdps(DPS):
        object_pose = (mpmath.eye(3), mpmath.matrix([0, 0, to_exact(aim[2])]))
    poses = reference_poses(scene)
    placements = [pose_to_exact(relative_pose(poses[last], object_pose)) for last in lasts]
    for i, (last, placement) in enumerate(zip(lasts, placements), 1):
        scene.add_frame(f"O{i}", last, **placement)

    size = OBJECT_SIZE
    scene.add_body("object", OBJECT_MASS, inertia=box_inertia(OBJECT_MASS, size, size, size))
    scene.add_joint("grip", "fixed", lasts[0], "object", **placements[0])
    for i in range(1, h):
        scene.add_constraint(f"grasp{i}{i + 1}", "weld", f"O{i}", f"O{i + 1}")
    scene.set_motion(frames={f"O{i}": f"1/{h}" for i in range(1, h + 1)})
    scene.constraint_forces = "operational"
    return scene
