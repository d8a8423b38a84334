"""A Pinocchio model of any scene's spanning tree, built from :attr:`symgen.model.Model.tree`.

Where :mod:`symgen.oracle.pinocchio_model` rebuilds a URDF scene from its files, this module
takes symgen's own tree (Step 3, :mod:`symgen.tree`) and states it in Pinocchio's terms, so every
scene -- the built-ins included -- has a Pinocchio twin:

* a revolute joint (about the internal z axis) is ``JointModelRZ``, a prismatic one ``JointModelPZ``,
  a spherical one ``JointModelSpherical`` (velocity: the angular velocity in the child frame, as in
  symgen; configuration: a unit quaternion, which Pinocchio stores ``[x, y, z, w]``);
* a joint's placement is the tree's constant ``(R_parent_joint, p_parent_joint)``; a fixed joint
  adds no Pinocchio joint: its child is merged into the moving joint it hangs from (with the
  composed placement), as Pinocchio's own URDF parser does;
* each massive body is appended to its joint with ``pin.Inertia(m, c, I_c)`` (centre of mass and
  inertia about it in the body's internal frame); a massless "frame carrier" body adds nothing;
* rotor inertias ``I*`` are Pinocchio's ``armature``; viscous ``b`` and Coulomb ``c`` friction are
  kept beside the model (Pinocchio's ``rnea`` leaves friction out), per velocity index;
* every named frame of the scene is an ``OP_FRAME`` on the joint that carries its body;
* a ``weld`` constraint is a ``RigidConstraintModel`` of type ``CONTACT_6D`` and a ``ball`` one of
  type ``CONTACT_3D``, both ``LOCAL``: joint 1 carries frame A and joint 2 frame B. The rows are
  then ``S (X_A - ^B U_A^T X_B)`` in A's axes, symgen's rows, and Pinocchio's ``[v; w]`` ordering is
  symgen's. ``planar_weld``, ``plane_contact`` and ``custom`` components have no Pinocchio type:
  :mod:`symgen.oracle.pinocchio_check` builds their KKT system from ``crba``,
  ``nonLinearEffects`` and ``getFrameJacobian``.

The velocity index of every symgen coordinate (the all-joint vector ``qd_all``, scene declaration
order) is recorded in :attr:`TreeRobot.v_of_coord`; Pinocchio numbers its coordinates in the order
the joints were added (parents first).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..scene.declaration import WORLD
from ..math.configuration import Configuration
from ..tree import WORLD_INDEX
from ..io.urdf._deps import require
from .pinocchio_model import OracleError, PinocchioRobot

#: constraint kinds that are one of Pinocchio's RigidConstraintModel types (with their components)
PINOCCHIO_CONSTRAINTS = {"weld": ("CONTACT_6D", ("vx", "vy", "vz", "wx", "wy", "wz")),
                         "ball": ("CONTACT_3D", ("vx", "vy", "vz"))}


@dataclass
class TreeRobot(PinocchioRobot):
    """:class:`PinocchioRobot` of a scene's spanning tree (see the module docstring).

    ``v_of_coord[k]`` is Pinocchio's velocity index of symgen's coordinate ``k``; ``labels`` maps a
    coordinate label (``j`` or ``s.wx``) to its index ``k``. ``damping``/``coulomb`` are per
    Pinocchio velocity index; a spherical joint's friction is ``b w + c w/|w|`` (eq. 23), kept in
    ``spherical_friction``.
    """

    tree: object = None
    scene: object = None
    v_of_coord: np.ndarray = None
    labels: dict = field(default_factory=dict)
    placements: dict = field(default_factory=dict)     # tree body index -> (joint id, SE3 body in joint)
    dropped: dict = field(default_factory=dict)        # tree body index -> its spherical joint (left out)
    spherical_friction: dict = field(default_factory=dict)   # joint id -> (b, c)

    def q_vector(self, config) -> np.ndarray:
        """Pinocchio's ``q`` of a symgen configuration (quaternions ``[x, y, z, w]``)."""
        pos = Configuration(config.positions if isinstance(config, Configuration) else dict(config)).as_float().positions
        q = self.pin.neutral(self.model)
        for name, jid in self.joints.items():
            if jid is None:
                continue
            joint = self.model.joints[jid]
            if joint.nq == 4:
                q[joint.idx_q:joint.idx_q + 4] = self.pin.Quaternion(np.asarray(pos[name], float)).coeffs()
            else:
                q[joint.idx_q] = float(pos[name])
        return q

    def v_index(self, names) -> np.ndarray:
        """Velocity indices of symgen coordinate labels (1-DOF joint names, or ``s.wx`` etc.)."""
        return np.array([self.v_of_coord[self.labels[n]] for n in names], dtype=int)

    def v_vector(self, qd_all) -> np.ndarray:
        """Pinocchio's ``v`` of symgen's all-joint rates ``qd_all`` (scene coordinate order; the
        rates of dropped joints are left out)."""
        v, kept = np.zeros(self.model.nv), self.v_of_coord >= 0
        v[self.v_of_coord[kept]] = np.asarray(qd_all, float)[kept]
        return v

    def to_coordinates(self, x) -> np.ndarray:
        """A Pinocchio velocity-space vector in symgen's all-coordinate order (NaN for the
        coordinates of dropped joints)."""
        x = np.append(np.asarray(x, float), np.nan)
        return x[self.v_of_coord]

    def frame_on_dropped(self, name: str) -> bool:
        """Whether scene frame ``name`` sits on a dropped massless spherical leaf."""
        return name != WORLD and self.tree.frames[name].body in self.dropped

    def friction(self, v) -> np.ndarray:
        """``xi`` of eqs. (22)-(23) at Pinocchio's ``v``."""
        out = self.damping * v + self.coulomb * np.sign(v)
        for jid, (b, c) in self.spherical_friction.items():
            s = slice(self.model.joints[jid].idx_v, self.model.joints[jid].idx_v + 3)
            w = v[s]
            norm = float(np.linalg.norm(w))
            out[s] = b * w + (c * w / norm if norm > 0 else 0.0)
        return out


