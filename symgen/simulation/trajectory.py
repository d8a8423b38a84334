"""The result of :func:`~symgen.simulation.integrators.simulate`: recorded states and their cost,
constraint drift and energy."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..math.configuration import Configuration
from .state import StateLayout


@dataclass
class Trajectory:
    """Recorded states ``x = [q; V_m]`` at ``times`` and what they cost.

    * ``rhs_calls``: right-hand-side evaluations (one ``forward_dynamics`` + one ``joint_rates``
      each; finite-difference Jacobians of Radau/BDF included); ``steps``: accepted steps;
    * ``wall_time``: seconds spent integrating (loading/compiling code and the drift and energy
      evaluation below excluded);
    * ``drift``: ``max |r|`` of the constraint residuals at each recorded state (m or rad);
      ``step_drift``: the largest residual seen *before* a projection (projection runs only);
    * ``kinetic``, ``potential``: energies (J) at each recorded state, when computed;
      ``conservative``: no friction, no contact force, and zero torque or a torque with a potential.
    """

    layout: StateLayout
    method: str
    backend: str
    stabilization: str
    times: np.ndarray
    states: np.ndarray
    rhs_calls: int
    steps: int
    wall_time: float
    drift: np.ndarray
    step_drift: float = 0.0
    kinetic: np.ndarray | None = None
    potential: np.ndarray | None = None
    conservative: bool = False
    settings: dict = field(default_factory=dict)

    @property
    def final_state(self) -> np.ndarray:
        return self.states[-1]

    @property
    def t_end(self) -> float:
        return float(self.times[-1])

    def q(self, k: int = -1) -> np.ndarray:
        """Position vector at record ``k`` (default: the last)."""
        return self.layout.split(self.states[k])[0]

    def V_m(self, k: int = -1) -> np.ndarray:
        return self.layout.split(self.states[k])[1]

    def configuration(self, k: int = -1) -> Configuration:
        return self.layout.configuration(self.q(k))

    @property
    def max_drift(self) -> float:
        """Largest constraint residual over the recorded states."""
        return float(np.max(self.drift)) if self.drift.size else 0.0

    @property
    def energy(self) -> np.ndarray | None:
        return None if self.kinetic is None else self.kinetic + self.potential

    @property
    def energy_drift(self) -> float | None:
        """``max_t |E(t) - E(0)| / max_t T(t)`` for a conservative run (``None`` otherwise).

        The kinetic-energy scale makes the measure independent of the potential's datum."""
        if not self.conservative or self.kinetic is None:
            return None
        e = self.energy
        scale = float(np.max(self.kinetic))
        return float(np.max(np.abs(e - e[0])) / scale) if scale > 0 else 0.0

    def summary(self) -> dict:
        """Plain-number summary (JSON-ready)."""
        labels = self.layout.coordinate_labels()
        return {"method": self.method, "backend": self.backend, "stabilization": self.stabilization,
                "settings": self.settings, "t_end": self.t_end,
                "final_state": dict(zip(labels, map(float, self.final_state))),
                "max_drift": self.max_drift, "step_drift": self.step_drift, "energy_drift": self.energy_drift,
                "rhs_calls": self.rhs_calls, "steps": self.steps, "wall_time": self.wall_time}
