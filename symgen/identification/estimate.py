"""Weighted least squares of the base parameters, with standard deviations (the two-step method).

From ``N`` samples with ``c`` channels each (:mod:`symgen.identification.regressor`) stack
``W_b x = y`` (``W_b``: the base columns, ``x = P_b``). Then

1. ordinary least squares ``x_0``; per channel ``j`` the residual standard deviation
   ``sigma_j^2 = |y_j - W_j x_0|^2 / (N - r/c)`` (the ``r`` degrees of freedom shared out evenly);
2. weighted least squares with each row of channel ``j`` divided by ``sigma_j``: ``x``, and with
   ``sigma_w^2 = |y_w - W_w x|^2 / (N c - r)`` (near 1 when the noise is what step 1 measured)
   the covariance ``sigma_w^2 (W_w^T W_w)^-1`` and the standard deviations its diagonal's roots.

``weights`` may instead be ``"none"`` (ordinary least squares, one common sigma) or given per
channel (the standard deviations of the measured forces, e.g. from a datasheet).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .base import BaseParameters, base_parameters
from .data import Samples, check_samples, column_names, states_from_samples
from .errors import DataColumnError, TooFewSamplesError
from .regressor import Problem, measured_side, sample_rows, evaluate_state


@dataclass(frozen=True)
class Observations:
    """Stacked rows of every sample: regressor (all standard columns), right-hand side, channel of each row."""

    W: np.ndarray
    y: np.ndarray
    channel: np.ndarray
    channels: list[str]
    samples: int


@dataclass(frozen=True)
class Estimate:
    """Base parameters identified from data."""

    base: BaseParameters
    values: np.ndarray          # P_b
    std: np.ndarray             # their standard deviations
    channel_std: np.ndarray     # sigma_j of step 1 (or the given weights)
    sigma_w: float              # weighted residual standard deviation (step 2)
    rows: int
    samples: int

    def as_dict(self) -> dict:
        return {"samples": self.samples, "rows": self.rows, "base_parameters": self.base.rank,
                "sigma_w": self.sigma_w,
                "parameters": [{"name": lab, "value": float(v), "std": float(s)}
                               for lab, v, s in zip(self.base.labels(), self.values, self.std)]}


def observations(problem: Problem, samples: Samples) -> Observations:
    """Rows of every sample (data checked first: :func:`~symgen.identification.data.check_samples`)."""
    model = problem.model
    present = check_samples(model, samples)
    names = column_names(model)
    if present["eta_m"] != problem.eta_m_measured:
        raise DataColumnError(names["eta_m"][0], "present in the data but the problem identifies the contact law"
                              if present["eta_m"] else "missing: the problem assumes measured contact forces")
    if problem.eta_f_measured and not present["eta_f"]:
        raise DataColumnError(names["eta_f"][0], "missing: the problem assumes measured constraint forces")
    tau = samples.block(names["tau"])
    eta_f = samples.block(names["eta_f"]) if present["eta_f"] else None
    eta_m = samples.block(names["eta_m"]) if present["eta_m"] else None
    ws, ys = [], []
    for k, state in enumerate(states_from_samples(model, samples)):
        data, dv = evaluate_state(model, state)
        w, t_map = sample_rows(problem, state, data, dv)
        ws.append(w)
        ys.append(measured_side(problem, data, t_map, tau[k], None if eta_f is None else eta_f[k],
                                None if eta_m is None else eta_m[k]))
    c = len(problem.channels)
    return Observations(np.vstack(ws), np.concatenate(ys), np.tile(np.arange(c), len(ws)), problem.channels,
                        len(ws))


def _solve(w, y):
    return np.linalg.lstsq(w, y, rcond=None)[0]


def weighted_least_squares(obs: Observations, base: BaseParameters, weights="residual") -> Estimate:
    """Steps 1-2 of the module docstring on ``obs`` for ``base``'s parameters."""
    wb = obs.W[:, list(base.independent)]
    r, c = base.rank, len(obs.channels)
    if wb.shape[0] < r:
        raise TooFewSamplesError(f"rows of the stacked regressor ({obs.samples} samples x {c} channels)",
                                 wb.shape[0], r, f"need at least {-(-r // c)} samples for {r} base parameters")
    rank = np.linalg.matrix_rank(wb)
    if rank < r:
        raise TooFewSamplesError("rank of the base regressor on these samples", int(rank), r,
                                 "the motion does not excite every base parameter; use an exciting trajectory "
                                 "(symgen excite) or more samples")
    if isinstance(weights, str) and weights == "none":
        sig = np.ones(c)
    elif isinstance(weights, str) and weights == "residual":
        res = obs.y - wb @ _solve(wb, obs.y)
        dof = max(obs.samples - r / c, 1.0)
        sig = np.array([np.sqrt(np.sum(res[obs.channel == j] ** 2) / dof) for j in range(c)])
        scale = np.array([np.sqrt(np.mean(obs.y[obs.channel == j] ** 2)) for j in range(c)])
        sig = np.maximum(sig, 1e-13 * np.maximum(scale, 1e-300))
    else:
        sig = np.asarray(weights, float)
        if sig.shape != (c,) or not np.all(sig > 0):
            raise DataColumnError("--weights", f"need {c} positive standard deviations ({', '.join(obs.channels)})")
    row_w = 1.0 / sig[obs.channel]
    ww, yw = wb * row_w[:, None], obs.y * row_w
    x = _solve(ww, yw)
    dof = max(len(yw) - r, 1)
    sigma_w = float(np.sqrt(np.sum((yw - ww @ x) ** 2) / dof))
    cov = sigma_w ** 2 * np.linalg.inv(ww.T @ ww)
    return Estimate(base, x, np.sqrt(np.maximum(np.diag(cov), 0.0)), sig, sigma_w, len(yw), obs.samples)


def identify(problem: Problem, samples: Samples, *, base: BaseParameters | None = None,
             weights="residual") -> Estimate:
    """Base parameters of ``problem`` from ``samples`` (base set from random states unless given)."""
    obs = observations(problem, samples)
    return weighted_least_squares(obs, base or base_parameters(problem), weights)
