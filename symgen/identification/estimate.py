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

Both steps come from one Householder QR per channel of ``[W_j, y_j]`` (``O(N r^2)`` in all, no
normal equations, so the condition number is not squared): a weighting of the channels is a QR
of the stacked ``r + 1``-row factors, and the residuals are read from them. 100,000 samples of a
6-joint arm (600,000 rows, 52 base parameters) take a few seconds.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .base import BaseParameters, base_parameters
from .batch import sample_rows_batch
from .data import Samples, check_samples, column_names
from .errors import DataColumnError, OptionError, TooFewSamplesError
from .regressor import Problem


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
    """Rows of every sample (data checked first: :func:`~symgen.identification.data.check_samples`),
    evaluated in one batched call of the generated rows function (:mod:`~symgen.identification.batch`)."""
    model = problem.model
    present = check_samples(model, samples)
    names = column_names(model)
    if present["eta_m"] != problem.eta_m_measured:
        raise DataColumnError(names["eta_m"][0], "present in the data but the problem identifies the contact law"
                              if present["eta_m"] else "missing: the problem assumes measured contact forces")
    if problem.eta_f_measured and not present["eta_f"]:
        raise DataColumnError(names["eta_f"][0], "missing: the problem assumes measured constraint forces")
    w, y = sample_rows_batch(problem, samples)
    c = len(problem.channels)
    return Observations(w.reshape(-1, len(problem.params)), y.reshape(-1), np.tile(np.arange(c), len(samples)),
                        problem.channels, len(samples))


#: a given channel standard deviation lies in [1/WEIGHT_LIMIT, WEIGHT_LIMIT] (N, N m): the rows
#: are divided by it and then squared
WEIGHT_LIMIT = 1e30


def _given_weights(weights, channels) -> np.ndarray:
    """One finite standard deviation per channel, in range, or :class:`OptionError` naming ``--weights``."""
    try:
        sig = np.asarray(weights, float)
    except (TypeError, ValueError):
        sig = None
    c = len(channels)
    if sig is None or sig.shape != (c,) or not np.all((sig >= 1 / WEIGHT_LIMIT) & (sig <= WEIGHT_LIMIT)):
        raise OptionError("--weights", f"{weights!r}: need 'residual', 'none' or {c} finite standard deviations "
                                       f"in [{1 / WEIGHT_LIMIT:g}, {WEIGHT_LIMIT:g}], one per channel "
                                       f"({', '.join(channels)})")
    return sig


def _channel_factors(obs: Observations, columns: list[int]) -> list[np.ndarray]:
    """Per channel ``j`` the triangular factor ``R_j`` of ``[W_j, y_j] = Q_j R_j`` (one Householder
    QR, ``Q_j`` never formed). Any weighting of the channels is then a QR of the stacked
    ``R_j / sigma_j`` (a few hundred rows), and ``|W_j x - y_j| = |R_j [x; -1]|`` exactly."""
    out = []
    for j in range(len(obs.channels)):
        rows = np.flatnonzero(obs.channel == j)
        block = np.empty((len(rows), len(columns) + 1), order="F")
        block[:, :-1] = obs.W[np.ix_(rows, columns)]
        block[:, -1] = obs.y[rows]
        out.append(np.linalg.qr(block, mode="r"))
    return out


def _combined(factors: list[np.ndarray], sigma: np.ndarray, r: int):
    """``(R, z, stacked)`` of the rows weighted by ``1/sigma_j``: their ``r x r`` factor ``R``, ``z =
    Q^T y`` (the solution is ``R^-1 z``) and the weighted ``[R_j]`` (residual ``|stacked [x; -1]|``)."""
    stacked = np.vstack([f / s for f, s in zip(factors, sigma)])
    aug = np.linalg.qr(stacked, mode="r")
    r_factor = aug[:r, :r]
    return r_factor, aug[:r, r], stacked


def _rank(r_factor: np.ndarray, rows: int) -> int:
    """Rank of ``w`` from its ``R`` (same singular values), at NumPy's default tolerance for the
    ``rows x r`` matrix (``matrix_rank``: largest singular value x max(rows, r) x eps)."""
    sv = np.linalg.svd(r_factor, compute_uv=False)
    if not sv.size:
        return 0
    return int(np.sum(sv > sv[0] * max(rows, r_factor.shape[1]) * np.finfo(float).eps))


def weighted_least_squares(obs: Observations, base: BaseParameters, weights="residual") -> Estimate:
    """Steps 1-2 of the module docstring on ``obs`` for ``base``'s parameters. One QR per channel
    of its stacked rows (``O(rows r^2)`` in all); each step is then ``O(c r^3)``."""
    r, c = base.rank, len(obs.channels)
    if obs.W.shape[0] < r:
        raise TooFewSamplesError(f"rows of the stacked regressor ({obs.samples} samples x {c} channels)",
                                 obs.W.shape[0], r, f"need at least {-(-r // c)} samples for {r} base parameters")
    factors = _channel_factors(obs, list(base.independent))
    r_plain, z_plain, _ = _combined(factors, np.ones(c), r)
    rank = _rank(r_plain, obs.W.shape[0])
    if rank < r:
        raise TooFewSamplesError("rank of the base regressor on these samples", rank, r,
                                 "the motion does not excite every base parameter; use an exciting trajectory "
                                 "(symgen excite) or more samples")
    if isinstance(weights, str) and weights == "none":
        sig = np.ones(c)
    elif isinstance(weights, str) and weights == "residual":
        end = np.append(np.linalg.solve(r_plain, z_plain), -1.0)
        dof = max(obs.samples - r / c, 1.0)
        sig = np.array([np.linalg.norm(f @ end) for f in factors]) / np.sqrt(dof)
        scale = np.array([np.linalg.norm(f[:, -1]) for f in factors]) / np.sqrt(obs.samples)
        sig = np.maximum(sig, 1e-13 * np.maximum(scale, 1e-300))
    else:
        sig = _given_weights(weights, obs.channels)
    r_w, z_w, stacked = _combined(factors, sig, r)
    x = np.linalg.solve(r_w, z_w)
    rows = obs.W.shape[0]
    sigma_w = float(np.linalg.norm(stacked @ np.append(x, -1.0)) / np.sqrt(max(rows - r, 1)))
    r_inv = np.linalg.solve(r_w, np.eye(r))            # cov = sigma_w^2 (R^T R)^-1 = sigma_w^2 R^-1 R^-T
    std = sigma_w * np.sqrt(np.sum(r_inv ** 2, axis=1))
    return Estimate(base, x, std, sig, sigma_w, rows, obs.samples)


def identify(problem: Problem, samples: Samples, *, base: BaseParameters | None = None,
             weights="residual") -> Estimate:
    """Base parameters of ``problem`` from ``samples`` (base set from random states unless given)."""
    obs = observations(problem, samples)
    return weighted_least_squares(obs, base or base_parameters(problem), weights)
