"""Independent float reference for constrained multibody dynamics (a test oracle for symgen).

This module deliberately shares nothing with symgen's derivation: it reads only the plain data of
:mod:`symgen.scene` / :mod:`symgen.math.configuration` and uses its own formulation, Featherstone-style
*world-frame* spatial vectors ``V = [w; v_O]`` (angular velocity, then the velocity of the body
point that currently coincides with the world origin).  symgen uses body-frame ``[v; w]`` twists;
the two only meet in the public outputs below.

The model computed is ::

    M(q) qdd + h(q, qd) = tau + K(q)^T lam + Q_c,      K(q) qdd + kbias(q, qd) = 0,
    Q_c = -D_m(q)^T eta_m,

with ``h`` = Coriolis/centrifugal + gravity + friction (``+b qd + c sign(qd)``).

Shapes: ``n`` = number of velocity coordinates (1 per revolute/prismatic joint, 3 per spherical
joint, 0 per fixed joint, in the scene's joint declaration order); ``n_c`` = sum of the
constraints' component counts.  ``q`` is a :class:`symgen.math.configuration.Configuration` or a plain dict
``joint name -> float | 3x3 rotation``.

Costs: every call recomputes kinematics, ``O(n_bodies * n)``; ``M`` is formed as
``sum_i J_i^T I_i J_i`` (``O(n_bodies * n^2)``); ``h`` by the recursive Newton-Euler algorithm.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from symgen.scene import WORLD
from symgen.math.configuration import Configuration

_COMPONENT_INDEX = {"vx": 0, "vy": 1, "vz": 2, "wx": 3, "wy": 4, "wz": 5}


# ----------------------------------------------------------------------------- small algebra
def skew(p) -> np.ndarray:
    """Cross-product matrix: ``skew(p) @ x == np.cross(p, x)``."""
    return np.array([[0.0, -p[2], p[1]], [p[2], 0.0, -p[0]], [-p[1], p[0], 0.0]])


def rotation_about(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rodrigues rotation by ``angle`` about the unit vector ``axis``."""
    k = skew(axis)
    return np.eye(3) + np.sin(angle) * k + (1.0 - np.cos(angle)) * (k @ k)


def rotation_vector(r: np.ndarray) -> np.ndarray:
    """Rotation vector (axis * angle) of a rotation matrix (scipy's quaternion-based log)."""
    from scipy.spatial.transform import Rotation

    return Rotation.from_matrix(r).as_rotvec()


def _crm(v: np.ndarray) -> np.ndarray:
    """Spatial motion cross product ``v x`` for ``v = [w; v_O]``."""
    out = np.zeros((6, 6))
    out[:3, :3] = skew(v[:3])
    out[3:, :3] = skew(v[3:])
    out[3:, 3:] = skew(v[:3])
    return out


def _crf(v: np.ndarray) -> np.ndarray:
    """Spatial force cross product ``v x*`` (= ``-crm(v)^T``)."""
    return -_crm(v).T


def _spatial_inertia(mass: float, com_w: np.ndarray, inertia_com_w: np.ndarray) -> np.ndarray:
    """6x6 spatial inertia about the world origin, world axes, ``[w; v_O]`` ordering."""
    c = skew(com_w)
    out = np.zeros((6, 6))
    out[:3, :3] = inertia_com_w + mass * c @ c.T
    out[:3, 3:] = mass * c
    out[3:, :3] = mass * c.T
    out[3:, 3:] = mass * np.eye(3)
    return out


def _f(scene, expr) -> float:
    return scene.value_of(expr)


def _mat(scene, m) -> np.ndarray:
    return np.array([[scene.value_of(v) for v in m.row(i)] for i in range(m.rows)], dtype=float)


def _vec(scene, m) -> np.ndarray:
    return np.array([scene.value_of(v) for v in m], dtype=float)


def _pose(scene, pose) -> tuple[np.ndarray, np.ndarray]:
    return _mat(scene, pose.rotation), _vec(scene, pose.translation)


# ----------------------------------------------------------------------------- coordinates
def coordinate_slices(scene) -> dict:
    """``joint name -> slice`` into the velocity vector ``qd_all`` (fixed joints omitted)."""
    out, k = {}, 0
    for j in scene.joints.values():
        n = {"revolute": 1, "prismatic": 1, "spherical": 3, "fixed": 0}[j.type]
        if n:
            out[j.name] = slice(k, k + n)
            k += n
    return out


