"""The forces of the loop-closure constraints, from the joint-space equations with *all* joints.

Model (32) eliminates the ``n_p`` constraints that fall on passive joints (eq. 10): they never
appear in it, and for a passive closed chain (``n_p = n_c``: four-bar, five-bar, Stewart platform)
there is no ``eta_f`` at all. Their forces are nonetheless fixed by the formulation.

Derivation. Take the spanning tree with every joint coordinate free, ``qd_all``. Its velocity map
is eq. (25) with ``P = 1`` (:func:`tree_velocity_map`), and eqs. (28)-(31) on it give the tree's
joint forces ``tau_tree = T_S,all^T (M_S dX + C_S X + G_S)`` (:func:`tree_forces`). Putting the
``n_c`` constraints (6) back, each constraint row ``T_k`` carries a multiplier ``lam_k``::

    tau_tree = tau_all + T^T lam - D_m,all^T eta_m                                          (*)

with ``tau_all`` the applied joint forces (zero on passive joints). ``T_k qd_all`` is component
``k`` of the twist of frame A relative to frame B in A's axes (:func:`symgen.kinematics.constraint_matrix`),
so by power ``T^T lam`` is the generalized force of the wrench ``[f; m]`` with components ``lam``
acting on the body of frame A at A's origin (A's axes) and the opposite wrench on the body of B:
**lam is the force and moment the constraint exerts on frame A's body**, component by component
(``vx, vy, vz`` -> ``f_x, f_y, f_z``; ``wx, wy, wz`` -> ``m_x, m_y, m_z``) -- the multipliers of the
KKT form ``M qdd + h = tau + K^T lam`` with ``K = T``.

Eq. (9) splits (*) by rows. Its ``q_a2, q_u2`` rows, projected with ``P`` (eq. 10), are the
joint-space model: ``P^T T^T = (T P)^T`` and ``T P = T_a1 [0 | 1, T21, T22] = T_a1 T_c^-1 J_f``
(eq. 12), so those rows are ``M_q qdd + C_q qd + G_q = tau - J_f^T eta_f - D_m^T eta_m`` with

    eta_f = -T_c^-T T_a1^T lam          (joint choice T_c = 1: -T_a1^T lam; operational: -lam)

(:func:`general_constraint_forces`). The rows of the dependent coordinates ``q_u1, q_a1`` --
exactly the columns of ``W = [T_u1, T_a1]``, the ``T_c = 1`` choice of eq. (12) extended to all
``n_c`` constraints -- determine ``lam`` alone::

    W^T lam = (tau_tree - tau_all + D_m,all^T eta_m)[q_u1, q_a1]                             (**)

one solve with the matrix of Step 5 (:func:`closure_multipliers`). ``tau_tree`` is one inward
force recursion (``T_S,all^T`` applied), here written with dense matrices.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..math.jet import identity
from ..math.scalar import FieldVector
from ..kinematics import TreeKinematics
from .constraints import ConstraintBlocks, ConstraintMap, ConstraintMatrix
from .structure import Partition
from .subsystem_space import VelocityMap, subsystem_terms, velocity_map

if TYPE_CHECKING:
    from ..math.fields import Field

#: force names of the constraint components (``lam`` component ``k`` is the force along the
#: twist component ``k`` of the constraint; a joint coupling's one component ``q`` has the generalized
#: force ``tau``, in joint units)
FORCE_NAMES = {"vx": "fx", "vy": "fy", "vz": "fz", "wx": "mx", "wy": "my", "wz": "mz", "q": "tau"}


def tree_velocity_map(field: Field, kin: TreeKinematics) -> VelocityMap:
    """Eq. (25) for the spanning tree with every joint coordinate free: ``T_S`` with ``P = 1``."""
    return velocity_map(field, kin, identity(field, kin.tree.n_coords))


def tree_forces(field: Field, kin: TreeKinematics, qd_all: FieldVector, qdd_all: FieldVector, *,
                gravity: bool = True) -> np.ndarray:
    """``tau_tree = T_S,all^T (M_S dX + C_S X + G_S)`` (eqs. 24, 30) with ``X = T_S,all qd_all`` and
    ``dX = T_S,all qdd_all + dT_S,all/dt qd_all``: the joint forces the open tree needs for this
    motion, friction ``xi`` included. ``kin`` must carry derivatives along ``qd_all``."""
    vmap = tree_velocity_map(field, kin)
    qd_v: np.ndarray = np.asarray(qd_all, dtype=field.dtype)
    x = vmap.T_S.v @ qd_v
    dx = vmap.T_S.v @ np.asarray(qdd_all, dtype=field.dtype) + vmap.T_S.d @ qd_v
    terms = subsystem_terms(field, kin, vmap.space, x, gravity=gravity)
    tau_tree: np.ndarray = vmap.T_S.v.T @ (terms.M_S @ dx + terms.C_S @ x + terms.G_S)
    return tau_tree


def closure_multipliers(field: Field, blocks: ConstraintBlocks, partition: Partition,
                        residual_all: FieldVector) -> np.ndarray:
    """Eq. (**) of the module docstring: ``lam`` from ``W^T lam = residual[q_u1, q_a1]`` with
    ``residual = tau_tree - tau_all + D_m,all^T eta_m`` over all joint coordinates."""
    r: np.ndarray = np.asarray(residual_all, dtype=field.dtype)[list(partition.u1 + partition.a1)]
    if not r.size:
        return field.zeros((0,))
    return field.solve(blocks.W.v.T, r, "[T_u1, T_a1]^T (eq. 9)")


def general_constraint_forces(field: Field, cm: ConstraintMatrix, partition: Partition, cmap: ConstraintMap,
                              lam: FieldVector) -> np.ndarray:
    """``eta_f = -T_c^-T T_a1^T lam`` (eq. 12 and the module docstring): the general constraint
    forces of model (32) that the closure forces ``lam`` amount to (empty when ``n_p = n_c``)."""
    t_a1 = cm.columns(partition.a1).v
    y = t_a1.T @ np.asarray(lam, dtype=field.dtype)
    if not y.size:
        return field.zeros((0,))
    eta_f: np.ndarray = -field.solve(cmap.T_c.v.T, y, "T_c^T (eq. 12)")
    return eta_f
