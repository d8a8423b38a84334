"""The scene's spanning tree in the paper's frame convention (Step 3).

Every 1-DOF joint gets an internal joint frame whose z axis is the joint axis, so that its motion
subspace is the paper's ``Z = e3`` (prismatic) or ``Z = e6`` (revolute). If a joint's axis ``a``
is not ``e3``, the constant rotation ``A`` with ``A e3 = a`` is folded into the placements: the
child body's internal frame is its user frame times ``A``, and the child's mass properties,
frames and outgoing joint origins are re-expressed in it. Spherical joints use ``Z = [0; 1_3]``
(relative angular velocity in the child frame); fixed joints have no motion.

Everything here is exact SymPy and depends only on the scene.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .scene.joint_kinds import JointKind
from .scene.declaration import WORLD, Scene
from .math.spatial import exact_align_z

WORLD_INDEX = -1


@dataclass(frozen=True)
class TreeJoint:
    name: str
    kind: JointKind             # what the joint contributes (motion subspace, motion, friction)
    parent: int                 # body index, WORLD_INDEX for the world
    child: int                  # body index
    rotation: sp.ImmutableMatrix     # R_parent_joint, internal frames
    translation: sp.ImmutableMatrix  # p_parent_joint, internal frames
    coords: tuple[int, ...]     # indices into the all-joint coordinate vector
    actuated: bool
    rotor_inertia: sp.Expr
    viscous: sp.Expr
    coulomb: sp.Expr
    stiffness: sp.Expr = sp.Integer(0)   # spring k (q - springref), 1-DOF joints only
    springref: sp.Expr = sp.Integer(0)

    @property
    def type(self) -> str:
        """The kind's scene-file spelling (for messages; ask :attr:`kind` anything else)."""
        return self.kind.name


@dataclass(frozen=True)
class TreeBody:
    name: str
    index: int
    mass: sp.Expr
    com: sp.ImmutableMatrix          # internal frame
    inertia: sp.ImmutableMatrix      # about the centre of mass, internal frame
    massless: bool
    align: sp.ImmutableMatrix        # A: internal frame = user frame * A


@dataclass(frozen=True)
class TreeFrame:
    name: str
    body: int                        # WORLD_INDEX for world frames
    rotation: sp.ImmutableMatrix     # R_body_frame (internal body frame)
    translation: sp.ImmutableMatrix


@dataclass(frozen=True)
class Coordinate:
    """One velocity coordinate of the all-joint vector ``qd_all``."""

    joint: str
    component: int                   # 0 for 1-DOF joints, 0..2 for spherical
    kind: JointKind                  # of the joint
    actuated: bool

    @property
    def label(self) -> str:
        """The joint's name, plus ``.wx``/``.wy``/``.wz`` for a coordinate of a multi-DOF joint."""
        return self.joint if self.kind.is_one_dof else f"{self.joint}.w{'xyz'[self.component]}"


@dataclass(frozen=True)
class Tree:
    joints: tuple[TreeJoint, ...]    # parents first
    bodies: tuple[TreeBody, ...]
    frames: dict[str, TreeFrame]
    coordinates: tuple[Coordinate, ...]
    gravity: sp.ImmutableMatrix
    parameters: dict[sp.Symbol, sp.Expr]    # scene parameter -> its value

    @property
    def n_coords(self) -> int:
        return len(self.coordinates)

    def coordinate_of(self, joint: str) -> int:
        """All-coordinate index of the (first) velocity coordinate of ``joint``."""
        return next(c for c, co in enumerate(self.coordinates) if co.joint == joint)

    def coordinate_index(self, label: str) -> int:
        """All-coordinate index of the velocity coordinate labelled ``label``
        (:attr:`Coordinate.label`: a 1-DOF joint's name, or ``j.wx`` etc.)."""
        return next(c for c, co in enumerate(self.coordinates) if co.label == label)


def build_tree(scene: Scene) -> Tree:
    """Map a validated scene to internal z-axis frames (see module docstring)."""
    order = scene.tree_order()
    body_names = [j.child for j in order]
    index = {name: i for i, name in enumerate(body_names)}
    index[WORLD] = WORLD_INDEX

    # coordinates in scene declaration order
    coordinates, coord_of = [], {}
    for j in scene.joints.values():
        idx = []
        for k in range(j.dof):
            idx.append(len(coordinates))
            coordinates.append(Coordinate(j.name, k, j.kind, j.actuated))
        coord_of[j.name] = tuple(idx)

    align = {WORLD: sp.ImmutableMatrix(sp.eye(3))}
    for j in order:
        align[j.child] = sp.ImmutableMatrix(exact_align_z(j.axis)) if j.kind.is_one_dof else sp.ImmutableMatrix(sp.eye(3))

    joints = []
    for j in order:
        a_parent, a_child = align[j.parent], align[j.child]
        rot = sp.ImmutableMatrix(sp.simplify(a_parent.T * j.origin.rotation * a_child))
        trans = sp.ImmutableMatrix(sp.simplify(a_parent.T * j.origin.translation))
        joints.append(TreeJoint(j.name, j.kind, index[j.parent], index[j.child], rot, trans,
                                coord_of[j.name], j.actuated, j.rotor_inertia, j.viscous, j.coulomb,
                                j.stiffness, j.springref))

    bodies = []
    for name in body_names:
        b, a = scene.bodies[name], align[name]
        bodies.append(TreeBody(name, index[name], b.mass, sp.ImmutableMatrix(a.T * b.com),
                               sp.ImmutableMatrix(sp.simplify(a.T * b.inertia * a)), b.is_massless, a))

    frames = {}
    for f in scene.frames.values():
        a = align[f.body]
        frames[f.name] = TreeFrame(f.name, index[f.body], sp.ImmutableMatrix(sp.simplify(a.T * f.pose.rotation)),
                                   sp.ImmutableMatrix(sp.simplify(a.T * f.pose.translation)))
    frames[WORLD] = TreeFrame(WORLD, WORLD_INDEX, sp.ImmutableMatrix(sp.eye(3)), sp.ImmutableMatrix([0, 0, 0]))
    return Tree(tuple(joints), tuple(bodies), frames, tuple(coordinates), scene.gravity, dict(scene.parameters))
