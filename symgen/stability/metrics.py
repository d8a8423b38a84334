"""What the stability suite measures at one state: condition numbers, the residual of the
equations of motion, and the error against the extended-precision model.

* :func:`conditions` -- the 2-norm condition numbers of the matrices model (32) inverts:
  ``[T_u1, T_a1]`` (eq. 9, closed chains only) and ``[J_m; J_f]`` (eq. 18), and of ``M_mm``, the
  block of ``M`` that forward dynamics solves with. Taken from the dense float model with the
  solver's condition limit lifted, so a near-singular state still reports its number.
* :func:`eom_residual` -- forward dynamics (generated ``forward_dynamics``) fed back into inverse
  dynamics (generated ``task_inverse_dynamics``, a separately traced function): the normwise
  relative mismatch ``|tau' - tau|_inf / max(|tau|_inf, |tau'_0|_inf)`` of model (32), where
  ``tau'_0`` is the inverse dynamics at zero acceleration (the scale of the bias forces).
* :func:`reference_error` -- the generated ``dV_m`` against :func:`symgen.accuracy.reference.
  mp_outputs` at 50 digits (or the dense float model where that is too slow), normwise relative.
"""
from __future__ import annotations

import numpy as np

from ..math.fields import FloatField
from ..codegen.runtime import call_by_name
from ..steps import evaluate_maps

#: inputs of the generated functions the suite calls
FUNCTIONS = ("forward_dynamics", "task_inverse_dynamics")


def _cond(a) -> float:
    a = np.asarray(a, dtype=float)
    return float(np.linalg.cond(a)) if a.size else 1.0


def conditions(model, config) -> dict[str, float]:
    """Condition numbers of ``[T_u1, T_a1]``, ``[J_m; J_f]`` and ``M_mm`` at ``config``."""
    fld = FloatField(model.tree.parameters, max_condition=np.inf)
    maps = evaluate_maps(model, config, fld)
    out = {}
    if model.partition.u1 or model.partition.a1:
        out["[T_u1, T_a1]"] = _cond(maps.W.v)
    out["[J_m; J_f]"] = _cond(maps.A.v)
    try:
        data = model.evaluate(config, V_m=np.zeros(model.counts.m), field=fld)
        m = model.counts.m
        out["M_mm"] = _cond(np.asarray(data.M, dtype=float)[:m, :m])
    except (ArithmeticError, np.linalg.LinAlgError):
        out["M_mm"] = float("inf")
    return out


def forward(module, state: dict) -> tuple[np.ndarray, np.ndarray]:
    """``(dV_m, eta_f)`` of the generated ``forward_dynamics`` (``eta_f`` empty when ``n = m``)."""
    out = call_by_name(module, "forward_dynamics", state)
    return np.asarray(out[0]), (np.asarray(out[1]) if len(out) > 1 else np.zeros(0))


def eom_residual(module, state: dict) -> float:
    """Relative residual of model (32) at the generated forward dynamics' answer."""
    dv, eta_f = forward(module, state)
    args = dict(state, dV_m=dv, eta_f=eta_f)
    tau = np.asarray(call_by_name(module, "task_inverse_dynamics", args)[0])
    bias = np.asarray(call_by_name(module, "task_inverse_dynamics",
                            dict(args, dV_m=np.zeros_like(dv), eta_f=np.zeros_like(eta_f)))[0])
    scale = max(float(np.max(np.abs(state["tau"]), initial=0.0)), float(np.max(np.abs(bias), initial=0.0)))
    return float(np.max(np.abs(tau - state["tau"]), initial=0.0) / scale) if scale > 0 else 0.0


def reference_error(model, module, state: dict, *, reference: str = "mp", dps: int = 50) -> float:
    """Normwise relative error of the generated ``dV_m`` against the ``dps``-digit model
    (``reference="mp"``), or against the dense float model (``"float"``: for scenes where the
    ``O(n^3)`` extended-precision evaluation is too slow, e.g. ~10 min for 100 links)."""
    from ..accuracy.reference import mp_outputs
    from ..codegen.reference import reference_outputs

    if reference == "mp":
        want = mp_outputs(model, "forward_dynamics", state, dps=dps)["dV_m"]
    else:
        config = _float_configuration(model, state["q"])
        want = reference_outputs(model, "forward_dynamics", dict(state, config=config))["dV_m"]
    want = np.asarray(want, dtype=float)
    got, _ = forward(module, state)
    scale = float(np.max(np.abs(want), initial=0.0))
    return float(np.max(np.abs(got - want), initial=0.0) / scale) if scale > 0 else float(np.max(np.abs(got)))


def _float_configuration(model, q):
    from ..simulation import StateLayout

    return StateLayout(model).configuration(np.asarray(q, dtype=float))
