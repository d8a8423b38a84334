"""The robot of an MJCF-read scene (:mod:`symgen.io.mjcf`), rebuilt by Pinocchio's own MJCF reader.

``pinocchio.buildModelFromMJCF`` reads the same file: bodies, joints, inertias and placements
are Pinocchio's. Taken from the scene, and none of it dynamics: the placement of each frame the
constraints and motion coordinates use (on its body, shifted by the body's joint offset, see
:mod:`symgen.io.mjcf.build`) and the gravity vector (Pinocchio's MJCF reader keeps its default
``(0, 0, -9.81)`` and ignores ``<option gravity>``). Pinocchio reads a ``connect`` as a 3-D point
contact and builds no constraint into the model; the check's KKT solve
(:mod:`symgen.oracle.pinocchio_check`) uses the scene's rows after
:func:`symgen.vanishing_rows.drop_vanishing_rows`, built from Pinocchio's frame Jacobians.
"""
from __future__ import annotations

import numpy as np

from ..scene.declaration import WORLD
from ..math.spatial import matrix_to_quat
from ..io.mjcf.build import mjcf_source
from ..io.urdf._deps import require
from .pinocchio_model import OracleError, PinocchioRobot


class MjcfPinocchioRobot(PinocchioRobot):
    """A :class:`PinocchioRobot` whose ball joints take unit quaternions (Pinocchio: x, y, z, w)."""

    def q_vector(self, config) -> np.ndarray:
        q = self.pin.neutral(self.model)
        for name, jid in self.joints.items():
            joint, value = self.model.joints[jid], config.positions[name]
            if joint.nq == 4:
                w, x, y, z = matrix_to_quat(np.asarray(value, dtype=float))
                q[joint.idx_q:joint.idx_q + 4] = x, y, z, w
            elif joint.nq == 1:
                q[joint.idx_q] = float(value)
            else:
                raise OracleError(f"joint {name!r}: Pinocchio joint with nq = {joint.nq} is not compared")
        return q

    def v_index(self, names) -> np.ndarray:
        out = []
        for name in names:
            joint, _, comp = name.partition(".w")
            out.append(self.model.joints[self.joints[joint]].idx_v + ("xyz".index(comp) if comp else 0))
        return np.array(out)


def pinocchio_robot_mjcf(scene) -> MjcfPinocchioRobot:
    """Rebuild an MJCF scene in Pinocchio from its file (see the module docstring)."""
    pin = require("pinocchio", "the Pinocchio cross-check")
    src = mjcf_source(scene)
    model = pin.buildModelFromMJCF(src.path)
    model.gravity = pin.Motion(np.array([scene.value_of(v) for v in scene.gravity]), np.zeros(3))
    robot = MjcfPinocchioRobot(pin, model, damping=np.array(model.damping), coulomb=np.array(model.friction))
    for joint in scene.joints.values():
        if joint.dof:
            if not model.existJointName(joint.name):
                raise OracleError(f"joint {joint.name!r} is not in Pinocchio's model of {src.path}")
            robot.joints[joint.name] = model.getJointId(joint.name)
    for frame in scene.frames.values():
        offset = np.array([float(v) for v in src.offsets[frame.body]])
        x_bf = pin.SE3(np.array(frame.pose.rotation, dtype=float),
                       offset + np.array(frame.pose.translation, dtype=float).reshape(3))
        if frame.body == WORLD:
            jid, x_jf = 0, x_bf
        else:
            body = model.frames[model.getFrameId(frame.body, pin.FrameType.BODY)]
            jid, x_jf = body.parentJoint, body.placement * x_bf
        robot.frames[frame.name] = model.addFrame(pin.Frame(f"symgen/{frame.name}", jid, x_jf, pin.FrameType.OP_FRAME))
    return robot
