"""Exciting trajectories: finite Fourier series of the free coordinates, optimised for the
condition number of the stacked base regressor.

Free coordinate ``i`` (``q_a2, q_u2`` of eq. 8; every joint of an open chain) follows, with base
angular frequency ``w = 2 pi f`` and ``H`` harmonics,

    q_i(t)   = c_i + s sum_l ( a_il/(w l) sin(w l t) - b_il/(w l) cos(w l t) )
    qd_i(t)  = s sum_l ( a_il cos(w l t) + b_il sin(w l t) )
    qdd_i(t) = s sum_l w l ( -a_il sin(w l t) + b_il cos(w l t) )

periodic with period ``2 pi / w`` (so a measured run can be averaged over periods). ``c_i`` is the
middle of the joint's range and ``s <= 1`` scales the whole motion down until every coordinate
stays inside its range (and under its velocity limit, when the scene has one) at every sample:
the limits hold by construction, whatever the coefficients. The range is the URDF
``<limit lower upper>`` where the scene has one, else :data:`OPEN_RANGE` (open chains) or
:data:`CLOSED_RANGE` (closed chains, where the loops must keep closing) either side of ``q0``; a
trajectory on which a loop does not close is given the condition number :data:`FAILED`.

The dependent positions come from closing the loops by continuation (:func:`trajectory_states`),
rates and accelerations from :func:`~symgen.identification.states.state_from_free`.
The optimiser (Powell's method, derivative-free) minimises ``log10 cond(W_b)``, ``W_b`` the
stacked regressor's base columns at the samples of one period; it starts at a random trajectory,
keeps the best point it has evaluated, and stops after ``max_evals`` evaluations or ``budget``
seconds, whichever comes first -- so the optimised condition number is never above the random one.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, replace

import numpy as np

from ..errors import SingularConfigurationError
from .base import BaseParameters
from .errors import OptionError, TooFewSamplesError
from .regressor import Problem, sample_rows
from .states import State, close_configuration, free_coordinates, state_from_free

#: half-width of the default range either side of q0 (rad or m) where the scene has no limits: open
#: and closed chains (five_bar leaves its workspace on some trajectories of +-0.5 rad)
OPEN_RANGE = 0.5
CLOSED_RANGE = 0.25
#: condition number given to a trajectory on which a loop does not close
FAILED = 1e16
#: largest change of a free coordinate (rad or m) between two loop-closure solves
MAX_STEP = 0.05

#: ranges of the options (the command line's too): harmonics, frequency (Hz), samples per period
#: (each closes the loops: tens of ms on a closed chain), evaluations, seconds
MAX_HARMONICS = 50
MAX_FREQUENCY = 100.0
MAX_PERIOD_SAMPLES = 1000
MAX_EVALS = 1_000_000
MAX_BUDGET = 86_400.0


def _check_range(option: str, value, low, high, *, integer: bool = False, low_open: bool = False) -> None:
    """:class:`OptionError` naming ``option`` unless ``value`` is a finite number (an ``int`` with
    ``integer``) in ``[low, high]`` (``low`` excluded with ``low_open``)."""
    ok = isinstance(value, (int, np.integer)) and not isinstance(value, bool) if integer else \
        isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool) \
        and np.isfinite(value)
    if ok:
        ok = (value > low if low_open else value >= low) and value <= high
    if not ok:
        kind = "an integer" if integer else "a finite number"
        raise OptionError(option, f"{value!r} is out of range: give {kind} {'>' if low_open else '>='} {low} "
                                  f"and <= {high}")


@dataclass(frozen=True)
class FourierTrajectory:
    """A finite Fourier series per free coordinate (module docstring); ``a, b``: ``k x H``."""

    names: tuple[str, ...]
    center: np.ndarray
    a: np.ndarray
    b: np.ndarray
    omega: float
    scale: float = 1.0

    @property
    def period(self) -> float:
        return 2 * np.pi / self.omega

    def times(self, samples: int) -> np.ndarray:
        """``samples`` equally spaced times over one period."""
        return np.arange(samples) * self.period / samples

    def evaluate(self, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(q, qd, qdd)`` at times ``t``, each ``len(t) x k``."""
        t = np.atleast_1d(np.asarray(t, float))
        harm = np.arange(1, self.a.shape[1] + 1)
        wl = self.omega * harm                       # H
        sin, cos = np.sin(np.outer(t, wl)), np.cos(np.outer(t, wl))   # T x H
        q = self.center + self.scale * (sin @ (self.a / wl).T - cos @ (self.b / wl).T)
        qd = self.scale * (cos @ self.a.T + sin @ self.b.T)
        qdd = self.scale * (-sin @ (self.a * wl).T + cos @ (self.b * wl).T)
        return q, qd, qdd