def _se3(pin, rotation, translation, value):
    r = np.array([[value(rotation[i, j]) for j in range(3)] for i in range(3)])
    return pin.SE3(r, np.array([value(t) for t in translation]))


def _joint_model(pin, tj):
    kind = tj.kind
    if not kind.moves:
        return None
    if not kind.is_one_dof:
        return pin.JointModelSpherical()
    return pin.JointModelPZ() if kind.translates else pin.JointModelRZ()


def _depth_first(tree) -> list:
    """The tree's joints in depth-first order: Pinocchio's algorithms (``crba``, the contact
    Cholesky) assume every subtree occupies consecutive velocity indices."""
    children = {}
    for tj in tree.joints:
        children.setdefault(tj.parent, []).append(tj)
    out, stack = [], list(reversed(children.get(WORLD_INDEX, [])))
    while stack:
        tj = stack.pop()
        out.append(tj)
        stack.extend(reversed(children.get(tj.child, [])))
    return out


def _droppable(tree, scene, value) -> dict:
    """Spherical joints whose child is a massless leaf that only carries frames (no rotor inertia,
    friction or actuation): ``child body index -> joint``. Such a joint transmits no moment, so a
    weld on its child is a ball constraint at the joint's centre."""
    parents = {tj.parent for tj in tree.joints}
    return {tj.child: tj for tj in tree.joints
            if tj.kind.position_is_rotation and tree.bodies[tj.child].massless and tj.child not in parents
            and not tj.actuated and not any(value(x) for x in (tj.rotor_inertia, tj.viscous, tj.coulomb))}