def _n_coords(scene) -> int:
    sl = coordinate_slices(scene)
    return max((s.stop for s in sl.values()), default=0)


def _positions(q) -> dict:
    """Float joint positions from a Configuration (CosSin allowed) or a plain dict."""
    positions = q.positions if isinstance(q, Configuration) else dict(q)
    return Configuration(positions).as_float().positions


def _tree_order(scene) -> list:
    """Joints sorted parents first (own topological sort, independent of Scene.tree_order)."""
    order, placed, pending = [], {WORLD}, list(scene.joints.values())
    while pending:
        ready = [j for j in pending if j.parent in placed]
        if not ready:
            raise ValueError(f"joints {[j.name for j in pending]} are not connected to the world")
        for j in ready:
            order.append(j)
            placed.add(j.child)
        pending = [j for j in pending if j not in ready]
    return order


# ----------------------------------------------------------------------------- kinematics
@dataclass
class _Kinematics:
    """Per-evaluation workspace: poses, world spatial velocities/accelerations, Jacobians."""

    R: dict        # body -> R_WB (3x3)
    p: dict        # body -> p_WB (3,)
    V: dict        # body -> world spatial velocity [w; v_O] (6,)
    A: dict        # body -> world spatial acceleration (6,) (with the gravity offset if asked)
    J: dict        # body -> 6 x n world spatial Jacobian, V = J qd
    S: dict        # joint -> 6 x dof motion subspace (world, [w; v_O])


def _kinematics(scene, q, qd=None, qdd=None, gravity=False) -> _Kinematics:
    """Forward pass over the tree.

    ``A`` is the true spatial acceleration for the given ``qdd`` (zero if None), shifted by
    ``-g`` when ``gravity`` is set (the usual RNEA trick: the base accelerates upwards).
    The motion subspace ``S`` of every joint is fixed in the child body, so ``dS/dt = V x S``.
    """
    pos = _positions(q)
    n = _n_coords(scene)
    qd = np.zeros(n) if qd is None else np.asarray(qd, dtype=float)
    qdd = np.zeros(n) if qdd is None else np.asarray(qdd, dtype=float)
    sl = coordinate_slices(scene)
    a0 = np.zeros(6)
    if gravity:
        a0[3:] = -_vec(scene, scene.gravity)
    kin = _Kinematics({WORLD: np.eye(3)}, {WORLD: np.zeros(3)}, {WORLD: np.zeros(6)},
                      {WORLD: a0}, {WORLD: np.zeros((6, n))}, {})
    for j in _tree_order(scene):
        r_pj, p_pj = _pose(scene, j.origin)
        R_WJ = kin.R[j.parent] @ r_pj
        p_WJ = kin.p[j.parent] + kin.R[j.parent] @ p_pj
        axis = _vec(scene, j.axis)
        if j.type == "revolute":
            R_WC, p_WC = R_WJ @ rotation_about(axis, pos[j.name]), p_WJ
            a = R_WJ @ axis
            S = np.concatenate([a, np.cross(p_WJ, a)])[:, None]
        elif j.type == "prismatic":
            R_WC, p_WC = R_WJ, p_WJ + R_WJ @ axis * pos[j.name]
            S = np.concatenate([np.zeros(3), R_WJ @ axis])[:, None]
        elif j.type == "spherical":
            R_WC, p_WC = R_WJ @ pos[j.name], p_WJ
            # child-frame angular velocity coordinates: w_W = R_WC w_C, pivot at p_WC
            S = np.vstack([R_WC, skew(p_WC) @ R_WC])
        elif j.type == "fixed":
            R_WC, p_WC, S = R_WJ, p_WJ, np.zeros((6, 0))
        else:
            raise ValueError(f"joint {j.name!r}: unknown type {j.type!r}")
        c = j.child
        kin.R[c], kin.p[c], kin.S[j.name] = R_WC, p_WC, S
        J = kin.J[j.parent].copy()
        vj = np.zeros(6)
        aj = np.zeros(6)
        if S.shape[1]:
            J[:, sl[j.name]] = S
            vj = S @ qd[sl[j.name]]
            aj = S @ qdd[sl[j.name]]
        kin.J[c] = J
        kin.V[c] = kin.V[j.parent] + vj
        kin.A[c] = kin.A[j.parent] + aj + _crm(kin.V[c]) @ vj
    return kin


