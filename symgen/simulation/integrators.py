"""Integrators and :func:`simulate`.

Fixed step, written here:

* ``rk4``: the classical fourth-order Runge-Kutta method on ``x = [q; V_m]``, quaternions
  renormalised after each step;
* ``semi_implicit_euler`` (symplectic Euler): ``V_m <- V_m + h dV_m(t, q, V_m)``, then
  ``q <- q`` moved by ``h`` at the rates ``qd_all(q, V_m_new)`` (quaternions along the exact
  rotation, :meth:`~symgen.simulation.state.StateLayout.advance`); first order.

Adaptive, from SciPy's ``solve_ivp``: ``RK45``, ``DOP853`` (explicit) and ``Radau``, ``BDF``
(implicit, for stiff problems; their Jacobian is SciPy's finite differences, or with
``jacobian="generated"`` the generated ``state_derivative_jacobian``,
:mod:`symgen.simulation.jacobian`). An explicit method that fails or
exceeds ``max_rhs_calls`` raises :class:`~symgen.simulation.errors.StiffnessError`, whose
message suggests Radau or BDF.

Stabilization (:mod:`symgen.simulation.stabilize`): ``"auto"`` is projection after every step
for the fixed-step methods and Baumgarte (gain ``gain``, default
:data:`~symgen.simulation.stabilize.BAUMGARTE_GAIN`) for solve_ivp, on scenes with dependent
coordinates; ``"none"`` integrates the positions as they come.
"""
from __future__ import annotations

import time

import numpy as np
from scipy.integrate import solve_ivp

from .dynamics import BACKENDS, Dynamics, diverged
from .errors import ConstraintViolationError, SimulationError, SimulationInputError, StiffnessError
from .stabilize import STABILIZATIONS
from .trajectory import Trajectory

FIXED_METHODS = ("rk4", "semi_implicit_euler")
EXPLICIT_ADAPTIVE = ("RK45", "DOP853")
IMPLICIT_ADAPTIVE = ("Radau", "BDF")
METHODS = FIXED_METHODS + EXPLICIT_ADAPTIVE + IMPLICIT_ADAPTIVE
#: an initial state farther than this from the constraint manifold is refused without stabilization
X0_TOL = 1e-8
#: where the implicit methods' Jacobian comes from
JACOBIANS = ("finite-difference", "generated")
#: default cap on right-hand-side calls of one run (an explicit method hitting it is "stiff")
MAX_RHS_CALLS = 1_000_000


class _CallLimit(Exception):
    def __init__(self, t):
        self.t = t


def resolve_method(method: str) -> str:
    """The canonical name of ``method`` (case-insensitive; ``symplectic_euler`` is an alias)."""
    names = {m.lower(): m for m in METHODS}
    names["symplectic_euler"] = "semi_implicit_euler"
    key = str(method).lower()
    if key not in names:
        raise SimulationInputError(f"unknown method {method!r}; choose from {', '.join(METHODS)}")
    return names[key]


def _positive(name: str, value) -> float:
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise SimulationInputError(f"{name} must be a number, got {value!r}") from None
    if not np.isfinite(value) or value <= 0:
        raise SimulationInputError(f"{name} must be positive and finite, got {value!r}")
    return value


def _resolve_stabilization(stabilization, method: str, model) -> str:
    if stabilization in (None, False):
        stabilization = "none"
    if stabilization == "auto":
        if not (model.partition.u1 or model.partition.a1):
            return "none"
        return "projection" if method in FIXED_METHODS else "baumgarte"
    if stabilization not in STABILIZATIONS:
        raise SimulationInputError(f"unknown stabilization {stabilization!r}; choose from auto, "
                                   f"{', '.join(STABILIZATIONS)}")
    if stabilization == "projection" and method not in FIXED_METHODS:
        raise SimulationInputError(f"projection after each step needs a fixed-step method, not {method}; "
                                   "use stabilization='baumgarte' with solve_ivp methods")
    return stabilization