def tree_robot(model, *, drop_massless_spherical_leaves: bool = False) -> TreeRobot:
    """The Pinocchio twin of ``model.tree`` (a derived :class:`~symgen.model.Model`), with the
    scene's frames. Raises :class:`OracleError` for a joint kind Pinocchio is not given here.

    With ``drop_massless_spherical_leaves`` the spherical joints of :func:`_droppable` are left out
    (their coordinates have ``v_of_coord = -1``), and :func:`constraint_models` turns a weld on such
    a leaf into a ``CONTACT_3D`` at the joint's centre. This is how the same robot is written for
    Pinocchio's ``constraintDynamics``, whose sparse Cholesky factorization needs a positive pivot
    for every joint: a joint that moves only a massless body has a zero one (the Stewart platform's
    sockets)."""
    pin = require("pinocchio", "the Pinocchio models of symgen scenes")
    tree, scene = model.tree, model.scene
    value = scene.value_of
    pmodel = pin.Model()
    pmodel.gravity = pin.Motion(np.array([value(g) for g in tree.gravity]), np.zeros(3))
    placements = {WORLD_INDEX: (0, pin.SE3.Identity())}
    joints, friction, springs = {}, {}, {}
    dropped = _droppable(tree, scene, value) if drop_massless_spherical_leaves else {}
    for tj in _depth_first(tree):
        jid_parent, x_parent = placements[tj.parent]
        x_joint = x_parent * _se3(pin, tj.rotation, tj.translation, value)
        if tj.child in dropped:                    # the joint's centre, on its parent
            placements[tj.child] = (jid_parent, x_joint)
            joints[tj.name] = None
            continue
        jmodel = _joint_model(pin, tj)
        if jmodel is None:                         # fixed: merge into the parent's joint
            placements[tj.child] = (jid_parent, x_joint)
            continue
        if tj.kind.is_one_dof and not (tj.kind.rotates or tj.kind.translates):
            raise OracleError(f"joint {tj.name!r} is {tj.type}: no Pinocchio joint model for it here")
        jid = pmodel.addJoint(jid_parent, jmodel, x_joint, tj.name)
        joints[tj.name] = jid
        placements[tj.child] = (jid, pin.SE3.Identity())
        friction[jid] = (value(tj.rotor_inertia), value(tj.viscous), value(tj.coulomb))
        if tj.kind.is_one_dof and value(tj.stiffness) != 0:
            springs[jid] = (value(tj.stiffness), value(tj.springref))
    for body in tree.bodies:
        if body.massless:
            continue
        jid, x_body = placements[body.index]
        if jid == 0:
            continue                               # welded to the world: no dynamics
        inertia = pin.Inertia(value(body.mass), np.array([value(c) for c in body.com]),
                              np.array([[value(body.inertia[i, j]) for j in range(3)] for i in range(3)]))
        pmodel.appendBodyToJoint(jid, inertia, x_body)
    robot = TreeRobot(pin, pmodel, joints=joints, tree=tree, scene=scene, placements=placements, dropped=dropped,
                      damping=np.zeros(pmodel.nv), coulomb=np.zeros(pmodel.nv))
    armature = np.zeros(pmodel.nv)
    for jid, (rotor, b, c) in friction.items():
        joint = pmodel.joints[jid]
        armature[joint.idx_v:joint.idx_v + joint.nv] = rotor
        if joint.nv == 1:
            robot.damping[joint.idx_v], robot.coulomb[joint.idx_v] = b, c
        elif b or c:
            robot.spherical_friction[jid] = (b, c)
    pmodel.armature = armature
    robot.springs = {pmodel.joints[jid].idx_v: (pmodel.joints[jid].idx_q, k, ref) for jid, (k, ref) in springs.items()}
    _index_coordinates(robot)
    _add_frames(robot)
    return robot


def _index_coordinates(robot: TreeRobot) -> None:
    v_of = []
    for k, coord in enumerate(robot.tree.coordinates):
        robot.labels[coord.label] = k
        jid = robot.joints[coord.joint]
        v_of.append(-1 if jid is None else robot.model.joints[jid].idx_v + coord.component)
    robot.v_of_coord = np.array(v_of, dtype=int)


