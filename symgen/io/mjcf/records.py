"""What :mod:`symgen.io.mjcf.parse` reads from an MJCF file: exact, located records, no scene yet.

Positions and rotations are exact SymPy values in the *MJCF* frames: a body's ``pos``/``rot`` place
its frame in its parent body's frame (``<frame>`` elements already composed in), and a joint's
``pos``/``axis``, a site's pose and an inertial are in their body's frame.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field

import sympy as sp

WORLD = "world"



def element_name(name: str | None) -> str | None:
    """A body's or site's name as a scene name: spaces, dots and hyphens (common in real files, e.g.
    the control suite's ``pinch site``) read as ``_``, a leading digit prefixed by ``_``, as the URDF
    reader names links. Any other character outside ``[A-Za-z0-9_]`` is kept, so the scene refuses
    the name with a typed error (it could reach generated code)."""
    if name is None or not re.fullmatch(r"[A-Za-z0-9_ .\-]+", name):
        return name
    out = re.sub(r"[ .\-]", "_", name)
    return "_" + out if out[0].isdigit() else out


@dataclass
class MjcfJoint:
    name: str
    kind: str                 # symgen joint kind: revolute | prismatic | spherical
    pos: sp.Matrix            # 3x1, in the body frame
    axis: sp.Matrix           # 3x1, in the body frame (any length, not zero)
    ref: sp.Expr              # MuJoCo's qpos0 of a hinge (radians) or slide; 0 for a ball
    damping: sp.Expr
    armature: sp.Expr
    frictionloss: sp.Expr
    line: int | None
    stiffness: sp.Expr = sp.Integer(0)   # the spring k (qpos - springref) of a hinge or slide
    springref: sp.Expr = sp.Integer(0)   # MuJoCo's qpos_spring (radians for a hinge)
    springdamper: tuple | None = None    # (timeconst, dampratio): stiffness and damping set from M(qpos0)


@dataclass
class MjcfInertial:
    mass: sp.Expr
    pos: sp.Matrix            # centre of mass, in the body frame
    inertia: sp.Matrix        # about the centre of mass, in the body frame
    rounded: bool = False     # computed in floating point (a mesh's), stored as exact decimals


@dataclass
class MjcfBody:
    name: str
    parent: str
    pos: sp.Matrix
    rot: sp.Matrix
    joints: list              # MjcfJoint, in file order (MuJoCo applies them in this order)
    inertial: MjcfInertial | None
    line: int | None = None


@dataclass
class MjcfSite:
    name: str
    body: str                 # a body name or "world"
    pos: sp.Matrix
    rot: sp.Matrix
    line: int | None


@dataclass
class MjcfEquality:
    """A ``joint`` coupling (``joint1``, ``joint2``, a linear ``polycoef``), or a ``connect`` or ``weld``: between two sites (``site1``, ``site2``), or between two bodies
    (``anchor`` in body1's frame for a connect, in body2's for a weld; ``relpose`` the pose in
    body1's frame that body2's anchor frame must take, None for its pose at qpos0)."""

    kind: str                 # connect | weld
    name: str
    body1: str | None
    body2: str | None
    anchor: sp.Matrix | None
    relpose: tuple | None     # (pos 3x1, rot 3x3)
    site1: str | None
    site2: str | None
    line: int | None
    #: a joint equality (``kind == "joint"``): ``q1 - q1_0 = c0 + c1 (q2 - q2_0)``, ``polycoef[:2]``
    joint1: str | None = None
    joint2: str | None = None
    polycoef: tuple = ()
    #: a fixed-tendon equality (``kind == "tendon"``): ``L1 - L1_0 = c0 + c1 (L2 - L2_0)`` with each
    #: length ``L = sum coef_i q_i`` given as ``((joint, coef), ...)`` (``tendon2`` empty if absent)
    tendon1: tuple = ()
    tendon2: tuple = ()


@dataclass
class MjcfModel:
    name: str
    gravity: tuple
    bodies: list              # MjcfBody, parents first
    sites: list               # MjcfSite
    equalities: list
    actuated: list            # joint names, each once
    source: str
    text: str
    notes: list = field(default_factory=list)
