"""Steps 9 and 10: the general task space O -- the dynamic contact forces' map ``D_m`` (eq. 16),
the motion coordinates ``V_m = J_m qd`` (eq. 17) and ``[J_m; J_f]^-1 = [Omega, Psi]`` (eq. 18).

Each map is also returned over *all* joint coordinates (``J_all`` with ``J = J_all P``), the form
in which its acceleration term ``d/dt(J qd) = dJ_all/dt qd_all + J_all dP/dt qd`` is cheapest
(:func:`acceleration_bias`).
"""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..errors import SceneError
from ..math.jet import Jet, identity, solve, vstack
from ..math.scalar import FieldVector
from ..kinematics import TreeKinematics
from ..math.spatial import COMPONENTS
from .constraints import ConstraintMap

if TYPE_CHECKING:
    from ..math.fields import Field
    from ..scene.elements import ContactForces, Motion

#: the name of ``A = [J_m; J_f]`` in the errors of its solves
TASK_MATRIX = "[J_m; J_f] (eq. 18)"


@dataclass(frozen=True)
class ContactMap:
    """Step 9: ``D_m`` of eq. (16) (``D_m^T eta_m`` is the contact forces' effect in A), and the
    same rows over all joint coordinates."""

    D_m: Jet
    D_m_all: Jet


@dataclass(frozen=True)
class TaskMap:
    """Step 10: ``J_m`` of eq. (17), ``V_m = J_m qd``, and the same rows over all joint
    coordinates (``J_m = J_m_all P``)."""

    J_m: Jet
    J_m_all: Jet


@dataclass(frozen=True)
class InverseTaskMap:
    """Step 10: ``A = [J_m; J_f]`` and ``A^-1 = [Omega, Psi]`` of eq. (18)."""

    A: Jet
    A_inv: Jet
    m: int

    @property
    def Omega(self) -> Jet:
        """``n x m``: ``qd = Omega V_m`` (eq. 20)."""
        return self.A_inv[:, : self.m]

    @property
    def Psi(self) -> Jet:
        """``n x (n - m)``: the columns dual to the constraint forces."""
        return self.A_inv[:, self.m:]


def frame_rows(kin: TreeKinematics, frame: str, components: Sequence[str]) -> Jet:
    """The named twist components of ``frame`` (its own axes) over all joint coordinates."""
    return kin.frame_jacobian(frame)[[COMPONENTS.index(c) for c in components], :]


def motion_rows(field: Field, kin: TreeKinematics, motion: Motion | None) -> Jet:
    """``V_m`` over all joint coordinates (eq. 17), the one place ``J_m`` is built: the rows
    ``sum_i gamma_i T_m J_i`` of the gamma-weighted frames of Section 3.3 (if any), then unit rows
    of the motion joints' rates (if any), stacked in that order. A scene without ``V_m`` (no
    motion, or one with neither joints nor frames) is a :class:`SceneError`."""
    if motion is None or not (motion.frames or motion.joints):
        raise SceneError("motion", "the scene declares no motion coordinates V_m (Step 10): give joints or frames")
    n_all = kin.tree.n_coords
    blocks = []
    if motion.frames:
        terms = [frame_rows(kin, frame, motion.components).scale(field.const(gamma))
                 for frame, gamma in motion.frames]
        total = terms[0]
        for term in terms[1:]:
            total = total + term
        blocks.append(total)
    if motion.joints:
        rows = field.zeros((len(motion.joints), n_all))
        for i, name in enumerate(motion.joints):
            rows[i, kin.tree.coordinate_index(name)] = field.one
        blocks.append(Jet.const(rows, field))
    return blocks[0] if len(blocks) == 1 else vstack(blocks, n_all, field)


def contact_rows(field: Field, kin: TreeKinematics, contact_forces: ContactForces | None) -> Jet:
    """``D_m`` over all joint coordinates: the contact frame's twist components along which
    ``eta_m`` acts (``T_m J``); no rows without contact forces."""
    if contact_forces is None:
        return Jet.const(field.zeros((0, kin.tree.n_coords)), field)
    return frame_rows(kin, contact_forces.frame, contact_forces.components)


def contact_map(field: Field, kin: TreeKinematics, contact_forces: ContactForces | None, p: Jet) -> ContactMap:
    """Step 9, eq. (16): ``D_m = T_m J P``."""
    rows = contact_rows(field, kin, contact_forces)
    return ContactMap(rows @ p, rows)


def task_map(field: Field, kin: TreeKinematics, motion: Motion | None, p: Jet) -> TaskMap:
    """Step 10, eq. (17): ``J_m = J_m_all P``, full row rank ``m x n``."""
    rows = motion_rows(field, kin, motion)
    return TaskMap(rows @ p, rows)


def task_matrix(field: Field, task: TaskMap, constraint: ConstraintMap) -> Jet:
    """Step 10: ``A = [J_m; J_f]`` (eq. 18), ``n x n``."""
    return vstack([task.J_m, constraint.J_f], task.J_m.shape[1], field)


def inverse_task_map(field: Field, task: TaskMap, constraint: ConstraintMap) -> InverseTaskMap:
    """Step 10, eq. (18): ``[J_m; J_f]^-1 = [Omega, Psi]`` by one solve with the identity."""
    a = task_matrix(field, task, constraint)
    a_inv = solve(field, a, identity(field, a.shape[0]), TASK_MATRIX)
    return InverseTaskMap(a, a_inv, task.J_m.shape[0])


def acceleration_bias(rows_all: Jet, qd_all: FieldVector, bias: FieldVector) -> np.ndarray:
    """``d/dt(J qd)`` at ``qdd = 0`` for ``J = J_all P``: ``dJ_all/dt qd_all + J_all dP/dt qd``
    (``rows_all`` must carry derivatives along ``qd_all``; ``bias = dP/dt qd`` from
    :func:`~symgen.steps.joint_space.rate_bias`)."""
    qd_v = np.asarray(qd_all, dtype=rows_all.v.dtype)
    acceleration: np.ndarray = rows_all.d @ qd_v + rows_all.v @ np.asarray(bias, dtype=rows_all.v.dtype)
    return acceleration
