"""``[J_m; J_f]^-1`` through per-arm blocks for h arms holding one object (Section 3.3,
DESIGN.md section 4).

When the motion is ``sum gamma_i X_Oi`` over one tool frame ``O_i`` per arm (all six components),
the constraints are welds ``O_i``-``O_(i+1)``, and each ``O_i`` moves with exactly six joint
coordinates of its own arm, then ``A = K D`` with ``D = diag(J_1 ... J_h)`` (``J_i``: the 6 x 6
Jacobian of ``O_i`` on arm i's coordinates) and

    K = [[g_1 1, g_2 1, ..., g_h 1],          motion rows
         [1, -V_1^T, 0, ...],                  weld O_1-O_2:  X_O1 - V_1^T X_O2
         [0, 1, -V_2^T, ...], ...]             V_i = ^(O_(i+1)) U_(O_i)

``K`` is eliminated block by block (one 6 x 6 solve), then ``J_i y = ...`` is solved per arm: the
cost is ``O(h)`` 6 x 6 operations and h + 1 small factorisations instead of one ``6h x 6h`` LU.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..dynamics.algebra import dot
from ..math.spatial import COMPONENTS, force_transform
from .graph import is_zero


@dataclass
class ArmStructure:
    gammas: list            # gamma_i (nodes)
    jacobians: list         # J_i, 6 x 6 node arrays
    columns: list           # qd columns of arm i, in the order of J_i's columns
    weld_maps: list         # V_i^T (6 x 6 node arrays), i = 1..h-1


def arm_structure(tracer) -> ArmStructure | None:
    """The block structure of ``A`` if the scene has it (see the module docstring), else ``None``."""
    scene, part = tracer.model.scene, tracer.part
    motion = scene.motion
    frames = [f for f, _ in motion.frames]
    cons = list(scene.constraints.values())
    if (part.u1 or motion.joints or tuple(motion.components) != COMPONENTS or len(frames) < 1
            or len(cons) != len(frames) - 1 or scene.contact_forces is not None
            or tracer.tree.n_coords != tracer.n):
        return None
    for k, con in enumerate(cons):
        if tuple(con.components) != COMPONENTS or (con.frame_a, con.frame_b) != (frames[k], frames[k + 1]):
            return None
    kin = tracer.kinematics()
    jacobians, columns, used = [], [], set()
    for f in frames:
        jac = kin.frame_jacobian(f).v
        support = [c for c in range(tracer.tree.n_coords) if not all(is_zero(jac[r, c]) for r in range(6))]
        if len(support) != 6 or used.intersection(support):
            return None
        used.update(support)
        cols = sorted(support, key=part.column)
        jacobians.append(jac[:, cols])
        columns.append([part.column(c) for c in cols])
    if len(used) != tracer.n:
        return None
    weld_maps = []
    for k in range(len(frames) - 1):
        u_ba = force_transform(*kin.relative_pose(frames[k], frames[k + 1]), tracer.field)
        weld_maps.append(u_ba.v.T)
    gammas = [tracer.field.const(g) for _, g in motion.frames]
    return ArmStructure(gammas, jacobians, columns, weld_maps)


def _matvec(m, v):
    return np.array([dot(m[i], v) for i in range(m.shape[0])], dtype=object)


def solve_arms(tracer, s: ArmStructure, b, transpose: bool) -> list:
    """``A^-1 b`` (or ``A^-T b``) for one right-hand side, by the block elimination above."""
    return _solve_transposed(tracer, s, b) if transpose else _solve(tracer, s, b)


def _solve(tracer, s, b):
    """``K y = b`` then ``J_i x_i = y_i``: ``y_i = L_i y_h + c_i`` from the weld rows, and
    ``(sum g_i L_i) y_h = b_m - sum g_i c_i`` from the motion rows."""
    h = len(s.jacobians)
    eye = np.array([[tracer.field.const(int(i == j)) for j in range(6)] for i in range(6)], dtype=object)
    lin, off = [None] * h, [None] * h
    lin[h - 1], off[h - 1] = eye, np.array([0] * 6, dtype=object)
    for i in range(h - 2, -1, -1):
        lin[i] = s.weld_maps[i] @ lin[i + 1]
        off[i] = _matvec(s.weld_maps[i], off[i + 1]) + b[6 * (i + 1): 6 * (i + 2)]
    mat = sum((s.gammas[i] * lin[i] for i in range(h)), np.zeros((6, 6), dtype=object))
    rhs = b[:6] - sum((s.gammas[i] * off[i] for i in range(h)), np.zeros(6, dtype=object))
    y_last = tracer.g.solve(mat, rhs, "sum gamma_i L_i (object block of [J_m; J_f])")
    x = [0] * tracer.n
    for i in range(h):
        y = _matvec(lin[i], y_last) + off[i]
        xi = tracer.g.solve(s.jacobians[i], y, f"J_{i + 1}, arm {i + 1}'s tool Jacobian (eq. 18)")
        for k, col in enumerate(s.columns[i]):
            x[col] = xi[k]
    return x


def _solve_transposed(tracer, s, r):
    """``J_i^T s_i = r_i`` per arm, then ``K^T z = s`` with ``z = [z_m; z_1 ...]``:
    ``z_i = P_i z_m + d_i`` from arm rows 1..h-1, the last arm row gives ``z_m``."""
    h = len(s.jacobians)
    s_arm = [tracer.g.solve(s.jacobians[i].T, np.array([r[c] for c in s.columns[i]], dtype=object),
                            f"J_{i + 1}^T (eq. 18)") for i in range(h)]
    eye = np.array([[tracer.field.const(int(i == j)) for j in range(6)] for i in range(6)], dtype=object)
    lin, off = [], []
    prev_lin, prev_off = np.zeros((6, 6), dtype=object), np.zeros(6, dtype=object)
    for i in range(h - 1):
        carry_lin = s.weld_maps[i - 1].T @ prev_lin if i else prev_lin
        carry_off = _matvec(s.weld_maps[i - 1].T, prev_off) if i else prev_off
        prev_lin = carry_lin - s.gammas[i] * eye
        prev_off = carry_off + s_arm[i]
        lin.append(prev_lin)
        off.append(prev_off)
    if h > 1:
        mat = s.gammas[h - 1] * eye - s.weld_maps[h - 2].T @ lin[h - 2]
        rhs = s_arm[h - 1] + _matvec(s.weld_maps[h - 2].T, off[h - 2])
    else:
        mat, rhs = s.gammas[0] * eye, s_arm[0]
    z_m = tracer.g.solve(mat, rhs, "object block of [J_m; J_f]^T")
    out = list(z_m)
    for i in range(h - 1):
        out.extend(_matvec(lin[i], z_m) + off[i])
    return out
