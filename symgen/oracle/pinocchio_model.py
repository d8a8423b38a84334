"""The robot of a URDF-built scene, rebuilt in Pinocchio from the same files.

Only what is not in the URDF files is taken from the scene, and none of it is dynamics:

* the prefix, the base placement and the locked joints of each :class:`~symgen.io.urdf.UrdfSource`;
* bodies that the scene adds on top of the files by fixed joints (the object of
  :func:`~symgen.io.urdf.add_hold`), with their mass properties;
* the placement of every named frame that constraints and motion coordinates use;
* the gravity vector.

Each file goes through Pinocchio's own URDF parser (``buildModelFromXML``), so masses,
inertias, joint placements, axes and the merging of fixed joints are Pinocchio's, not symgen's.
For a prefix the link and joint names are renamed in the XML. Locked joints go through
``buildReducedModel``, and each robot is attached to the world at its base with ``appendModel``.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import SymgenError
from ..scene.declaration import WORLD
from ..io.urdf._deps import require
from ..io.urdf.build import urdf_sources


class OracleError(SymgenError):
    """The Pinocchio cross-check cannot rebuild this scene (named in the message)."""


@dataclass
class PinocchioRobot:
    """A Pinocchio ``model`` of the scene, and how symgen's names map onto it."""

    pin: object
    model: object
    joints: dict = field(default_factory=dict)   # scene joint -> Pinocchio joint id
    frames: dict = field(default_factory=dict)   # scene frame -> Pinocchio frame id
    damping: np.ndarray | None = None   # Pinocchio's parse of <dynamics damping> per velocity index
    coulomb: np.ndarray | None = None   # ... and of <dynamics friction> (0 where the scene has no friction)
    #: the parts of a free joint (scene joint -> offset of its first coordinate in the root joint)
    free_parts: dict = field(default_factory=dict)
    #: joint springs ``k (q - q_spring)`` kept beside the model (Pinocchio's has none): Pinocchio
    #: velocity index of a 1-DOF joint -> (q index, k, q_spring)
    springs: dict = field(default_factory=dict)

    def q_vector(self, config) -> np.ndarray:
        """Pinocchio's ``q`` of a symgen configuration (``cos, sin`` for continuous joints; a free
        joint's quaternion ``x, y, z, w``)."""
        q = self.pin.neutral(self.model)
        for name, jid in self.joints.items():
            joint = self.model.joints[jid]
            if name in self.free_parts:
                value = config.positions[name]
                start = joint.idx_q + self.free_parts[name]
                if np.ndim(value) == 2:
                    quat = self.pin.Quaternion(np.asarray(value, dtype=float))
                    q[start:start + 4] = quat.x, quat.y, quat.z, quat.w
                else:
                    q[start] = float(value)
                continue
            angle = float(config.positions[name])
            if joint.nq == 2:
                q[joint.idx_q:joint.idx_q + 2] = np.cos(angle), np.sin(angle)
            else:
                q[joint.idx_q] = angle
        return q

    def friction(self, v) -> np.ndarray:
        """Joint friction ``b v + c sign(v)`` (eq. 22) at Pinocchio's ``v``."""
        return self.damping * v + self.coulomb * np.sign(v)

    def spring_forces(self, q) -> np.ndarray:
        """Joint springs ``k (q - q_spring)`` at Pinocchio's ``q`` (zero without springs)."""
        out = np.zeros(self.model.nv)
        for iv, (iq, k, ref) in self.springs.items():
            out[iv] = k * (q[iq] - ref)
        return out

    def v_index(self, names) -> np.ndarray:
        """Velocity indices in Pinocchio of the scene's coordinate labels ``names`` (1-DOF joints,
        and ``j.wx`` etc. of a free joint's rotation)."""
        out = []
        for label in names:
            name, _, component = label.partition(".w")
            offset = self.free_parts.get(name, 0) + ("xyz".index(component) if component else 0)
            out.append(self.model.joints[self.joints[name]].idx_v + offset)
        return np.array(out, dtype=int)


def _prefixed(text: str, prefix: str) -> str:
    """The URDF text with ``prefix`` put in front of every link and joint name and reference."""
    if not prefix:
        return text
    etree = require("lxml.etree", "the Pinocchio cross-check")
    root = etree.fromstring(text.encode("utf-8"), etree.XMLParser(remove_comments=True, resolve_entities=False))
    for el in root.findall("link") + root.findall("joint"):
        el.set("name", prefix + el.get("name"))
    for joint in root.findall("joint"):
        for role in ("parent", "child"):
            joint.find(role).set("link", prefix + joint.find(role).get("link"))
        mimic = joint.find("mimic")
        if mimic is not None:
            mimic.set("joint", prefix + mimic.get("joint"))
    return etree.tostring(root, encoding="unicode")


def _se3(pin, rotation, translation):
    return pin.SE3(np.array(rotation, dtype=float).reshape(3, 3), np.array(translation, dtype=float).reshape(3))


