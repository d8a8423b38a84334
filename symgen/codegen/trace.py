"""Traced building blocks shared by the generated functions: positions, loop closure (eqs. 10-11),
the task maps ``[J_m; J_f]`` (eqs. 12, 17-18) and their time derivatives, and the projection
``P^T`` of joint forces onto the independent coordinates.

One :class:`Tracer` records one generated function. Every block is computed on first use and
cached, so a function only contains what it needs.
"""
from __future__ import annotations

from functools import cached_property

import numpy as np

from ..errors import CodegenError
from ..kinematics import constants, constraint_matrix, tree_kinematics
from ..state import Configuration, CosSin
from ..steps import _frame_components
from .arms import arm_structure, solve_arms
from .graph import Graph, is_zero
from .rnea import dot, joint_friction, rnea
from .trace_field import TraceField


def position_layout(model) -> list[tuple[str, str, int, int]]:
    """``(joint, type, offset, size)`` of each joint's entries in the position input ``q``:
    an angle (revolute), a displacement (prismatic) or a unit quaternion ``w, x, y, z``
    (spherical), in scene declaration order; fixed joints have none."""
    out, offset = [], 0
    for j in model.scene.joints.values():
        size = {"revolute": 1, "prismatic": 1, "spherical": 4}.get(j.type, 0)
        if size:
            out.append((j.name, j.type, offset, size))
            offset += size
    return out


def quaternion_matrix(w, x, y, z):
    """Rotation matrix of a unit quaternion (the homogeneous form without the ``1/|q|^2``)."""
    return [[w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z]]


def _matmul3(a, b):
    return [[a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j] for j in range(3)] for i in range(3)]


