"""Pinocchio twins of symgen's floating-base scenes: the same URDF on a ``JointModelFreeFlyer``
root, and the maps between the two coordinate conventions (written here from the conventions'
definitions, not from symgen's code):

* positions: symgen's free joint is ``x, y, z, qw, qx, qy, qz``; Pinocchio's ``x, y, z, qx, qy, qz, qw``;
* velocities: symgen's ``[pd (world); w (body)]``, Pinocchio's ``[R^T pd; w]``;
* accelerations: Pinocchio's ``a = dv/dt``, so ``a_lin = R^T pdd - w x (R^T pd)``;
* other joints by name.
"""
from __future__ import annotations

import numpy as np


def quat_matrix(w, x, y, z):
    """The rotation of a unit quaternion (Hamilton convention), written out."""
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


class FloatingTwin:
    """Pinocchio's model of ``path`` (a URDF file, or the XML text itself) on a free-flyer root
    (``lock``: joints held at 0), and the maps from a symgen model's all-joint vectors."""

    def __init__(self, pin, model, path, lock=()):
        self.pin, self.model = pin, model
        if isinstance(path, str) and path.lstrip().startswith("<"):
            full = pin.buildModelFromXML(path, pin.JointModelFreeFlyer())
        else:
            full = pin.buildModelFromUrdf(str(path), pin.JointModelFreeFlyer())
        if lock:
            ids = [full.getJointId(n) for n in lock]
            full = pin.buildReducedModel(full, ids, pin.neutral(full))
        self.pmodel, self.data = full, full.createData()
        self.labels = [c.label for c in model.tree.coordinates]
        self.base = next(iter(model.scene.free_joints.values()))
        self.rot = self.base.rotation

    def _joint(self, name):
        jid = self.pmodel.getJointId(name)
        assert jid < self.pmodel.njoints, f"Pinocchio has no joint {name!r}"
        return self.pmodel.joints[jid]

    def rotation(self, config):
        return np.asarray(config.positions[self.rot], float)

    def q(self, config):
        q = np.zeros(self.pmodel.nq)
        pos = config.positions
        q[:3] = [float(pos[j]) for j in self.base.translations]
        r = self.rotation(config)
        quat = self.pin.Quaternion(r)
        q[3:7] = [quat.x, quat.y, quat.z, quat.w]
        for j in self.model.scene.joints.values():
            if j.dof == 1 and j.name not in self.base.joints:
                q[self._joint(j.name).idx_q] = float(pos[j.name])
        return q

    def v(self, config, qd_all, accel=None):
        """Pinocchio's v of symgen's ``qd_all`` or, with ``accel`` (symgen's ``qdd_all``), its a."""
        r = self.rotation(config)
        qd = np.asarray(qd_all, float)
        out = np.zeros(self.pmodel.nv)
        v_lin, w = r.T @ qd[:3], qd[3:6]
        if accel is None:
            out[:3], out[3:6] = v_lin, w
        else:
            qdd = np.asarray(accel, float)
            out[:3], out[3:6] = r.T @ qdd[:3] - np.cross(w, v_lin), qdd[3:6]
        vec = qd if accel is None else np.asarray(accel, float)
        for k, label in enumerate(self.labels[6:], 6):
            out[self._joint(label).idx_v] = vec[k]
        return out

    def generalized_force(self, config, tau_all):
        """Pinocchio's generalised force of symgen's all-joint force ``tau_all`` (``f_pin = R^T f``
        on the base's translations: the dual of the velocity map)."""
        r = self.rotation(config)
        f = np.asarray(tau_all, float)
        out = np.zeros(self.pmodel.nv)
        out[:3], out[3:6] = r.T @ f[:3], f[3:6]
        for k, label in enumerate(self.labels[6:], 6):
            out[self._joint(label).idx_v] = f[k]
        return out

    def contact_kkt(self, q, v, tau_p, frames, dims):
        """``(a, lam)`` of ``M a + h = tau + J^T lam``, ``J a + dJ v = 0`` for contact frames held
        still, ``J`` the frames' LOCAL Jacobians (first ``dim`` rows: 3 linear, or all 6)."""
        pin, pm, d = self.pin, self.pmodel, self.data
        m = pin.crba(pm, d, q)
        m = np.triu(m) + np.triu(m, 1).T
        h = pin.nonLinearEffects(pm, d, q, v)
        pin.forwardKinematics(pm, d, q, v, np.zeros(pm.nv))
        pin.computeJointJacobians(pm, d, q)
        pin.updateFramePlacements(pm, d)
        rows, drift = [], []
        for frame, dim in zip(frames, dims):
            fid = pm.getFrameId(frame)
            rows.append(pin.getFrameJacobian(pm, d, fid, pin.LOCAL)[:dim])
            drift.append(pin.getFrameAcceleration(pm, d, fid, pin.LOCAL).vector[:dim])
        jac, gamma = np.vstack(rows), np.concatenate(drift)
        nc = jac.shape[0]
        kkt = np.block([[m, -jac.T], [jac, np.zeros((nc, nc))]])
        sol = np.linalg.solve(kkt, np.concatenate([tau_p - h, -gamma]))
        return sol[: pm.nv], sol[pm.nv:]
