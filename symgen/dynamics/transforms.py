"""The pose of each tree joint's child in its parent, ``(R_PC, p_PC)``, in any field.

A joint ``k`` is placed in its parent by the scene's constant ``(R_k, p_k)`` and moves its child
by the joint motion: a rotation ``R_m`` about z (revolute, from ``(cos, sin)``), a translation
``d e3`` (prismatic) or a rotation matrix (spherical). Then ``R_PC = R_k R_m`` (kept as its two
factors where ``R_k`` is a twist, :func:`is_twist`) and ``p_PC = p_k + R_k d e3``. The recursions
of this package read these transforms; the code generator's tracer builds them from its position
inputs with :func:`joint_transforms` too.
"""
from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import sympy as sp

from ..math.fields import Field
from ..scene.joint_kinds import JointKind
from ..kinematics import ConstantCache
from ..math.configuration import Configuration, CosSin
from ..tree import Tree
from .algebra import FactoredRotation, Rows, Transform, matmul3


def joint_rotation(kind: JointKind, value: Any) -> Rows:
    """``R_m`` (3x3 nested lists) of a rotating joint's position: a :class:`~symgen.math.configuration.CosSin`
    pair (revolute, about z) or a rotation matrix (spherical)."""
    if kind.position_is_angle:
        c: Any
        s: Any
        c, s = (value.c, value.s) if isinstance(value, CosSin) else value
        return [[c, -s, 0], [s, c, 0], [0, 0, 1]]
    return [[value[i][j] for j in range(3)] for i in range(3)]


def is_twist(rotation: sp.MatrixBase) -> bool:
    """Whether a joint's exact placement rotation turns about x or about y alone, through an angle
    that is not a multiple of 90 degrees (a Denavit-Hartenberg twist): applied apart from the
    joint's own turn about z (:class:`~symgen.dynamics.algebra.FactoredRotation`) it costs fewer
    operations than their product."""
    for axis in (0, 1):
        others = [i for i in range(3) if i != axis]
        if rotation[axis, axis] == 1 and all(rotation[axis, i] == 0 and rotation[i, axis] == 0 for i in others):
            return all(rotation[i, j] != 0 for i in others for j in others)
    return False


def joint_transforms(tree: Tree, consts: ConstantCache, motion: Mapping[str, Any]) -> list[Transform]:
    """``(R_PC, p_PC)`` of every tree joint, indexed like ``tree.joints``. ``consts`` holds the
    scene constants in the field (:func:`symgen.kinematics.constants`); ``motion[name]`` is a
    rotating joint's ``R_m`` (:func:`joint_rotation`) or a prismatic joint's displacement."""
    out: list[Transform] = []
    for k, joint in enumerate(tree.joints):
        r_c = consts.joint_rot[k].tolist()
        p_c = tuple(consts.joint_trans[k])
        if joint.kind.rotates and joint.kind.position_is_angle and is_twist(joint.rotation):
            out.append((FactoredRotation(r_c, motion[joint.name]), p_c))
        elif joint.kind.rotates:
            out.append((matmul3(r_c, motion[joint.name]), p_c))
        elif joint.kind.translates:
            d = motion[joint.name]
            out.append((r_c, tuple(p_c[i] + r_c[i][2] * d for i in range(3))))
        else:
            out.append((r_c, p_c))
    return out


def configuration_transforms(tree: Tree, consts: ConstantCache, field: Field,
                             config: Configuration) -> list[Transform]:
    """:func:`joint_transforms` at a configuration (angles or ``CosSin`` pairs, displacements,
    rotation matrices), converted into ``field``."""
    positions = config.positions
    motion: dict[str, Any] = {}
    for joint in tree.joints:
        if joint.kind.rotates or joint.kind.translates:
            value = joint.kind.field_position(positions[joint.name], field)
            motion[joint.name] = joint_rotation(joint.kind, value) if joint.kind.rotates else value
    return joint_transforms(tree, consts, motion)
