"""Physically consistent identification: every standard parameter, under linear matrix inequalities.

Least squares determines only the base parameters (:mod:`symgen.identification.base`). Here all
standard parameters ``P`` are fitted to the same weighted rows, subject to, per massive body,
the pseudo-inertia about the body frame's origin being positive semidefinite

    J(P_alpha) = [[ tr(I_o)/2 1 - I_o,  h ],
                  [ h^T,                m ]]  >= 0           (J = integral of [x; 1][x; 1]^T dm)

-- equivalent to ``m >= 0``, the centre of mass's inertia ``I_c`` positive semidefinite and its
principal moments satisfying the triangle inequalities (and the mass inside its own ellipsoid).
Rotor inertias, viscous and Coulomb coefficients (joints and contact law) are ``>= 0``. The
solver meets these to its own tolerance; afterwards each ``J``'s eigenvalues are raised to
:data:`MARGIN` times its largest and negative coefficients set to 0 (a change at the 1e-9 level).

The directions the data cannot see are fixed by a small pull towards the prior (the scene's own
parameters): the objective is ``|W_w P - y_w| / sqrt(N_rows) + gamma |P - P_prior| / sqrt(p)``
with ``gamma`` = :data:`PRIOR_WEIGHT` (relative to a unit weighted residual). Norms, not their
squares: near the data's optimum the pull moves ``P`` only along directions the data term does
not resist, so noise-free data give back the true base parameters, and the solution is unique.
Solved with cvxpy (a semidefinite program): Clarabel, and SCS if Clarabel fails.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..control.parameters import BODY_QUANTITIES
from .errors import ConsistencyError
from .estimate import Estimate, Observations

#: weight of the pull towards the prior parameters (module docstring)
PRIOR_WEIGHT = 1e-6
#: channel standard deviations below this fraction of the channel's rms are raised to it: noise-free
#: data would otherwise give weights of 1e13 and a program the conic solvers cannot scale (Clarabel
#: fails on the UR5 at 1e-6; the weights only change the fit's efficiency, not what it converges to)
WEIGHT_FLOOR = 1e-4
#: after the solve, eigenvalues of each J are raised to at least MARGIN times the largest
MARGIN = 1e-9
#: quantities that must be non-negative
NONNEGATIVE = ("Ir", "b", "c")


@dataclass(frozen=True)
class ConsistentEstimate:
    names: tuple[str, ...]
    values: np.ndarray              # all standard parameters
    base_values: np.ndarray         # K P: the base parameters they imply
    min_eigenvalue: dict            # body -> smallest eigenvalue of J
    status: str


def pseudo_inertia(p_alpha) -> np.ndarray:
    """``J`` (4 x 4) of ``P_alpha = [m, h, Ixx, Iyy, Izz, Ixy, Ixz, Iyz]`` (numbers)."""
    m, hx, hy, hz, xx, yy, zz, xy, xz, yz = p_alpha
    io = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
    out = np.zeros((4, 4))
    out[:3, :3] = np.trace(io) / 2 * np.eye(3) - io
    out[:3, 3] = out[3, :3] = [hx, hy, hz]
    out[3, 3] = m
    return out


def from_pseudo_inertia(j) -> np.ndarray:
    """``P_alpha`` from ``J`` (inverse of :func:`pseudo_inertia`: ``I_o = tr(S) 1 - S``, ``S = J[:3, :3]``)."""
    s = np.asarray(j, float)[:3, :3]
    io = np.trace(s) * np.eye(3) - s
    return np.array([j[3, 3], j[0, 3], j[1, 3], j[2, 3], io[0, 0], io[1, 1], io[2, 2], io[0, 1], io[0, 2], io[1, 2]])


def lift_to_margin(p_alpha, margin: float = MARGIN) -> np.ndarray:
    """``P_alpha`` with the eigenvalues of ``J`` raised to at least ``margin`` times the largest: the
    solver meets the LMI only to its own tolerance (eigenvalues of -1e-10 occur), and a scene file
    must hold a body whose inertia passes symgen's checks exactly."""
    lam, vec = np.linalg.eigh(pseudo_inertia(p_alpha))
    lam = np.maximum(lam, margin * max(float(lam[-1]), 0.0))
    return from_pseudo_inertia(vec @ np.diag(lam) @ vec.T)