def _initial_state(dyn: Dynamics, x0, stabilization: str, V_m=None) -> np.ndarray:
    layout, stab = dyn.layout, dyn.stabilizer
    x = layout.state_from(x0, V_m)
    q, v = layout.split(x)
    if stabilization == "none":
        name, value = stab.worst_constraint(q)
        if value > X0_TOL:
            raise ConstraintViolationError(name, value, f"at the initial state (more than {X0_TOL:g}); close the "
                                           "loops first (symgen.closure.solve_closure) or turn stabilization on")
        return x
    return layout.join(stab.project(q), v)


_WITHOUT_GRAVITY: dict[int, tuple[object, object]] = {}


def with_gravity(model, gravity):
    """``model`` (``gravity`` true) or the same scene derived with zero gravity (cached per model,
    so its generated code is traced once)."""
    if not isinstance(gravity, (bool, np.bool_)):
        raise SimulationInputError(f"gravity must be True or False, got {gravity!r}")
    if gravity:
        return model
    cached = _WITHOUT_GRAVITY.get(id(model))
    if cached is None or cached[0] is not model:
        from ..model import derive
        from .scenes import scene_variant

        cached = (model, derive(scene_variant(model.scene, gravity=(0, 0, 0))))
        _WITHOUT_GRAVITY[id(model)] = cached
    return cached[1]


#: right-hand-side calls per step of the fixed-step methods
STAGES = {"rk4": 4, "semi_implicit_euler": 1}


def fixed_step_count(method: str, t_end: float, step: float, max_calls: int) -> int:
    """The number of steps of a fixed-step run; a :class:`SimulationInputError` naming ``step`` and
    ``t_end`` before any work when they need more than ``max_calls`` right-hand-side calls."""
    count = t_end / step - 1e-9
    if not count * STAGES.get(method, 1) <= max_calls:
        raise SimulationInputError(f"step {step:g} s over t_end {t_end:g} s needs {count:.3g} steps of {method}, more "
                                   f"than the {max_calls} right-hand-side calls allowed (max_rhs_calls): take a "
                                   "larger step or a shorter run")
    return max(1, int(np.ceil(count)))


def _fixed_step(dyn: Dynamics, method: str, x, t_end: float, step: float, projection: bool, record_every: int,
                max_calls: int = MAX_RHS_CALLS):
    layout, stab = dyn.layout, dyn.stabilizer
    count = fixed_step_count(method, t_end, step, max_calls)
    h = t_end / count
    times, states, worst = [0.0], [x.copy()], 0.0
    t = 0.0
    for k in range(count):
        if method == "rk4":
            k1 = dyn(t, x)
            k2 = dyn(t + h / 2, x + h / 2 * k1)
            k3 = dyn(t + h / 2, x + h / 2 * k2)
            k4 = dyn(t + h, x + h * k3)
            x = x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
            if not np.all(np.isfinite(x)):
                raise diverged(t + h)
            q, v = layout.split(x)
            q = layout.normalized(q)
        else:
            q, v = layout.split(x)
            dyn.calls += 1
            v = v + h * dyn.acceleration(t, q, v)
            q = layout.advance(q, dyn.joint_rates(t, q, v), h)
        t = (k + 1) * h
        if projection:
            worst = max(worst, stab.drift(q))
            q = stab.project(q)
        x = layout.join(q, v)
        if (k + 1) % record_every == 0 or k + 1 == count:
            times.append(t)
            states.append(x.copy())
    return np.array(times), np.array(states), count, worst


