"""The generated ``control`` (eq. 34) and ``adaptation`` (eq. 38): their inputs, the task-space
part around the recursion of :mod:`symgen.control.recursive`, and their dense reference.

Inputs, in order::

    control(q, V_m, V_mr, dV_mr[, eta_fr][, P_hat][, K_A]) -> tau        (n)
    adaptation(q, V_m, V_mr, dV_mr) -> s                                 (one per uncertain parameter)

``eta_fr`` only when ``n > m``; ``P_hat`` holds the uncertain parameters in the order of
:func:`symgen.control.law.default_parameters` (joints, then bodies, then the contact law) and is
absent when none is uncertain; ``K_A`` is an ``n x n`` input (row-major) only when generated with
``gain="input"`` -- by default it is folded (``K_A = gain``, 1 when not given). ``adaptation``
does not depend on ``P_hat``. The functions read a :class:`~symgen.codegen.builder.Builder`
(its inputs and task solves) without importing it.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import steps
from ..control.errors import ControlInputError
from ..control.law import control as dense_control
from ..control.law import default_parameters
from ..control.parameters import BODY_QUANTITIES
from ..dynamics.algebra import dot
from ..control.recursive import (BodyMotion, ControlSpec, body_signal, parameter_nodes, regressor_torque,
                  required_motion, unit, velocity_pass)


@dataclass
class RequiredRates:
    """``A``, the actual rates, the velocity error ``e`` and the required rates and accelerations
    (space A and all joint coordinates)."""

    a: np.ndarray
    qd: list
    e: list
    qd_all: list
    e_all: list
    qd_r_all: list
    qdd_r_all: list


def required_rates(t, v_m, v_mr, dv_mr) -> RequiredRates:
    """``[qd, e] = A^-1 [[V_m, V_mr - V_m]; 0]`` in one solve, ``qd_r = qd + e`` (eq. 36),
    ``qdd_r = A^-1 ([dV_mr; 0] - dA/dt qd_r)`` with the jets' derivatives along the actual
    ``qd_all`` contracted with the required rates (:func:`symgen.steps.rate_bias`,
    :func:`symgen.steps.acceleration_bias`), and eqs. (10)-(11)."""
    n, m = t.n, t.m
    a = t.task_matrix()
    rhs = np.array([[v_m[i], v_mr[i] - v_m[i]] for i in range(m)] + [[0, 0]] * (n - m), dtype=object)
    sol = t.solve_task(a, rhs)
    qd, e = list(sol[:, 0]), list(sol[:, 1])
    qd_r = [x + y for x, y in zip(qd, e)]
    qd_all, qd_r_all = t.complete_rates(qd), t.complete_rates(qd_r)
    _, kin = t.rate_bias(qd_all)
    bias_r = [0] * t.tree.n_coords
    if t.part.u1:
        bias_r = list(steps.rate_bias(t.field, t._constraints(kin), t.blocks, t.part, qd_r_all))
    rhs = [x - y for x, y in zip(list(dv_mr) + [0] * (n - m), t.task_bias(qd_r_all, bias_r, kin))]
    qdd_r = t.solve_task(a, rhs)
    return RequiredRates(a, qd, e, qd_all, t.complete_rates(e), qd_r_all,
                         t.complete_accelerations(list(qdd_r), bias_r))


def _gravity(t):
    return tuple(t.consts.gravity)


def _common_inputs(b):
    m = b.m
    return (b.arg("V_m", m, "actual task velocity (eq. 17)"),
            b.arg("V_mr", m, "required task velocity (eq. 34)"),
            b.arg("dV_mr", m, "time derivative of V_mr"))


def _contact(t, spec: ControlSpec, qd):
    """``(D_m, v_c = D_m qd)`` of eqs. (16), (37), or ``(None, None)``."""
    d_m = t.contact_map() if spec.contact is not None else None
    return (None, None) if d_m is None else (d_m, [dot(row, qd) for row in d_m])


def trace_control(b, spec: ControlSpec) -> list:
    """Eq. (34) recorded into ``b``'s graph; the ``(name, nodes, doc)`` outputs."""
    t, n, m = b.t, b.n, b.m
    v_m, v_mr, dv_mr = _common_inputs(b)
    eta_fr = b.arg("eta_fr", n - m, "required constraint forces (eq. 34)") if n > m else []
    p_hat = (b.arg("P_hat", len(spec.uncertain), "estimates of the uncertain parameters, in the order of "
                   "default_parameters (names in the docstring and ops.json)") if spec.uncertain else [])
    k_in = b.arg("K_A", n * n, "feedback gain K_A (n x n, row-major), symmetric positive definite") \
        if isinstance(spec.gain, str) else None
    r = required_rates(t, v_m, v_mr, dv_mr)
    values = parameter_nodes(t, spec, p_hat)
    motion = required_motion(t, r.qd_all, r.qd_r_all, r.qdd_r_all, _gravity(t))
    tau = regressor_torque(t, values, r.qd_all, r.qd_r_all, r.qdd_r_all, motion)
    d_m, v_c = _contact(t, spec, r.qd)
    if d_m is not None:                                   # Y_m P_m = D_m^T eta_m, eq. (37)
        comps = spec.contact.components
        eta = [values[f"b_{c}_{spec.contact.frame}"] * v + values[f"c_{c}_{spec.contact.frame}"] * t.field.sign(v)
               for c, v in zip(comps, v_c)]
        tau = [x + dot(d_m[:, i], eta) for i, x in enumerate(tau)]
    tau = [x + y for x, y in zip(tau, r.a.T @ np.array([0] * m + list(eta_fr), dtype=object))]
    k_a = spec.gain if k_in is None else np.array(k_in, dtype=object).reshape(n, n)
    tau = [x + dot(k_a[i], r.e) for i, x in enumerate(tau)]
    return [("tau", tau, "actuator forces (n)")]


