"""Base (minimal identifiable) parameters from the stacked regressor, by column-pivoted QR.

Stack ``W`` (the regressor of :mod:`symgen.identification.regressor`) over random loop-closed
states. A parameter whose column of ``W`` is zero at every state *vanishes* (it never acts on the
measured forces). Of the rest, a column-pivoted QR ``W Pi = Q R`` on the columns scaled to unit
norm gives the rank ``r``: the number of diagonal entries with ``|R_kk| > RANK_TOL |R_00|``.

Which ``r`` parameters are kept is then chosen in a fixed order of preference (not by the pivots'
column norms, which depend on the units), so that the result reads like the classical regrouping
rules: Gram-Schmidt on the unit columns in the order of :func:`preference_order` (the diagonal
of a QR without pivoting) keeps a column when its distance from the span of the columns kept
before it exceeds the same tolerance. Inertia entries ``Ixx, Ixy, Ixz, Iyz, Izz`` and first moments ``hx, hy`` come
first, the joints' and contact law's parameters next, and ``hz, m, Iyy`` last -- in symgen's
internal body frames the z axis is the joint axis, so these are the ones the classical rules
move onto the previous link (``Ixx - Iyy``, ``Izz + m L^2``, ...). Both passes must agree on ``r``.
Every dropped column is a combination of the kept ones, ``W_d = W_i beta`` (least squares on
the unscaled columns), so

    W P = W_i (P_i + beta P_d) = W_b P_b,        P_b = P_i + beta P_d

and ``P_b`` (``r`` entries) is what data can determine. Regrouping coefficients ``beta`` are
lengths, squared lengths and 1 (e.g. ``Izz_link1 + Ir_j1`` for a joint about z): they are
rounded to :data:`BETA_DIGITS` significant digits for display, and entries below
:data:`BETA_ZERO` (measured between the unit-norm columns, so independent of units) are zero.

Rank tolerance: the columns are scaled to unit norm, so ``|R_kk|`` is the distance of column k
from the span of the earlier pivots, relative to its own size. Structural dependences leave
``|R_kk|`` at rounding level (``1e-13``..``1e-16`` on the built-in and URDF scenes measured in
``benchmarks/identification.md``); independent columns stay above ``1e-5`` with 60 random states.
``RANK_TOL = 1e-9`` sits in the middle of that gap (``symgen params --json`` prints both sides).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import IdentificationError, TooFewSamplesError
from .regressor import Problem, stacked_regressor
from .states import random_states

#: kept pivots have |R_kk| > RANK_TOL |R_00| (columns scaled to unit norm; module docstring)
RANK_TOL = 1e-9
#: a column of W below this fraction of the largest column norm is zero (the parameter vanishes)
ZERO_COLUMN = 1e-10
#: |beta| (between unit columns) below this is zero; displayed coefficients have BETA_DIGITS digits
BETA_ZERO = 1e-7
BETA_DIGITS = 6
#: random states stacked by default, and at most (each is a dense evaluation, with a loop-closure
#: solve on a closed chain: 5 to 50 ms)
STATES = 60
MAX_STATES = 2000


class RankDecisionError(IdentificationError):
    """The pivoted and the ordered QR disagree on the rank: a column sits at the tolerance."""

    def __init__(self, pivoted: int, ordered: int, tol: float):
        super().__init__(f"rank of the stacked regressor is {pivoted} by pivoted QR but {ordered} in the "
                         f"order of preference at tolerance {tol:g}; use more or other states")


@dataclass(frozen=True)
class BaseParameters:
    """The base parameters ``P_b = P[independent] + beta @ P[dependent]`` of a parameter list."""

    names: tuple[str, ...]          # the standard parameters, in order
    independent: tuple[int, ...]    # r indices into names
    dependent: tuple[int, ...]      # the rest (vanishing ones included)
    beta: np.ndarray                # r x len(dependent)
    vanishing: tuple[int, ...]      # indices whose column of W is zero
    diagonal: np.ndarray            # |R_kk| / |R_00| of the pivoted QR, in pivot order
    tolerance: float

    @property
    def rank(self) -> int:
        return len(self.independent)

    def matrix(self) -> np.ndarray:
        """``K`` (r x p) with ``P_b = K P``."""
        k = np.zeros((self.rank, len(self.names)))
        k[np.arange(self.rank), list(self.independent)] = 1.0
        if self.dependent:
            k[:, list(self.dependent)] = self.beta
        return k

    def values(self, p) -> np.ndarray:
        """``P_b`` of a standard parameter vector ``p``."""
        return self.matrix() @ np.asarray(p, float)

    def regrouped(self, i: int) -> list[tuple[float, str]]:
        """``[(coefficient, name), ...]`` of base parameter ``i`` (its own parameter first)."""
        out = [(1.0, self.names[self.independent[i]])]
        for j, d in enumerate(self.dependent):
            if abs(self.beta[i, j]) > BETA_ZERO:
                out.append((float(self.beta[i, j]), self.names[d]))
        return out

    def labels(self) -> list[str]:
        """Readable base parameters, e.g. ``Izz_link0 + Ir_j0 + 0.01 m_link1``."""
        return [format_combination(self.regrouped(i)) for i in range(self.rank)]

    def classification(self) -> dict[str, list[str]]:
        """Names of the vanishing, the alone-identifiable and the regrouped parameters."""
        alone = [self.names[self.independent[i]] for i in range(self.rank) if len(self.regrouped(i)) == 1]
        grouped = [n for i in range(self.rank) if len(self.regrouped(i)) > 1 for _, n in self.regrouped(i)]
        return {"vanishing": [self.names[k] for k in self.vanishing], "identifiable": alone, "regrouped": grouped}


def _coefficient(c: float) -> str:
    return f"{float(f'{c:.{BETA_DIGITS}g}'):g}"


def format_combination(terms) -> str:
    """``a + 0.5 b - c`` from ``[(1, a), (0.5, b), (-1, c)]``."""
    text = ""
    for k, (c, name) in enumerate(terms):
        sign = "-" if c < 0 else "+"
        mag = abs(c)
        body = name if abs(mag - 1) < 10 ** -BETA_DIGITS else f"{_coefficient(mag)} {name}"
        text += (f"-{body}" if sign == "-" else body) if k == 0 else f" {sign} {body}"
    return text


PREFERRED = ("Ixx", "Ixy", "Ixz", "Iyz", "Izz", "hx", "hy")
LAST = ("hz", "m", "Iyy")


def preference_order(names) -> list[int]:
    """Indices of ``names`` (``quantity_owner``) in the order in which columns are kept (module
    docstring): the preferred body quantities, then everything else, then ``hz, m, Iyy``."""
    quantity = [n.split("_", 1)[0] for n in names]
    first = [k for k, q in enumerate(quantity) if q in PREFERRED]
    last = [k for k, q in enumerate(quantity) if q in LAST]
    middle = [k for k in range(len(names)) if k not in first and k not in last]
    return first + middle + last


def _kept_in_order(scaled: np.ndarray, order, tol: float) -> list[int]:
    """Positions (into ``order``) of the columns kept by Gram-Schmidt in ``order`` (the diagonal of
    an unpivoted QR: a column is kept when its distance from the span of the kept ones, each
    column having unit norm, exceeds ``tol``; re-orthogonalised once for accuracy)."""
    basis = np.zeros((scaled.shape[0], 0))
    kept = []
    for pos, k in enumerate(order):
        res = scaled[:, k] - basis @ (basis.T @ scaled[:, k])
        res -= basis @ (basis.T @ res)
        dist = np.linalg.norm(res)
        if dist > tol:
            kept.append(pos)
            basis = np.column_stack([basis, res / dist])
    return kept


def base_from_regressor(w: np.ndarray, names, *, tol: float = RANK_TOL) -> BaseParameters:
    """:class:`BaseParameters` of a stacked regressor ``w`` (module docstring)."""
    w = np.asarray(w, float)
    if w.shape[0] < w.shape[1]:
        raise TooFewSamplesError("rows of the stacked regressor for the base parameters", w.shape[0], w.shape[1],
                                 "the rank could be limited by the rows; stack more states")
    norms = np.linalg.norm(w, axis=0)
    big = norms.max() if norms.size and norms.max() > 0 else 1.0
    vanishing = tuple(int(k) for k in np.flatnonzero(norms <= ZERO_COLUMN * big))
    live = [k for k in range(w.shape[1]) if k not in vanishing]
    if not live:
        return BaseParameters(tuple(names), (), tuple(range(w.shape[1])), np.zeros((0, w.shape[1])),
                              vanishing, np.zeros(0), tol)
    from scipy.linalg import qr      # here: SciPy's import slows every CLI command's start-up

    scaled = w[:, live] / norms[live]
    _, r, piv = qr(scaled, mode="economic", pivoting=True)
    diag = np.abs(np.diag(r)) / abs(r[0, 0])
    rank = int(np.sum(diag > tol))
    order = [k for k in preference_order([names[j] for j in live])]
    kept = _kept_in_order(scaled, order, tol)
    if len(kept) != rank:
        raise RankDecisionError(rank, len(kept), tol)
    independent = tuple(sorted(int(live[order[k]]) for k in kept))
    dependent = tuple(sorted(set(range(w.shape[1])) - set(independent)))
    beta = _regrouping(w, norms, independent, dependent, rank)
    return BaseParameters(tuple(names), independent, dependent, beta, vanishing, diag, tol)


def _regrouping(w, norms, independent, dependent, rank) -> np.ndarray:
    """``beta`` with ``W_d = W_i beta`` (least squares on unit columns, then unscaled); entries
    below :data:`BETA_ZERO` on the unit columns are rounding noise and set to zero."""
    if not dependent:
        return np.zeros((rank, 0))
    ind, dep = list(independent), list(dependent)
    safe = np.where(norms > 0, norms, 1.0)
    beta_unit = np.linalg.lstsq(w[:, ind] / safe[ind], w[:, dep] / safe[dep], rcond=None)[0]
    beta_unit[np.abs(beta_unit) < BETA_ZERO] = 0.0
    return beta_unit / safe[ind][:, None] * safe[dep][None, :]


def default_count(problem: Problem) -> int:
    """Random states stacked by default: :data:`STATES`, or twice the states whose rows equal the
    parameter count if that is more (``arm_on_plane`` with ``eta_f`` unmeasured: 3 rows a state)."""
    return max(STATES, 2 * -(-len(problem.params) // len(problem.channels)))


def base_parameters(problem: Problem, *, states=None, count: int | None = None, seed: int = 0,
                    tol: float = RANK_TOL) -> BaseParameters:
    """Base parameters of ``problem`` from ``count`` random loop-closed states (default
    :func:`default_count`, at most :data:`MAX_STATES`), or from ``states``."""
    count = default_count(problem) if count is None else count
    if states is None and not (isinstance(count, (int, np.integer)) and 1 <= count <= MAX_STATES):
        raise IdentificationError(f"count of random states {count!r} is out of range: give an integer "
                                  f">= 1 and <= {MAX_STATES}")
    if not (isinstance(seed, (int, np.integer)) and seed >= 0):
        raise IdentificationError(f"seed {seed!r} must be an integer >= 0")
    states = random_states(problem.model, count, seed=seed) if states is None else states
    return base_from_regressor(stacked_regressor(problem, states), problem.params.names, tol=tol)
