"""Straight-line elimination of sparse matrices of traced nodes, with a static pivot order.

The loop-closure matrix ``[T_u1, T_a1]`` (eq. 9) of a parallel robot is mostly structural zeros:
each leg's joints appear only in the rows of its own closure, and a spherical joint's three
columns in three rows only (Stewart: 168 nonzeros of 900). A dense LU pays ``2n^3/3`` on all of it.
Here the generator

1. reads the pattern of structural zeros (constant-zero nodes) and the entries' values at a few
   sample configurations (the reference ``q0`` and deterministic perturbations of it,
   :meth:`symgen.codegen.graph.Graph.sample_values`);
2. chooses a static pivot order (:func:`plan`) by the Markowitz rule -- fewest fill-ins first --
   among the entries that pass a threshold test at every sample (``|a_ij| >= 0.1 max_i |a_ij|`` in
   the pivot's column, the classical threshold-pivoting criterion), so the order is the one partial
   pivoting would accept near ``q0`` while keeping the fill small (per leg, for the Stewart
   platform);
3. emits the elimination as scalar operations (:func:`factor`), which the graph folds: a
   constant pivot (a spherical joint's unit entries) costs nothing, a zero never appears;
4. guards the order at run time: every non-constant pivot enters a *pivot check* statement, which
   computes the same estimate as the dense library LU (``max |pivot| / min |pivot|``) and reports a
   singular solve above ``SYMGEN_MAX_CONDITION`` (C) or ``MAX_CONDITION`` (NumPy). A state where the
   static order meets a small pivot is therefore reported, never silently divided through.

The static order is chosen where it is cheaper: :func:`plan` returns ``None`` (keep the dense
library LU with partial pivoting) when no admissible pivot exists at some step, or when the
elimination would cost more than the dense factorisation, for matrices up to
:data:`SMALL` x :data:`SMALL`, or more than half of it above (:data:`DENSE_FRACTION`). A small
dense matrix (an arm's 6 x 6 tool Jacobian) is thus eliminated in line too: at equal flops the
straight-line code is faster per call than the library LU, whose loops, pivot search and row swaps
the flop count does not see (``benchmarks/small_dense_solves.md``: ``multi_arm:h=2``
``forward_dynamics`` 0.55x, Stewart's 0.82x).
"""
from __future__ import annotations

import contextlib
from dataclasses import dataclass

import numpy as np

#: threshold of the pivot test, relative to the largest entry of the pivot's column (per sample)
THRESHOLD = 0.1
#: above ``SMALL x SMALL``, the straight-line elimination is used when its factorisation flops are
#: at most this fraction of the dense ``2n^3/3`` (the code grows as the flops; the library LU's
#: overhead per call matters less)
DENSE_FRACTION = 0.5
#: decimals to which a candidate pivot's strength is rounded before it breaks a Markowitz tie
STRENGTH_DECIMALS = 6
#: up to this size, the straight-line elimination is used when it costs no more than the dense LU
SMALL = 16


_ENABLED = [True]


def enabled() -> bool:
    """Whether the straight-line routes are in use (see :func:`library_solves_only`)."""
    return _ENABLED[-1]


@contextlib.contextmanager
def library_solves_only():
    """Trace every non-constant solve with the library LU and eq. (10) through ``P`` only, as
    before the straight-line routes existed: the baseline column of the op-count tables
    (``benchmarks/complexity``)."""
    _ENABLED.append(False)
    try:
        yield
    finally:
        _ENABLED.pop()


class ConstantZeroPivot(ArithmeticError):
    """A pivot of the static order folded to the constant zero (a mass matrix that is singular
    at every state, e.g. a joint that moves no mass): the caller keeps the library LU, which
    reports the singular solve at run time."""


@dataclass(frozen=True)
class Plan:
    """A static pivot order: step ``k`` eliminates column ``cols[k]`` with row ``rows[k]``;
    ``flops`` counts the factorisation (multipliers and updates), ``solve_flops`` one right-hand
    side (forward and back substitution)."""

    rows: tuple[int, ...]
    cols: tuple[int, ...]
    flops: int
    solve_flops: int


@dataclass
class Factors:
    """The traced factors of a :class:`Plan`: reciprocal pivots, multipliers ``lower[(row, k)]``
    and the rows of ``U`` (``upper[k]``: column -> node, pivot excluded)."""

    plan: Plan
    reciprocals: list
    lower: dict
    upper: list


def _markowitz(pattern: np.ndarray, rows, cols) -> np.ndarray:
    """``(r_i - 1)(c_j - 1)`` on the active submatrix: an upper bound of the fill of pivot ``(i, j)``."""
    sub = pattern[np.ix_(rows, cols)]
    return np.outer(sub.sum(axis=1) - 1, sub.sum(axis=0) - 1)


