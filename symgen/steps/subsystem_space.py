"""Steps 11 and 12: the extended subsystem space S, the velocity map ``T_S`` (eq. 25), the
subsystem dynamics ``M_S, C_S, G_S`` (eqs. 21-24) and model (32) in the general task space O.

    M = B^T M_S B,   C = B^T M_S dB/dt + B^T C_S B,   G = B^T G_S + A^-T D_m^T eta_m      (32)

with ``B = T_S [J_m; J_f]^-1`` and ``A = [J_m; J_f]``; the joint-space form is the same with
``B = T_S``. ``M_S`` is constant and ``C_S`` skew, which is why ``1/2 dM/dt - C`` is skew
(Remark 2.7).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..math.jet import Jet, matmul, vstack
from ..math.scalar import FieldVector
from ..kinematics import TreeKinematics
from ..subsystems import (SubsystemSpace, assemble_coriolis, assemble_gravity, assemble_mass,
                          subsystem_space)
from .task_space import ContactMap, InverseTaskMap

if TYPE_CHECKING:
    from ..math.fields import Field


@dataclass(frozen=True)
class VelocityMap:
    """Step 11: ``X = T_S qd`` (eq. 25) -- joint rates first (``P``), then the twist of every
    massive body in its own frame (``J_b P``: the rows of ``T_S*`` in Section 3.2)."""

    T_S: Jet
    space: SubsystemSpace


@dataclass(frozen=True)
class SubsystemTerms:
    """Step 12: the block-diagonal ``M_S``, ``C_S`` and the vector ``G_S`` of eq. (24) at the
    velocity ``X`` in S."""

    M_S: np.ndarray
    C_S: np.ndarray
    G_S: np.ndarray
    #: the diagonal blocks of ``M_S`` and ``C_S`` (the joint rows, then each body's 6), so that
    #: products skip the zeros between them; empty: treat them as dense
    blocks: tuple[slice, ...] = ()


@dataclass(frozen=True)
class DynamicModel:
    """``M``, ``C``, ``G`` of a model ``M dv + C v + G``: eq. (32) in space O, or the joint-space
    form in space A."""

    M: np.ndarray
    C: np.ndarray
    G: np.ndarray


def velocity_map(field: Field, kin: TreeKinematics, p: Jet) -> VelocityMap:
    """Step 11, eq. (25): ``T_S = [P; J_b P for each massive body b]``."""
    space = subsystem_space(kin.tree)
    body_rows = [kin.jacobian[b] @ p for b in space.bodies]
    return VelocityMap(vstack([p] + body_rows, p.shape[1], field), space)


def subsystem_terms(field: Field, kin: TreeKinematics, space: SubsystemSpace, x: np.ndarray, *,
                    gravity: bool = True) -> SubsystemTerms:
    """Step 12, eqs. (21)-(24): ``M_S = diag(I*_j, 0, M_alpha)``, ``C_S = diag(0, 0, C_alpha)``
    and ``G_S = [xi_1j; xi_3i; G_alpha]`` at the S velocity ``x`` (friction and gravity)."""
    tree, const = kin.tree, kin.const
    m_s = assemble_mass(space, tree, const, field)
    c_s = assemble_coriolis(space, const, x, field)
    g_s = assemble_gravity(space, tree, const, kin.rot, x, m_s, field, gravity, kin.positions)
    blocks = (slice(0, space.n_coords),) + tuple(space.body_rows(k) for k in range(len(space.bodies)))
    return SubsystemTerms(m_s, c_s, g_s, blocks)


#: below this many columns a symmetric product is taken whole (:func:`_symmetric_product`)
_SYMMETRIC_SPLIT = 16


def _symmetric_product(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """``x^T y`` known to be symmetric, object entries: the columns halved, the two diagonal
    blocks by recursion, the upper off-diagonal block by one product and the lower one its
    mirror -- about half the dot products of the whole ``x^T y`` on many columns."""
    c = x.shape[1]
    if c < _SYMMETRIC_SPLIT:
        return matmul(x.T, y)
    h = c // 2
    upper = matmul(x[:, :h].T, y[:, h:])
    return np.block([[_symmetric_product(x[:, :h], y[:, :h]), upper],
                     [upper.T, _symmetric_product(x[:, h:], y[:, h:])]])


def _quadratic(mat: np.ndarray, left: np.ndarray, right: np.ndarray, blocks: tuple[slice, ...], *,
               mirror: bool = False) -> np.ndarray:
    """``left^T mat right`` for a block-diagonal ``mat`` with diagonal ``blocks`` (dense without
    them): the cost is that of the blocks, not of the whole ``n_S x n_S`` matrix (a robot with 40
    bodies has ``n_S`` near 300). ``mirror`` (``left`` is ``right``, ``mat`` symmetric, a field
    that rounds): each body's ``x^T (mat x)`` by :func:`_symmetric_product`, whose left-out
    entries are the same sums in another order -- the result differs from the whole product in
    the last digit at most."""
    if not blocks:
        out: np.ndarray = left.T @ mat @ right
        return out
    if left.dtype != object:
        total: np.ndarray = left[blocks[0]].T @ (mat[blocks[0], blocks[0]] @ right[blocks[0]])
        for rows in blocks[1:]:
            total = total + left[rows].T @ (mat[rows, rows] @ right[rows])
        return total
    # exact, multi-digit and symbolic fields: the joint block (the rotors' inertias, eq. 21) is
    # mostly zero -- its zero rows and columns are left out (at least one kept, so every entry is
    # a product of field elements); a body's rows of a velocity map are zero in every column
    # its joints do not move (a quarter of the entries are non-zero on a humanoid), so each block
    # only adds to the columns where its rows have entries (exact zeros skipped, no rounding)
    joint = mat[blocks[0], blocks[0]]
    used_r = np.flatnonzero((joint != 0).any(axis=1)) if joint.size else np.arange(0)
    used_c = np.flatnonzero((joint != 0).any(axis=0)) if joint.size else np.arange(0)
    if not used_r.size:
        used_r = used_c = np.arange(min(1, joint.shape[0]))
    start = blocks[0].start or 0
    total = matmul(left[start + used_r].T, matmul(joint[np.ix_(used_r, used_c)], right[start + used_c]))
    for rows in blocks[1:]:
        cols_l = np.flatnonzero((left[rows] != 0).any(axis=0))
        cols_r = cols_l if mirror else np.flatnonzero((right[rows] != 0).any(axis=0))
        if cols_l.size and cols_r.size:
            x, y = left[rows][:, cols_l], matmul(mat[rows, rows], right[rows][:, cols_r])
            total[np.ix_(cols_l, cols_r)] += _symmetric_product(x, y) if mirror else matmul(x.T, y)
    return total


def mass_congruence(terms: SubsystemTerms, b: np.ndarray, *, rounds: bool = False) -> np.ndarray:
    """``B^T M_S B``: the ``M`` of eq. (32) for ``B = T_S [J_m; J_f]^-1``, ``M_q`` for ``B = T_S``.
    ``rounds``: the field's arithmetic rounds (:attr:`~symgen.math.fields.Field.rounds`), so each
    body's product may be taken on one triangle of column blocks and mirrored (:func:`_quadratic`);
    an exact or symbolic field forms it whole, so the proofs check that ``M`` is symmetric."""
    return _quadratic(terms.M_S, b, b, terms.blocks, mirror=rounds)


def coriolis_congruence(terms: SubsystemTerms, b: Jet) -> np.ndarray:
    """``B^T M_S dB/dt + B^T C_S B``: the ``C`` of eq. (32) (``C_q`` for ``B = T_S``)."""
    blocks = terms.blocks
    out: np.ndarray = _quadratic(terms.M_S, b.v, b.d, blocks) + _quadratic(terms.C_S, b.v, b.v, blocks)
    return out


def congruence(terms: SubsystemTerms, b: Jet) -> DynamicModel:
    """``B^T M_S B``, ``B^T M_S dB/dt + B^T C_S B`` and ``B^T G_S``: the subsystem dynamics seen
    through the velocity map ``B`` (eqs. 28-31: power is invariant, ``X^T F = v^T B^T F``)."""
    return DynamicModel(mass_congruence(terms, b.v), coriolis_congruence(terms, b), b.v.T @ terms.G_S)


def _block_apply(mat: np.ndarray, x: np.ndarray, blocks: tuple[slice, ...]) -> np.ndarray:
    """``mat @ x`` for a block-diagonal ``mat`` with diagonal ``blocks`` (dense without them)."""
    if not blocks:
        out: np.ndarray = mat @ x
        return out
    return np.concatenate([mat[rows, rows] @ x[rows] for rows in blocks])


def velocity_product(terms: SubsystemTerms, b: Jet, v: np.ndarray) -> np.ndarray:
    """``C v = B^T (M_S dB/dt v + C_S B v)`` by products of vectors, without forming ``C``:
    ``O(n_S n)`` where the congruence costs ``O(n_S n^2)``. ``C_S`` is the one of ``terms``."""
    force = _block_apply(terms.M_S, matmul(b.d, v), terms.blocks) + _block_apply(terms.C_S, matmul(b.v, v), terms.blocks)
    return matmul(b.v.T, force)


def joint_force(terms: SubsystemTerms, t_s: Jet, qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
    """``M_q qdd + C_q qd + G_q`` of the joint-space form by products of vectors, without a
    matrix: ``T_S^T (M_S (T_S qdd + dT_S/dt qd) + C_S T_S qd + G_S)`` (eqs. 28-31 with
    ``B = T_S``), ``O(n_S n)``. ``C_S`` must be the one at ``X = T_S qd``."""
    inertial = _block_apply(terms.M_S, matmul(t_s.v, qdd), terms.blocks) + terms.G_S
    out: np.ndarray = matmul(t_s.v.T, inertial) + velocity_product(terms, t_s, qd)
    return out


def task_gravity(terms: SubsystemTerms, b: Jet, inverse: InverseTaskMap, contact: ContactMap,
                 eta_m: FieldVector) -> np.ndarray:
    """``G`` of eq. (32): ``B^T G_S + A^-T D_m^T eta_m`` (the contact forces ``eta_m``)."""
    out: np.ndarray = b.v.T @ terms.G_S + inverse.A_inv.v.T @ (contact.D_m.v.T @ eta_m)
    return out


def task_space_model(terms: SubsystemTerms, vmap: VelocityMap, inverse: InverseTaskMap,
                     contact: ContactMap, eta_m: FieldVector) -> tuple[DynamicModel, Jet]:
    """Model (32) with ``B = T_S [J_m; J_f]^-1``, and ``B`` (with ``dB/dt``). The contact forces
    enter ``G`` as ``A^-T D_m^T eta_m``."""
    b = vmap.T_S @ inverse.A_inv
    return DynamicModel(mass_congruence(terms, b.v), coriolis_congruence(terms, b),
                        task_gravity(terms, b, inverse, contact, eta_m)), b


def joint_space_model(terms: SubsystemTerms, vmap: VelocityMap) -> DynamicModel:
    """The joint-space form ``M_q qdd + C_q qd + G_q = tau - J_f^T eta_f - D_m^T eta_m``
    (eqs. 30-31 with (24)-(25)): ``B = T_S``."""
    return congruence(terms, vmap.T_S)
