"""Model (32) solved at an evaluated state, and the checks of what the Python API is handed and
returns: forward dynamics for ``(dV_m, eta_f)``, inverse dynamics for ``tau``, in any field."""
from __future__ import annotations

import numbers
from typing import TYPE_CHECKING, Protocol

import numpy as np
import sympy as sp

from .math.fields import Field
from .math.scalar import FieldVector
from .errors import NonFiniteResultError, SingularConfigurationError, StateError

if TYPE_CHECKING:
    from .steps.pipeline import Maps


class Evaluation(Protocol):
    """What the solves of model (32) read of an evaluated state: a :class:`symgen.model.ModelData`
    (model.py imports this module, so it is named by what is used) -- its field, the maps of
    Steps 4-11, the velocities and ``M``, ``c = C [V_m; 0]``, ``G`` of eq. (32)."""

    @property
    def field(self) -> Field: ...

    @property
    def maps(self) -> Maps: ...

    @property
    def qd(self) -> np.ndarray: ...

    @property
    def V_m(self) -> np.ndarray: ...

    @property
    def eta_m(self) -> np.ndarray: ...

    @property
    def M(self) -> np.ndarray: ...

    @property
    def c(self) -> np.ndarray: ...

    @property
    def G(self) -> np.ndarray: ...


def solve_forward(data: Evaluation, tau: FieldVector,
                  extra_g: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Model (32) solved for ``(dV_m, eta_f)`` at evaluated ``data``, in its field: ``M_mm dV_m =
    (A^-T tau - C [V_m; 0] - G)_m``, then ``eta_f`` from the remaining rows. ``extra_g`` (n) is
    added to ``G`` (e.g. contact forces ``A^-T D_m^T eta_m`` found after the evaluation)."""
    fld, m = data.field, len(data.V_m)
    g = data.G if extra_g is None else data.G + extra_g
    rhs = data.maps.A_inv.v.T @ field_vector(fld, tau) - data.c - g
    what = "the motion block of M (eq. 32)"
    if fld.dtype is float:
        cond = np.linalg.cond(data.M[:m, :m])
        if not np.isfinite(cond) or cond > 1e14:
            raise SingularConfigurationError(what, float(cond))
        dv = np.linalg.solve(data.M[:m, :m], rhs[:m])
    else:
        dv = fld.solve(data.M[:m, :m], rhs[:m], what)
    return dv, rhs[m:] - data.M[m:, :m] @ dv


def solve_inverse(data: Evaluation, dV_m: FieldVector, eta_f: FieldVector | None = None) -> np.ndarray:
    """``tau = [J_m; J_f]^T (M [dV_m; 0] + C [V_m; 0] + G + [0; eta_f])`` of model (32) at
    evaluated ``data``, in its field."""
    fld, m, n = data.field, len(data.V_m), data.M.shape[0]
    ef = fld.zeros((n - m,)) if eta_f is None else field_vector(fld, eta_f)
    lhs = data.M[:, :m] @ field_vector(fld, dV_m) + data.c + data.G \
        + np.concatenate([fld.zeros((m,)), ef])
    return data.maps.A.v.T @ lhs


def field_vector(fld: Field, values: FieldVector) -> np.ndarray:
    """A vector of numbers (floats taken at their exact binary value) as an array of ``fld``."""
    if fld.dtype is float:
        return np.asarray(values, dtype=float)
    return np.array([fld.const(v) for v in np.asarray(values, dtype=object).ravel()], dtype=object)


def check_length(name: str, value: FieldVector | None, expected: int) -> None:
    """``value`` (if given) has ``expected`` entries, and none is NaN or infinite."""
    if value is None:
        return
    try:
        shape = np.shape(value)
    except ValueError:                       # a ragged nesting
        shape = None
    if shape != (expected,):
        raise StateError(f"{name} must have shape ({expected},), got {'a ragged sequence' if shape is None else shape}")
    for k, v in enumerate(np.asarray(value, dtype=object)):
        if isinstance(v, (bool, np.bool_)) or not isinstance(v, (numbers.Real, sp.Basic)):
            raise StateError(f"{name}[{k}] must be a real number, got {type(v).__name__}")
        if isinstance(v, (float, np.floating)) and not np.isfinite(v):
            raise StateError(f"{name}[{k}] is {float(v)} (not finite)")


def required(name: str, value: FieldVector | None) -> FieldVector:
    if value is None:
        raise StateError(f"{name} is required")
    return value


def finite_result(function: str, output: str, values: np.ndarray) -> np.ndarray:
    """``values`` unchanged, or :class:`NonFiniteResultError` naming the function and output
    when a float entry is NaN or infinite (an input near overflow)."""
    arr = np.asarray(values)
    if arr.dtype.kind == "f" and not np.all(np.isfinite(arr)):
        raise NonFiniteResultError(f"{function}: the result {output} is not finite (an input near overflow?)")
    return values
