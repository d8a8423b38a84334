"""Plain-NumPy forward kinematics of the position vector ``q``: body poses, centres of mass and
the constraint residuals with their exact Jacobian.

This is the simulation's fast path for what :func:`symgen.closure.closure_residual` computes
through jets: a position-level residual per constraint between frames A and B,

    r = [R_A^T (p_B - p_A);  log(R_A^T R_B)]   restricted to the constraint's components,

and its derivative with respect to chosen joint coordinates (spherical coordinates are rotations
about the child frame's axes, as in ``qd_all``). The rows of ``dr/dq`` are exact:

    d(R_A^T (p_B - p_A)) = R_A^T (dp_B - dp_A - w_A x (p_B - p_A))
    d log(E)             = J_r^-1(log E) R_B^T (w_B - w_A),      E = R_A^T R_B,

with world-frame point velocities and angular velocities of each coordinate's unit motion.
``O(N)`` small NumPy operations per call; no jets, no symbolic constants.
"""
from __future__ import annotations

import numpy as np

from ..codegen.trace import position_layout
from ..kinematics import constants
from ..math.spatial import COMPONENTS, rot_log
from ..tree import WORLD_INDEX
from .state import StateLayout


def _rz(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _quat_matrix(q) -> np.ndarray:
    w, x, y, z = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array([[w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z]])


def _cross(a, b) -> np.ndarray:
    """``a x b`` for 3-vectors (faster than ``np.cross`` on single vectors)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def _hat(v) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def inverse_right_jacobian(rho) -> np.ndarray:
    """``J_r^-1(rho)`` of SO(3): ``Exp(rho + J_r^-1 d) = Exp(rho) Exp(d)`` to first order."""
    theta = float(np.linalg.norm(rho))
    k = _hat(rho)
    if theta < 1e-6:
        return np.eye(3) + 0.5 * k + k @ k / 12.0
    coef = 1.0 / theta**2 - (1.0 + np.cos(theta)) / (2.0 * theta * np.sin(theta))
    return np.eye(3) + 0.5 * k + coef * (k @ k)


class Poses:
    """Forward kinematics of one model's tree from the position vector ``q``.

    ``bodies(q)`` returns world rotations and positions of every tree body (internal frames,
    :mod:`symgen.tree`); ``residual(q)`` the constraint residuals; ``residual_jacobian(q, coords)``
    their derivative with respect to the all-coordinate indices ``coords``.
    """

    def __init__(self, model):
        self.model = model
        self.tree = model.tree
        self.layout = StateLayout(model)
        fld = model.float_field
        self.const = constants(self.tree, fld)
        offsets = {name: off for name, _, off, _ in position_layout(model)}
        self.q_offset = [offsets.get(j.name) for j in self.tree.joints]
        self.offsets = offsets
        self.constraints = list(model.scene.constraints.values())
        self.selections = [[] if con.is_coupling else [COMPONENTS.index(c) for c in con.components]
                           for con in self.constraints]
        # joints on the path from the root to each body (tree order), for the Jacobians
        self.path: list[list[int]] = [[] for _ in self.tree.bodies]
        for k, joint in enumerate(self.tree.joints):
            self.path[joint.child] = ([] if joint.parent == WORLD_INDEX else list(self.path[joint.parent])) + [k]

    # ------------------------------------------------------------------ poses
    def bodies(self, q) -> tuple[list[np.ndarray], list[np.ndarray]]:
        """``(R_W_b, p_W_b)`` of every body, indexed like ``tree.bodies``."""
        n = len(self.tree.bodies)
        rot, pos = [None] * n, [None] * n
        for k, joint in enumerate(self.tree.joints):
            r_c, p_c = self.const.joint_rot[k], self.const.joint_trans[k]
            off = self.q_offset[k]
            kind = joint.kind
            if kind.position_is_angle:
                r_rel, p_rel = r_c @ _rz(q[off]), p_c
            elif kind.translates:
                r_rel, p_rel = r_c, p_c + r_c[:, 2] * q[off]
            elif kind.position_is_rotation:
                r_rel, p_rel = r_c @ _quat_matrix(q[off:off + 4]), p_c
            else:
                r_rel, p_rel = r_c, p_c
            if joint.parent == WORLD_INDEX:
                rot[joint.child], pos[joint.child] = r_rel, p_rel
            else:
                r_p, p_p = rot[joint.parent], pos[joint.parent]
                rot[joint.child], pos[joint.child] = r_p @ r_rel, p_p + r_p @ p_rel
        return rot, pos

    def frame(self, rot, pos, name: str) -> tuple[np.ndarray, np.ndarray]:
        """World pose of a named frame from the body poses."""
        f = self.tree.frames[name]
        r_f, p_f = self.const.frame[name]
        if f.body == WORLD_INDEX:
            return r_f, p_f
        return rot[f.body] @ r_f, pos[f.body] + rot[f.body] @ p_f

    def frame_twist(self, q, qd_all, name: str, bodies=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(R_W_f, p_W_f, V_f)``: the world pose of frame ``name`` and its twist ``[v; w]`` in its
        own axes (DESIGN.md section 2) at the all-coordinate rates ``qd_all``; ``bodies`` is
        :meth:`bodies` at ``q`` when the caller has it already."""
        rot, pos = self.bodies(q) if bodies is None else bodies
        r_f, p_f = self.frame(rot, pos, name)
        coords = range(len(qd_all))
        v, w = self._unit_motions(rot, pos, self.tree.frames[name].body, p_f, coords)
        qd = np.asarray(qd_all, float)
        return r_f, p_f, np.concatenate([r_f.T @ (v @ qd), r_f.T @ (w @ qd)])

    def centres_of_mass(self, q) -> tuple[np.ndarray, np.ndarray]:
        """``(masses, world positions of the centres of mass)`` of every body."""
        rot, pos = self.bodies(q)
        masses = np.array(self.const.mass, dtype=float)
        coms = np.array([p + r @ c for r, p, c in zip(rot, pos, self.const.com)])
        return masses, coms

    def potential_energy(self, q) -> float:
        """Gravitational potential ``-sum_b m_b g . c_b`` (J), zero datum at the world origin, plus
        the joint springs' ``sum_j k_j (q_j - q_spring,j)^2 / 2``."""
        masses, coms = self.centres_of_mass(q)
        springs = sum(0.5 * float(k) * (float(q[off]) - float(ref)) ** 2
                      for k, ref, off in zip(self.const.stiffness, self.const.springref, self.q_offset) if k != 0)
        return float(-masses @ (coms @ self.const.gravity)) + springs

    # ------------------------------------------------------------------ constraints
    def residual(self, q) -> np.ndarray:
        """Stacked position residuals of every constraint (zero on the constraint manifold)."""
        if not self.constraints:
            return np.zeros(0)
        rot, pos = self.bodies(q)
        out = []
        for con, sel in zip(self.constraints, self.selections):
            if con.is_coupling:
                out.append(self._coupling(q, con, ())[0])
                continue
            r_a, p_a = self.frame(rot, pos, con.frame_a)
            r_b, p_b = self.frame(rot, pos, con.frame_b)
            rel = np.concatenate([r_a.T @ (p_b - p_a), rot_log(r_a.T @ r_b)])
            out.append(rel[sel])
        return np.concatenate(out)

    def _coupling(self, q, con, coords) -> tuple[np.ndarray, np.ndarray]:
        """Residual ``offset - sum_i c_i q_i`` of a joint coupling and its derivative over ``coords``
        (:func:`symgen.kinematics.coupling_residual`)."""
        value, row = float(con.offset.xreplace(self.tree.parameters)), np.zeros((1, len(coords)))
        col = {c: i for i, c in enumerate(coords)}
        for joint, coefficient in con.terms:
            c = float(coefficient.xreplace(self.tree.parameters))
            value -= c * q[self.offsets[joint]]
            if self.tree.coordinate_of(joint) in col:
                row[0, col[self.tree.coordinate_of(joint)]] = -c
        return np.array([value]), row

    def _unit_motions(self, rot, pos, body: int, point, coords) -> tuple[np.ndarray, np.ndarray]:
        """World velocity of ``point`` (on ``body``) and angular velocity of ``body`` for a unit
        rate of each coordinate in ``coords`` (3 x len(coords) each)."""
        v, w = np.zeros((3, len(coords))), np.zeros((3, len(coords)))
        if body == WORLD_INDEX:
            return v, w
        col = {c: i for i, c in enumerate(coords)}
        for k in self.path[body]:
            joint = self.tree.joints[k]
            r_j, p_j = rot[joint.child], pos[joint.child]
            for comp, c in enumerate(joint.coords):
                if c not in col:
                    continue
                i = col[c]
                if joint.kind.translates:
                    v[:, i] = r_j[:, 2]
                else:
                    axis = r_j[:, 2] if joint.kind.is_one_dof else r_j[:, comp]
                    w[:, i] = axis
                    v[:, i] = _cross(axis, point - p_j)
        return v, w

    def residual_jacobian(self, q, coords) -> np.ndarray:
        """``dr/dq`` over the all-coordinate indices ``coords`` (n_c x len(coords)), exact."""
        return self.residual_and_jacobian(q, coords)[1]

    def residual_and_jacobian(self, q, coords) -> tuple[np.ndarray, np.ndarray]:
        """``(r, dr/dq)`` from one pass over the poses (see :meth:`residual_jacobian`)."""
        rot, pos = self.bodies(q)
        res, rows = [], []
        for con, sel in zip(self.constraints, self.selections):
            if con.is_coupling:
                r, row = self._coupling(q, con, coords)
                res.append(r)
                rows.append(row)
                continue
            r_a, p_a = self.frame(rot, pos, con.frame_a)
            r_b, p_b = self.frame(rot, pos, con.frame_b)
            body_a, body_b = self.tree.frames[con.frame_a].body, self.tree.frames[con.frame_b].body
            v_a, w_a = self._unit_motions(rot, pos, body_a, p_a, coords)
            v_b, w_b = self._unit_motions(rot, pos, body_b, p_b, coords)
            d = p_b - p_a
            rho = rot_log(r_a.T @ r_b)
            res.append(np.concatenate([r_a.T @ d, rho])[sel])
            lin = r_a.T @ (v_b - v_a - _hat(d).T @ w_a)
            ang = inverse_right_jacobian(rho) @ r_b.T @ (w_b - w_a)
            rows.append(np.vstack([lin, ang])[sel])
        if not rows:
            return np.zeros(0), np.zeros((0, len(coords)))
        return np.concatenate(res), np.vstack(rows)
