"""Closed-loop simulation: the plant (model (32) with the true parameters) driven by the adaptive
controller of Section 4 (eqs. 34-38) whose estimates start wrong and are integrated with the state.

State ``y = [q; V_m; P_hat (uncertain entries); z]``: joint positions as in
:class:`symgen.simulation.state.StateLayout`, task velocity, the adapted estimates, and the
integral of the constraint-force error ``z = int (eta_fd - eta_f) dt``, which gives the required
constraint force ``eta_fr = eta_fd + K_F z`` (integral force feedback). Per right-hand side one
dense evaluation (:meth:`symgen.model.Model.evaluate`) serves both the controller (its maps and
the actual velocities; parameters come only from ``P_hat``) and the plant
(:func:`symgen.model.solve_forward` with the true contact law). Loop closures are held by
Baumgarte's rate correction (:class:`symgen.simulation.stabilize.Stabilizer`).

The Lyapunov function reported is ``V = 1/2 e^T M_q e + 1/2 sum_k (P_hat_k - P_k)^2 / rho_k`` with
``e = A^-1 [V_mr - V_m; 0]`` in space A (so the mass matrix is the joint-space ``M_q``).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from ..model_solves import solve_forward
from .stabilize import Stabilizer
from .state import StateLayout
from ..control.adaptation import clip_to_bounds, parameter_error_energy, parameter_rate
from ..control.contact import ContactLaw, contact_velocity
from ..control.errors import ControlInputError, ParameterBoundsError
from ..control.law import check_fully_actuated, control
from ..control.parameters import ParameterSet


#: simulated seconds a closed-loop run may last: a right-hand side costs a few ms on the dense
#: model, and the demonstrations need 370 to 2,000 of them per simulated second (README table)
MAX_T_END = 60.0
#: samples of one run (each is one more evaluation of the closed loop)
MAX_SAMPLES = 100_000
#: pieces a run is integrated in (the steps of its progress bar on a terminal)
SEGMENTS = 40


@dataclass
class ControlSettings:
    """Gains and the desired constraint force: ``K_A`` (34), integral force gain ``K_F`` (1/s),
    ``eta_fd`` (n - m), and whether the estimates adapt (38)."""

    gain: object = 10.0
    force_gain: float = 0.0
    eta_fd: object = None
    adapt: bool = True


@dataclass
class ClosedLoopResult:
    """Sampled closed-loop trajectory: task error, constraint-force error, estimates, Lyapunov ``V``."""

    times: np.ndarray
    task_error: np.ndarray          # |e| on the motion components (m and rad mixed as the task is)
    velocity_error: np.ndarray      # |V_mr - V_m|
    force_error: np.ndarray         # |eta_f - eta_fd| (zero when n = m)
    estimates: np.ndarray           # uncertain parameters, one column each
    lyapunov: np.ndarray
    names: tuple[str, ...]
    lower: np.ndarray
    upper: np.ndarray
    true: np.ndarray
    rhs_calls: int
    wall_time: float
    extra: dict = field(default_factory=dict)


def _estimates(p_hat0, params: ParameterSet) -> np.ndarray:
    """``p_hat0`` as floats, one finite number per parameter, or :class:`ControlInputError`
    (:class:`ParameterBoundsError` naming the first non-finite estimate)."""
    try:
        out = np.asarray(p_hat0, dtype=float)
    except (TypeError, ValueError):
        raise ControlInputError(f"p_hat0 must hold real numbers, one per parameter ({len(params)})") from None
    if out.shape != (len(params),):
        raise ControlInputError(f"p_hat0 has shape {out.shape}; the parameter set has {len(params)}")
    bad = np.flatnonzero(~np.isfinite(out))
    if bad.size:
        raise ParameterBoundsError(params.names[bad[0]], f"initial estimate {out[bad[0]]} is not finite")
    return out


class ClosedLoop:
    """The closed-loop right-hand side (see the module docstring)."""

    def __init__(self, model, params: ParameterSet, p_hat0, task, settings: ControlSettings,
                 contact: ContactLaw | None = None):
        check_fully_actuated(model)
        self.model, self.params, self.task, self.settings, self.contact = model, params, task, settings, contact
        self.layout, self.stabilizer = StateLayout(model), Stabilizer(model)
        self.true = np.asarray(params.values, float)
        self.unc = np.flatnonzero(params.uncertain)
        self.lower, self.upper = (np.asarray(a, float)[self.unc] for a in (params.lower, params.upper))
        self.rho = np.asarray(params.rho, float)[self.unc]
        self.p_hat0 = _estimates(p_hat0, params)
        known = np.setdiff1d(np.arange(len(params)), self.unc)
        if not np.array_equal(self.p_hat0[known], self.true[known]):
            raise ControlInputError("p_hat0 differs from a known parameter's value; make it uncertain to adapt it")
        inside = (self.lower <= self.p_hat0[self.unc]) & (self.p_hat0[self.unc] <= self.upper)
        outside = [params.names[k] for k, ok in zip(self.unc, inside) if not ok]
        if outside:
            raise ControlInputError(f"initial estimates outside their bounds: {', '.join(outside)}")
        n, m = model.counts.n, model.counts.m
        self.eta_fd = np.zeros(n - m) if settings.eta_fd is None else np.asarray(settings.eta_fd, float)
        if self.eta_fd.shape != (n - m,):
            raise ControlInputError(f"eta_fd must have shape ({n - m},) (the constraint forces of the scene), "
                                    f"got {self.eta_fd.shape}")
        self.calls = 0

    # ------------------------------------------------------------------ state
    def split(self, y):
        nq, m, k = self.layout.nq, self.model.counts.m, len(self.unc)
        return y[:nq], y[nq:nq + m], y[nq + m:nq + m + k], y[nq + m + k:]

    def initial_state(self, x0) -> np.ndarray:
        return np.concatenate([np.asarray(x0, float), self.p_hat0[self.unc], np.zeros(len(self.eta_fd))])

    def estimates(self, p_unc) -> np.ndarray:
        """``P_hat``: the known values, and the uncertain ones from the state (clipped to their
        bounds against an integrator's overshoot), or frozen at their start without adaptation."""
        p_hat = self.p_hat0.copy()
        if self.settings.adapt:
            p_hat[self.unc] = clip_to_bounds(p_unc, self.lower, self.upper)
        return p_hat

    # ------------------------------------------------------------------ one evaluation
    def evaluate(self, t, y) -> dict:
        q, v_m, p_unc, z = self.split(y)
        q = self.layout.normalized(q)
        config = self.layout.configuration(q)
        data = self.model.evaluate(config, V_m=v_m)
        p_hat = self.estimates(p_unc)
        v_mr, dv_mr, e_task = self.task.required(t, config, data)
        eta_fr = self.eta_fd + self.settings.force_gain * z
        out = control(self.model, data, self.params, p_hat, v_mr, dv_mr, eta_fr=eta_fr if len(z) else None,
                      gain=self.settings.gain, contact=self.contact)
        extra = None
        if self.contact is not None:
            eta_m = self.contact.forces(contact_velocity(data), data.field)
            extra = data.maps.A_inv.v.T @ (data.maps.D_m.v.T @ np.asarray(eta_m, float))
        dv, eta_f = solve_forward(data, out.tau, extra)
        return dict(q=q, v_m=v_m, data=data, p_hat=p_hat, v_mr=v_mr, e_task=e_task, out=out, dv=dv, eta_f=eta_f)

    def __call__(self, t, y) -> np.ndarray:
        self.calls += 1
        ev = self.evaluate(t, y)
        q, data = ev["q"], ev["data"]
        rates = data.maps.P.v @ data.qd
        if self.stabilizer.dependent:
            rates = rates + self.stabilizer.baumgarte(q)
        dp = (parameter_rate(ev["p_hat"][self.unc], ev["out"].s[self.unc], self.lower, self.upper, self.rho)
              if self.settings.adapt else np.zeros(len(self.unc)))
        return np.concatenate([self.layout.position_rates(q, rates), ev["dv"], dp, self.eta_fd - ev["eta_f"]])

    def lyapunov(self, ev) -> float:
        e = ev["out"].e
        kinetic = 0.5 * float(e @ ev["data"].M_q @ e)
        if not self.settings.adapt or not len(self.unc):
            return kinetic
        return kinetic + float(parameter_error_energy(ev["p_hat"][self.unc], self.true[self.unc], self.rho))


def check_run(t_end, samples) -> None:
    """``t_end`` a finite number in ``(0, MAX_T_END]`` and ``samples`` an integer in ``[2, MAX_SAMPLES]``."""
    try:
        t = float(t_end)
    except (TypeError, ValueError):
        t = float("nan")
    if not (0 < t <= MAX_T_END):
        raise ControlInputError(f"t_end = {t_end!r} s: give a finite time > 0 and <= {MAX_T_END:g} s "
                                "(a closed-loop run evaluates the dense model thousands of times per second)")
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or not 2 <= samples <= MAX_SAMPLES:
        raise ControlInputError(f"samples = {samples!r}: give an integer >= 2 and <= {MAX_SAMPLES}")


def _integrate(loop, y0, times, method: str, rtol: float, atol: float, label: str):
    """The closed loop sampled at ``times``, integrated in :data:`SEGMENTS` pieces (one step of the
    progress bar of :func:`symgen.codegen.progress.progress` each, drawn on a terminal only)."""
    from scipy.integrate import solve_ivp      # here: SciPy's import slows every CLI command's start-up

    from ..codegen.progress import progress

    cuts = np.unique(np.linspace(0, len(times) - 1, min(SEGMENTS, len(times) - 1) + 1).round().astype(int))
    t_out, y_out, y = [times[0]], [np.asarray(y0, float)], np.asarray(y0, float)
    for a, b in progress(list(zip(cuts[:-1], cuts[1:])), desc=label or "closed loop",
                         label=lambda ab: f"t = {times[ab[1]]:.3g} s"):
        sol = solve_ivp(loop, (times[a], times[b]), y, method=method, t_eval=times[a + 1:b + 1], rtol=rtol,
                        atol=atol)
        if sol.status != 0:
            reached = sol.t[-1] if len(sol.t) else times[a]
            raise ControlInputError(f"closed-loop integration ({method}) failed at t = {reached:.4g} s: {sol.message}")
        t_out.extend(sol.t)
        y_out.extend(sol.y.T)
        y = sol.y[:, -1]
    return t_out, y_out


def run_closed_loop(loop: ClosedLoop, x0, t_end: float, *, samples: int = 201, rtol: float = 1e-8,
                    atol: float = 1e-10, method: str = "DOP853", label: str = "") -> ClosedLoopResult:
    """Integrate the closed loop from the plant state ``x0 = [q; V_m]`` over ``(0, t_end]``
    (``0 < t_end <=`` :data:`MAX_T_END` s) and sample it at ``samples`` times (``2 ..``
    :data:`MAX_SAMPLES`); out-of-range arguments are :class:`ControlInputError` naming them."""
    check_run(t_end, samples)
    numbers = all(isinstance(v, (int, float, np.floating)) and not isinstance(v, bool) for v in (rtol, atol))
    if not (numbers and 1e-14 <= rtol <= 0.1 and 0 < atol <= 1):
        raise ControlInputError(f"rtol = {rtol!r}, atol = {atol!r}: give 1e-14 <= rtol <= 0.1 and 0 < atol <= 1")
    times = np.linspace(0.0, float(t_end), int(samples))
    start = time.perf_counter()
    t_all, y_all = _integrate(loop, loop.initial_state(x0), times, method, rtol, atol, label)
    wall = time.perf_counter() - start
    rows = [loop.evaluate(t, y) for t, y in zip(t_all, y_all)]
    unc = loop.unc
    return ClosedLoopResult(
        times=np.asarray(t_all),
        task_error=np.array([np.linalg.norm(r["e_task"]) for r in rows]),
        velocity_error=np.array([np.linalg.norm(r["v_mr"] - r["v_m"]) for r in rows]),
        force_error=np.array([np.linalg.norm(r["eta_f"] - loop.eta_fd) for r in rows]),
        estimates=np.array([r["p_hat"][unc] for r in rows]).reshape(len(rows), len(unc)),
        lyapunov=np.array([loop.lyapunov(r) for r in rows]),
        names=tuple(loop.params.names[k] for k in unc), lower=loop.lower, upper=loop.upper,
        true=loop.true[unc], rhs_calls=loop.calls, wall_time=wall)