def body_blocks(params):
    """``{owner: [10 indices]}`` of the massive bodies, in ``BODY_QUANTITIES`` order."""
    out = {}
    for k, p in enumerate(params.parameters):
        if p.quantity in BODY_QUANTITIES:
            out.setdefault(p.owner, {})[p.quantity] = k
    return {o: [d[q] for q in BODY_QUANTITIES] for o, d in out.items() if len(d) == len(BODY_QUANTITIES)}


def consistent_fit(problem, obs: Observations, estimate: Estimate, *, prior_weight: float = PRIOR_WEIGHT,
                   solver: str | None = None) -> ConsistentEstimate:
    """All standard parameters under the LMIs (module docstring), rows weighted by the estimate's
    ``channel_std`` (step 1 of the two-step method)."""
    try:
        import cvxpy as cp
    except ImportError:
        raise ConsistencyError("--consistent needs cvxpy: pip install 'symgen[identify]'") from None
    params = problem.params
    prior = np.asarray(params.values, float)
    rms = np.array([np.sqrt(np.mean(obs.y[obs.channel == j] ** 2)) for j in range(len(obs.channels))])
    row_w = 1.0 / np.maximum(estimate.channel_std, WEIGHT_FLOOR * rms)[obs.channel]
    ww, yw = obs.W * row_w[:, None], obs.y * row_w
    q, r = np.linalg.qr(ww)                 # |W_w P - y_w|^2 = |R P - Q^T y_w|^2 + const: a p x p problem
    z = q.T @ yw
    p = cp.Variable(len(params))
    cons = []
    blocks = body_blocks(params)
    for idx in blocks.values():
        m, hx, hy, hz, xx, yy, zz, xy, xz, yz = (p[k] for k in idx)
        tr = (xx + yy + zz) / 2
        j = cp.bmat([[tr - xx, -xy, -xz, hx], [-xy, tr - yy, -yz, hy], [-xz, -yz, tr - zz, hz],
                     [hx, hy, hz, m]])
        cons.append((j + j.T) / 2 >> 0)
    nonnegative = [k for k, q in enumerate(params.parameters)
                   if q.quantity in NONNEGATIVE or q.quantity.startswith(("b_", "c_"))]
    cons += [p[k] >= 0 for k in nonnegative]
    objective = cp.norm(r @ p - z) / np.sqrt(len(yw)) + prior_weight * cp.norm(p - prior) / np.sqrt(len(prior))
    prob = cp.Problem(cp.Minimize(objective), cons)
    solvers = [solver] if solver else [s for s in ("CLARABEL", "SCS") if s in cp.installed_solvers()] or [None]
    for k, name in enumerate(solvers):          # Clarabel first; SCS if Clarabel gives up
        try:
            prob.solve(solver=name)
            break
        except cp.error.SolverError as exc:
            if k == len(solvers) - 1:
                raise ConsistencyError(f"the semidefinite program failed: {exc}") from None
    if p.value is None or prob.status not in ("optimal", "optimal_inaccurate"):
        raise ConsistencyError(f"the semidefinite program ended with status {prob.status!r}")
    values = np.asarray(p.value, float)
    for idx in blocks.values():
        values[idx] = lift_to_margin(values[idx])
    for k in nonnegative:
        values[k] = max(values[k], 0.0)
    eig = {o: float(np.linalg.eigvalsh(pseudo_inertia(values[idx])).min()) for o, idx in blocks.items()}
    return ConsistentEstimate(params.names, values, estimate.base.values(values), eig, prob.status)
