"""The elements a scene declares -- poses, bodies, joints, frames, constraints, the motion
coordinates and the contact forces -- as immutable records (:class:`symgen.scene.Scene` builds and
checks them)."""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .joint_kinds import JointKind, joint_kind
from ..math.spatial import COMPONENTS

WORLD = "world"
#: constraint kinds and the relative-velocity components each one removes (in frame_a axes)
CONSTRAINT_KINDS = {
    "weld": COMPONENTS,
    "ball": ("vx", "vy", "vz"),
    # planar kinds take the normal axis of frame_a; the components below are for normal = z
    "planar_weld": ("vx", "vy", "wz"),
    "plane_contact": ("vz", "wx", "wy"),
    # two bodies share a point: the same rows as ball; planar_point keeps the two in-plane ones
    "point": ("vx", "vy", "vz"),
    "planar_point": ("vx", "vy"),
}
#: the kind of a joint coupling (:meth:`symgen.scene.Scene.add_coupling`) and its one component: a
#: linear relation of joint coordinates, not of two frames
COUPLING = "coupling"
COUPLING_COMPONENT = "q"
#: the kind that closes the same joint of a planar loop with only the rows the plane leaves
PLANAR_KIND = {"weld": "planar_weld", "point": "planar_point", "ball": "planar_point"}


def planar_hint(kinds) -> str:
    """What to write instead when a loop is planar: ``"use planar_weld instead of weld, ..."`` for
    the spatial kinds among ``kinds`` (empty when none)."""
    swaps = sorted({f"{PLANAR_KIND[k]} instead of {k}" for k in kinds if k in PLANAR_KIND})
    return f"; if the loop is planar, use {', '.join(swaps)} (the rows out of the plane vanish)" if swaps else ""


@dataclass(frozen=True)
class Pose:
    """A constant placement: rotation ``R_parent_child`` and translation ``p_parent_child``."""

    rotation: sp.ImmutableMatrix
    translation: sp.ImmutableMatrix

    @staticmethod
    def identity() -> "Pose":
        return Pose(sp.ImmutableMatrix(sp.eye(3)), sp.ImmutableMatrix([0, 0, 0]))


@dataclass(frozen=True)
class Body:
    """A rigid body: mass, centre of mass and rotational inertia about the centre of mass, all in
    the body's own frame. A body of zero mass and inertia is a massless frame carrier."""

    name: str
    mass: sp.Expr
    com: sp.ImmutableMatrix
    inertia: sp.ImmutableMatrix

    @property
    def is_massless(self) -> bool:
        return self.mass == 0 and all(v == 0 for v in self.inertia)


@dataclass(frozen=True)
class Joint:
    """A joint from ``parent`` to ``child``; ``q0`` is its reference position (an angle, a
    displacement, or for a spherical joint an exact rotation matrix)."""

    name: str
    type: str
    parent: str
    child: str
    origin: Pose
    axis: sp.ImmutableMatrix
    actuated: bool
    rotor_inertia: sp.Expr = sp.Integer(0)
    viscous: sp.Expr = sp.Integer(0)
    coulomb: sp.Expr = sp.Integer(0)
    q0: object = sp.Integer(0)
    #: passive spring ``k (q - q_spring)`` of a 1-DOF joint (a potential term of ``G``, eq. 22)
    stiffness: sp.Expr = sp.Integer(0)
    springref: sp.Expr = sp.Integer(0)

    @property
    def kind(self) -> JointKind:
        """The :class:`~symgen.scene.joint_kinds.JointKind` named by ``type`` (the scene-file spelling)."""
        return joint_kind(self.type)

    @property
    def dof(self) -> int:
        return self.kind.dof


@dataclass(frozen=True)
class Frame:
    name: str
    body: str
    pose: Pose


@dataclass(frozen=True)
class Constraint:
    """Frames ``frame_a`` and ``frame_b`` must not move relative to each other along
    ``components`` (names from ``vx vy vz wx wy wz``, in frame_a's axes).

    A joint coupling (``kind == "coupling"``) ties joint coordinates instead: ``sum_i c_i q_i =
    offset`` over ``terms = ((joint_i, c_i), ...)`` of 1-DOF joints; its one row of ``T`` (eq. 6)
    is the constant ``c_i`` at each joint's column, its one component is ``"q"`` and both its
    frames are ``world``."""

    name: str
    kind: str
    frame_a: str
    frame_b: str
    components: tuple[str, ...]
    terms: tuple[tuple[str, sp.Expr], ...] = ()
    offset: sp.Expr = sp.Integer(0)

    @property
    def dim(self) -> int:
        return len(self.components)

    @property
    def is_coupling(self) -> bool:
        """Whether this is a joint coupling (a linear relation of joint coordinates)."""
        return self.kind == COUPLING


@dataclass(frozen=True)
class Motion:
    """Motion coordinates ``V_m`` (Step 10, eq. 17): the ``components`` of the twist of the
    gamma-weighted ``frames`` (Section 3.3), then the rates named in ``joints``, in that order.
    Either part may be empty (not both): joint rates alone, frames alone, or a mixed ``V_m``."""

    joints: tuple[str, ...] = ()
    frames: tuple[tuple[str, sp.Expr], ...] = ()
    components: tuple[str, ...] = ()

    @property
    def frame_dim(self) -> int:
        """Rows of ``V_m`` taken from the weighted frames' twist (they come first)."""
        return len(self.components) if self.frames else 0

    @property
    def dim(self) -> int:
        """``m``: the frame rows and then the joint rates."""
        return self.frame_dim + len(self.joints)

    @property
    def on_joints(self) -> bool:
        """True when ``V_m`` is joint rates only, so ``J_m`` is a constant selection of rates."""
        return bool(self.joints) and not self.frames

    @property
    def mixed(self) -> bool:
        """True when ``V_m`` holds twist components of frames and joint rates."""
        return bool(self.joints) and bool(self.frames)

    def labels(self, frame_label: str = "") -> list[str]:
        """Names of ``V_m``'s entries in order: ``frame.component`` (``frame_label`` in place of
        the frame's name if given, e.g. for several weighted frames), then the joint rates."""
        if not self.frames:
            return list(self.joints)
        label = frame_label or (self.frames[0][0] if len(self.frames) == 1 else "task")
        return [f"{label}.{c}" for c in self.components] + list(self.joints)


@dataclass(frozen=True)
class ContactForces:
    """Dynamic contact forces ``eta_m`` along twist components of ``frame`` (``D_m = T_m J``)."""

    frame: str
    components: tuple[str, ...]


def _components_for(kind: str, normal: str) -> tuple[str, ...]:
    base = CONSTRAINT_KINDS[kind]
    if kind not in ("planar_weld", "plane_contact", "planar_point") or normal == "z":
        return base
    others = [a for a in "xyz" if a != normal]
    if kind == "planar_point":
        return (f"v{others[0]}", f"v{others[1]}")
    if kind == "planar_weld":
        return (f"v{others[0]}", f"v{others[1]}", f"w{normal}")
    return (f"v{normal}", f"w{others[0]}", f"w{others[1]}")