class Tracer:
    """Records one function of ``model`` into a fresh :class:`Graph`."""

    def __init__(self, model):
        self.model = model
        self.tree = model.tree
        self.part = model.partition
        self.g = Graph()
        self.field = TraceField(self.g, self.tree.parameters)
        self.consts = constants(self.tree, self.field)
        self.n, self.m = model.counts.n, model.counts.m
        self._closure = None
        self._kin0 = None
        self.config, self.transforms = self._positions()

    # ---------------------------------------------------------------- positions
    def _positions(self):
        g = self.g
        layout = position_layout(self.model)
        q = g.input("q", sum(size for *_, size in layout)) if layout else []
        pos, motion = {}, {}
        for name, kind, off, _size in layout:
            if kind == "revolute":
                c, s = g.func("cos", q[off]), g.func("sin", q[off])
                g.label(c, f"c_{name}")
                g.label(s, f"s_{name}")
                pos[name] = CosSin(c, s)
                motion[name] = [[c, -s, 0], [s, c, 0], [0, 0, 1]]
            elif kind == "prismatic":
                pos[name] = q[off]
            else:
                rot = quaternion_matrix(*q[off:off + 4])
                for i in range(3):
                    for k in range(3):
                        g.label(rot[i][k], f"R_{name}_{i + 1}{k + 1}")
                pos[name] = rot
                motion[name] = rot
        transforms = []
        for k, joint in enumerate(self.tree.joints):
            r_c = self.consts.joint_rot[k].tolist()
            p_c = tuple(self.consts.joint_trans[k])
            if joint.type in ("revolute", "spherical"):
                transforms.append((_matmul3(r_c, motion[joint.name]), p_c))
            elif joint.type == "prismatic":
                d = pos[joint.name]
                transforms.append((r_c, tuple(p_c[i] + r_c[i][2] * d for i in range(3))))
            else:
                transforms.append((r_c, p_c))
        return Configuration(pos), transforms

    # ---------------------------------------------------------------- loop closure, eqs. (10)-(11)
    def kinematics(self, qd_all=None):
        """Reference kinematics (jets) recorded into the graph; without rates, cached."""
        if qd_all is None:
            if self._kin0 is None:
                self._kin0 = tree_kinematics(self.tree, self.field, self.config)
            return self._kin0
        return tree_kinematics(self.tree, self.field, self.config, np.array(qd_all, dtype=object))

    def closure(self):
        """``(W, P_u1)``: ``W = [T_u1, T_a1]`` and the rows of ``P`` for ``q_u1`` (eq. 10)
        over the columns ``q_a2, q_u2`` -- one factorisation of ``W``, several right-hand sides."""
        if self._closure is None:
            t = constraint_matrix(self.kinematics(), self.model.scene.constraints.values()).v
            w = t[:, list(self.part.u1 + self.part.a1)]
            rhs = t[:, list(self.part.a2 + self.part.u2)]
            x = self.field.solve(w, rhs, "[T_u1, T_a1] (eq. 9)")
            self._closure = (w, -x[: len(self.part.u1)])
        return self._closure

    def _dependent_columns(self):
        return [self.part.column(c) for c in self.part.a2 + self.part.u2]

    def complete_rates(self, qd):
        """``qd_all = P qd`` (eq. 10): the independent rates placed, the ``q_u1`` rates computed."""
        qd_all = [0] * self.tree.n_coords
        for col, coord in enumerate(self.part.independent):
            qd_all[coord] = qd[col]
        if self.part.u1:
            _, p_u1 = self.closure()
            cols = self._dependent_columns()
            for i, coord in enumerate(self.part.u1):
                qd_all[coord] = dot(p_u1[i], [qd[c] for c in cols])
        return qd_all

    def rate_bias(self, qd_all):
        """``(dP/dt qd, kin)``: the ``q_u1`` accelerations at ``qdd = 0`` (eq. 11) and the
        kinematics with derivatives along ``qd_all``."""
        kin = None
        bias = [0] * self.tree.n_coords
        if self.part.u1 or self.model.scene.constraints or self.model.scene.motion.frames \
                or self.model.scene.contact_forces:
            kin = self.kinematics(qd_all)
        if self.part.u1:
            w, _ = self.closure()
            t = constraint_matrix(kin, self.model.scene.constraints.values())
            y = self.field.solve(w, t.d @ np.array(qd_all, dtype=object), "[T_u1, T_a1] (eq. 9)")
            for i, coord in enumerate(self.part.u1):
                bias[coord] = -y[i]
        return bias, kin

    def complete_accelerations(self, qdd, bias):
        """``qdd_all = P qdd + dP/dt qd`` (eq. 11)."""
        qdd_all = list(bias)
        for col, coord in enumerate(self.part.independent):
            qdd_all[coord] = qdd_all[coord] + qdd[col]
        if self.part.u1:
            _, p_u1 = self.closure()
            cols = self._dependent_columns()
            for i, coord in enumerate(self.part.u1):
                qdd_all[coord] = qdd_all[coord] + dot(p_u1[i], [qdd[c] for c in cols])
        return qdd_all

    def project(self, tau_all):
        """``P^T tau_all``: joint forces on the independent coordinates."""
        out = [tau_all[c] for c in self.part.independent]
        if self.part.u1:
            _, p_u1 = self.closure()
            for j, col in enumerate(self._dependent_columns()):
                for i, coord in enumerate(self.part.u1):
                    out[col] = out[col] + p_u1[i][j] * tau_all[coord]
        return out

    # ---------------------------------------------------------------- task maps, eqs. (12)-(18)
    def p_full(self):
        """``P`` (N_all x n) as nested lists of nodes."""
        n_all = self.tree.n_coords
        rows = [[0] * self.n for _ in range(n_all)]
        for col, coord in enumerate(self.part.independent):
            rows[coord][col] = 1
        if self.part.u1:
            _, p_u1 = self.closure()
            for i, coord in enumerate(self.part.u1):
                for j, col in enumerate(self._dependent_columns()):
                    rows[coord][col] = p_u1[i][j]
        return np.array(rows, dtype=object)

    def _frame_map(self, kin):
        """``sum gamma_i S J_F_i`` (Section 3.3) over all joint coordinates, as a jet."""
        motion = self.model.scene.motion
        total = None
        for frame, gamma in motion.frames:
            term = _frame_components(kin, frame, motion.components).scale(self.field.const(gamma))
            total = term if total is None else total + term
        return total

    def _motion_coordinates(self) -> list[int]:
        """All-coordinate indices of the joints that give the motion (Step 9 with joints)."""
        return [next(c for c, co in enumerate(self.tree.coordinates) if co.joint == j)
                for j in self.model.scene.motion.joints]

    @cached_property
    def arms(self):
        """The per-arm block structure of ``[J_m; J_f]`` (:mod:`symgen.codegen.arms`), or ``None``."""
        return arm_structure(self)

    def task_matrix(self):
        """``A = [J_m; J_f]`` (n x n, eq. 18) at the configuration."""
        scene = self.model.scene
        if scene.constraint_forces != "operational" and self.model.counts.nc > self.model.counts.np:
            raise CodegenError("constraint_forces: joint with n_c > n_p is not supported by the code "
                               "generator; use constraint_forces: operational")
        p = self.p_full()
        if scene.motion.joints:
            j_m = p[self._motion_coordinates(), :]
        else:
            j_m = self._frame_map(self.kinematics()).v @ p
        parts = [j_m]
        if self.n > self.m:
            t = constraint_matrix(self.kinematics(), scene.constraints.values()).v
            parts.append(t @ p)
        return np.vstack(parts)

    def task_bias(self, qd_all, bias, kin):
        """``dA/dt qd`` (n): the task rows' accelerations at ``qdd = 0``."""
        scene = self.model.scene
        qd_v, b_v = np.array(qd_all, dtype=object), np.array(bias, dtype=object)
        if scene.motion.joints:
            out = [bias[r] for r in self._motion_coordinates()]
        else:
            jac = self._frame_map(kin)
            out = list(jac.d @ qd_v + jac.v @ b_v)
        if self.n > self.m:
            t = constraint_matrix(kin, scene.constraints.values())
            out += list(t.d @ qd_v + t.v @ b_v)
        return out

    def contact_map(self):
        """``D_m`` (eq. 16) as an array of nodes, or ``None`` without contact forces."""
        cf = self.model.scene.contact_forces
        if cf is None:
            return None
        return _frame_components(self.kinematics(), cf.frame, cf.components).v @ self.p_full()

    def solve(self, a, b, what):
        return self.g.solve(a, np.array(b, dtype=object), what)

    def solve_task(self, a, b, *, transpose: bool = False):
        """``A^-1 b`` or ``A^-T b`` for ``A = [J_m; J_f]``: through the per-arm blocks when the scene
        has them (:mod:`symgen.codegen.arms`), else one dense library solve."""
        b = np.array(b, dtype=object)
        structure = self.arms
        if structure is not None:
            cols = [solve_arms(self, structure, b[:, k] if b.ndim == 2 else b, transpose)
                    for k in range(b.shape[1] if b.ndim == 2 else 1)]
            return np.array(cols, dtype=object).T if b.ndim == 2 else np.array(cols[0], dtype=object)
        if transpose:
            return self.g.solve(a.T, b, "[J_m; J_f]^T (eq. 18)")
        return self.g.solve(a, b, "[J_m; J_f] (eq. 18)")

    # ---------------------------------------------------------------- dynamics
    def joint_forces(self, qd_all, qdd_all, *, gravity: bool, friction_rates=None, tag: str = ""):
        """``P^T (T_S^T (M_S dX + C_S X + G_S))`` by recursion (eqs. 21-25): velocity products
        from ``qd_all``, joint friction ``xi`` from ``friction_rates`` (``None``: left out)."""
        tau = rnea(self.tree, self.consts, self.transforms, qd_all, qdd_all, gravity=gravity,
                   graph=self.g, tag=tag)
        if friction_rates is not None:
            for k, joint in enumerate(self.tree.joints):
                if joint.type == "spherical" and not is_zero(self.consts.coulomb[k]):
                    raise CodegenError(f"joint {joint.name!r}: Coulomb friction on a spherical joint "
                                       "is not supported by the code generator")
            xi = joint_friction(self.tree, self.consts, friction_rates, lambda x: self.g.func("sign", x), self.g)
            tau = [a + b for a, b in zip(tau, xi)]
        return self.project(tau)