def _robot_model(pin, src):
    """One source's Pinocchio model: its file, renamed, locked joints removed."""
    text = _prefixed(src.robot.text, src.prefix)
    if src.floating:      # symgen's free joint: Pinocchio's translation then spherical joint, as one
        root = pin.JointModelComposite(2)
        root.addJoint(pin.JointModelTranslation())
        root.addJoint(pin.JointModelSpherical())
        model = pin.buildModelFromXML(text, root)
    else:
        model = pin.buildModelFromXML(text)
    if not src.lock:
        return model
    q_ref, ids = pin.neutral(model), []
    for name, value in src.lock.items():
        jid = model.getJointId(src.prefix + name)
        joint, x = model.joints[jid], float(value)
        q_ref[joint.idx_q:joint.idx_q + joint.nq] = (np.cos(x), np.sin(x)) if joint.nq == 2 else (x,)
        ids.append(jid)
    return pin.buildReducedModel(model, ids, q_ref)


def _attach_extras(pin, robot: PinocchioRobot, scene, placement: dict) -> None:
    """Bodies the scene adds by fixed joints, with their inertias; other extra joints are refused."""
    for joint in scene.tree_order():
        if joint.child in placement:
            continue
        if joint.kind.moves:
            raise OracleError(f"joint {joint.name!r} is not from a URDF file and is {joint.type}: the Pinocchio "
                              "check rebuilds URDF robots plus bodies attached by fixed joints only")
        jid, x_jp = placement[joint.parent]
        x_jc = x_jp * _se3(pin, joint.origin.rotation, joint.origin.translation)
        body = scene.bodies[joint.child]
        if not body.is_massless:
            inertia = pin.Inertia(scene.value_of(body.mass), np.array([scene.value_of(v) for v in body.com]),
                                  np.array([[scene.value_of(v) for v in body.inertia.row(i)] for i in range(3)]))
            robot.model.appendBodyToJoint(jid, inertia, x_jc)
        placement[joint.child] = (jid, x_jc)


def _place_free_joint(pin, robot: PinocchioRobot, scene, src, placement: dict) -> None:
    """A floating source's free joint is Pinocchio's root joint (translation, then spherical)."""
    jid = robot.model.getJointId(src.prefix + "root_joint")
    free = scene.free_joints[src.floating]
    for k, name in enumerate(free.joints):
        robot.joints[name] = jid
        robot.free_parts[name] = k
    for body in free.carriers + (free.child,):
        placement[body] = (jid, pin.SE3.Identity())


def pinocchio_robot(scene) -> PinocchioRobot:
    """Rebuild ``scene`` in Pinocchio (see the module docstring).

    Raises:
        OracleError: the scene was not built from URDF files, adds moving joints to them, or was
            loaded with ``inertia="repair"`` and a link's inertia was replaced.
        MissingExtraError: Pinocchio (extra ``oracle``) is not installed.
    """
    pin = require("pinocchio", "the Pinocchio cross-check")
    sources = urdf_sources(scene)
    if not sources:
        raise OracleError(f"scene {scene.name!r} was not built from a URDF file; the Pinocchio check rebuilds "
                          "the robot from its URDF (use symgen.io.urdf.scene_from_urdf or a scene YAML with 'urdf:')")
    repaired = [(src.robot.name, link) for src in sources for link in src.repaired]
    if repaired:
        raise OracleError(f"robot {repaired[0][0]!r} was loaded with inertia='repair', which replaced the inertia of "
                          f"link {repaired[0][1]!r}: Pinocchio reads the file as written, so the check would compare "
                          "two different robots; check the file loaded with inertia='warn'")
    model = pin.Model()
    for src in sources:
        part = _robot_model(pin, src)
        base = pin.SE3.Identity() if src.floating else _se3(pin, src.base_rotation, src.base_translation)
        model = pin.appendModel(model, part, 0, base)
    g = np.array([scene.value_of(v) for v in scene.gravity])
    model.gravity = pin.Motion(g, np.zeros(3))
    robot = PinocchioRobot(pin, model, damping=np.array(model.damping), coulomb=np.array(model.friction))
    placement = {WORLD: (0, pin.SE3.Identity())}
    for src in sources:
        if src.floating:
            _place_free_joint(pin, robot, scene, src, placement)
        for urdf_name, scene_name in src.joints.items():
            jid = model.getJointId(src.prefix + urdf_name)
            robot.joints[scene_name] = jid
            placement[scene.joints[scene_name].child] = (jid, pin.SE3.Identity())
            if not src.friction:  # the scene left this robot's <dynamics> out
                robot.damping[model.joints[jid].idx_v] = robot.coulomb[model.joints[jid].idx_v] = 0.0
    _attach_extras(pin, robot, scene, placement)
    for frame in scene.frames.values():
        jid, x_jb = placement[frame.body]
        x_jf = x_jb * _se3(pin, frame.pose.rotation, frame.pose.translation)
        robot.frames[frame.name] = model.addFrame(pin.Frame(f"symgen/{frame.name}", jid, x_jf, pin.FrameType.OP_FRAME))
    return robot
