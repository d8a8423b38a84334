"""Typed errors of the control package (all under :class:`symgen.errors.SymgenError`).

Every error names what it is about: the parameter (``m_link3``), the gain (``K_A``), the input.
"""
from __future__ import annotations

from ..errors import SymgenError


class ControlError(SymgenError):
    """A controller (Section 4, eqs. 34-38) cannot be set up or evaluated with the given input."""


class ControlInputError(ControlError):
    """An argument has the wrong shape or kind (a pose that is not 3x3, a gain of wrong size)."""


class ParameterError(ControlError):
    """A parameter of ``P_r`` (eq. 35) or its adaptation data (eq. 38) is invalid.

    ``parameter`` is the parameter's name, e.g. ``"m_link3"``.
    """

    def __init__(self, parameter: str, message: str):
        self.parameter = parameter
        self.message = message
        super().__init__(f"parameter {parameter!r}: {message}")


class UnknownParameterError(ParameterError):
    """A name that is not in the parameter set (a typo, or a joint without that parameter)."""


class ParameterBoundsError(ParameterError):
    """Bounds ``P- > P+``, an estimate outside ``[P-, P+]``, a bound allowing negative mass, or a
    value that is not a finite real number."""


class UpdateGainError(ParameterError):
    """An update gain ``rho_k`` of eq. (38) that is not a finite number ``> 0``."""


class GainMatrixError(ControlError):
    """A feedback gain (``K_A`` of eq. 34, ``Lambda``) that is not symmetric positive definite.

    ``gain`` names it; ``smallest_eigenvalue`` is the smallest eigenvalue of its symmetric part
    (a float, ``nan`` when the matrix is not symmetric or not numeric).
    """

    def __init__(self, gain: str, smallest_eigenvalue: float, message: str):
        self.gain = gain
        self.smallest_eigenvalue = smallest_eigenvalue
        super().__init__(f"gain {gain!r} {message} (smallest eigenvalue {smallest_eigenvalue:.6g}); "
                         "a feedback gain must be symmetric positive definite")
