"""The free joint: a floating base as the paper's footnote 1 builds it.

A floating base is a fixed-base robot with a virtual six-DOF joint between the world and the base
(footnote 1 of the paper). symgen declares that joint as a chain of joints it already has, so the
evaluator, the twelve steps, the proofs, the recursions and the generated code take it without a
special case:

* three prismatic joints ``<name>_x``, ``<name>_y``, ``<name>_z`` along the axes of the free
  joint's frame (placed in the parent by ``origin``), carried by two massless bodies
  ``<name>_x_link``, ``<name>_y_link`` and a third ``<name>_z_link``;
* one spherical joint ``<name>_rot`` from ``<name>_z_link`` to the child.

Coordinates (MuJoCo's ``free`` joint, entry for entry):

* position ``q`` (generated code, simulation): ``x, y, z`` -- the child's origin in the free
  joint's frame -- then the unit quaternion ``w, x, y, z`` of the child's orientation in it;
* velocity ``qd`` (7 -> 6): ``xd, yd, zd`` -- the origin's velocity **in the free joint's frame**
  (the world for a root) -- then the angular velocity ``w`` **in the child's frame**.

Pinocchio's ``JointModelFreeFlyer`` orders the quaternion ``x, y, z, w`` and takes the linear
velocity in the child's frame: ``v_pin = [R^T pd; w]`` with ``R`` the child's orientation
(:class:`symgen.io.coordinates.CoordinateMap` maps states; the generalised forces map by the transpose,
``f_pin = R^T f``, and the accelerations by ``a_pin = [R^T pdd - w x (R^T pd); wd]``).

The free joint is not actuated and carries no friction or rotor inertia: a floating base is moved
only through its contacts and the robot's own joints.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import SceneError

#: the parts a free joint ``name`` becomes: the three prismatic joints, then the spherical one
TRANSLATION_AXES = ("x", "y", "z")


@dataclass(frozen=True)
class FreeJoint:
    """A declared free joint and the joints and massless bodies it stands for."""

    name: str
    parent: str
    child: str

    @property
    def translations(self) -> tuple[str, str, str]:
        """The prismatic joints along the free joint frame's ``x, y, z``."""
        return tuple(f"{self.name}_{a}" for a in TRANSLATION_AXES)   # type: ignore[return-value]

    @property
    def rotation(self) -> str:
        """The spherical joint that turns the child."""
        return f"{self.name}_rot"

    @property
    def joints(self) -> tuple[str, ...]:
        """Every joint of the free joint, in coordinate order."""
        return self.translations + (self.rotation,)

    @property
    def carriers(self) -> tuple[str, str, str]:
        """The massless bodies between the translations and the rotation."""
        return tuple(f"{self.name}_{a}_link" for a in TRANSLATION_AXES)   # type: ignore[return-value]

    @property
    def velocity_labels(self) -> tuple[str, ...]:
        """The six velocity coordinates' labels (:attr:`symgen.tree.Coordinate.label`)."""
        return self.translations + tuple(f"{self.rotation}.w{a}" for a in "xyz")


def _reference(element: str, q0) -> tuple[list, list]:
    """``q0`` of a free joint: 7 numbers ``x, y, z, qw, qx, qy, qz`` (default: the origin,
    unturned)."""
    if q0 is None:
        return [0, 0, 0], [1, 0, 0, 0]
    values = list(q0) if isinstance(q0, (list, tuple, np.ndarray)) else None
    if values is None or len(values) != 7:
        raise SceneError(element, "a free joint's q0 is 7 numbers: x, y, z, then the quaternion "
                                  f"qw, qx, qy, qz (got {q0!r})")
    return values[:3], values[3:]


def add_free_joint(scene: Any, name: str, parent: str, child: str, *, xyz=None, rpy=None, quat=None,
                   rotation=None, actuated: bool = False, rotor_inertia=0, viscous=0, coulomb=0,
                   q0=None) -> FreeJoint:
    """Declare a free joint ``name`` from ``parent`` to ``child`` in ``scene`` (a
    :class:`~symgen.scene.Scene`, which calls this for ``add_joint(..., "free", ...)``; see the
    module docstring): three prismatic joints and a spherical joint through three massless bodies."""
    element = f"joint {name!r}"
    free = FreeJoint(name, parent, child)
    if actuated:
        raise SceneError(element, "a free joint is not actuated: the base moves through its contacts "
                                  "and the robot's joints")
    for what, value in (("rotor_inertia", rotor_inertia), ("viscous", viscous), ("coulomb", coulomb)):
        if value not in (0, None):
            raise SceneError(element, f"a free joint has no {what}")
    taken = [j for j in free.joints if j in scene.joints] + [b for b in free.carriers if b in scene.bodies]
    if taken:
        raise SceneError(element, f"a free joint {name!r} declares {', '.join(free.joints)} and the massless "
                                  f"bodies {', '.join(free.carriers)}; {', '.join(taken)} already exist")
    for role, body in (("parent", parent), ("child", child)):
        if not isinstance(body, str) or (body != "world" and body not in scene.bodies):
            raise SceneError(element, f"{role} body {body!r} is not declared")
    position, orientation = _reference(element, q0)
    for body in free.carriers:
        scene.add_body(body, 0)
    links = (parent,) + free.carriers
    for k, (joint, axis) in enumerate(zip(free.translations, TRANSLATION_AXES)):
        placement = dict(xyz=xyz, rpy=rpy, quat=quat, rotation=rotation) if k == 0 else {}
        scene.add_joint(joint, "prismatic", links[k], links[k + 1], axis=axis, q0=position[k], **placement)
    scene.add_joint(free.rotation, "spherical", free.carriers[-1], child, q0=orientation)
    scene.free_joints[name] = free
    return free