def plan(pattern: np.ndarray, samples: np.ndarray) -> Plan | None:
    """Choose the static pivot order for an ``n x n`` matrix with nonzero ``pattern`` and values
    ``samples`` (``S x n x n``, one matrix per sample configuration); ``None`` when no admissible
    pivot exists at some step or the order is not cheaper than the dense LU."""
    n = pattern.shape[0]
    pattern = pattern.copy()
    values = np.array(samples, dtype=float)
    rows, cols = list(range(n)), list(range(n))
    chosen_rows, chosen_cols = [], []
    flops = solve = 0
    for _ in range(n):
        sub = np.abs(values[:, rows][:, :, cols])
        column_max = sub.max(axis=1, keepdims=True)
        ok = np.all(sub >= THRESHOLD * column_max, axis=0) & np.all(column_max > 0, axis=0)
        ok &= pattern[np.ix_(rows, cols)]
        if not ok.any():
            return None
        cost = np.where(ok, _markowitz(pattern, rows, cols), np.iinfo(np.int64).max)
        # rounded: pivots of equal strength in exact arithmetic (symmetric legs or arms) must tie
        # on every float library, and then the lower row and column index decides
        strength = np.round(np.where(ok, (sub / np.where(column_max > 0, column_max, 1)).min(axis=0), -1.0),
                            STRENGTH_DECIMALS)
        best = min(zip(*np.nonzero(ok)), key=lambda ij: (cost[ij], -strength[ij], rows[ij[0]], cols[ij[1]]))
        i, j = rows[best[0]], cols[best[1]]
        below = [r for r in rows if r != i and pattern[r, j]]
        right = [c for c in cols if c != j and pattern[i, c]]
        flops += 1 + len(below) * (1 + 2 * len(right))
        solve += 2 * len(below) + 2 * len(right) + 1
        for r in below:
            pattern[r, right] = True
            factor = values[:, r, j] / values[:, i, j]
            values[:, r, :] -= factor[:, None] * values[:, i, :]
        chosen_rows.append(i)
        chosen_cols.append(j)
        rows.remove(i)
        cols.remove(j)
    if flops > (1.0 if n <= SMALL else DENSE_FRACTION) * 2 * n**3 / 3:
        return None
    return Plan(tuple(chosen_rows), tuple(chosen_cols), flops, solve)


def factor(graph, entries, order: Plan, what: str) -> Factors:
    """Trace the elimination of ``entries`` (``n x n`` nodes) in the static ``order``, and record
    the run-time check of its non-constant pivots (:meth:`symgen.codegen.graph.Graph.pivot_check`)."""
    a = [list(row) for row in entries]
    n = len(a)
    active_rows, active_cols = set(range(n)), set(range(n))
    reciprocals, lower, upper, pivots = [], {}, [], []
    for k, (i, j) in enumerate(zip(order.rows, order.cols)):
        active_rows.discard(i)
        active_cols.discard(j)
        pivot = a[i][j]
        if _zero(pivot):
            raise ConstantZeroPivot(what)
        pivots.append(pivot)
        r = 1 / pivot
        reciprocals.append(r)
        row = {c: a[i][c] for c in sorted(active_cols) if not _zero(a[i][c])}
        upper.append(row)
        for rr in sorted(active_rows):
            if _zero(a[rr][j]):
                continue
            mult = a[rr][j] * r
            lower[(rr, k)] = mult
            for c, u in row.items():
                a[rr][c] = a[rr][c] - mult * u
    graph.pivot_check(pivots, reciprocals, what)
    return Factors(order, reciprocals, lower, upper)


def _zero(x) -> bool:
    return getattr(x, "is_const", False) and x.value == 0


def _by_step(f: Factors) -> dict[int, list]:
    """The multipliers of each elimination step: ``k -> [(row, multiplier), ...]``."""
    out: dict[int, list] = {}
    for (row, k), mult in f.lower.items():
        out.setdefault(k, []).append((row, mult))
    return out


def solve(f: Factors, b) -> list:
    """``A^-1 b`` for one right-hand side ``b`` (``n`` nodes) from the factors of :func:`factor`."""
    y = list(b)
    n = len(y)
    by_step = _by_step(f)
    for k, i in enumerate(f.plan.rows):
        for rr, mult in by_step.get(k, ()):
            y[rr] = y[rr] - mult * y[i]
    x = [None] * n
    for k in reversed(range(n)):
        i, j = f.plan.rows[k], f.plan.cols[k]
        acc = y[i]
        for c, u in f.upper[k].items():
            acc = acc - u * x[c]
        x[j] = acc * f.reciprocals[k]
    return x