def _adaptive(dyn: Dynamics, method: str, x, t_end: float, rtol: float, atol: float, max_calls: int, t_eval,
              jac=None):
    def fun(t, y):
        if dyn.calls >= max_calls:
            raise _CallLimit(t)
        return dyn(t, y)

    options = {} if jac is None else {"jac": jac}
    try:
        sol = solve_ivp(fun, (0.0, t_end), x, method=method, rtol=rtol, atol=atol, t_eval=t_eval, **options)
    except _CallLimit as limit:
        if method in EXPLICIT_ADAPTIVE:
            raise StiffnessError(method, limit.t, f"needed more than {max_calls} right-hand-side calls") from None
        raise SimulationError(f"{method} needed more than {max_calls} right-hand-side calls at t = {limit.t:.6g}; "
                              "loosen the tolerances or raise max_rhs_calls") from None
    if sol.status != 0:
        t_fail = float(sol.t[-1]) if sol.t.size else 0.0
        if method in EXPLICIT_ADAPTIVE:
            raise StiffnessError(method, t_fail, f"failed ({sol.message})")
        raise SimulationError(f"{method} failed at t = {t_fail:.6g}: {sol.message}")
    states = sol.y.T.copy()
    for row in states:
        q, _ = dyn.layout.split(row)
        q[:] = dyn.layout.normalized(q)
    steps = len(sol.t) - 1 if t_eval is None else -1
    return sol.t.copy(), states, steps, int(getattr(sol, "njev", 0))


def _check_settings(method: str, backend: str, step, rtol, atol, record_every) -> tuple:
    """``(step, rtol, atol)`` of :func:`simulate`, checked: a step for a fixed-step method only,
    tolerances for an adaptive one; a known backend; ``record_every >= 1``."""
    if backend not in BACKENDS:
        raise SimulationInputError(f"unknown backend {backend!r}; choose from {', '.join(BACKENDS)}")
    if method in FIXED_METHODS:
        if step is None:
            raise SimulationInputError(f"fixed-step method {method} needs a step size (step=...)")
        step = _positive("step", step)
    elif step is not None:
        raise SimulationInputError(f"{method} is adaptive: give rtol/atol, not step")
    else:
        rtol = _positive("rtol", rtol)
        atol = rtol if atol is None else _positive("atol", atol)
    if int(record_every) < 1:
        raise SimulationInputError(f"record_every must be a positive integer, got {record_every!r}")
    return step, rtol, atol


