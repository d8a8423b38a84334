"""User force functions ``tau(t, q, V_m)`` and ``eta_m(t, q, V_m)``, checked at every call, and
two ready-made torques.

A force function takes the time ``t`` (s), the position vector ``q`` (quaternions unit) and the
motion coordinates ``V_m``, and returns ``tau`` (``n`` actuator forces, conjugate to ``qd`` of
eq. 14: one per actuated coordinate, then zeros for passive independent ones) or ``eta_m`` (the
contact forces of eq. 16). A wrong shape, a non-real value, NaN or infinity raises
:class:`~symgen.simulation.errors.SimulationInputError` naming the function and the time.

A torque object may also define ``potential(q)`` (J): then a run without friction and contact
forces counts as conservative and its energy includes that potential (see :class:`SpringTorque`).
"""
from __future__ import annotations

import numpy as np

from .errors import SimulationInputError
from .state import StateLayout


def function_name(fn) -> str:
    return getattr(fn, "__name__", None) or type(fn).__name__


class CheckedForce:
    """Wraps a force function (or ``None`` for zero) and checks what it returns."""

    def __init__(self, fn, size: int, what: str):
        if fn is not None and not callable(fn):
            constant = np.asarray(fn, dtype=float)
            fn = lambda t, q, v: constant  # noqa: E731 - a constant force
            fn.__name__ = f"constant {what}"
        self.fn, self.size, self.what = fn, size, what
        self.zero = np.zeros(size)

    @property
    def is_zero(self) -> bool:
        return self.fn is None

    def __call__(self, t, q, v_m) -> np.ndarray:
        if self.fn is None:
            return self.zero
        name = function_name(self.fn)
        try:
            value = np.asarray(self.fn(t, q, v_m))
        except (TypeError, ValueError) as exc:
            raise SimulationInputError(f"{self.what} function {name!r} failed at t = {t:.6g}: {exc}") from exc
        if value.dtype.kind not in "biuf":
            raise SimulationInputError(f"{self.what} function {name!r} returned dtype {value.dtype} at t = {t:.6g}; "
                                       "it must return real numbers")
        if value.shape != (self.size,):
            raise SimulationInputError(f"{self.what} function {name!r} returned shape {value.shape} at t = {t:.6g}; "
                                       f"expected ({self.size},)")
        if not np.all(np.isfinite(value)):
            raise SimulationInputError(f"{self.what} function {name!r} returned NaN or infinity at t = {t:.6g}: "
                                       f"{value}")
        return value.astype(float, copy=False)

    def potential(self, q) -> float | None:
        """The force's potential energy at ``q``, or ``None`` when it has none."""
        if self.fn is None:
            return 0.0
        pot = getattr(self.fn, "potential", None)
        return None if pot is None else float(pot(q))


def _actuated_positions(model) -> tuple[np.ndarray, np.ndarray]:
    """``(tau index, q index)`` of every actuated 1-DOF coordinate."""
    layout = StateLayout(model)
    part = model.partition
    tau_idx, q_idx = [], []
    for col, coord in enumerate(part.independent):
        if coord in part.actuated and coord in layout.q_of_coord:
            tau_idx.append(col)
            q_idx.append(layout.q_of_coord[coord])
    return np.array(tau_idx, dtype=int), np.array(q_idx, dtype=int)


class SpringTorque:
    """``tau_i = -K_i (q_i - q0_i)`` on every actuated 1-DOF joint: a conservative torque with
    potential ``1/2 sum K_i (q_i - q0_i)^2``. ``K_i = (2 pi / period)^2 M_q,ii(q0)``, so each
    joint alone would swing with the given period (s) about the scene's reference ``q0``."""

    __name__ = "spring"

    def __init__(self, model, period: float = 1.0, center=None):
        if not np.isfinite(period) or period <= 0:
            raise SimulationInputError(f"spring period must be positive, got {period!r}")
        self.n = model.counts.n
        self.tau_idx, self.q_idx = _actuated_positions(model)
        m_q = np.asarray(model.evaluate(model.reference).M_q, dtype=float)
        self.stiffness = (2 * np.pi / period) ** 2 * np.diag(m_q)[self.tau_idx]
        q0 = StateLayout(model).positions(model.reference)
        self.center = q0[self.q_idx] if center is None else np.asarray(center, dtype=float)

    def __call__(self, t, q, v_m) -> np.ndarray:
        out = np.zeros(self.n)
        out[self.tau_idx] = -self.stiffness * (q[self.q_idx] - self.center)
        return out

    def jacobian(self, t, q, v_m) -> tuple[np.ndarray, np.ndarray]:
        """``(dtau/dq, dtau/dV_m)``: ``-K_i`` at each actuated joint's position, nothing in ``V_m``
        (what :mod:`symgen.simulation.jacobian` uses instead of differencing the torque)."""
        d_q = np.zeros((self.n, len(q)))
        d_q[self.tau_idx, self.q_idx] = -self.stiffness
        return d_q, np.zeros((self.n, len(v_m)))

    def potential(self, q) -> float:
        d = q[self.q_idx] - self.center
        return float(0.5 * self.stiffness @ (d * d))


class SineTorque:
    """``tau_i = a_i sin(2 pi t / period + i)`` on every actuated 1-DOF joint, ``a_i`` chosen as
    ``accel M_q,ii(q0)`` so each joint alone would accelerate at up to ``accel`` (rad/s^2 or m/s^2)."""

    __name__ = "sine"

    def __init__(self, model, accel: float = 1.0, period: float = 1.0):
        self.n = model.counts.n
        self.tau_idx, _ = _actuated_positions(model)
        m_q = np.asarray(model.evaluate(model.reference).M_q, dtype=float)
        self.amplitude = accel * np.diag(m_q)[self.tau_idx]
        self.omega = 2 * np.pi / period

    def __call__(self, t, q, v_m) -> np.ndarray:
        out = np.zeros(self.n)
        out[self.tau_idx] = self.amplitude * np.sin(self.omega * t + np.arange(len(self.tau_idx)))
        return out


TORQUES = {"none": None, "spring": SpringTorque, "sine": SineTorque}


def named_torque(model, name: str):
    """A torque by name: ``none``, ``spring`` (conservative) or ``sine``."""
    if name not in TORQUES:
        raise SimulationInputError(f"unknown torque {name!r}; choose from {', '.join(TORQUES)}")
    maker = TORQUES[name]
    return None if maker is None else maker(model)