def solve_transposed(f: Factors, c) -> list:
    """``A^-T c`` for one right-hand side: ``U^T w = c`` then ``L^T z = w`` in the pivot order."""
    n = len(c)
    rows, cols = f.plan.rows, f.plan.cols
    w = [None] * n
    for k in range(n):
        acc = c[cols[k]]
        for kk in range(k):
            u = f.upper[kk].get(cols[k])
            if u is not None:
                acc = acc - u * w[kk]
        w[k] = acc * f.reciprocals[k]
    z = [None] * n
    by_step = _by_step(f)
    for k in reversed(range(n)):
        acc = w[k]
        for rr, mult in by_step.get(k, ()):
            acc = acc - mult * z[rr]
        z[rows[k]] = acc
    return z


#: a symmetric positive definite matrix up to this size is factored by straight-line LDL^T in its
#: natural order whatever its pattern; a larger one in the minimum-degree order, when that takes
#: fewer multiply-adds than the ``n^3/6`` of a dense LDL^T (a tree's mass matrix: the branches;
#: a dense matrix does not pass), else the library LU keeps it (the straight-line code grows as
#: the multiply-adds)
LDLT_MAX = 16


def minimum_degree(pattern: np.ndarray) -> tuple[tuple[int, ...], int]:
    """A symmetric elimination order of the nonzero ``pattern`` (``n x n``, symmetric) and the
    multiply-adds of its LDL^T (a reciprocal, the multipliers and the lower triangle's updates per
    pivot): at each step the remaining index with the fewest
    off-diagonal nonzeros among the remaining ones (the lowest index on a tie, so a dense matrix
    keeps its natural order), its neighbours then joined pairwise (the fill). On a tree's mass
    matrix this takes the leaves first, and the factorisation has no fill at all (Featherstone's
    ``L^T L`` order, in RBDA's terms)."""
    n = pattern.shape[0]
    adjacent = [set(np.nonzero(pattern[i])[0]) - {i} for i in range(n)]
    remaining = set(range(n))
    order, flops = [], 0
    for _ in range(n):
        k = min(remaining, key=lambda i: (len(adjacent[i] & remaining), i))
        near = adjacent[k] & remaining
        remaining.discard(k)
        order.append(k)
        flops += 1 + len(near) * (len(near) + 3) // 2
        for i in near:
            adjacent[i] |= near - {i}
    return tuple(order), flops


def ldlt_applies(pattern: np.ndarray) -> tuple[int, ...] | None:
    """The elimination order of the straight-line LDL^T of an SPD matrix with ``pattern``: the
    natural one up to :data:`LDLT_MAX` rows, the minimum-degree one above if it is sparse enough;
    ``None`` for the library LU."""
    n = pattern.shape[0]
    if n <= LDLT_MAX:
        return tuple(range(n))
    order, flops = minimum_degree(pattern)
    return order if flops <= n**3 / 6 else None


def ldlt(graph, entries, what: str, order: tuple[int, ...] | None = None) -> Factors:
    """``A = L D L^T`` of a symmetric positive definite ``A`` (the mass matrix of eq. 32),
    eliminated in ``order`` (default natural; :func:`minimum_degree` keeps a sparse matrix
    sparse): no pivoting is needed for SPD matrices, and only the lower triangle of ``entries``
    is read (``n^3/3`` flops where LU takes ``2n^3/3`` on a dense one). Returned as
    :class:`Factors` (``U = D L^T``), so :func:`solve` applies; the pivots ``d_k`` are checked at
    run time as those of :func:`factor` are, which reports a matrix that lost definiteness to
    rounding."""
    n = len(entries)
    order = tuple(range(n)) if order is None else tuple(order)
    a = {(r, c): entries[r][c] for r in range(n) for c in range(r + 1)}      # lower triangle

    def key(i, j):
        return (i, j) if i >= j else (j, i)

    remaining = set(range(n))
    reciprocals, lower, upper, pivots = [], {}, [], []
    flops = solve_flops = 0
    for k, p in enumerate(order):
        remaining.discard(p)
        d = a[(p, p)]
        if _zero(d):
            raise ConstantZeroPivot(what)
        pivots.append(d)
        r = 1 / d
        reciprocals.append(r)
        column = {c: a[key(c, p)] for c in sorted(remaining) if not _zero(a[key(c, p)])}
        upper.append(column)
        mults = {row: v * r for row, v in column.items()}
        for row, mult in mults.items():
            lower[(row, k)] = mult
            for c, u in column.items():
                if c <= row:
                    a[(row, c)] = a[(row, c)] - mult * u
        flops += 1 + len(mults) * (1 + len(column))
        solve_flops += 4 * len(column) + 1
    graph.pivot_check(pivots, reciprocals, what)
    return Factors(Plan(order, order, flops, solve_flops), reciprocals, lower, upper)