def body_poses(scene, q) -> dict:
    """``body name -> (R_WB, p_WB)`` for every body, plus ``'world'`` (identity)."""
    kin = _kinematics(scene, q)
    return {b: (kin.R[b], kin.p[b]) for b in kin.R}


def _frame_on(scene, kin: _Kinematics, name: str):
    """(body, R_WF, p_WF) of a named frame; ``'world'`` is the world origin frame."""
    if name == WORLD:
        return WORLD, np.eye(3), np.zeros(3)
    fr = scene.frames[name]
    r_bf, p_bf = _pose(scene, fr.pose)
    R, p = kin.R[fr.body], kin.p[fr.body]
    return fr.body, R @ r_bf, p + R @ p_bf


def frame_pose(scene, q, frame_name: str) -> tuple[np.ndarray, np.ndarray]:
    """``(R_WF, p_WF)`` of a named frame."""
    _, R, p = _frame_on(scene, _kinematics(scene, q), frame_name)
    return R, p


def _to_frame(R_WF: np.ndarray, p_WF: np.ndarray) -> np.ndarray:
    """6x6 map: world spatial ``[w; v_O]`` -> twist ``[v; w]`` at F's origin in F's axes."""
    out = np.zeros((6, 6))
    out[:3, :3] = -R_WF.T @ skew(p_WF)
    out[:3, 3:] = R_WF.T
    out[3:, :3] = R_WF.T
    return out


def _relative_twist_rate(R_WF, p_WF, Va, Aa, Vb, Ab):
    """Twist of body a relative to body b at frame F (fixed to a), in F's axes, and the time
    derivative of those F-axes coordinates, from world spatial velocities/accelerations.

    With ``u = dv_O + dw x p_F`` (relative point velocity at F's origin) and ``R = R_WF``:
    ``X = [R^T u; R^T dw]``, ``dR^T/dt = -R^T skew(w_a)``, ``dp_F/dt = v_aO + w_a x p_F``.
    """
    dV, dA = Va - Vb, Aa - Ab
    dw, dvO, dal, daO = dV[:3], dV[3:], dA[:3], dA[3:]
    wa = Va[:3]
    pdot = Va[3:] + np.cross(wa, p_WF)
    u = dvO + np.cross(dw, p_WF)
    X = np.concatenate([R_WF.T @ u, R_WF.T @ dw])
    udot = daO + np.cross(dal, p_WF) + np.cross(dw, pdot)
    Xdot = np.concatenate([R_WF.T @ (udot - np.cross(wa, u)), R_WF.T @ (dal - np.cross(wa, dw))])
    return X, Xdot


def _select(components) -> list:
    return [_COMPONENT_INDEX[c] for c in components]


def frame_jacobian(scene, q, frame_name: str) -> np.ndarray:
    """6 x n map ``qd -> [v; w]`` of the frame, in its own axes (v = velocity of its origin)."""
    kin = _kinematics(scene, q)
    body, R, p = _frame_on(scene, kin, frame_name)
    return _to_frame(R, p) @ kin.J[body]


# ----------------------------------------------------------------------------- dynamics
def _bodies_inertia(scene, kin: _Kinematics) -> dict:
    """body -> world spatial inertia (about the world origin)."""
    out = {}
    for name, b in scene.bodies.items():
        R, p = kin.R[name], kin.p[name]
        com_w = p + R @ _vec(scene, b.com)
        out[name] = _spatial_inertia(_f(scene, b.mass), com_w, R @ _mat(scene, b.inertia) @ R.T)
    return out


def _friction(scene, qd: np.ndarray) -> np.ndarray:
    """Friction term of ``h``: ``+b qd + c sign(qd)`` (``c w/|w|`` for a spherical joint)."""
    out = np.zeros_like(qd)
    for name, s in coordinate_slices(scene).items():
        j = scene.joints[name]
        b, c = _f(scene, j.viscous), _f(scene, j.coulomb)
        w = qd[s]
        out[s] += b * w
        norm = np.linalg.norm(w)
        if c and norm > 0:
            out[s] += c * (np.sign(w) if w.size == 1 else w / norm)
    return out


