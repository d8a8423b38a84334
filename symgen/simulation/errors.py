"""Typed errors of the simulation package (all under :class:`symgen.errors.SymgenError`)."""
from __future__ import annotations

from ..errors import SymgenError


class SimulationError(SymgenError):
    """An integration could not be carried out (diverged, failed, or too costly)."""


class SimulationInputError(SimulationError):
    """Bad input to a simulation: times, steps, methods, states or user force functions."""


class StiffnessError(SimulationError):
    """An explicit method failed or needed too many steps: the problem looks stiff.

    The message always suggests the implicit methods ``Radau`` and ``BDF``.
    """

    def __init__(self, method: str, t: float, detail: str):
        self.method = method
        self.t = t
        super().__init__(f"explicit method {method} {detail} at t = {t:.6g}; the problem looks stiff: "
                         "use an implicit method, method='Radau' or method='BDF'")


class ConstraintViolationError(SimulationError):
    """A state lies off the constraint manifold (loop closures, contact) by more than allowed.

    ``residual`` is the largest absolute position residual (m or rad), ``constraint`` its name.
    """

    def __init__(self, constraint: str, residual: float, hint: str):
        self.constraint = constraint
        self.residual = residual
        super().__init__(f"constraint {constraint!r} is violated by {residual:.3g} {hint}")
