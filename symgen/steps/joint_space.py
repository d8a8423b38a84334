"""Step 8: the general joint space A -- ``qd = [qd_a; qd_u2]`` (eq. 14) -- and how the rates and
accelerations of every joint follow from it through the constraints (eqs. 10-11).

``P`` (``N_all x n``) completes ``qd`` to the rates of all joint coordinates: the rows of the
independent coordinates are the identity, the rows of ``q_u1`` are eq. (10),
``qd_u1 = -T11 qd_a2 - T12 qd_u2``. ``P^T`` maps joint forces back onto ``qd``.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..math.jet import Jet, identity, matmul, scatter
from ..math.scalar import FieldVector
from .constraints import ConstraintBlocks, ConstraintMatrix
from .structure import Partition

if TYPE_CHECKING:
    from ..math.fields import Field


@dataclass(frozen=True)
class RateMap:
    """Step 8: ``qd_all = P qd`` (eqs. 10 and 14), ``P`` of shape ``N_all x n``."""

    P: Jet


def rate_map(field: Field, blocks: ConstraintBlocks, partition: Partition) -> RateMap:
    """Step 8: ``P`` from the blocks of eq. (9) -- identity rows for ``qd`` (eq. 14), and
    ``-[T11, T12]`` on the columns of ``q_a2, q_u2`` for the rows of ``q_u1`` (eq. 10)."""
    n = len(partition.independent)
    n_all = n + len(partition.u1)
    p_u1 = -Jet(np.hstack([blocks.T11.v, blocks.T12.v]), np.hstack([blocks.T11.d, blocks.T12.d]))
    return RateMap(scatter(field, (n_all, n), [
        (partition.independent, range(n), identity(field, n)),
        (partition.u1, partition.independent_columns, p_u1)]))


def all_rates(rates: RateMap, qd: FieldVector) -> np.ndarray:
    """Eq. (10): the rates of every joint coordinate, ``qd_all = P qd``."""
    return matmul(rates.P.v, np.asarray(qd, dtype=rates.P.v.dtype))


def rate_bias(field: Field, cm: ConstraintMatrix, blocks: ConstraintBlocks, partition: Partition,
              qd_all: FieldVector) -> np.ndarray:
    """``dP/dt qd``: the accelerations of all joint coordinates at ``qdd = 0``.

    Differentiating the constraints ``T qd_all = 0`` (eq. 6) gives ``T qdd_all = -dT/dt qd_all``;
    with eq. (9)'s partition the ``q_u1`` rows are ``-W^-1 dT/dt qd_all`` (eq. 11 differentiated)
    and all other rows are zero. ``cm`` must carry derivatives along ``qd_all``. One solve with
    ``W``, a vector right-hand side (:func:`rate_bias_of_drift`)."""
    if not partition.u1:
        return rate_bias_of_drift(field, [], blocks, partition)
    return rate_bias_of_drift(field, cm.T.d @ np.asarray(qd_all, dtype=field.dtype), blocks, partition)


def rate_bias_of_drift(field: Field, drift: FieldVector, blocks: ConstraintBlocks,
                       partition: Partition) -> np.ndarray:
    """``dP/dt qd`` of :func:`rate_bias` from the constraints' drift ``dT/dt qd_all`` (one entry
    per row of ``T``), however it was computed (the code generator's outward recursion,
    :func:`symgen.dynamics.twists.constraint_drift`, or the jets of ``T``)."""
    n_all = len(partition.independent) + len(partition.u1)
    bias = field.zeros((n_all,))
    if partition.u1:
        y = field.solve(blocks.W.v, np.asarray(drift, dtype=field.dtype), "[T_u1, T_a1] (eq. 9)")
        for i, coord in enumerate(partition.u1):
            bias[coord] = -y[i]
    return bias


def all_accelerations(rates: RateMap, qdd: FieldVector, bias: np.ndarray) -> np.ndarray:
    """Eq. (11) differentiated: ``qdd_all = P qdd + dP/dt qd`` with ``bias = dP/dt qd``."""
    qdd_all: np.ndarray = matmul(rates.P.v, np.asarray(qdd, dtype=rates.P.v.dtype)) + bias
    return qdd_all


def project(rates: RateMap, tau_all: FieldVector) -> np.ndarray:
    """``P^T tau_all``: forces on every joint coordinate mapped onto ``qd`` (power: ``qd_all^T
    tau_all = qd^T P^T tau_all``)."""
    return matmul(rates.P.v.T, np.asarray(tau_all, dtype=rates.P.v.dtype))


def rates_by_solve(field: Field, cm: ConstraintMatrix, blocks: ConstraintBlocks, partition: Partition,
                   qd: FieldVector, bias: FieldVector | None = None, drift: FieldVector | None = None) -> np.ndarray:
    """Eq. (10) for one vector, without forming ``P``: ``qd_u1 = -(W^-1 [T_a2, T_u2] qd_(a2,u2))``
    restricted to its ``n_p`` rows, the other rows of ``qd_all`` being ``qd`` itself (eq. 14);
    ``bias`` (``dP/dt qd``, :func:`rate_bias`) is added, which makes it eq. (11) differentiated
    for ``qd = qdd``. One solve with ``W`` and a vector right-hand side, where ``P qd`` needs
    ``n - n_a1`` of them to form ``P`` first: what generated code does for joint-space functions.
    ``drift`` (``dT/dt qd_all``, one entry per row of ``T``) joins the right-hand side instead:
    eq. (11) differentiated, ``qdd_u1 = -W^-1 ([T_a2, T_u2] qdd + dT/dt qd_all)``, in the same
    one solve, where ``bias`` takes a solve of its own (:func:`rate_bias_of_drift`)."""
    n_all = len(partition.independent) + len(partition.u1)
    qd_v: np.ndarray = np.asarray(qd, dtype=field.dtype)
    out = field.zeros((n_all,)) if bias is None else np.array(bias, dtype=field.dtype)
    for i, coord in enumerate(partition.independent):
        out[coord] = out[coord] + qd_v[i]
    if partition.u1:
        b = cm.columns(partition.a2 + partition.u2).v
        rhs = b @ qd_v[list(partition.independent_columns)]
        if drift is not None:
            rhs = rhs + np.asarray(drift, dtype=field.dtype)
        y = field.solve(blocks.W.v, rhs, "[T_u1, T_a1] (eq. 9)")
        for i, coord in enumerate(partition.u1):
            out[coord] = out[coord] - y[i]
    return out


def project_by_solve(field: Field, cm: ConstraintMatrix, blocks: ConstraintBlocks, partition: Partition,
                     tau_all: FieldVector) -> np.ndarray:
    """``P^T tau_all`` without forming ``P``: the independent coordinates' own entries, and
    ``-[T_a2, T_u2]^T W^-T [tau_u1; 0]`` on the columns of ``q_a2, q_u2`` (the transpose of
    :func:`rates_by_solve`; one transposed solve with ``W``)."""
    tau_v: np.ndarray = np.asarray(tau_all, dtype=field.dtype)
    out: np.ndarray = np.array([tau_v[c] for c in partition.independent], dtype=field.dtype)
    if partition.u1:
        nc = blocks.W.v.shape[0]
        rhs = field.zeros((nc,))
        for i, coord in enumerate(partition.u1):
            rhs[i] = tau_v[coord]
        z = field.solve(blocks.W.v.T, rhs, "[T_u1, T_a1]^T (eq. 9)")
        back = cm.columns(partition.a2 + partition.u2).v.T @ z
        for k, col in enumerate(partition.independent_columns):
            out[col] = out[col] - back[k]
    return out
