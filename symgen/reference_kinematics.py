"""Forward kinematics of a scene at its reference configuration ``q0``, in 50-digit arithmetic.

:func:`reference_poses` walks the joints of a (possibly partly built) :class:`~symgen.scene.Scene`
in tree order, following its frame conventions, and gives every body's world pose ``(R, p)`` as
mpmath matrices at ``DPS`` digits (:mod:`symgen.math.numbers`); :func:`reference_pose` gives one
declared frame's. Built-in scenes and the URDF constraint overlay use them to place frames that
must coincide at ``q0`` (loop closures, grasps, contact planes) and to compute ``q0`` by inverse
kinematics; :func:`symgen.math.spatial.pose_to_exact` rounds the result back to exact numbers.
"""
from __future__ import annotations

import mpmath

from .math.numbers import DPS, mp, mp_matrix
from .scene.declaration import WORLD, Scene


def _rodrigues(axis: mpmath.matrix, angle) -> mpmath.matrix:
    k = mpmath.matrix([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return mpmath.eye(3) + mpmath.sin(angle) * k + (1 - mpmath.cos(angle)) * (k * k)


def reference_poses(scene: Scene) -> dict:
    """World pose ``(R, p)`` (mpmath) of every body reachable from the world at ``q0``."""
    with mpmath.workdps(DPS):
        poses = {WORLD: (mpmath.eye(3), mpmath.matrix(3, 1))}
        for joint in scene.tree_order():
            r_p, p_p = poses[joint.parent]
            r_j = r_p * mp_matrix(joint.origin.rotation)
            p_j = p_p + r_p * mp_matrix(joint.origin.translation)
            axis = mp_matrix(joint.axis)
            kind = joint.kind
            if kind.position_is_angle:
                r_j = r_j * _rodrigues(axis, mp(joint.q0))
            elif kind.translates:
                p_j = p_j + r_j * (axis * mp(joint.q0))
            elif kind.position_is_rotation:
                r_j = r_j * mp_matrix(joint.q0)
            poses[joint.child] = (r_j, p_j)
        return poses


def reference_pose(scene: Scene, frame: str, poses: dict | None = None):
    """World pose ``(R, p)`` of a declared frame or body at ``q0``."""
    poses = reference_poses(scene) if poses is None else poses
    with mpmath.workdps(DPS):
        if frame in scene.frames:
            f = scene.frames[frame]
            r_b, p_b = poses[f.body]
            return r_b * mp_matrix(f.pose.rotation), p_b + r_b * mp_matrix(f.pose.translation)
        return poses[frame]
