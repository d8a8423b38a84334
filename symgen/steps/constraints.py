"""Steps 4, 6 and 7: the constraints on the joints, solved for the dependent rates, and the map
of the general constraint forces.

Every function takes jets (:class:`~symgen.math.jet.Jet`): values and, when the kinematics carries
joint rates, their exact time derivatives; the same code runs in every field.
"""
from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..errors import ConstraintError
from ..math.jet import Jet, hstack, identity, scatter, solve
from ..kinematics import TreeKinematics
from ..kinematics import constraint_matrix as constraint_rows
from .structure import Partition

if TYPE_CHECKING:
    from ..math.fields import Field
    from ..scene.elements import Constraint


@dataclass(frozen=True)
class ConstraintMatrix:
    """Step 4: ``T = [T_a, T_u]`` of eq. (6), ``T_a qd_a + T_u qd_u = 0``.

    ``T`` has one row per constraint component and its columns in all-coordinate (scene) order;
    ``T_a`` and ``T_u`` are its actuated and unactuated columns, each in scene order."""

    T: Jet
    T_a: Jet
    T_u: Jet

    def columns(self, coords: Sequence[int]) -> Jet:
        """The columns of ``T`` at the all-coordinate indices ``coords``."""
        return self.T[:, list(coords)]


@dataclass(frozen=True)
class ConstraintBlocks:
    """Step 6: eq. (9), ``[[T11, T12], [T21, T22]] = [T_u1, T_a1]^-1 [T_a2, T_u2]``.

    ``W = [T_u1, T_a1]`` is the ``n_c x n_c`` matrix of Step 5; ``T11, T12`` (``n_p`` rows) give
    the passive dependent rates of eq. (10), ``T21, T22`` (``n_c - n_p`` rows) the constraints left
    on the actuated joints, eq. (11)."""

    W: Jet
    T11: Jet
    T12: Jet
    T21: Jet
    T22: Jet


@dataclass(frozen=True)
class ConstraintMap:
    """Step 7: ``T_c`` and ``J_f = T_c [1, T21, T22]`` of eq. (12), ``(n_c - n_p) x n`` over ``qd``.

    The rows of ``J_f`` span the general constraint forces: ``J_f^T eta_f`` is their effect in
    the joint space A (eq. 16)."""

    T_c: Jet
    J_f: Jet


def constraint_matrix(kin: TreeKinematics, constraints: Iterable[Constraint], partition: Partition) -> ConstraintMatrix:
    """Step 4, eq. (6): the constraint rows over all joint coordinates, split into actuated and
    unactuated columns. Each constraint contributes the selected components of the relative twist
    of its two frames (:func:`symgen.kinematics.constraint_matrix`)."""
    t = constraint_rows(kin, constraints)
    return ConstraintMatrix(t, t[:, list(partition.actuated)], t[:, list(partition.unactuated)])


def constraint_blocks(field: Field, cm: ConstraintMatrix, partition: Partition) -> ConstraintBlocks:
    """Step 6, eq. (9): one solve with ``W = [T_u1, T_a1]`` for all right-hand sides
    ``[T_a2, T_u2]``; the time derivatives follow ``d(W^-1 B) = W^-1 (dB - dW W^-1 B)``."""
    w = cm.columns(partition.u1 + partition.a1)
    nc = cm.T.shape[0]
    rhs = hstack([cm.columns(partition.a2), cm.columns(partition.u2)], nc, field)
    x = solve(field, w, rhs, "[T_u1, T_a1] (eq. 9)")
    n_p, na2 = len(partition.u1), len(partition.a2)
    return ConstraintBlocks(w, x[:n_p, :na2], x[:n_p, na2:], x[n_p:, :na2], x[n_p:, na2:])


def constraint_map(field: Field, cm: ConstraintMatrix, blocks: ConstraintBlocks, p: Jet,
                   partition: Partition, choice: str) -> ConstraintMap:
    """Step 7, eq. (12), for the scene's choice of ``T_c``:

    * ``"operational"``: ``T_c = T_a1``, so ``J_f = T_a1 [1, T21, T22] = T P`` -- the constraint
      rows themselves on the independent rates (``P`` of eq. 10). Then ``eta_f`` are the
      constraint wrench components, as in Sections 3.2-3.3. This needs ``n_p = 0`` (``T_a1`` must
      be square) or ``n_p = n_c`` (no ``eta_f``).
    * ``"joint"``: ``T_c = 1`` and ``J_f = [1, T21, T22]`` placed at the columns of
      ``q_a1, q_a2, q_u2`` in ``qd``.
    """
    nc, n_p = cm.T.shape[0], len(partition.u1)
    n = len(partition.independent)
    if nc == n_p:
        empty = Jet.const(field.zeros((0, n)), field)
        return ConstraintMap(Jet.const(field.zeros((0, 0)), field), empty)
    if choice == "operational":
        if n_p:
            raise ConstraintError("constraint_forces", f"'operational' takes T_c = T_a1, which is not square "
                                  f"when {n_p} of the {nc} constraints fall on passive joints (n_p = {n_p}); "
                                  "write constraint_forces: joint")
        return ConstraintMap(cm.columns(partition.a1), cm.T @ p)
    column = partition.column
    j_f = scatter(field, (nc - n_p, n), [
        (range(nc - n_p), [column(c) for c in partition.a1], identity(field, nc - n_p)),
        (range(nc - n_p), [column(c) for c in partition.a2], blocks.T21),
        (range(nc - n_p), [column(c) for c in partition.u2], blocks.T22)])
    return ConstraintMap(identity(field, nc - n_p), j_f)