def inverse_dynamics(scene, q, qd_all, qdd_all) -> np.ndarray:
    """``M qdd + h`` by the recursive Newton-Euler algorithm (world spatial vectors), including
    gravity, rotor inertia and friction."""
    qd, qdd = np.asarray(qd_all, float), np.asarray(qdd_all, float)
    kin = _kinematics(scene, q, qd, qdd, gravity=True)
    inertia = _bodies_inertia(scene, kin)
    force = {b: inertia[b] @ kin.A[b] + _crf(kin.V[b]) @ inertia[b] @ kin.V[b] for b in inertia}
    tau = np.zeros(len(qd))
    sl = coordinate_slices(scene)
    for j in reversed(_tree_order(scene)):
        f = force.get(j.child, np.zeros(6))
        if j.name in sl:
            tau[sl[j.name]] = kin.S[j.name].T @ f
        if j.parent != WORLD:
            force[j.parent] = force.get(j.parent, np.zeros(6)) + f
    return tau + _rotor_diagonal(scene) * qdd + _friction(scene, qd)


def _rotor_diagonal(scene) -> np.ndarray:
    d = np.zeros(_n_coords(scene))
    for name, s in coordinate_slices(scene).items():
        d[s] += _f(scene, scene.joints[name].rotor_inertia)
    return d


def mass_matrix(scene, q) -> np.ndarray:
    """``M = sum_i J_i^T I_i J_i + diag(rotor inertia)`` (n x n)."""
    kin = _kinematics(scene, q)
    inertia = _bodies_inertia(scene, kin)
    M = np.diag(_rotor_diagonal(scene))
    for b, inertia_b in inertia.items():
        M += kin.J[b].T @ inertia_b @ kin.J[b]
    return M


def joint_space(scene, q, qd_all) -> tuple[np.ndarray, np.ndarray]:
    """Tree model without constraints: ``(M, h)``, ``M qdd + h = tau``."""
    qd = np.asarray(qd_all, dtype=float)
    return mass_matrix(scene, q), inverse_dynamics(scene, q, qd, np.zeros(len(qd)))


def kinetic_energy(scene, q, qd_all) -> float:
    """Kinetic energy from body-frame quantities: ``m|v_c|^2/2 + w^T I_c w/2`` per body, plus
    ``I_rotor qd^2 / 2`` per 1-DOF joint (a path independent of ``M``)."""
    qd = np.asarray(qd_all, dtype=float)
    kin = _kinematics(scene, q, qd)
    ke = 0.5 * float(qd @ (_rotor_diagonal(scene) * qd))
    for name, b in scene.bodies.items():
        R, p, V = kin.R[name], kin.p[name], kin.V[name]
        w = V[:3]
        v_com = V[3:] + np.cross(w, p + R @ _vec(scene, b.com))
        w_b = R.T @ w
        ke += 0.5 * _f(scene, b.mass) * v_com @ v_com + 0.5 * w_b @ _mat(scene, b.inertia) @ w_b
    return float(ke)


def potential_energy(scene, q) -> float:
    """Gravitational potential ``-sum m_i g . c_i`` (zero at the world origin)."""
    poses = body_poses(scene, q)
    g = _vec(scene, scene.gravity)
    return float(-sum(_f(scene, b.mass) * g @ (poses[n][1] + poses[n][0] @ _vec(scene, b.com))
                      for n, b in scene.bodies.items()))


# ----------------------------------------------------------------------------- constraints, task
def constraint_rows(scene, q, qd_all) -> tuple[np.ndarray, np.ndarray]:
    """``(K, kbias)``: ``K qd = 0`` and ``K qdd + kbias = 0``, one row per constraint component.

    Row ``k`` is the listed component of the twist of body a relative to body b, taken at frame
    A's origin in A's axes; ``kbias = dK/dt qd`` is the time derivative of those A-axes
    coordinates at ``qdd = 0``.
    """
    qd = np.asarray(qd_all, dtype=float)
    kin = _kinematics(scene, q, qd)
    rows, bias = [], []
    for c in scene.constraints.values():
        body_a, R_A, p_A = _frame_on(scene, kin, c.frame_a)
        body_b, _, _ = _frame_on(scene, kin, c.frame_b)
        idx = _select(c.components)
        rows.append((_to_frame(R_A, p_A) @ (kin.J[body_a] - kin.J[body_b]))[idx])
        _, Xdot = _relative_twist_rate(R_A, p_A, kin.V[body_a], kin.A[body_a],
                                       kin.V[body_b], kin.A[body_b])
        bias.append(Xdot[idx])
    n = len(qd)
    if not rows:
        return np.zeros((0, n)), np.zeros(0)
    return np.vstack(rows), np.concatenate(bias)


