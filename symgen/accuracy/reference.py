"""Extended-precision values of the generated functions' outputs, from the dense model (32).

:func:`mp_outputs` mirrors :func:`symgen.codegen.reference.reference_outputs` (same functions,
same output names, same formulas) but evaluates :meth:`symgen.model.Model.evaluate` in
:class:`~symgen.math.fields.MpField` at the generated function's own inputs: the float arrays of a
state (``q``, ``qd``, ``V_m``, ...) are taken at their exact binary values, so the reference is
the exact function of what the generated code receives, to about ``dps`` digits.

Positions come from ``q`` (:func:`mp_configuration`), not from the state's float
``Configuration``: a revolute angle gives ``cos`` and ``sin`` at ``dps`` digits, a prismatic
displacement its value, and a quaternion ``(w, x, y, z)`` the rotation ``R(q) / |q|^2`` -- the
rotation it stands for; the generated code assumes ``|q| = 1`` and drops the division, which
differs by the float rounding of ``|q|`` (about 1e-16). Closed chains are evaluated at ``q`` as
given (all joints), like the generated code: the identities hold whether or not the float ``q``
closes the loops exactly.
"""
from __future__ import annotations

import numpy as np

from ..math.fields import MpField
from ..codegen.reference import ReferenceState, field_configuration
from ..errors import CodegenError
from ..math.configuration import Configuration
from . import AccuracyError


def mp_configuration(model, q, field: MpField) -> Configuration:
    """The configuration of the generated code's position vector ``q`` in ``field``
    (:func:`symgen.codegen.reference.field_configuration`)."""
    try:
        return field_configuration(model, q, field)
    except CodegenError as exc:
        raise AccuracyError(str(exc)) from None


class MpState(ReferenceState):
    """One state in extended precision (:class:`symgen.codegen.reference.ReferenceState` in an
    :class:`MpField`): positions from ``q``, the other inputs taken exactly."""

    def __init__(self, model, state: dict, field: MpField):
        state = {k: v for k, v in state.items() if k != "config"}
        try:
            super().__init__(model, state, field)
        except CodegenError as exc:
            raise AccuracyError(str(exc)) from None

    def outputs(self, name: str) -> dict[str, np.ndarray]:
        if name not in REFERENCE_FUNCTIONS:
            raise AccuracyError(f"no extended-precision reference for function {name!r}; choose from "
                                f"{', '.join(REFERENCE_FUNCTIONS)}")
        return super().outputs(name)


#: functions ``symgen accuracy`` compares (those of :meth:`MpState.outputs`)
REFERENCE_FUNCTIONS = ("inverse_dynamics", "task_inverse_dynamics", "forward_dynamics", "mass_matrix",
                       "coriolis_times_v", "gravity", "joint_rates")


def mp_outputs(model, function_name: str, state: dict, *, dps: int = MpField.default_dps) -> dict[str, np.ndarray]:
    """Extended-precision outputs of generated function ``function_name`` at ``state`` (a dict
    as :func:`symgen.codegen.reference.reference_states` makes), rounded to float64.

    Same names as :func:`~symgen.codegen.reference.reference_outputs`; computed at ``dps``
    decimal digits (>= 20) from the state's float inputs taken exactly.
    """
    if function_name not in REFERENCE_FUNCTIONS:
        raise AccuracyError(f"no extended-precision reference for function {function_name!r}; choose from "
                            f"{', '.join(REFERENCE_FUNCTIONS)}")
    field = make_mp_field(model, dps)
    values = MpState(model, state, field).outputs(function_name)
    return {k: field.to_float(v) for k, v in values.items()}


def check_dps(dps) -> int:
    """``dps`` as an int; :class:`AccuracyError` unless it is an integer >= ``MpField.min_dps``."""
    if isinstance(dps, bool) or not isinstance(dps, (int, np.integer)) or dps < MpField.min_dps:
        raise AccuracyError(f"dps must be an integer >= {MpField.min_dps} (a reference needs more digits "
                            f"than float64's 16), got {dps!r}")
    return int(dps)


def make_mp_field(model, dps: int) -> MpField:
    """An :class:`MpField` for ``model``'s parameters; a typed error for too few digits."""
    return MpField(model.tree.parameters, dps=check_dps(dps))


def relative_error(got, want, field: MpField, floor: float) -> float:
    """Normwise relative error ``|got - want|_inf / max(|want|_inf, floor)`` with ``want`` the
    unrounded mpf reference and ``got`` (floats) taken exactly; the floor keeps an output that
    is zero in exact arithmetic from dividing rounding noise by nothing."""
    want = np.asarray(want, dtype=object).ravel()
    got = np.asarray(got, dtype=float).ravel()
    if got.shape != want.shape:
        raise AccuracyError(f"output has {got.size} entries, the reference {want.size}")
    if want.size == 0:
        return 0.0
    if not np.all(np.isfinite(got)):
        return float("inf")
    diff = max(abs(field.const(float(g)) - w) for g, w in zip(got, want))
    scale = max(max(abs(w) for w in want), field.const(floor))
    return float(diff / scale)