def _add_frames(robot: TreeRobot) -> None:
    pin, value = robot.pin, robot.scene.value_of
    for name, frame in robot.tree.frames.items():
        if name == WORLD or frame.body in robot.dropped:
            continue               # a frame on a dropped leaf moves with no Pinocchio joint
        jid, x_body = robot.placements[frame.body]
        x_frame = x_body * _se3(pin, frame.rotation, frame.translation, value)
        robot.frames[name] = robot.model.addFrame(pin.Frame(f"symgen/{name}", jid, x_frame, pin.FrameType.OP_FRAME))


def frame_placement(robot: TreeRobot, name: str):
    """``(joint id, SE3 of the frame in the joint)`` of a scene frame (the world is joint 0)."""
    if name == WORLD:
        return 0, robot.pin.SE3.Identity()
    f = robot.model.frames[robot.frames[name]]
    return f.parentJoint, f.placement


def _ball_at_dropped_joint(robot: TreeRobot, con):
    """A weld between a frame on a dropped spherical leaf and a frame B, as the ball constraint it
    amounts to: the joint's centre (on the leaf's parent) coincides with the point of B's body
    where the centre sits when the weld holds, ``X_B X_{A in leaf}^-1``."""
    if con.kind != "weld":
        raise OracleError(f"constraint {con.name!r} ({con.kind}) holds a massless spherical leaf: only a weld "
                          "on it becomes a Pinocchio ball constraint")
    leaf_frame, other = (con.frame_a, con.frame_b) if robot.frame_on_dropped(con.frame_a) else (con.frame_b, con.frame_a)
    if robot.frame_on_dropped(other):
        raise OracleError(f"constraint {con.name!r} joins two massless spherical leaves")
    pin, value = robot.pin, robot.scene.value_of
    f = robot.tree.frames[leaf_frame]
    x_leaf_frame = _se3(pin, f.rotation, f.translation, value)
    j1, x_centre = robot.placements[f.body]
    j2, x_other = frame_placement(robot, other)
    return (j1, x_centre), (j2, x_other * x_leaf_frame.inverse()), "CONTACT_3D"


def maps_to_pinocchio(scene) -> bool:
    """Whether every constraint of ``scene`` is a Pinocchio ``RigidConstraintModel`` type (weld,
    ball) with all its components, and the scene has no contact forces ``eta_m``."""
    return bool(scene.constraints) and scene.contact_forces is None and all(
        c.kind in PINOCCHIO_CONSTRAINTS and tuple(c.components) == PINOCCHIO_CONSTRAINTS[c.kind][1]
        for c in scene.constraints.values())


def constraint_models(robot: TreeRobot) -> list:
    """The scene's constraints as ``RigidConstraintModel`` (LOCAL): joint 1 carries frame A,
    joint 2 frame B. Raises :class:`OracleError` naming a constraint with no Pinocchio type."""
    pin = robot.pin
    out = []
    for con in robot.scene.constraints.values():
        spec = PINOCCHIO_CONSTRAINTS.get(con.kind)
        if spec is None or tuple(con.components) != spec[1]:
            raise OracleError(f"constraint {con.name!r} ({con.kind}, components {' '.join(con.components)}) is "
                              "not a Pinocchio RigidConstraintModel type (weld -> CONTACT_6D, ball -> CONTACT_3D); "
                              "use the KKT reference of symgen.oracle.pinocchio_check")
        kind = spec[0]
        if robot.frame_on_dropped(con.frame_a) or robot.frame_on_dropped(con.frame_b):
            (j1, x1), (j2, x2), kind = _ball_at_dropped_joint(robot, con)
        else:
            j1, x1 = frame_placement(robot, con.frame_a)
            j2, x2 = frame_placement(robot, con.frame_b)
        cm = pin.RigidConstraintModel(getattr(pin.ContactType, kind), robot.model, j1, x1, j2, x2,
                                      pin.ReferenceFrame.LOCAL)
        cm.name = con.name
        out.append(cm)
    return out
