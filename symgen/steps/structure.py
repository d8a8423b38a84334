"""The structural steps of Section 3.1: what is decided once, for the whole robot.

Steps 1, 2, the rank of Step 4, the partition of Step 5 and the dimension of Step 8 are decided at
the scene's reference configuration, in floating point with column pivoting and an explicit rank
tolerance, then checked (the chosen ``[T_u1, T_a1]`` must be well conditioned). The matrices of
Steps 4-12 at any configuration and in any field are in the sibling modules.
"""
from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..math.elimination import pivot_columns
from ..errors import ConstraintError, SingularConfigurationError
from ..scene.elements import planar_hint

if TYPE_CHECKING:
    from ..scene.elements import Constraint
    from ..tree import Tree

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

    @property
    def unactuated(self) -> tuple[int, ...]:
        """All-coordinate indices of ``q_u`` (eq. 6), in scene order."""
        return tuple(sorted(self.u1 + self.u2))

    @property
    def independent_columns(self) -> tuple[int, ...]:
        """Positions in ``qd`` of ``[q_a2; q_u2]``, the columns of eq. (9)'s right-hand side."""
        return tuple(self.column(c) for c in self.a2 + self.u2)


def count_joints(tree: Tree) -> tuple[int, int, int, int]:
    """Step 1: ``n1a, n1u, n3a, n3u`` -- actuated and unactuated 1-DOF and spherical joints
    (eqs. 3-4)."""
    def count(dof: int, actuated: bool) -> int:
        return sum(1 for j in tree.joints if j.kind.dof == dof and j.actuated == actuated)

    return count(1, True), count(1, False), count(3, True), count(3, False)


def _rank(a: np.ndarray, scale: float | None = None) -> int:
    """Numerical rank: singular values above ``RANK_TOL`` times ``scale`` (default: the largest
    singular value of ``a`` itself; a block of ``T`` is judged against the whole of ``T``, so a
    column of rounding noise does not count)."""
    if a.size == 0:
        return 0
    s = np.linalg.svd(a, compute_uv=False)
    return int(np.sum(s > RANK_TOL * max(s[0] if scale is None else scale, 1e-300)))


def check_full_row_rank(t: np.ndarray, constraints: Iterable[Constraint]) -> None:
    """``T`` must have full row rank (eq. 6); otherwise name the first redundant constraint."""
    rows = 0
    for con in constraints:
        block = t[: rows + con.dim]
        if _rank(block) < rows + con.dim:
            raise ConstraintError(
                f"constraint {con.name!r}",
                f"its rows are linearly dependent on the previous constraints at the reference "
                f"configuration (rank {_rank(block)} < {rows + con.dim}): the constraints are "
                "redundant; remove the components the mechanism already enforces"
                + (planar_hint([con.kind]) or " (e.g. use planar_weld instead of weld for a planar loop)"))
        rows += con.dim


def choose_partition(t: np.ndarray, tree: Tree) -> Partition:
    """Steps 4-5: ``n_p = rank T_u``; ``T_u1`` by column-pivoted QR of ``T_u``; ``T_a1`` by
    column-pivoted QR of ``T_a`` projected off the range of ``T_u1`` (both by
    :func:`~symgen.math.elimination.pivot_columns`, whose ties do not depend on the float library).
    Returns the partition."""
    coords = tree.coordinates
    act = tuple(i for i, c in enumerate(coords) if c.actuated)
    una = tuple(i for i, c in enumerate(coords) if not c.actuated)
    nc = t.shape[0]
    if nc == 0:
        return Partition((), una, (), act, act)
    t_u, t_a = t[:, list(una)], t[:, list(act)]
    n_p = _rank(t_u, float(np.linalg.norm(t, 2)))
    u1: tuple[int, ...] = ()
    q = np.zeros((nc, 0))
    if n_p:
        u1 = tuple(sorted(una[k] for k in pivot_columns(t_u, n_p)))
        q, _ = np.linalg.qr(t[:, list(u1)])
    rest = nc - n_p
    a1: tuple[int, ...] = ()
    if rest:
        projected = t_a - q @ (q.T @ t_a)
        if _rank(projected, float(np.linalg.norm(t, 2))) < rest:
            raise ConstraintError("constraints", f"the actuated joints cannot take the remaining {rest} "
                                                 "constraint dimensions: [T_u1, T_a1] cannot be invertible (eq. 8)")
        a1 = tuple(sorted(act[k] for k in pivot_columns(projected, rest)))
    w = t[:, list(u1) + list(a1)]
    cond = np.linalg.cond(w)
    if not np.isfinite(cond) or cond > MAX_PARTITION_CONDITION:
        raise SingularConfigurationError("[T_u1, T_a1] at the reference configuration", float(cond),
                                         "move the reference configuration away from the singularity")
    return Partition(u1, tuple(i for i in una if i not in u1), a1,
                     tuple(i for i in act if i not in a1), act)


def counts_from(tree: Tree, partition: Partition, nc: int) -> Counts:
    """Steps 2 and 8: ``m = N_all - n_c`` (eq. 5) and ``n = N_all - n_p = m + (n_c - n_p)``
    (eq. 13), with ``N_all = n1a + n1u + 3 (n3a + n3u)`` and ``n_p`` the size of ``q_u1``."""
    n1a, n1u, n3a, n3u = count_joints(tree)
    total = n1a + n1u + 3 * (n3a + n3u)
    n_p = len(partition.u1)
    return Counts(n1a, n1u, n3a, n3u, total - nc, nc, n_p, total - n_p)
