"""The simulation right-hand side ``dx/dt = f(t, x)`` from the generated code (Remark 2.4).

For ``x = [q; V_m]`` (:mod:`symgen.simulation.state`)::

    dV_m/dt = forward_dynamics(q, V_m, tau(t, q, V_m)[, eta_m(t, q, V_m)])      model (32)
    dq/dt   = position rates of qd_all = joint_rates(q, V_m)                     eqs. (10), (18)
              (+ the Baumgarte correction of the dependent coordinates, if on)

One call of the generated ``state_derivative`` gives both in a single pass (the solve with
``[J_m; J_f]`` and eq. (10) are shared); the semi-implicit Euler step, which needs them at different
``V_m``, calls ``forward_dynamics`` and ``joint_rates`` apart. All come from
:func:`symgen.codegen.runtime.load_generated` for the ``"numpy"`` or ``"c"`` backend; the trace is shared between backends and cached per model. Every evaluation is
counted (:attr:`Dynamics.calls`). Energy for conservative runs: kinetic
``1/2 V_m^T M_mm V_m`` from the generated ``mass_matrix`` (``= 1/2 X^T M_S X``, eq. 32) and the
gravitational potential of the body centres of mass (:class:`~symgen.simulation.poses.Poses`),
plus the torque's own potential when it has one.
"""
from __future__ import annotations

import numpy as np

from ..codegen.targets import TARGETS
from ..errors import SingularConfigurationError
from .errors import SimulationError, SimulationInputError
from .forcing import CheckedForce
from .stabilize import Stabilizer
from .state import StateLayout

#: the generated-code targets a simulation runs on
BACKENDS = TARGETS
#: the generated functions a simulation uses
SIMULATION_FUNCTIONS = ("forward_dynamics", "mass_matrix", "joint_rates", "state_derivative")

_TRACES: dict[int, tuple[object, list]] = {}
_MODULES: dict[tuple[int, str], tuple[object, object]] = {}


def load_backend(model, backend: str):
    """The generated module of ``model`` for ``backend`` with :data:`SIMULATION_FUNCTIONS`
    (traced once per model, compiled once per content for C; cached in this process)."""
    from ..codegen.generate import trace_all
    from ..codegen.runtime import load_generated

    if backend not in BACKENDS:
        raise SimulationInputError(f"unknown backend {backend!r}; choose from {', '.join(BACKENDS)}")
    key = (id(model), backend)
    if key not in _MODULES or _MODULES[key][0] is not model:
        if id(model) not in _TRACES or _TRACES[id(model)][0] is not model:
            _TRACES[id(model)] = (model, trace_all(model, SIMULATION_FUNCTIONS))
        module = load_generated(model, backend, lowered=_TRACES[id(model)][1])
        _MODULES[key] = (model, module)
    return _MODULES[key][1]


def diverged(t: float, detail: str = "") -> SimulationError:
    """The error for a state that became NaN or infinite at time ``t``."""
    return SimulationError(f"the state became non-finite at t = {t:.6g}{f' ({detail})' if detail else ''}; the "
                           "integration diverged: take a smaller step, or for a stiff problem use method='Radau' "
                           "or method='BDF'")


def guarded_call(t, call, *args):
    """Call generated code; a singular solve becomes a typed error with the time, and a
    non-finite result (the generated code's ``NonFiniteOutputError``: overflow of a diverging
    state) a :class:`SimulationError`."""
    try:
        with np.errstate(over="ignore", invalid="ignore"):
            out = call(*args)
    except ArithmeticError as exc:
        raise SingularConfigurationError(f"{getattr(exc, 'what', 'a dense solve')} at t = {t:.6g}",
                                         float(getattr(exc, "condition", float("inf"))),
                                         "the state is at or near a singular configuration") from None
    except ValueError as exc:   # NonFiniteOutputError (an overflow) or a NaN argument
        if hasattr(exc, "output") or "NaN" in str(exc):
            raise diverged(t, str(exc)) from None
        raise
    return out