def simulate(model, t_end: float, method: str = "DOP853", *, step: float | None = None, rtol: float = 1e-10,
             atol: float | None = None, backend: str = "numpy", stabilization="auto", gain: float | None = None,
             tau=None, eta_m=None, x0=None, V_m=None, gravity: bool = True, energy: bool = True,
             record_every: int = 1, max_rhs_calls: int = MAX_RHS_CALLS, t_eval=None,
             jacobian: str = "finite-difference") -> Trajectory:
    """Integrate ``model`` from ``x0`` (default: reference configuration at rest) over ``[0, t_end]``.

    ``method``: one of :data:`METHODS`; fixed-step methods need ``step`` (s; rounded down so an
    integer number of steps ends at ``t_end``), adaptive ones take ``rtol``/``atol`` (``atol``
    defaults to ``rtol``). ``backend``: ``"numpy"`` or ``"c"`` generated code. ``tau``,
    ``eta_m``: force functions of ``(t, q, V_m)`` or ``None``. ``x0``: the initial state as
    users hold it (:meth:`~symgen.simulation.state.StateLayout.state_from`): a
    :class:`~symgen.math.configuration.Configuration`, a mapping joint -> position or the positions ``q`` in
    scene order (with ``V_m``, default zero), or the whole ``[q; V_m]``; it is projected onto the
    constraint manifold when stabilization is on, and refused if off it by more than
    :data:`X0_TOL` when it is off. ``gravity``: ``False`` simulates without gravity, as
    :meth:`symgen.model.Model.evaluate` evaluates without it (the trajectory's model is then the
    scene with zero gravity).
    ``energy``: evaluate kinetic and potential energy at the recorded states. ``record_every``:
    keep every k-th step of a fixed-step run; ``t_eval``: output times of a solve_ivp run (default:
    every accepted step). ``max_rhs_calls``: an explicit solve_ivp method that needs more raises
    :class:`~symgen.simulation.errors.StiffnessError`; a fixed-step run that would need more is
    refused before it starts (:class:`~symgen.simulation.errors.SimulationInputError`). ``gain``: Baumgarte gain (1/s).
    ``jacobian``: for ``Radau`` and ``BDF``, ``"finite-difference"`` (SciPy's, from extra
    right-hand-side calls) or ``"generated"`` (the generated ``state_derivative_jacobian`` with the
    chain rule through the force functions, :mod:`symgen.simulation.jacobian`; a quaternion's
    four entries as columns; not with Baumgarte's correction and a spherical joint); the trajectory's ``settings`` record it and SciPy's count of Jacobian evaluations
    (``jacobian_calls``; with finite differences each costs ``len(x)`` of the counted right-hand sides).

    Raises :class:`~symgen.simulation.errors.SimulationInputError` for bad arguments or force
    functions, :class:`~symgen.simulation.errors.ConstraintViolationError` for an initial state off
    the manifold without stabilization, :class:`~symgen.errors.SingularConfigurationError` (with
    the time and the condition number) when a solve of the model becomes singular, and
    :class:`~symgen.simulation.errors.SimulationError` when the integration diverges or fails.
    Cost per right-hand side: one generated ``forward_dynamics`` and ``joint_rates`` call (``O(n)``
    recursions plus the dense solves of the scene), plus ``O(N)`` NumPy work for Baumgarte.
    """
    t_end = _positive("t_end", t_end)
    method = resolve_method(method)
    step, rtol, atol = _check_settings(method, backend, step, rtol, atol, record_every)
    if jacobian not in JACOBIANS:
        raise SimulationInputError(f"unknown jacobian {jacobian!r}; choose from {', '.join(JACOBIANS)}")
    if jacobian == "generated" and method not in IMPLICIT_ADAPTIVE:
        raise SimulationInputError(f"jacobian='generated' is for the implicit methods {', '.join(IMPLICIT_ADAPTIVE)}, "
                                   f"not {method}")
    if method in FIXED_METHODS:
        fixed_step_count(method, t_end, step, int(max_rhs_calls))
    stabilization = _resolve_stabilization(stabilization, method, model)
    model = with_gravity(model, gravity)
    dyn = Dynamics(model, backend, tau=tau, eta_m=eta_m, baumgarte=stabilization == "baumgarte", gain=gain)
    x = _initial_state(dyn, x0, stabilization, V_m)
    start = time.perf_counter()
    if method in FIXED_METHODS:
        times, states, steps, worst = _fixed_step(dyn, method, x, t_end, step, stabilization == "projection",
                                                  int(record_every), int(max_rhs_calls))
        settings = {"step": t_end / steps}
    else:
        jac = None
        if jacobian == "generated":
            from .jacobian import StateJacobian

            jac = StateJacobian(dyn)
        times, states, steps, njev = _adaptive(dyn, method, x, t_end, rtol, atol, int(max_rhs_calls), t_eval, jac)
        worst = 0.0
        settings = {"rtol": rtol, "atol": atol}
        if method in IMPLICIT_ADAPTIVE:
            settings["jacobian"] = jacobian
            settings["jacobian_calls"] = njev
    wall = time.perf_counter() - start
    if stabilization == "baumgarte":
        settings["gain"] = dyn.stabilizer.gain
    drift = np.array([dyn.stabilizer.drift(dyn.layout.split(s)[0]) for s in states])
    traj = Trajectory(dyn.layout, method, backend, stabilization, times, states, dyn.calls, steps, wall, drift,
                      worst, conservative=dyn.conservative, settings=settings)
    if energy:
        values = np.array([dyn.energy(s) for s in states])
        traj.kinetic, traj.potential = values[:, 0], values[:, 1]
    return traj
