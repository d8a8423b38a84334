"""The twist of every body of the tree, by the outward recursion of Section 3.2, in any field.

``X_c = ^P U_C^T X_p + Z_j qd_j`` per tree joint (the rows of ``T_S*``): each body's ``[v; w]``,
velocity of its frame's origin and angular velocity, in its own axes. The articulated-body pass
(:mod:`symgen.dynamics.aba`) runs the same two steps, :func:`~symgen.dynamics.algebra.motion_to_child`
and :func:`~symgen.dynamics.algebra.joint_twist`; this is the pass alone, for the consumers that
need velocities only (the centroidal momentum of :mod:`symgen.frame_kinematics`).
"""
from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from ..tree import WORLD_INDEX, Tree
from .algebra import Transform, Vector, add, joint_twist, motion_to_child


def body_twists(tree: Tree, transforms: Sequence[Transform], qd_all: Sequence[Any]) -> list[Vector]:
    """``[v; w]`` of every body (indexed like ``tree.bodies``) in its own axes, for the rates
    ``qd_all`` of every tree coordinate; ``transforms[k]`` is ``(R_PC, p_PC)`` of tree joint ``k``.
    ``O(N)``."""
    zero6: Vector = (0,) * 6
    out: list[Vector] = [zero6] * len(tree.bodies)
    for k, joint in enumerate(tree.joints):
        r, p = transforms[k]
        parent = zero6 if joint.parent == WORLD_INDEX else motion_to_child(r, p, out[joint.parent])
        out[joint.child] = add(parent, joint_twist(joint, qd_all))
    return out
