"""The twelve steps of Section 3.1, as functions a user can call and inspect.

Structural steps (1, 2, 4's rank, 5's partition, 8's dimensions) are decided once, at the scene's
reference configuration, in floating point with column pivoting and an explicit rank tolerance,
then checked (the chosen ``[T_u1, T_a1]`` must be well conditioned). The per-configuration steps
(the matrices of Steps 4-11) are computed by :func:`evaluate_maps` in any field, as jets.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

from .errors import ConstraintError, SingularConfigurationError
from .jet import Jet, hstack, solve, vstack
from .kinematics import constraint_matrix, tree_kinematics
from .spatial import COMPONENTS
from .subsystems import subsystem_space

#: singular values below RANK_TOL * (largest) count as zero in Step 4
RANK_TOL = 1e-9
#: the partition matrix [T_u1, T_a1] must have a smaller condition number
MAX_PARTITION_CONDITION = 1e10


@dataclass(frozen=True)
class Counts:
    """Steps 1, 2, 4 and 8: joint counts, motion DOF ``m``, constraints ``n_c`` (eq. 5),
    ``n_p = rank T_u`` and the dimension ``n`` of spaces A and O (eq. 13)."""

    n1a: int
    n1u: int
    n3a: int
    n3u: int
    m: int
    nc: int
    np: int
    n: int

    def as_dict(self) -> dict[str, int]:
        return {k: getattr(self, k) for k in ("n1a", "n1u", "n3a", "n3u", "m", "nc", "np", "n")}


@dataclass(frozen=True)
class Partition:
    """Step 5: all-coordinate indices of ``q_u1, q_u2, q_a1, q_a2`` such that ``[T_u1, T_a1]``
    is invertible (eq. 8). ``q`` of eq. (14) is ``[q_a; q_u2]`` with ``q_a`` in scene order."""

    u1: tuple[int, ...]
    u2: tuple[int, ...]
    a1: tuple[int, ...]
    a2: tuple[int, ...]
    actuated: tuple[int, ...]

    @property
    def independent(self) -> tuple[int, ...]:
        """All-coordinate indices of the entries of ``qd`` (eq. 14), in order."""
        return self.actuated + self.u2

    def column(self, coord: int) -> int:
        """Position of all-coordinate ``coord`` in ``qd``."""
        return self.independent.index(coord)


def count_joints(tree) -> tuple[int, int, int, int]:
    """Step 1: ``n1a, n1u, n3a, n3u``."""
    n1a = sum(1 for j in tree.joints if j.type in ("revolute", "prismatic") and j.actuated)
    n1u = sum(1 for j in tree.joints if j.type in ("revolute", "prismatic") and not j.actuated)
    n3a = sum(1 for j in tree.joints if j.type == "spherical" and j.actuated)
    n3u = sum(1 for j in tree.joints if j.type == "spherical" and not j.actuated)
    return n1a, n1u, n3a, n3u


def _rank(a: np.ndarray) -> int:
    if a.size == 0:
        return 0
    s = np.linalg.svd(a, compute_uv=False)
    return int(np.sum(s > RANK_TOL * max(s[0], 1e-300)))


def check_full_row_rank(t: np.ndarray, constraints) -> None:
    """``T`` must have full row rank (eq. 6); otherwise name the first redundant constraint."""
    rows = 0
    for con in constraints:
        block = t[: rows + con.dim]
        if _rank(block) < rows + con.dim:
            raise ConstraintError(
                f"constraint {con.name!r}",
                f"its rows are linearly dependent on the previous constraints at the reference "
                f"configuration (rank {_rank(block)} < {rows + con.dim}): the constraints are "
                "redundant; remove the components the mechanism already enforces (e.g. use "
                "planar_weld instead of weld for a planar loop)")
        rows += con.dim


def choose_partition(t: np.ndarray, tree) -> Partition:
    """Steps 4-5: ``n_p = rank T_u``; ``T_u1`` by column-pivoted QR of ``T_u``; ``T_a1`` by
    column-pivoted QR of ``T_a`` projected off the range of ``T_u1``. Returns the partition."""
    coords = tree.coordinates
    act = tuple(i for i, c in enumerate(coords) if c.actuated)
    una = tuple(i for i, c in enumerate(coords) if not c.actuated)
    nc = t.shape[0]
    if nc == 0:
        return Partition((), una, (), act, act)
    t_u, t_a = t[:, list(una)], t[:, list(act)]
    n_p = _rank(t_u)
    u1: tuple[int, ...] = ()
    q = np.zeros((nc, 0))
    if n_p:
        _, _, piv = scipy.linalg.qr(t_u, pivoting=True, mode="economic")
        u1 = tuple(sorted(una[k] for k in piv[:n_p]))
        q, _ = np.linalg.qr(t[:, list(u1)])
    rest = nc - n_p
    a1: tuple[int, ...] = ()
    if rest:
        projected = t_a - q @ (q.T @ t_a)
        if _rank(projected) < rest:
            raise ConstraintError("constraints", f"the actuated joints cannot take the remaining {rest} "
                                                 "constraint dimensions: [T_u1, T_a1] cannot be invertible (eq. 8)")
        _, _, piv = scipy.linalg.qr(projected, pivoting=True, mode="economic")
        a1 = tuple(sorted(act[k] for k in piv[:rest]))
    w = t[:, list(u1) + list(a1)]
    cond = np.linalg.cond(w)
    if not np.isfinite(cond) or cond > MAX_PARTITION_CONDITION:
        raise SingularConfigurationError("[T_u1, T_a1] at the reference configuration", float(cond),
                                         "move the reference configuration away from the singularity")
    return Partition(u1, tuple(i for i in una if i not in u1), a1,
                     tuple(i for i in act if i not in a1), act)


def counts_from(tree, partition: Partition, nc: int) -> Counts:
    n1a, n1u, n3a, n3u = count_joints(tree)
    total = n1a + n1u + 3 * (n3a + n3u)
    n_p = len(partition.u1)
    return Counts(n1a, n1u, n3a, n3u, total - nc, nc, n_p, total - n_p)


# ---------------------------------------------------------------------------- per-state maps
@dataclass
class Maps:
    """Every kinematic quantity of Steps 4-11 at one configuration (jets)."""

    kin: object
    T: Jet          # eq. (6), n_c x N_all (columns in all-coordinate order)
    T_a: Jet
    T_u: Jet
    W: Jet          # [T_u1, T_a1]
    T11: Jet
    T12: Jet
    T21: Jet
    T22: Jet        # eq. (9)
    T_c: Jet        # eq. (12)
    J_f: Jet        # eq. (12), (nc - np) x n
    P: Jet          # qd_all = P qd  (eq. 10 for the dependent rows)
    J_m: Jet        # eq. (17)
    D_m: Jet        # eq. (16)
    A: Jet          # [J_m; J_f]
    A_inv: Jet      # [Omega, Psi], eq. (18)
    T_S: Jet        # eq. (25)
    m: int

    @property
    def Omega(self) -> Jet:
        return self.A_inv[:, : self.m]

    @property
    def Psi(self) -> Jet:
        return self.A_inv[:, self.m:]


def _select_rows(jet: Jet, idx) -> Jet:
    return jet[list(idx), :]


def _select_cols(jet: Jet, idx) -> Jet:
    return jet[:, list(idx)]


def evaluate_maps(model, config, field, qd_all=None) -> Maps:
    """Steps 4-11 at ``config`` in ``field``; derivatives along ``qd_all`` when given."""
    tree, part = model.tree, model.partition
    n_all, n, m = tree.n_coords, model.counts.n, model.counts.m
    kin = tree_kinematics(tree, field, config, qd_all)
    t = constraint_matrix(kin, model.scene.constraints.values())
    nc, n_p = t.shape[0], len(part.u1)
    t_a, t_u = _select_cols(t, part.actuated), _select_cols(t, [i for i in range(n_all) if i not in part.actuated])
    w = _select_cols(t, part.u1 + part.a1)
    rhs = hstack([_select_cols(t, part.a2), _select_cols(t, part.u2)], nc, field)
    blocks = solve(field, w, rhs, "[T_u1, T_a1] (eq. 9)")
    na2 = len(part.a2)
    t11, t12 = blocks[:n_p, :na2], blocks[:n_p, na2:]
    t21, t22 = blocks[n_p:, :na2], blocks[n_p:, na2:]

    # P: rows of the independent coordinates are the identity, rows of q_u1 follow eq. (10)
    p = Jet.const(field.zeros((n_all, n)), field)
    for col, coord in enumerate(part.independent):
        p.v[coord, col] = field.one
    for row, coord in enumerate(part.u1):
        for k, a in enumerate(part.a2):
            p.v[coord, part.column(a)] = -t11.v[row, k]
            p.d[coord, part.column(a)] = -t11.d[row, k]
        for k, u in enumerate(part.u2):
            p.v[coord, part.column(u)] = -t12.v[row, k]
            p.d[coord, part.column(u)] = -t12.d[row, k]

    # Step 7: J_f = T_c [1, T21, T22] (columns placed at q_a1, q_a2, q_u2 of qd)
    j_joint = Jet.const(field.zeros((nc - n_p, n)), field)
    for k, a in enumerate(part.a1):
        j_joint.v[k, part.column(a)] = field.one
    for cols, block in ((part.a2, t21), (part.u2, t22)):
        for k, coord in enumerate(cols):
            j_joint.v[:, part.column(coord)] = block.v[:, k]
            j_joint.d[:, part.column(coord)] = block.d[:, k]
    if model.scene.constraint_forces == "operational" and nc > n_p:
        t_c = _select_cols(t, part.a1)          # J_f = T_a1 [1, T21] = T_a  (Sections 3.2-3.3)
    else:
        t_c = Jet.const(field.eye(nc - n_p), field)
    j_f = t_c @ j_joint

    # Step 11: T_S = [P; J_b P for each massive body]
    space = subsystem_space(tree)
    body_rows = [kin.jacobian[b] @ p for b in space.bodies]
    t_s = vstack([p] + body_rows, n, field)

    # Steps 9-10: J_m and D_m
    j_m = _task_map(model.scene.motion, kin, p, part, field)
    d_m = (_frame_components(kin, model.scene.contact_forces.frame, model.scene.contact_forces.components) @ p
           if model.scene.contact_forces is not None else Jet.const(field.zeros((0, n)), field))
    a = vstack([j_m, j_f], n, field)
    a_inv = solve(field, a, Jet.const(field.eye(n), field), "[J_m; J_f] (eq. 18)")
    return Maps(kin, t, t_a, t_u, w, t11, t12, t21, t22, t_c, j_f, p, j_m, d_m, a, a_inv, t_s, m)


def _frame_components(kin, frame: str, components) -> Jet:
    sel = [COMPONENTS.index(c) for c in components]
    return kin.frame_jacobian(frame)[sel, :]


def _task_map(motion, kin, p: Jet, part: Partition, field) -> Jet:
    """``J_m`` of eq. (17): joint-rate rows of ``P``, or ``sum gamma_i T_m J_i`` (Section 3.3)."""
    if motion.joints:
        idx = [next(c for c, co in enumerate(kin.tree.coordinates) if co.joint == j) for j in motion.joints]
        return _select_rows(p, idx)
    total = None
    for frame, gamma in motion.frames:
        term = (_frame_components(kin, frame, motion.components) @ p).scale(field.const(gamma))
        total = term if total is None else total + term
    return total