def coordinate_ranges(model, half_width: float | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(lower, upper, velocity_limit)`` of the free coordinates (module docstring; ``inf`` where
    the scene has no velocity limit)."""
    width = (CLOSED_RANGE if _closed(model) else OPEN_RANGE) if half_width is None else half_width
    lo, hi, vel = [], [], []
    for c in free_coordinates(model):
        joint = model.tree.coordinates[c].joint
        limit = model.scene.joint_limits.get(joint)
        q0 = float(model.reference.as_float().positions[joint])
        if limit is not None and limit.lower is not None and limit.upper is not None and half_width is None:
            lo.append(float(limit.lower))
            hi.append(float(limit.upper))
        else:
            lo.append(q0 - width)
            hi.append(q0 + width)
        v = getattr(limit, "velocity", None) if limit is not None else None
        vel.append(float(v) if v else np.inf)
    return np.array(lo), np.array(hi), np.array(vel)


#: times per period at which fit_to_limits checks the ranges (independent of the samples used)
LIMIT_GRID = 400


def fit_to_limits(traj: FourierTrajectory, lower, upper, velocity, samples: int = LIMIT_GRID) -> FourierTrajectory:
    """The trajectory scaled (``s <= 1``) so that it stays in ``[lower, upper]`` and under ``velocity``
    at :data:`LIMIT_GRID` times per period, with 2% margin (covering the motion between them)."""
    unit = replace(traj, scale=1.0)
    q, qd, _ = unit.evaluate(unit.times(max(samples, LIMIT_GRID)))
    dev = np.max(np.abs(q - unit.center), axis=0)
    half = 0.98 * (np.asarray(upper) - np.asarray(lower)) / 2
    with np.errstate(divide="ignore", invalid="ignore"):
        ratios = np.concatenate([half / dev, 0.98 * np.asarray(velocity) / np.max(np.abs(qd), axis=0)])
    ratios = ratios[np.isfinite(ratios)]
    return replace(unit, scale=float(min(1.0, ratios.min())) if ratios.size else 1.0)


def random_trajectory(model, *, harmonics: int = 5, frequency: float = 0.3, seed: int = 0,
                      samples: int = 40, half_width: float | None = None) -> FourierTrajectory:
    """Coefficients normal with standard deviation 1 (rad/s), fitted to the ranges. Options out of
    range are :class:`OptionError` naming them."""
    _check_range("harmonics", harmonics, 1, MAX_HARMONICS, integer=True)
    _check_range("frequency", frequency, 0.0, MAX_FREQUENCY, low_open=True)
    _check_range("seed", seed, 0, 2 ** 63 - 1, integer=True)
    rng = np.random.default_rng(seed)
    k = len(free_coordinates(model))
    lo, hi, vel = coordinate_ranges(model, half_width)
    names = tuple(model.tree.coordinates[c].label for c in free_coordinates(model))
    traj = FourierTrajectory(names, (lo + hi) / 2, rng.normal(size=(k, harmonics)),
                             rng.normal(size=(k, harmonics)), 2 * np.pi * frequency)
    return fit_to_limits(traj, lo, hi, vel)


def _closed(model) -> bool:
    return bool(model.partition.u1 or model.partition.a1)


def _continue(model, joints, guess, points):
    """Close the loops at each position in ``points`` (rows), each solve starting at the last."""
    for row in points:
        guess = close_configuration(model, dict(zip(joints, row)), guess)
    return guess


def _substeps(start, end) -> int:
    """Intermediate points so that no free coordinate moves more than :data:`MAX_STEP` per solve."""
    return max(1, int(np.ceil(np.max(np.abs(np.asarray(end) - np.asarray(start)), initial=0.0) / MAX_STEP)))


def trajectory_states(model, traj: FourierTrajectory, samples: int) -> list[tuple[State, object]]:
    """``(state, data)`` at ``samples`` times of one period. On a closed chain the loops are closed
    by continuation: from ``q0`` to the first sample along a straight line, then along the
    trajectory itself, in steps of at most :data:`MAX_STEP` of every free coordinate (so Newton
    stays on the reference configuration's assembly mode)."""
    times = traj.times(samples)
    q, qd, qdd = traj.evaluate(times)
    joints = [model.tree.coordinates[c].joint for c in free_coordinates(model)]
    guess, out = model.reference, []
    if _closed(model):
        q0 = np.array([float(model.reference.as_float().positions[j]) for j in joints])
        k = _substeps(q0, q[0])
        guess = _continue(model, joints, guess, q0 + np.outer(np.arange(1, k) / k, q[0] - q0))
    for i in range(samples):
        if _closed(model) and i:
            k = _substeps(q[i - 1], q[i])
            between = traj.evaluate(times[i - 1] + (times[i] - times[i - 1]) * np.arange(1, k) / k)[0]
            guess = _continue(model, joints, guess, between)
        config = close_configuration(model, dict(zip(joints, q[i])), guess)
        state, data = state_from_free(model, config, qd[i], qdd[i])
        out.append((state, data))
        guess = config
    return out


def base_condition(problem: Problem, base: BaseParameters, traj: FourierTrajectory, samples: int) -> float:
    """``cond(W_b)`` of the stacked base columns along ``traj`` (``FAILED`` if a loop does not close)."""
    try:
        rows = []
        for state, data in trajectory_states(problem.model, traj, samples):
            dv = (data.maps.A.v @ state.qdd + data.maps.A.d @ state.qd)[:problem.model.counts.m]
            rows.append(sample_rows(problem, state, data, dv)[0][:, list(base.independent)])
    except (SingularConfigurationError, np.linalg.LinAlgError):
        return FAILED
    cond = np.linalg.cond(np.vstack(rows))
    return float(cond) if np.isfinite(cond) else FAILED


@dataclass(frozen=True)
class Excitation:
    """Result of :func:`optimise_trajectory`."""

    random: FourierTrajectory
    optimised: FourierTrajectory
    cond_random: float
    cond_optimised: float
    evaluations: int
    seconds: float
    samples: int


class _Budget(Exception):
    """Raised inside the optimiser's cost when the evaluations or the time are spent; caught here."""


def check_options(problem: Problem, base: BaseParameters, *, harmonics, frequency, samples, max_evals, budget,
                  seed, half_width=None) -> None:
    """The options of :func:`optimise_trajectory` in range (``budget`` may be ``inf``: then
    ``max_evals`` alone bounds the work), and one period's rows enough for the base parameters
    (``samples x channels >= rank``); typed errors name the option."""
    _check_range("harmonics", harmonics, 1, MAX_HARMONICS, integer=True)
    _check_range("frequency", frequency, 0.0, MAX_FREQUENCY, low_open=True)
    _check_range("samples", samples, 1, MAX_PERIOD_SAMPLES, integer=True)
    _check_range("max_evals", max_evals, 1, MAX_EVALS, integer=True)
    if budget != np.inf:              # no time limit: max_evals bounds the work
        _check_range("budget", budget, 0.0, MAX_BUDGET, low_open=True)
    _check_range("seed", seed, 0, 2 ** 63 - 1, integer=True)
    if half_width is not None:
        _check_range("half_width", half_width, 0.0, 100.0, low_open=True)
    channels = len(problem.channels)
    if samples * channels < base.rank:
        raise TooFewSamplesError(f"rows of one period ({samples} samples x {channels} channels) for cond(W_b)",
                                 samples * channels, base.rank, f"use at least {-(-base.rank // channels)} samples")


def optimise_trajectory(problem: Problem, base: BaseParameters, *, harmonics: int = 5, frequency: float = 0.3,
                        samples: int = 30, max_evals: int = 200, budget: float = 30.0, seed: int = 0,
                        half_width: float | None = None) -> Excitation:
    """Minimise ``cond(W_b)`` over the Fourier coefficients (module docstring). The random start
    is always evaluated; ``max_evals`` and ``budget`` bound the evaluations after it. Options out
    of range are :class:`OptionError` (:func:`check_options`)."""
    check_options(problem, base, harmonics=harmonics, frequency=frequency, samples=samples, max_evals=max_evals,
                  budget=budget, seed=seed, half_width=half_width)
    model = problem.model
    lo, hi, vel = coordinate_ranges(model, half_width)
    start = random_trajectory(model, harmonics=harmonics, frequency=frequency, seed=seed, samples=samples,
                              half_width=half_width)
    k = len(start.names)
    best = {"x": None, "f": np.inf, "n": 0}
    t0 = time.perf_counter()

    def build(x) -> FourierTrajectory:
        a, b = x[:k * harmonics].reshape(k, harmonics), x[k * harmonics:].reshape(k, harmonics)
        return fit_to_limits(replace(start, a=a, b=b), lo, hi, vel)

    def cost(x, first: bool = False) -> float:
        if not first and (best["n"] >= max_evals or time.perf_counter() - t0 > budget):
            raise _Budget
        best["n"] += 1
        f = np.log10(base_condition(problem, base, build(x), samples))
        if f < best["f"]:
            best.update(x=np.array(x), f=f)
        return f

    from scipy.optimize import minimize      # here, not at the top: it slows every CLI command's start-up

    x0 = np.concatenate([start.a.ravel(), start.b.ravel()])
    cond_random = 10 ** cost(x0, first=True)
    try:
        minimize(cost, x0, method="Powell", options={"maxfev": max_evals, "xtol": 1e-3, "ftol": 1e-4})
    except _Budget:
        pass
    return Excitation(start, build(best["x"]), cond_random, float(10 ** best["f"]), best["n"],
                      time.perf_counter() - t0, samples)


#: samples :func:`trajectory_samples` writes at most: on an open chain (evaluated in one batch), and
#: on a closed chain (each sample closes the loops by continuation: 30 to 80 ms on the built-ins)
MAX_DATA_SAMPLES = 100_000
MAX_CLOSED_DATA_SAMPLES = 1_000


def _free_states(model, traj: FourierTrajectory, count: int):
    """``(q, qd, qdd)`` of an open chain at ``count`` times: positions in the generated layout,
    rates on the independent coordinates (``qd = S^-1 qd_free``, :func:`state_from_free`)."""
    from ..codegen.trace import position_layout
    from .states import _selector

    q_free, qd_free, qdd_free = traj.evaluate(traj.times(count))
    joints = [model.tree.coordinates[c].joint for c in free_coordinates(model)]
    order = [joints.index(name) for name, *_ in position_layout(model)]
    s_inv_t = np.linalg.inv(_selector(model)).T
    return q_free[:, order], qd_free @ s_inv_t, qdd_free @ s_inv_t


def _closed_states(model, traj: FourierTrajectory, count: int):
    """``(q, qd, qdd)`` of a closed chain, the loops closed by continuation (:func:`trajectory_states`)."""
    from ..codegen.trace import position_vector

    states = [s for s, _ in trajectory_states(model, traj, count)]
    return (np.array([position_vector(model, s.config) for s in states]), np.array([s.qd for s in states]),
            np.array([s.qdd for s in states]))


def trajectory_samples(problem: Problem, traj: FourierTrajectory, count: int, *, noise: float = 0.0,
                       seed: int = 0):
    """Simulated samples along ``traj`` (:class:`~symgen.identification.data.Samples`: every
    joint's position, ``qd``, ``qdd``, ``tau``): ``tau = Y P`` with the scene's parameters (the
    truth; no constraint or contact force, as :func:`~symgen.identification.data.simulated_samples`
    without ``eta_f`` and ``law``), evaluated in one batch (:mod:`~symgen.identification.batch`),
    plus Gaussian noise of standard deviation ``noise``."""
    from ..codegen.trace import position_layout
    from .batch import batch_rows
    from .data import SAMPLE_LIMIT, Samples, column_names
    from .regressor import make_problem

    model = problem.model
    closed = _closed(model)
    _check_range("data samples", count, 1, MAX_CLOSED_DATA_SAMPLES if closed else MAX_DATA_SAMPLES, integer=True)
    _check_range("noise", noise, 0.0, SAMPLE_LIMIT)
    q, qd, qdd = (_closed_states if closed else _free_states)(model, traj, count)
    full = make_problem(model, eta_f_measured=True, contact=problem.contact)     # n rows: Y itself
    w, _ = batch_rows(full, q, qd, qdd, np.zeros_like(qd), np.zeros((count, model.counts.n - model.counts.m)))
    tau = w @ np.asarray(full.params.values, float)
    tau = tau + noise * np.random.default_rng(seed).normal(size=tau.shape)
    names = column_names(model)
    cols = {f"q_{name}": q[:, k] for k, (name, *_) in enumerate(position_layout(model))}
    cols = {n: cols[n] for n in names["q"] + names["q_dependent"]}
    for group, values in (("qd", qd), ("qdd", qdd), ("tau", tau)):
        cols.update({n: values[:, k] for k, n in enumerate(names[group])})
    return Samples(cols)