def has_friction(model) -> bool:
    return any(j.viscous != 0 or j.coulomb != 0 for j in model.tree.joints)


class Dynamics:
    """``f(t, x)`` of one model, backend, force functions and Baumgarte setting.

    Parameters: ``tau`` and ``eta_m`` are force functions of ``(t, q, V_m)`` (``None``: zero;
    :mod:`symgen.simulation.forcing`); ``baumgarte`` turns the rate correction on with
    ``gain`` (1/s). Calling the object evaluates the right-hand side and increments ``calls``.
    """

    def __init__(self, model, backend: str = "numpy", *, tau=None, eta_m=None, baumgarte: bool = False,
                 gain: float | None = None):
        self.model = model
        self.backend = backend
        self.module = load_backend(model, backend)
        self.layout = StateLayout(model)
        cf = model.scene.contact_forces
        self.n_eta = len(cf.components) if cf is not None else 0
        if eta_m is not None and not self.n_eta:
            raise SimulationInputError(f"scene {model.scene.name!r} declares no contact forces; eta_m must be None")
        self.tau = CheckedForce(tau, model.counts.n, "tau")
        self.eta_m = CheckedForce(eta_m, self.n_eta, "eta_m")
        self.stabilizer = Stabilizer(model) if gain is None else Stabilizer(model, gain=gain)
        self.baumgarte = bool(baumgarte) and bool(self.stabilizer.dependent)
        self.calls = 0

    # ------------------------------------------------------------------ pieces
    def _guard(self, t, call, *args):
        """:func:`guarded_call`."""
        return guarded_call(t, call, *args)

    def acceleration(self, t, q, v_m) -> np.ndarray:
        """``dV_m/dt`` from the generated ``forward_dynamics`` (``q`` with unit quaternions)."""
        args = (q, v_m, self.tau(t, q, v_m)) + ((self.eta_m(t, q, v_m),) if self.n_eta else ())
        out = self._guard(t, self.module.forward_dynamics, *args)
        return out[0] if isinstance(out, tuple) else out

    def joint_rates(self, t, q, v_m) -> np.ndarray:
        """``qd_all`` (all joint coordinates), Baumgarte correction included when on."""
        rates = self._guard(t, self.module.joint_rates, q, v_m)
        if self.baumgarte:
            rates = rates + self.stabilizer.baumgarte(q)
        return rates

    def __call__(self, t, x) -> np.ndarray:
        """``dx/dt``: one call of the generated ``state_derivative`` (``dV_m`` and ``qd_all`` in
        one pass), the Baumgarte correction added to the rates when on."""
        self.calls += 1
        q, v_m = self.layout.split(x)
        if not np.all(np.isfinite(x)):
            raise diverged(t)
        q = self.layout.normalized(q)
        args = (q, v_m, self.tau(t, q, v_m)) + ((self.eta_m(t, q, v_m),) if self.n_eta else ())
        dv, rates = self._guard(t, self.module.state_derivative, *args)
        if self.baumgarte:
            rates = rates + self.stabilizer.baumgarte(q)
        return np.concatenate([self.layout.position_rates(q, rates), dv])

    # ------------------------------------------------------------------ energy
    @property
    def conservative(self) -> bool:
        """No friction, no contact force, and a torque that is zero or has a potential."""
        return (not has_friction(self.model) and self.eta_m.is_zero
                and self.tau.potential(self.layout.positions(self.model.reference)) is not None)

    def energy(self, x) -> tuple[float, float]:
        """``(kinetic, potential)`` (J) at state ``x``; the potential includes gravity and the
        torque's potential (if it has one)."""
        q, v_m = self.layout.split(np.asarray(x, dtype=float))
        q = self.layout.normalized(q)
        mass = self._guard(0.0, self.module.mass_matrix, q)
        m = self.layout.m
        kinetic = 0.5 * float(v_m @ mass[:m, :m] @ v_m)
        potential = self.stabilizer.poses.potential_energy(q) + (self.tau.potential(q) or 0.0)
        return kinetic, potential
