"""Desired task trajectories and the required velocity ``V_mr`` with position feedback (eq. 34).

A task follows the scene's motion coordinates ``V_m`` (Step 10):

* **joints** (``motion: {joints: [...]}``): ``x = q_motion``, ``V_m = qd_motion``::

      V_mr  = xd_d + Lambda (x_d - x)          dV_mr = xdd_d + Lambda (xd_d - V_m)

  (``dV_mr`` is the exact time derivative of ``V_mr``, as in Slotine and Li's reference);
* **both** (a mixed ``V_m``: the frame's components, then the joint rates): each part as
  below and above, stacked (:class:`MixedTask`);
* **a frame** (``motion: {frame: F, components}`` or the gamma-weighted frames of Section 3.3,
  which coincide on the constraint manifold, so the first one is used): the pose error of
  :mod:`symgen.control.pose_error` on rotations, no Euler angles, restricted to the motion
  components ``S``::

      V_mr  = S (V_d' + Lambda e)               dV_mr = S d/dt (V_d' + Lambda e)

  with ``V`` the frame's actual twist (all six components) in the exact derivative of
  :func:`symgen.control.pose_error.required_twist_rate`: the components outside ``S`` (the
  orientation of a planar pin, of a tool sliding on a plane) are not driven to the desired ones,
  so the pose error stays finite and a derivative exact only at ``e = 0`` would break the
  Lyapunov argument of Section 4.

The desired motion is a smooth periodic excursion from the initial pose (or joint positions),
``1 - cos(2 pi f t)`` along each motion component with its amplitude: for frames, a translation along
the initial frame's axes and a rotation about one fixed axis, so the desired twist and its
derivative are known in closed form and a constrained task (a plane contact) stays on its plane.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..math.spatial import COMPONENTS, rot_exp
from .errors import ControlInputError
from .pose_error import pose_error, required_twist_rate


@dataclass(frozen=True)
class Excursion:
    """``s(t) = 1 - cos(2 pi f t)`` and its first two derivatives, times per-component amplitudes:
    a closed path that starts at rest at the initial pose (so a robot at rest starts on it)."""

    amplitude: np.ndarray
    frequency: float

    def __call__(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        w = 2 * np.pi * self.frequency
        return (self.amplitude * (1 - np.cos(w * t)), self.amplitude * w * np.sin(w * t),
                self.amplitude * w * w * np.cos(w * t))


class JointTask:
    """Desired motion joint positions ``x_d(t) = x_0 + excursion(t)``."""

    def __init__(self, model, x0, excursion: Excursion, gain: float):
        self.names = list(model.scene.motion.joints)
        self.x0, self.excursion, self.gain = np.asarray(x0, float), excursion, float(gain)

    def position(self, config) -> np.ndarray:
        return np.array([float(config.positions[j]) for j in self.names])

    def desired(self, t: float):
        d, dd, ddd = self.excursion(t)
        return self.x0 + d, dd, ddd

    def required(self, t: float, config, data) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(V_mr, dV_mr, e)`` with ``e = x_d - x``."""
        return self.required_at(t, self.position(config), np.asarray(data.V_m, float))

    def required_at(self, t: float, x, v_m) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`required` from the motion joints' positions ``x`` and rates ``v_m``."""
        x_d, v_d, a_d = self.desired(t)
        e = x_d - np.asarray(x, float)
        return v_d + self.gain * e, a_d + self.gain * (v_d - v_m), e


