"""Scenes: the declarative description of a constrained robot (what the user states).

A :class:`Scene` holds rigid bodies, joints (revolute, prismatic, spherical, fixed), named frames,
closure/contact constraints and the task-space choice of Steps 7, 9 and 10 of the paper:

* ``motion``: the motion coordinates ``V_m`` (eq. 17), either joint rates or components of the
  twist of one frame, or the ``gamma``-weighted average of several frames (Section 3.3);
* ``contact_forces``: the dynamic contact forces ``eta_m`` and their map ``D_m`` (eq. 16);
* ``constraint_forces``: the choice of ``T_c`` in eq. (12): ``"operational"`` (``eta_f`` are the
  constraint forces in the constraints' own frames, ``J_f = T_a`` as in Sections 3.2-3.3; needs
  ``n_p = 0`` or ``n_p = n_c``) or ``"joint"`` (``T_c = 1``, ``eta_f`` in joint units).

Conventions: each joint's frame is placed in its parent body's frame by ``origin``; the child
body's frame is the joint frame after the joint motion (as in URDF). A joint's axis is given in
its joint frame; symgen maps it internally to a frame whose z axis is the axis (the paper's
``Z = e3`` / ``e6``). The joints must form a tree rooted at ``world``; every kinematic loop is
closed by an explicit constraint between two frames.

The scene only stores and checks what was declared; :func:`symgen.model.derive` does the rest.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from ..errors import ConstraintError, SceneError
from .input_limits import magnitude_problem
from .joint_kinds import UnknownJointKindError, joint_kind
from ..math.numbers import is_identifier
from .checks import bounded_number, check_mass_properties, check_topology, inertia_entries
from ..math.spatial import AXIS_NAMES, COMPONENTS, exact_quat, exact_rpy
from .elements import (CONSTRAINT_KINDS, COUPLING, COUPLING_COMPONENT, WORLD, Body, Constraint, ContactForces, Frame, Joint,  # noqa: F401
                             Motion, Pose, _components_for, planar_hint)


@dataclass
class Scene:
    """A constrained robot as declared by its user (bodies, joints, frames, constraints, task)."""

    name: str
    description: str = ""
    gravity: sp.ImmutableMatrix = field(default_factory=lambda: sp.ImmutableMatrix([0, 0, sp.Rational("-9.81")]))
    parameters: dict = field(default_factory=dict)  # Symbol -> numeric value
    bodies: dict = field(default_factory=dict)
    joints: dict = field(default_factory=dict)
    frames: dict = field(default_factory=dict)
    constraints: dict = field(default_factory=dict)
    motion: Motion | None = None
    contact_forces: ContactForces | None = None
    constraint_forces: str = "operational"
    #: joint name -> limits (``symgen.io.urdf.parse.JointLimits``), carried from a URDF; not used by the
    #: derivation and not written to YAML
    joint_limits: dict = field(default_factory=dict)
    #: the files this scene was read from, as their readers record them (opaque here: the derivation
    #: never reads them; ``symgen check`` rebuilds the robot in Pinocchio from them)
    sources: list = field(default_factory=list)
    #: what a reader changed on the way in (e.g. constraint rows dropped), for the user to read
    notes: list = field(default_factory=list)
    #: free joints by name (:class:`~symgen.scene.free_joint.FreeJoint`): each stands for the three
    #: prismatic joints, the spherical joint and the massless bodies it declared
    free_joints: dict = field(default_factory=dict)

    def __post_init__(self):
        if not is_identifier(self.name):
            raise SceneError(f"scene {self.name!r}", "names must be plain identifiers "
                                                      "([A-Za-z_][A-Za-z0-9_]*, at most 64 characters)")

    # ------------------------------------------------------------------ helpers for values
    def _num(self, element: str, value, what: str, scale_free: bool = False) -> sp.Expr:
        """An exact scene number; ``scale_free`` (directions: axes, quaternions) skips the
        magnitude bound, whose overall scale does not matter."""
        symbols = {str(s): s for s in self.parameters}
        return bounded_number(element, what, value, symbols, not scale_free)

    def _vec(self, element: str, value, what: str, length: int = 3, scale_free: bool = False) -> sp.ImmutableMatrix:
        if isinstance(value, sp.MatrixBase):
            value = list(value)
        if not isinstance(value, (list, tuple)) or len(value) != length:
            raise SceneError(element, f"{what} must be a list of {length} numbers, got {value!r}")
        return sp.ImmutableMatrix([self._num(element, v, what, scale_free) for v in value])

    def value_of(self, expr: sp.Expr) -> float:
        """Numeric value of a scene expression, parameters substituted."""
        return float(sp.sympify(expr).xreplace(self.parameters))

    def _check_name(self, kind: str, name: str, table: dict) -> str:
        element = f"{kind} {name!r}"
        if not is_identifier(name):
            raise SceneError(element, "names must be plain identifiers ([A-Za-z_][A-Za-z0-9_]*, "
                                      "at most 64 characters)")
        if name == WORLD and kind in ("body", "frame"):
            raise SceneError(element, "'world' is reserved for the fixed base and its origin frame")
        if name in table:
            raise SceneError(element, f"a {kind} of this name is already declared")
        return element

    def pose(self, element: str, xyz=None, rpy=None, quat=None, rotation=None) -> Pose:
        """A :class:`Pose` from ``xyz`` and one of ``rpy`` (URDF convention), ``quat`` (w,x,y,z) or
        ``rotation`` (a 3x3 matrix; floating-point entries orthonormal to 1e-6 are snapped to an
        exact rotation, :mod:`symgen.math.rotations_snap`)."""
        t = self._vec(element, xyz, "xyz") if xyz is not None else sp.ImmutableMatrix([0, 0, 0])
        if sum(v is not None for v in (rpy, quat, rotation)) > 1:
            raise SceneError(element, "give one of rpy, quat and rotation, not several")
        if rotation is not None:
            from ..math.rotations_snap import snap_rotation

            r = snap_rotation(element, rotation)
        elif quat is not None:
            q = self._vec(element, quat, "quat", 4, scale_free=True)
            if all(v == 0 for v in q):
                raise SceneError(element, "quat must not be zero")
            r = exact_quat(*q)
        elif rpy is not None:
            r = exact_rpy(*self._vec(element, rpy, "rpy"))
        else:
            r = sp.eye(3)
        return Pose(sp.ImmutableMatrix(r), t)

    # ------------------------------------------------------------------ declaration API
    def add_parameter(self, name: str, value) -> sp.Symbol:
        """Declare a symbolic parameter (usable as any body or joint value) with its numeric value."""
        element = f"parameter {name!r}"
        if not is_identifier(name) or name in ("pi", "E", "I", WORLD):
            raise SceneError(element, "names must be plain identifiers other than pi, E, I, world")
        sym = sp.Symbol(name, real=True)
        if sym in self.parameters:
            raise SceneError(element, "a parameter of this name is already declared")
        self.parameters[sym] = bounded_number(element, "value", value)
        return sym

    def add_body(self, name: str, mass, com=(0, 0, 0), inertia=(0, 0, 0)) -> Body:
        """Declare a rigid body. ``inertia`` about the centre of mass, in the body frame:
        ``[ixx, iyy, izz]``, ``[ixx, iyy, izz, ixy, ixz, iyz]`` or the full symmetric 3x3 matrix
        ``[[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]]`` (products of inertia with the
        sign of the matrix, as URDF, MJCF and Pinocchio write them)."""
        element = self._check_name("body", name, self.bodies)
        m = self._num(element, mass, "mass")
        c = self._vec(element, com, "com")
        inertia = inertia_entries(self, element, inertia)
        vals = list(inertia) if isinstance(inertia, (list, tuple)) else None
        if vals is None or len(vals) not in (3, 6):
            raise SceneError(element, "inertia must be [ixx, iyy, izz] or [ixx, iyy, izz, ixy, ixz, iyz]")
        i = [self._num(element, v, "inertia") for v in vals] + [0, 0, 0][: 6 - len(vals)]
        ixx, iyy, izz, ixy, ixz, iyz = i
        inertia_m = sp.ImmutableMatrix([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
        body = Body(name, m, c, inertia_m)
        check_mass_properties(element, body, self.parameters)
        self.bodies[name] = body
        return body

    def add_joint(self, name: str, type: str, parent: str, child: str, *, xyz=None, rpy=None,
                  quat=None, axis="z", actuated: bool = False, rotor_inertia=0, viscous=0,
                  coulomb=0, q0=None, rotation=None, stiffness=0, springref=0) -> Joint:
        """Declare a joint. ``axis`` is ``"x"``, ``"-y"``, ... or a 3-vector in the joint frame.
        ``q0`` is the reference position: a number, or for a spherical joint a quaternion
        ``[w, x, y, z]``. ``stiffness`` ``k`` and ``springref`` ``q_spring`` give a 1-DOF joint a
        passive spring: the joint force ``k (q - q_spring)`` joins the potential terms ``G``
        (eq. 22; MuJoCo's ``stiffness`` and ``springref``).

        ``type="free"`` declares a floating base's six-DOF joint: three prismatic joints and a
        spherical one through massless bodies (:mod:`symgen.scene.free_joint`; its ``q0`` is
        ``[x, y, z, qw, qx, qy, qz]``); it returns the spherical joint."""
        element = self._check_name("joint", name, self.joints)
        if type == "free":
            if name in self.free_joints:
                raise SceneError(element, "a free joint of this name is already declared")
            if axis != "z":
                raise SceneError(element, "a free joint has no axis")
            from .free_joint import add_free_joint

            if stiffness not in (0, None):
                raise SceneError(element, "a free joint has no spring (stiffness must be 0)")
            free = add_free_joint(self, name, parent, child, xyz=xyz, rpy=rpy, quat=quat, rotation=rotation,
                                  actuated=actuated, rotor_inertia=rotor_inertia, viscous=viscous,
                                  coulomb=coulomb, q0=q0)
            return self.joints[free.rotation]
        try:
            kind = joint_kind(type)
        except UnknownJointKindError as exc:
            raise SceneError(element, str(exc)) from None
        for role, body in (("parent", parent), ("child", child)):
            if not isinstance(body, str) or (body != WORLD and body not in self.bodies):
                raise SceneError(element, f"{role} body {body!r} is not declared")
        if child == WORLD:
            raise SceneError(element, "the world cannot be a joint's child")
        if parent == child:
            raise SceneError(element, "parent and child are the same body")
        axis_v = self._axis(element, axis)
        if not kind.is_one_dof:
            axis_v = sp.ImmutableMatrix([0, 0, 1])
        vals = {k: self._num(element, v, k) for k, v in
                (("rotor_inertia", rotor_inertia), ("viscous", viscous), ("coulomb", coulomb),
                 ("stiffness", stiffness))}
        for k, v in vals.items():
            if v.is_number and v < 0:
                raise SceneError(element, f"{k} must not be negative (got {v})")
        spring_ref = self._num(element, springref, "springref")
        if not kind.is_one_dof and (vals["stiffness"] != 0 or spring_ref != 0):
            raise SceneError(element, f"a {kind.name} joint has no spring: stiffness and springref are for "
                                      "1-DOF joints (a rotational spring of a ball joint is not modelled)")
        if kind.dof > 1 and vals["rotor_inertia"] != 0:
            raise SceneError(element, f"a {kind.name} joint has no rotor inertia (eq. 23); put it in the links")
        if kind.position_is_rotation:
            q_ref = self._vec(element, q0, "q0 (quaternion)", 4, scale_free=True) if q0 is not None else None
            if q_ref is not None and all(v == 0 for v in q_ref):
                raise SceneError(element, "q0 (quaternion) must not be zero")
            ref = sp.ImmutableMatrix(exact_quat(*q_ref)) if q_ref is not None else sp.ImmutableMatrix(sp.eye(3))
        else:
            ref = self._num(element, 0 if q0 is None else q0, "q0")
        joint = Joint(name, kind.name, parent, child, self.pose(element, xyz, rpy, quat, rotation), axis_v,
                      bool(actuated) and kind.moves, vals["rotor_inertia"], vals["viscous"],
                      vals["coulomb"], ref, vals["stiffness"], spring_ref)
        self.joints[name] = joint
        return joint

    def _axis(self, element: str, axis) -> sp.ImmutableMatrix:
        if isinstance(axis, str):
            text = axis.strip()
            sign = -1 if text.startswith("-") else 1
            key = text.lstrip("+-")
            if key not in AXIS_NAMES:
                raise SceneError(element, f"axis {axis!r} must be x, y, z (optionally signed) or a 3-vector")
            v = [0, 0, 0]
            v[AXIS_NAMES[key]] = sign
            return sp.ImmutableMatrix(v)
        vec = self._vec(element, axis, "axis", scale_free=True)
        norm2 = sum(v * v for v in vec)
        if norm2 == 0:
            raise SceneError(element, "axis must not be zero")
        return sp.ImmutableMatrix(vec / sp.sqrt(norm2))

    def add_frame(self, name: str, body: str, xyz=None, rpy=None, quat=None, rotation=None) -> Frame:
        """Declare a named frame fixed to ``body`` (or to ``world``)."""
        element = self._check_name("frame", name, self.frames)
        if not isinstance(body, str) or (body != WORLD and body not in self.bodies):
            raise SceneError(element, f"body {body!r} is not declared")
        frame = Frame(name, body, self.pose(element, xyz, rpy, quat, rotation))
        self.frames[name] = frame
        return frame

    def add_constraint(self, name: str, kind: str, frame_a: str, frame_b: str = WORLD,
                       normal: str = "z", components=None) -> Constraint:
        """Declare a constraint between two frames (``frame_b = "world"`` is the world origin).

        Every kind removes components of the twist of frame_a relative to frame_b, **in frame_a's
        axes** (eq. 6 row by row; :meth:`symgen.model.Model.loop_forces` reports the force of each
        component in the same axes, on frame_a's body):

        * ``weld`` (6): ``vx vy vz wx wy wz``;
        * ``ball`` and ``point`` (3): ``vx vy vz`` -- the two bodies share frame_a's origin;
        * ``planar_point`` (2): the translations along frame_a's two axes other than ``normal``
          (``vx vy`` for ``normal = z``): a point shared in a planar loop;
        * ``planar_weld`` (3): the in-plane translations and the rotation about ``normal`` (``vx vy
          wz`` for ``z``);
        * ``plane_contact`` (3): the translation along ``normal`` and the two tilts about the other
          axes (``vz wx wy`` for ``z``);
        * ``custom``: the listed ``components``, frame_a's axes as well."""
        element = self._check_name("constraint", name, self.constraints)
        for f in (frame_a, frame_b):
            if not isinstance(f, str) or (f != WORLD and f not in self.frames):
                raise SceneError(element, f"frame {f!r} is not declared")
        if frame_a == frame_b:
            raise SceneError(element, "a constraint needs two different frames")
        body_of = lambda f: WORLD if f == WORLD else self.frames[f].body  # noqa: E731
        if body_of(frame_a) == body_of(frame_b):
            raise SceneError(element, f"frames {frame_a!r} and {frame_b!r} are on the same body "
                                      f"{body_of(frame_a)!r}: the constraint would remove nothing")
        if kind == "custom":
            comps = tuple(components or ())
        elif kind in CONSTRAINT_KINDS:
            if normal not in AXIS_NAMES:
                raise SceneError(element, f"normal {normal!r} must be x, y or z")
            comps = _components_for(kind, normal)
        else:
            raise SceneError(element, f"unknown constraint kind {kind!r}; use one of "
                                      f"{', '.join(list(CONSTRAINT_KINDS) + ['custom'])}")
        bad = [c for c in comps if c not in COMPONENTS] or (not comps and ["(none)"])
        if bad or len(set(comps)) != len(comps):
            raise SceneError(element, f"components must be distinct names from {COMPONENTS}, got {comps}")
        con = Constraint(name, kind, frame_a, frame_b, comps)
        self.constraints[name] = con
        return con

    def add_coupling(self, name: str, joint: str, leader: str | None = None, multiplier=1, offset=0, *,
                     terms=None) -> Constraint:
        """Declare a joint coupling, a constraint of eq. (6) on joint coordinates alone.

        The mimic form ``add_coupling(name, joint, leader, multiplier=a, offset=b)`` states
        ``q_joint = a q_leader + b`` (URDF ``<mimic>``); its row of ``T`` is ``qd_joint - a
        qd_leader = 0``. The general form ``add_coupling(name, joint, terms={other: c, ...},
        offset=b)`` states ``q_joint + sum c q_other = b`` (MJCF fixed tendons). Both joints must
        be 1-DOF (revolute or prismatic). A passive (unactuated) coupled joint becomes a dependent
        rate (``q_u1``, ``n_p``); the coupling's force (:meth:`symgen.model.Model.loop_forces`,
        label ``<name>.tau``) is the generalized force ``T^T lam`` it adds to each joint, in joint
        units (N m or N)."""
        element = self._check_name("constraint", name, self.constraints)
        if (leader is None) == (terms is None):
            raise SceneError(element, "give a leader joint (mimic form) or terms={joint: coefficient}, not both")
        if leader is not None:
            pairs = [(joint, sp.Integer(1)), (leader, -self._num(element, multiplier, "multiplier"))]
        else:
            if not isinstance(terms, dict) or not terms:
                raise SceneError(element, f"terms must map joint names to coefficients, got {terms!r}")
            pairs = [(joint, sp.Integer(1))] + [(j, self._num(element, c, f"coefficient of {j!r}"))
                                                 for j, c in terms.items()]
        seen = set()
        for j, c in pairs:
            if not isinstance(j, str) or j not in self.joints:
                raise SceneError(element, f"joint {j!r} is not declared")
            if self.joints[j].dof != 1:
                raise SceneError(element, f"joint {j!r} is {self.joints[j].type}: only revolute and "
                                          "prismatic joints can be coupled")
            if j in seen:
                raise SceneError(element, f"joint {j!r} appears twice: a joint cannot be coupled with itself")
            seen.add(j)
            if c == 0:
                raise SceneError(element, f"the coefficient of joint {j!r} is zero")
        con = Constraint(name, COUPLING, WORLD, WORLD, (COUPLING_COMPONENT,), tuple(pairs),
                         self._num(element, offset, "offset"))
        self.constraints[name] = con
        return con

    def set_motion(self, *, joints=None, frame=None, frames=None, components=None) -> Motion:
        """Choose ``V_m`` (Step 10, eq. 17): ``joints=[...]`` (joint rates), ``frame=F`` /
        ``frames={F: gamma}`` with ``components`` (default all six), or both: then ``V_m`` is the
        frames' chosen twist components followed by the listed joint rates (a mixed motion space),
        and ``J_m`` stacks their rows in that order."""
        element = "motion"
        if isinstance(joints, str) or isinstance(components, str):
            raise SceneError(element, "joints and components must be lists of names")
        if frame and frames:
            raise SceneError(element, "give frame=... or frames={...}, not both")
        labels = [label for j in joints or () for label in self._rate_labels(element, j)]
        if len(set(labels)) != len(labels):
            raise SceneError(element, f"a joint rate is named twice in {list(joints)}")
        weights = {frame: 1} if frame else dict(frames or {})
        if not weights:
            if components:
                raise SceneError(element, "components go with frame=... / frames={...}, not with joints alone")
            if not labels:
                raise SceneError(element, "give joints=[...] or frame=... / frames={...}")
            self.motion = Motion(joints=tuple(labels))
            return self.motion
        pairs = []
        for f, g in weights.items():
            if f not in self.frames:
                raise SceneError(element, f"frame {f!r} is not declared")
            gamma = self._num(element, g, f"weight of {f}")
            if gamma.is_number and gamma < 0:
                raise SceneError(element, f"weight of frame {f!r} must be >= 0 (got {gamma})")
            pairs.append((f, gamma))
        total = sp.nsimplify(sum(g for _, g in pairs))
        if total.is_number and total != 1:
            raise SceneError(element, f"the weights gamma_i must sum to 1 (they sum to {total})")
        comps = tuple(components or COMPONENTS)
        if any(c not in COMPONENTS for c in comps) or len(set(comps)) != len(comps):
            raise SceneError(element, f"components must be distinct names from {COMPONENTS}")
        self.motion = Motion(joints=tuple(labels), frames=tuple(pairs), components=comps)
        return self.motion

    def _rate_labels(self, element: str, name) -> list[str]:
        """The velocity coordinates a motion entry names: a 1-DOF joint's rate; all of a
        spherical joint's (``j.wx, j.wy, j.wz``, the angular velocity in the child frame) or one of
        them; all six of a free joint's (:attr:`~symgen.scene.free_joint.FreeJoint.velocity_labels`)."""
        if not isinstance(name, str):
            raise SceneError(element, f"joint names must be strings, got {name!r}")
        if name in self.free_joints:
            return list(self.free_joints[name].velocity_labels)
        joint, dot, component = name.partition(".")
        if joint not in self.joints:
            raise SceneError(element, f"joint {joint!r} is not declared")
        dof = self.joints[joint].dof
        if dot:
            if dof != 3 or component not in ("wx", "wy", "wz"):
                raise SceneError(element, f"{name!r}: only a spherical joint's rates have components "
                                          "(.wx, .wy, .wz)")
            return [name]
        if dof == 0:
            raise SceneError(element, f"joint {joint!r} is fixed: it has no rate")
        return [joint] if dof == 1 else [f"{joint}.w{a}" for a in "xyz"]

    def set_contact_forces(self, frame: str, components) -> ContactForces:
        """Declare dynamic contact forces ``eta_m`` along ``components`` of ``frame`` (Step 9)."""
        if not isinstance(frame, str) or frame not in self.frames:
            raise SceneError("contact_forces", f"frame {frame!r} is not declared")
        if isinstance(components, str) or not isinstance(components, (list, tuple)):
            raise SceneError("contact_forces", "components must be a list of names")
        comps = tuple(components)
        if any(c not in COMPONENTS for c in comps) or len(set(comps)) != len(comps) or not comps:
            raise SceneError("contact_forces", f"components must be distinct names from {COMPONENTS}")
        self.contact_forces = ContactForces(frame, comps)
        return self.contact_forces

    # ------------------------------------------------------------------ global checks
    def validate(self) -> None:
        """Check what needs the whole scene: tree topology, loop closures, counts, task space."""
        check_topology(self)
        for i, g in enumerate(self.gravity):
            problem = magnitude_problem(g)
            if problem:
                raise SceneError("gravity", f"component {i}: {problem}")
        n_coords = sum(j.dof for j in self.joints.values())
        n_c = sum(c.dim for c in self.constraints.values())
        if n_coords == 0:
            raise ConstraintError("scene", "has no moving joint")
        if n_c >= n_coords:
            names = ", ".join(self.constraints)
            raise ConstraintError(f"constraints ({names})",
                                  f"{n_c} constraint equations but only {n_coords} joint coordinates: "
                                  f"no motion is left (m = {n_coords - n_c} <= 0, eq. 5)"
                                  + planar_hint(c.kind for c in self.constraints.values()))
        if self.motion is None:
            raise SceneError("motion", "the scene declares no motion coordinates V_m (Step 10)")
        m = n_coords - n_c
        if self.motion.dim != m:
            parts = (f" ({self.motion.frame_dim} frame components + {len(self.motion.joints)} joint rates)"
                     if self.motion.mixed else "")
            raise ConstraintError("motion", f"V_m has {self.motion.dim} coordinates{parts} but the scene has "
                                            f"m = {n_coords} - {n_c} = {m} motion DOF (eq. 5)")
        if self.contact_forces is not None and len(self.contact_forces.components) != m:
            raise ConstraintError("contact_forces", f"eta_m must have m = {m} coordinates (eq. 16)")
        if self.constraint_forces not in ("operational", "joint"):
            raise SceneError("constraint_forces", "must be 'operational' or 'joint'")

    def tree_order(self) -> list[Joint]:
        """Joints ordered parents first (valid after :meth:`validate`)."""
        order, placed = [], {WORLD}
        pending = list(self.joints.values())
        while pending:
            nxt = [j for j in pending if j.parent in placed]
            if not nxt:
                break
            for j in nxt:
                order.append(j)
                placed.add(j.child)
            pending = [j for j in pending if j not in nxt]
        return order