def _joint_signals(t, r: RequiredRates) -> dict:
    """``Y_1j^T e_j = [qdd_r, qd, sign qd] e_j`` and ``Y_3i^T e_i = [w . e_i, w/|w| . e_i]``."""
    out = {}
    for joint in t.tree.joints:
        coords = list(joint.coords)
        if joint.kind.dof == 1:
            c = coords[0]
            e, qd = r.e_all[c], r.qd_all[c]
            out.update({f"Ir_{joint.name}": r.qdd_r_all[c] * e, f"b_{joint.name}": qd * e,
                        f"c_{joint.name}": t.field.sign(qd) * e})
        elif joint.kind.dof == 3:
            w, e = [r.qd_all[c] for c in coords], [r.e_all[c] for c in coords]
            out.update({f"b_{joint.name}": dot(w, e), f"c_{joint.name}": dot(unit(w, t.g), e)})
    return out


def trace_adaptation(b, spec: ControlSpec) -> list:
    """``s = Y^T e`` of eq. (38) for the uncertain parameters, recorded into ``b``'s graph."""
    t = b.t
    if not spec.uncertain:
        raise ControlInputError(f"scene {t.model.scene.name!r}: adaptation needs at least one uncertain "
                                "parameter (every parameter is folded)")
    v_m, v_mr, dv_mr = _common_inputs(b)
    r = required_rates(t, v_m, v_mr, dv_mr)
    motion = required_motion(t, r.qd_all, r.qd_r_all, r.qdd_r_all, _gravity(t))
    x_e = velocity_pass(t, r.e_all)
    s = _joint_signals(t, r)
    for k, body in enumerate(t.tree.bodies):
        mo: BodyMotion = motion[k]
        if not body.massless and mo is not None:
            s.update({f"{q}_{body.name}": v for q, v in zip(BODY_QUANTITIES, body_signal(mo, *x_e[k]))})
    d_m, v_c = _contact(t, spec, r.qd)
    if d_m is not None:
        frame = spec.contact.frame
        for comp, row, v in zip(spec.contact.components, d_m, v_c):
            de = dot(row, r.e)
            s.update({f"b_{comp}_{frame}": v * de, f"c_{comp}_{frame}": t.field.sign(v) * de})
    return [("s", [s[name] for name in spec.uncertain_names],
             "adaptation signals s_k = Y_k^T e of the uncertain parameters, in the order of P_hat")]


def parameter_doc(spec: ControlSpec) -> str:
    """The docstring's account of ``P_hat`` and ``K_A``."""
    names = spec.uncertain_names
    listed = ", ".join(names) if names else "none (every parameter folded)"
    gain = "K_A is an n x n input (row-major)" if isinstance(spec.gain, str) else "K_A folded at generation time"
    return (f"P_hat (uncertain parameters, order of symgen.control.law.default_parameters: joints, bodies, "
            f"contact law): {listed}; the other parameters are the scene's values. {gain}.")


# ------------------------------------------------------------------------- dense reference
def reference_inputs(model, spec: ControlSpec, state: dict, seed: int = 0) -> dict:
    """Random ``V_mr, dV_mr, eta_fr, P_hat`` (and ``K_A``) for ``state`` (the estimates are the
    scene's values off by up to 50 %)."""
    rng = np.random.default_rng(seed + 34)
    m, n = model.counts.m, model.counts.n
    values = np.asarray(default_parameters(model, spec.contact).values, dtype=float)[list(spec.uncertain)]
    out = dict(V_mr=np.asarray(state["V_m"], float) + rng.uniform(-1, 1, m), dV_mr=rng.uniform(-1, 1, m),
               eta_fr=rng.uniform(-1, 1, n - m),
               P_hat=values * (1 + 0.5 * rng.uniform(-1, 1, values.size)) + 0.1 * rng.uniform(-1, 1, values.size))
    if isinstance(spec.gain, str):
        k = rng.uniform(-1, 1, (n, n))
        out["K_A"] = (k @ k.T + n * np.eye(n)).ravel()
    return out


def reference_outputs(model, spec: ControlSpec, name: str, state: dict, field=None) -> dict:
    """``{"tau": ...}`` or ``{"s": ...}`` from the dense controller of :mod:`symgen.control.law`,
    in ``field`` (float by default; an ``mp`` field takes the state's floats exactly and returns
    its own numbers)."""
    from .field_configuration import field_configuration

    fld = field or model.float_field
    n, m = model.counts.n, model.counts.m
    params = default_parameters(model, spec.contact, field=fld)
    p = np.array(params.values, dtype=fld.dtype)
    p[list(spec.uncertain)] = [fld.const(v) for v in state["P_hat"]] if spec.uncertain else []
    gain = np.reshape(state["K_A"], (n, n)) if isinstance(spec.gain, str) else spec.gain
    config = state["config"] if fld.dtype is float else field_configuration(model, state["q"], fld)
    data = model.evaluate(config, V_m=state["V_m"], field=fld)
    out = dense_control(model, data, params, p, state["V_mr"], state["dV_mr"],
                        eta_fr=state["eta_fr"] if n > m else None, gain=gain, contact=spec.contact)
    tau, s = (out.tau, out.s) if fld.dtype is not float else (np.asarray(out.tau, float), np.asarray(out.s, float))
    return {"tau": tau} if name == "control" else {"s": s[list(spec.uncertain)]}
