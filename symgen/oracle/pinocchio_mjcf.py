"""The robot of an MJCF-read scene (:mod:`symgen.io.mjcf`), rebuilt by Pinocchio's own MJCF reader.

``pinocchio.buildModelFromMJCF`` reads the same file: bodies, joints, inertias and placements
are Pinocchio's. Taken from the scene: the joint springs ``k (q - q_spring)`` (Pinocchio's model
has none; kept beside it like friction, so this check does not test them -- MuJoCo's
``qfrc_spring`` does, ``benchmarks/mjcf_coverage.py``), and, none of it dynamics, the placement of each frame the
constraints and motion coordinates use (on its body, shifted by the body's joint offset, see
:mod:`symgen.io.mjcf.build`) and the gravity vector (Pinocchio's MJCF reader keeps its default
``(0, 0, -9.81)`` and ignores ``<option gravity>``). Pinocchio reads a ``connect`` as a 3-D point
contact and builds no constraint into the model; the check's KKT solve
(:mod:`symgen.oracle.pinocchio_check`) uses the scene's rows after
:func:`symgen.vanishing_rows.drop_vanishing_rows`, built from Pinocchio's frame Jacobians.
"""
from __future__ import annotations

import re
import tempfile
from pathlib import Path

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
    model = _read(pin, src.path)
    _check_same_joints(model, scene, src.path)
    model.gravity = pin.Motion(np.array([scene.value_of(v) for v in scene.gravity]), np.zeros(3))
    robot = MjcfPinocchioRobot(pin, model, damping=np.array(model.damping), coulomb=np.array(model.friction))
    for joint in scene.joints.values():
        if joint.dof:
            if not model.existJointName(joint.name):
                raise OracleError(f"joint {joint.name!r} is not in Pinocchio's model of {src.path}")
            robot.joints[joint.name] = model.getJointId(joint.name)
            if joint.stiffness != 0:        # Pinocchio's model has no springs: kept beside it
                pj = model.joints[robot.joints[joint.name]]
                robot.springs[pj.idx_v] = (pj.idx_q, scene.value_of(joint.stiffness), scene.value_of(joint.springref))
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


_KEYFRAMES = re.compile(r"<keyframe\b.*?</keyframe\s*>|<keyframe\b[^>]*/>", re.S)


def _read(pin, path: str):
    """Pinocchio's model of the MJCF file at ``path``. A file Pinocchio refuses (its reader raises
    ``ValueError``, e.g. for a ``<key qpos>`` sized for joints it does not read) is read again
    without its keyframes, which do not change the dynamics; an :class:`OracleError` names
    Pinocchio's reason if that fails too."""
    try:
        return pin.buildModelFromMJCF(path)
    except (ValueError, RuntimeError) as exc:
        first = exc
    text = Path(path).read_text(encoding="utf-8")
    stripped = _KEYFRAMES.sub("", text)
    if stripped != text:
        with tempfile.TemporaryDirectory() as tmp:
            copy = Path(tmp) / Path(path).name
            copy.write_text(stripped, encoding="utf-8")
            try:
                return pin.buildModelFromMJCF(str(copy))
            except (ValueError, RuntimeError) as exc:
                first = exc
    raise OracleError(f"Pinocchio's MJCF reader cannot read {path}: {first} (the Pinocchio cross-check needs "
                      "the file as Pinocchio reads it)")


def _check_same_joints(model, scene, path: str) -> None:
    """An :class:`OracleError` unless Pinocchio read the same moving joints as symgen, each once
    (Pinocchio's MJCF reader does not read every form MuJoCo accepts, e.g. bodies inside a
    ``<frame>``), listing both."""
    theirs = [name for name, joint in zip(model.names[1:], model.joints[1:]) if joint.nv > 0]
    ours = [j.name for j in scene.joints.values() if j.dof]
    if sorted(theirs) != sorted(ours):
        raise OracleError(f"Pinocchio's MJCF reader read the joints [{', '.join(theirs)}] of {path}, symgen "
                          f"[{', '.join(ours)}]: the cross-check compares one tree read the same way by both "
                          "(Pinocchio's reader skips some MJCF forms MuJoCo accepts)")