class FrameTask:
    """Desired pose ``(R_0 rot(a, theta(t)), p_0 + R_0 d(t))`` of the task frame."""

    def __init__(self, model, pose0, excursion: Excursion, gain: float):
        motion = model.scene.motion
        self.frame = motion.frames[0][0]
        self.select = [COMPONENTS.index(c) for c in motion.components]
        self.r0, self.p0 = (np.asarray(x, float) for x in pose0)
        self.gain = float(gain)
        amp6 = np.zeros(6)
        amp6[self.select] = excursion.amplitude
        self.trans, rot = amp6[:3], amp6[3:]
        self.angle = float(np.linalg.norm(rot))
        self.axis = rot / self.angle if self.angle else np.array([0.0, 0.0, 1.0])
        self.unit = Excursion(np.array([1.0]), excursion.frequency)

    def desired(self, t: float):
        """``(R_d, p_d, V_d, dV_d)``: pose and twist (with derivative) in the desired frame's axes."""
        s, ds, dds = (float(v[0]) for v in self.unit(t))
        rot = rot_exp(self.axis * self.angle * s)
        r_d, p_d = self.r0 @ rot, self.p0 + self.r0 @ (self.trans * s)
        v_lin = rot.T @ (self.trans * ds)
        w = self.axis * self.angle * ds
        dv_lin = rot.T @ (self.trans * dds) - np.cross(w, v_lin)
        return r_d, p_d, np.concatenate([v_lin, w]), np.concatenate([dv_lin, self.axis * self.angle * dds])

    def required(self, t: float, config, data) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(V_mr, dV_mr, e)`` with ``e`` the pose error on the motion components."""
        r, p = (j.v for j in data.maps.kin.frame_pose(self.frame))
        twist = data.maps.kin.frame_jacobian(self.frame).v @ (data.maps.P.v @ data.qd)
        return self.required_at(t, r, p, twist)

    def required_at(self, t: float, r, p, twist) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`required` from the frame's pose ``(r, p)`` and its twist (6, own axes)."""
        r_d, p_d, v_d, dv_d = self.desired(t)
        e = pose_error(r, p, r_d, p_d)
        v_mr, dv_mr = required_twist_rate(r, p, r_d, p_d, twist, v_d, dv_d, self.gain)
        return v_mr[self.select], dv_mr[self.select], e[self.select]


class MixedTask:
    """A mixed ``V_m`` (frame components, then joint rates): the :class:`FrameTask` on the first
    rows and the :class:`JointTask` on the rest, each exact as above; ``V_mr``, ``dV_mr`` and ``e``
    are stacked in ``V_m``'s order."""

    def __init__(self, frame: FrameTask, joints: JointTask):
        self.frame_task, self.joint_task = frame, joints
        self.k = len(frame.select)

    def required(self, t: float, config, data) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(V_mr, dV_mr, e)`` of both parts."""
        first = self.frame_task.required(t, config, data)
        rest = self.joint_task.required_at(t, self.joint_task.position(config), np.asarray(data.V_m, float)[self.k:])
        return self.stack(first, rest)

    def required_at(self, t: float, r, p, twist, x, v_m) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`required` from the frame's pose and twist and the motion joints' positions ``x``
        and all of ``V_m``."""
        return self.stack(self.frame_task.required_at(t, r, p, twist),
                          self.joint_task.required_at(t, x, np.asarray(v_m, float)[self.k:]))

    @staticmethod
    def stack(first, rest) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        v_mr, dv_mr, e = (np.concatenate([a, b]) for a, b in zip(first, rest))
        return v_mr, dv_mr, e


def make_task(model, config, data, *, amplitude, frequency: float, gain: float):
    """The scene's task, starting at ``config`` (``data`` evaluated there): a :class:`JointTask`,
    a :class:`FrameTask` or, for a mixed ``V_m``, a :class:`MixedTask`, with ``amplitude`` (scalar or one per motion component, m or rad)."""
    motion = model.scene.motion
    try:
        amp = np.broadcast_to(np.asarray(amplitude, float), (model.counts.m,)).copy()
    except ValueError:
        raise ControlInputError(f"amplitude must be a scalar or {model.counts.m} values (one per motion "
                                f"component), got {np.shape(amplitude)}") from None
    k = motion.frame_dim
    joints = JointTask(model, [float(config.positions[j]) for j in motion.joints],
                       Excursion(amp[k:], float(frequency)), gain) if motion.joints else None
    if not motion.frames:
        return joints
    pose0 = tuple(j.v for j in data.maps.kin.frame_pose(motion.frames[0][0]))
    frame = FrameTask(model, pose0, Excursion(amp[:k], float(frequency)), gain)
    return MixedTask(frame, joints) if joints is not None else frame
