"""The projected parameter adaptation law of eq. (38), vectorized over the parameters ``k``.

Given ``s_k = Y_k^T [J_m; J_f]^-1 [V_mr - V_m; 0]`` (computed by the caller from the regressor
columns of ``Y = [T_S^T Y_r, Y_m]``, eq. 38), the estimate ``P_hat_k`` moves as::

    d/dt P_hat_k = rho_k kappa_k s_k                                                    (38)
    kappa_k = 0   if P_hat_k <= P-_k and s_k <= 0
              0   if P_hat_k >= P+_k and s_k >= 0
              1   otherwise

so an estimate at a bound can only move back inside ``[P-_k, P+_k]``. The Lyapunov function of
the adaptive controller carries ``sum_k (P_hat_k - P_k)^2 / (2 rho_k)``
(:func:`parameter_error_energy`); projection never increases it when ``P_k`` lies in its bounds.

All functions accept float arrays or object arrays (Fractions, mpmath numbers). A known
parameter has ``rho_k = 0`` (:class:`~symgen.control.parameters.ParameterSet`), so it never moves
and is left out of the energy.
"""
from __future__ import annotations

import numpy as np

from .errors import ControlInputError


def _arrays(*arrays):
    out = [np.asarray(a) for a in arrays]
    shape = out[0].shape
    for a in out[1:]:
        if a.shape != shape:
            raise ControlInputError(f"adaptation arrays of different shapes {[x.shape for x in out]}")
    return out


def projection(p_hat, s, lower, upper) -> np.ndarray:
    """``kappa_k`` of eq. (38): an int array of 0 (update blocked at a bound) and 1."""
    p_hat, s, lower, upper = _arrays(p_hat, s, lower, upper)
    blocked = ((p_hat <= lower) & (s <= 0)) | ((p_hat >= upper) & (s >= 0))
    return np.where(np.asarray(blocked, dtype=bool), 0, 1)


def parameter_rate(p_hat, s, lower, upper, rho) -> np.ndarray:
    """``d/dt P_hat = rho * kappa * s`` (eq. 38), elementwise."""
    p_hat, s, lower, upper, rho = _arrays(p_hat, s, lower, upper, rho)
    return rho * projection(p_hat, s, lower, upper) * s


def clip_to_bounds(p_hat, lower, upper) -> np.ndarray:
    """``P_hat`` with each entry moved into ``[P-_k, P+_k]``.

    Eq. (38) keeps the exact solution inside its bounds, but an integrator step of finite length
    can end slightly past one (the rate switches off only at the bound); apply this after each
    step. Entries already inside are returned unchanged (same objects, exact fields stay exact).
    """
    p_hat, lower, upper = _arrays(p_hat, lower, upper)
    if p_hat.dtype.kind == "f" and lower.dtype.kind == "f" and upper.dtype.kind == "f":
        return np.minimum(np.maximum(p_hat, lower), upper)
    out = np.array(p_hat, dtype=object, copy=True)
    for k in range(out.size):
        if out.flat[k] < lower.flat[k]:
            out.flat[k] = lower.flat[k]
        elif out.flat[k] > upper.flat[k]:
            out.flat[k] = upper.flat[k]
    return out


def parameter_error_energy(p_hat, p_true, rho):
    """``1/2 sum_k (P_hat_k - P_k)^2 / rho_k`` over the adapted parameters (``rho_k > 0``);
    the parameter part of the Lyapunov function of eqs. (34)-(38)."""
    p_hat, p_true, rho = _arrays(p_hat, p_true, rho)
    total = 0
    for e, r in zip((p_hat - p_true).flat, rho.flat):
        if r > 0:
            total = total + e * e / (2 * r)
    return total


def adaptation_step(p_hat, s, lower, upper, rho, dt) -> np.ndarray:
    """One explicit Euler step of eq. (38) followed by :func:`clip_to_bounds`."""
    return clip_to_bounds(np.asarray(p_hat) + dt * parameter_rate(p_hat, s, lower, upper, rho),
                          lower, upper)
