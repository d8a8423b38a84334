"""The virtual-decomposition adaptive controller of Section 4 for any scene, dense in any field.

With ``A = [J_m; J_f]``, the required task velocity ``V_mr`` and its derivative ``dV_mr``, the
required constraint force ``eta_fr``, estimates ``P_hat = [P_r; P_m]`` and a positive definite
``K_A`` (n x n, space A)::

    e     = A^-1 [V_mr - V_m; 0]                                 velocity error in space A
    Y     = [T_S^T Y_r, Y_m]                                     eqs. (35)-(37)
    tau   = Y P_hat + J_f^T eta_fr + K_A e                       (34)
    s     = Y^T e,   dP_hat_k/dt = rho_k kappa_k s_k             (38)

With exact parameters and ``V_mr = V_m``, ``dV_mr = dV_m``, ``eta_fr = eta_f``, ``tau`` is the
model's inverse dynamics (32) -- a property ``symgen prove`` checks exactly. ``tau`` lives in
space A, ``[tau_a; 0]`` (eq. 15): every independent coordinate must be actuated.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..model import ModelData
from .contact import ContactLaw, contact_regressor
from .errors import ControlInputError
from .gains import check_positive_definite, gain_matrix
from .parameters import ParameterSet, tree_parameters
from .stacked import joint_regressor, required_velocity, subsystem_regressor


@dataclass(frozen=True)
class ControlOutput:
    """One evaluation of the controller: torque (34), adaptation signal (38) and what they used."""

    tau: np.ndarray           # space A, n
    s: np.ndarray             # eq. (38), one per parameter
    e: np.ndarray             # A^-1 [V_mr - V_m; 0]
    Y: np.ndarray             # n x p, [T_S^T Y_r, Y_m]
    X_r: np.ndarray           # eq. (36)
    dX_r: np.ndarray


def check_fully_actuated(model) -> None:
    """``tau = [tau_a; 0]`` (eq. 15): control (34) needs no unactuated independent coordinate."""
    part = model.partition
    if part.u2:
        names = ", ".join(model.tree.coordinates[c].label for c in part.u2)
        raise ControlInputError(f"scene {model.scene.name!r}: the independent coordinates {names} are not "
                                "actuated (q_u2 of eq. 9); control (34) needs every coordinate of qd actuated")


def default_parameters(model, contact: ContactLaw | None = None, field=None) -> ParameterSet:
    """``P = [P_r; P_m]`` with the scene's values, all known (eqs. 35, 37)."""

    fld = field or model.float_field
    params = list(tree_parameters(model.tree, fld).parameters)
    if contact is not None:
        params += [replace(p, value=fld.const(p.value)) for p in contact.parameters()]
    return ParameterSet(params)


def velocity_error(data: ModelData, v_mr) -> np.ndarray:
    """``e = A^-1 [V_mr - V_m; 0] = Omega (V_mr - V_m)`` (eq. 18)."""
    return data.maps.Omega.v @ (np.asarray(v_mr, dtype=data.field.dtype) - data.V_m)


def regressor(model, data: ModelData, params: ParameterSet, v_mr, dv_mr, *, contact: ContactLaw | None = None,
              gravity: bool = True):
    """``(Y, X_r, dX_r)``: ``Y = [T_S^T Y_r, Y_m]`` (n x p, columns in ``params`` order) at ``data``."""
    x_r, dx_r = required_velocity(data, v_mr, dv_mr)
    y_r = subsystem_regressor(model, data, params, x_r, dx_r, gravity=gravity)
    y = joint_regressor(data, y_r)
    if contact is not None:
        cols = params.owner_indices(contact.frame)
        y[:, cols] = y[:, cols] + contact_regressor(data)
    return y, x_r, dx_r


def control(model, data: ModelData, params: ParameterSet, p_hat, v_mr, dv_mr, *, eta_fr=None, gain=1.0,
            contact: ContactLaw | None = None, gravity: bool = True) -> ControlOutput:
    """Eqs. (34) and (38) at the evaluated actual state ``data`` (``model.evaluate(config, V_m=...)``)."""
    check_fully_actuated(model)
    fld = data.field
    n, m = model.counts.n, model.counts.m
    _check_vector("p_hat", p_hat, len(params.parameters))
    _check_vector("V_mr", v_mr, m)
    _check_vector("dV_mr", dv_mr, m)
    if eta_fr is not None and n > m:
        _check_vector("eta_fr", eta_fr, n - m)
    k_a = gain_matrix(gain, n, "K_A")
    check_positive_definite(k_a, "K_A")
    y, x_r, dx_r = regressor(model, data, params, v_mr, dv_mr, contact=contact, gravity=gravity)
    e = velocity_error(data, v_mr)
    tau = y @ np.asarray(p_hat, dtype=fld.dtype) + fld.array(np.asarray(k_a).tolist()) @ e
    if n > m:
        eta = fld.zeros((n - m,)) if eta_fr is None else np.asarray(eta_fr, dtype=fld.dtype)
        tau = tau + data.maps.J_f.v.T @ eta
    elif eta_fr is not None and len(eta_fr):
        raise ControlInputError(f"scene {model.scene.name!r} has no constraint forces eta_f (n = m); "
                                "eta_fr must be empty")
    return ControlOutput(tau, y.T @ e, e, y, x_r, dx_r)


def _check_vector(name: str, values, size: int) -> None:
    """:func:`symgen.model_solves.check_length` (length, real entries, finiteness), as a
    :class:`ControlInputError` naming ``name``."""
    from ..errors import StateError
    from ..model_solves import check_length

    try:
        check_length(name, values, size)
    except StateError as exc:
        raise ControlInputError(str(exc)) from None