def constraint_residual(scene, q) -> np.ndarray:
    """Position-level error per constraint: components of ``[^A p_B; rotvec(^A R_B)]``."""
    kin = _kinematics(scene, q)
    out = []
    for c in scene.constraints.values():
        _, R_A, p_A = _frame_on(scene, kin, c.frame_a)
        _, R_B, p_B = _frame_on(scene, kin, c.frame_b)
        err = np.concatenate([R_A.T @ (p_B - p_A), rotation_vector(R_A.T @ R_B)])
        out.append(err[_select(c.components)])
    return np.concatenate(out) if out else np.zeros(0)


def contact_map(scene, q) -> np.ndarray:
    """``D_m``: the contact frame's twist components (its own axes) as rows over ``qd``."""
    cf = scene.contact_forces
    return frame_jacobian(scene, q, cf.frame)[_select(cf.components)]


def kkt(scene, q, qd_all, tau_all, eta_m=None) -> tuple[np.ndarray, np.ndarray]:
    """Forward dynamics with constraints: solve ::

        [ M  -K^T ] [qdd]   [tau + Q_c - h]
        [ K    0  ] [lam] = [   -kbias    ]

    ``lam`` is the constraint wrench on body a: the listed components of ``[f; m]`` at A's
    origin in A's axes (body b receives the opposite). Redundant constraints: least squares.
    """
    qd = np.asarray(qd_all, dtype=float)
    M, h = joint_space(scene, q, qd)
    K, kbias = constraint_rows(scene, q, qd)
    rhs_q = np.asarray(tau_all, dtype=float) - h
    if eta_m is not None:
        if scene.contact_forces is None:
            raise ValueError("eta_m given but the scene declares no contact_forces")
        rhs_q = rhs_q - contact_map(scene, q).T @ np.asarray(eta_m, dtype=float)
    n, nc = M.shape[0], K.shape[0]
    A = np.block([[M, -K.T], [K, np.zeros((nc, nc))]])
    b = np.concatenate([rhs_q, -kbias])
    try:
        x = np.linalg.solve(A, b)
    except np.linalg.LinAlgError:
        x = np.linalg.lstsq(A, b, rcond=None)[0]
    return x[:n], x[n:]


def _task_terms(scene, q, qd, qdd):
    """``(V_m, Vdot_m)`` of ``scene.motion``."""
    mo = scene.motion
    sl = coordinate_slices(scene)
    if mo.joints:
        idx = [sl[j].start for j in mo.joints]
        return qd[idx], qdd[idx]
    kin = _kinematics(scene, q, qd, qdd)
    idx = _select(mo.components)
    V, Vdot = np.zeros(len(idx)), np.zeros(len(idx))
    for name, gamma in mo.frames:
        body, R, p = _frame_on(scene, kin, name)
        X, Xdot = _relative_twist_rate(R, p, kin.V[body], kin.A[body], np.zeros(6), np.zeros(6))
        V += _f(scene, gamma) * X[idx]
        Vdot += _f(scene, gamma) * Xdot[idx]
    return V, Vdot


def task_velocity(scene, q, qd_all) -> np.ndarray:
    """``V_m = sum_i gamma_i S X_i`` (or the chosen joint rates)."""
    qd = np.asarray(qd_all, dtype=float)
    return _task_terms(scene, q, qd, np.zeros(len(qd)))[0]


def task_acceleration(scene, q, qd_all, qdd_all) -> np.ndarray:
    """``dV_m/dt`` (derivative of the frames' own-axes coordinates)."""
    return _task_terms(scene, q, np.asarray(qd_all, float), np.asarray(qdd_all, float))[1]
