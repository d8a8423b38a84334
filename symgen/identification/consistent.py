"""Physically consistent identification: every standard parameter, under linear matrix inequalities.

Least squares determines only the base parameters (:mod:`symgen.identification.base`). Here all
standard parameters ``P`` are fitted to the same weighted rows, subject to, per massive body,
the pseudo-inertia about the body frame's origin being positive semidefinite

    J(P_alpha) = [[ tr(I_o)/2 1 - I_o,  h ],
                  [ h^T,                m ]]  >= 0           (J = integral of [x; 1][x; 1]^T dm)

-- equivalent to ``m >= 0``, the centre of mass's inertia ``I_c`` positive semidefinite and its
principal moments satisfying the triangle inequalities (and the mass inside its own ellipsoid).
Rotor inertias, viscous and Coulomb coefficients (joints and contact law) are ``>= 0``.

The directions the data cannot see are fixed by a small pull towards the prior (the scene's own
parameters): the objective is ``|W_w P - y_w|^2 / N_rows + gamma |P - P_prior|^2 / p`` with
``gamma`` = :data:`PRIOR_WEIGHT` (relative to a unit weighted residual), small enough to leave the
identified base parameters where the data put them (within their standard deviations) and large
enough to make the solution unique. Solved with cvxpy (a semidefinite program; Clarabel, or SCS).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..control.parameters import BODY_QUANTITIES
from .errors import ConsistencyError
from .estimate import Estimate, Observations

#: weight of the pull towards the prior parameters (module docstring)
PRIOR_WEIGHT = 1e-6
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


def _body_blocks(params):
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
    row_w = 1.0 / estimate.channel_std[obs.channel]
    ww, yw = obs.W * row_w[:, None], obs.y * row_w
    q, r = np.linalg.qr(ww)                 # |W_w P - y_w|^2 = |R P - Q^T y_w|^2 + const: a p x p problem
    z = q.T @ yw
    p = cp.Variable(len(params))
    cons = []
    blocks = _body_blocks(params)
    for idx in blocks.values():
        m, hx, hy, hz, xx, yy, zz, xy, xz, yz = (p[k] for k in idx)
        tr = (xx + yy + zz) / 2
        j = cp.bmat([[tr - xx, -xy, -xz, hx], [-xy, tr - yy, -yz, hy], [-xz, -yz, tr - zz, hz],
                     [hx, hy, hz, m]])
        cons.append((j + j.T) / 2 >> 0)
    for k, q in enumerate(params.parameters):
        if q.quantity in NONNEGATIVE or q.quantity.startswith(("b_", "c_")):
            cons.append(p[k] >= 0)
    objective = cp.sum_squares(r @ p - z) / len(yw) + prior_weight * cp.sum_squares(p - prior) / len(prior)
    prob = cp.Problem(cp.Minimize(objective), cons)
    solver = solver or ("CLARABEL" if "CLARABEL" in cp.installed_solvers() else None)
    try:
        prob.solve(solver=solver)
    except cp.error.SolverError as exc:
        raise ConsistencyError(f"the semidefinite program failed: {exc}") from None
    if p.value is None or prob.status not in ("optimal", "optimal_inaccurate"):
        raise ConsistencyError(f"the semidefinite program ended with status {prob.status!r}")
    values = np.asarray(p.value, float)
    eig = {o: float(np.linalg.eigvalsh(pseudo_inertia(values[idx])).min()) for o, idx in blocks.items()}
    return ConsistentEstimate(params.names, values, estimate.base.values(values), eig, prob.status)
