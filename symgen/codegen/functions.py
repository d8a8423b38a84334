"""The functions symgen emits, each traced into its own graph (one CSE scope per function).

=========================  ==================================================================
``inverse_dynamics``       ``(q, qd, qdd) -> tau``: ``M_q qdd + C_q qd + G_q`` on the
                           independent coordinates (eqs. 10-11 inside for closed chains)
``task_inverse_dynamics``  ``(q, V_m, dV_m[, eta_f][, eta_m]) -> tau`` from (32)
``forward_dynamics``       ``(q, V_m, tau[, eta_m]) -> (dV_m[, eta_f])`` from (32)
``mass_matrix``            ``q -> M`` of (32), ``n x n``
``coriolis_times_v``       ``(q, V_m) -> C [V_m; 0]`` of (32)
``gravity``                ``(q[, V_m][, eta_m]) -> G`` of (32) (friction ``xi`` and the contact
                           term ``A^-T D_m^T eta_m`` included, as in the paper)
``joint_rates``            ``(q, V_m) -> qd_all = P A^-1 [V_m; 0]`` (eqs. 10, 18): the rates of
                           every joint coordinate, the simulation's position kinematics
=========================  ==================================================================

On request only (by name; never in the default set, so ``generated/`` does not change):

=========================  ==================================================================
``state_derivative``       ``(q, V_m, tau[, eta_m]) -> (dV_m, qd_all)``, the simulation's one pass
``dynamics_terms``         ``(q, V_m[, eta_m]) -> (M, c, G)``: the three terms of (32) at one
                           state, kinematics and the ``[J_m; J_f]`` solve computed once
``joint_accelerations``    ``(q, V_m, tau[, eta_m]) -> (qd_all, qdd_all)``: forward dynamics (32),
                           then the rates and accelerations of every joint (eqs. 10-11)
``loop_forces``            ``(q, V_m, tau[, eta_m]) -> lam``: the force of every loop-closure
                           constraint on frame A's body, at A's origin in A's axes
                           (:mod:`symgen.steps.loop_forces`)
``control``                ``(q, V_m, V_mr, dV_mr[, eta_fr][, P_hat][, K_A]) -> tau``: the
                           adaptive law (34) by recursion (:mod:`symgen.control.recursive`)
``adaptation``             ``(q, V_m, V_mr, dV_mr) -> s``: ``s = Y^T e`` of (38), one entry per
                           uncertain parameter
=========================  ==================================================================

and ``inverse_dynamics_derivatives``, ``(q, qd, qdd) -> (dtau_dq, dtau_dqd, M)``: the Jacobians of
``inverse_dynamics``, by forward differentiation of its traced graph
(:mod:`symgen.codegen.dynamics_derivatives`, built there); ``forward_dynamics_derivatives`` and
``state_derivative_jacobian``, the Jacobians of ``forward_dynamics`` and ``state_derivative`` in
``q``, ``V_m`` and ``tau`` (:mod:`symgen.codegen.forward_derivatives`, built there).

With ``A = [J_m; J_f]``: ``qd = A^-1 [V_m; 0]`` and ``qdd = A^-1 ([dV_m; 0] - dA/dt qd)``; then
``A^T (M [dV_m; 0] + C [V_m; 0] + G) = M_q qdd + C_q qd + G_q + D_m^T eta_m``, so each function is
the recursive joint-space pass plus solves with ``A`` -- solves that fold away when ``A`` is
constant (motion given on joints). ``M_q`` itself comes from the composite-rigid-body algorithm
(:mod:`symgen.dynamics.crba`), not from one recursive pass per column.

For a tree (``n_c = 0``) ``forward_dynamics``, ``state_derivative`` and ``joint_accelerations`` are
also traced by the articulated-body recursion (:mod:`symgen.codegen.aba`, ``O(N)``, no ``M``), and
where ``V_m`` are joint rates with exactly ``n_c`` coordinates left (a robot standing on its feet)
by the null space of the loop closures (:mod:`symgen.codegen.null_space`); the route with fewer
operations is kept and recorded (:func:`_choose`, option ``method``).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .. import steps
from ..dynamics.algebra import dot
from ..dynamics.rnea import joint_friction, rnea
from ..errors import CodegenError
from ..math.jet import matmul as product
from . import aba, null_space
from .builder import (MOTION_BLOCK, Argument, Builder, Function, eta_m_size, has_friction, has_gravity,
                      has_springs, projected_mass)

__all__ = ["Argument", "ChosenFunction", "Function", "traced_cost"]


def _inverse_dynamics(model) -> Function:
    b = Builder(model)
    _, _, tau = b.joint_space_forces()
    return b.finish("inverse_dynamics", "Joint-space inverse dynamics: M_q qdd + C_q qd + G_q "
                    "(= tau - J_f^T eta_f - D_m^T eta_m).", [("tau", tau, "generalized joint forces (n)")])


def _task_inverse_dynamics(model) -> Function:
    b = Builder(model)
    v_m = b.arg("V_m", b.m, "task velocity (eq. 17)")
    dv_m = b.arg("dV_m", b.m, "task acceleration")
    eta_f = b.arg("eta_f", b.n - b.m, "constraint forces (eq. 12)") if b.n > b.m else []
    eta_m = b.arg("eta_m", eta_m_size(model), "contact forces (eq. 16)") if eta_m_size(model) else None
    a, qd_all = b.task_rates(v_m)
    qdd_all = b.task_accelerations(a, qd_all, dv_m)
    tau = b.t.joint_forces(qd_all, qdd_all, gravity=has_gravity(model),
                          friction_rates=qd_all if has_friction(model) else None, springs=has_springs(model))
    extra = a.T @ np.array([0] * b.m + list(eta_f), dtype=object)
    tau = [x + y for x, y in zip(tau, extra)]
    if eta_m is not None:
        tau = [x + y for x, y in zip(tau, b.contact_term(eta_m))]
    return b.finish("task_inverse_dynamics", "Actuator forces from model (32): "
                    "tau = [J_m; J_f]^T (M [dV_m; 0] + C [V_m; 0] + G + [0; eta_f]).",
                    [("tau", tau, "actuator forces (n)")])


def _mass_matrix(model) -> Function:
    b = Builder(model)
    a = b.t.task_matrix()
    return b.finish("mass_matrix", "M of model (32), n x n, symmetric positive definite.",
                    [("M", b.mass(a), "mass matrix in space O (n x n)")])


def _coriolis_times_v(model) -> Function:
    b = Builder(model)
    v_m = b.arg("V_m", b.m, "task velocity (eq. 17)")
    a, qd_all = b.task_rates(v_m)
    return b.finish("coriolis_times_v", "C [V_m; 0] of model (32).",
                    [("c", b.coriolis(a, qd_all), "Coriolis and centripetal forces in space O (n)")])


def _gravity(model) -> Function:
    b = Builder(model)
    v_m = b.arg("V_m", b.m, "task velocity (friction)") if has_friction(model) else None
    eta_m = b.arg("eta_m", eta_m_size(model), "contact forces (eq. 16)") if eta_m_size(model) else None
    if v_m is not None:
        a, qd_all = b.task_rates(v_m)
    else:
        a, qd_all = b.t.task_matrix(), None
    return b.finish("gravity", "G of model (32): gravity, joint friction xi and A^-T D_m^T eta_m.",
                    [("G", b.gravity(a, qd_all, eta_m), "gravity and friction forces in space O (n)")])


def _forward(b: Builder, method: str = "dense"):
    """``(dV_m, eta_f, qd_all, qdd_all)`` of model (32) for the inputs ``V_m``, ``tau`` (and
    ``eta_m``): by the dense route (``M`` formed and factored; ``qdd_all`` is ``None``), by the
    joint-space route (:func:`_forward_in_joint_space`) or, for a tree, by the articulated-body
    recursion (:mod:`symgen.codegen.aba`)."""
    m, n = b.m, b.n
    v_m = b.arg("V_m", m, "task velocity (eq. 17)")
    tau = b.arg("tau", n, "actuator forces")
    eta_m = b.arg("eta_m", eta_m_size(b.model), "contact forces (eq. 16)") if eta_m_size(b.model) else None
    if method == "articulated-body":
        dv, qd_all, qdd_all = aba.tree_forward(b.t, v_m, tau, eta_m, task_rates=b.task_rates,
                                               gravity=has_gravity(b.model), friction=has_friction(b.model),
                                               springs=has_springs(b.model))
        return dv, [], qd_all, qdd_all
    if method == "null-space":
        return null_space.forward(b, v_m, tau, eta_m, friction=has_friction(b.model), springs=has_springs(b.model))
    a, qd_all = b.task_rates(v_m)
    if method == "joint-space":
        return _forward_in_joint_space(b, a, qd_all, tau, eta_m)
    mass = b.mass(a)
    h = b.t.solve_task(a, tau, transpose=True)
    c = b.coriolis(a, qd_all)
    grav = b.gravity(a, qd_all, eta_m)
    h = [x - y - z for x, y, z in zip(h, c, grav)]
    dv = b.g.solve_spd(mass[:m, :m], h[:m], MOTION_BLOCK)
    eta_f = [h[m + i] - dot(mass[m + i, :m], dv) for i in range(n - m)]
    return list(dv), eta_f, qd_all, None


def _forward_in_joint_space(b: Builder, a, qd_all, tau, eta_m):
    """Model (32) solved through the joint space, without forming ``M``: with ``W = A^-1`` and
    ``M = W^T M_q W``, the motion rows read ``W_m^T`` (``W_m = A^-1 [I_m; 0]``, :meth:`Builder.
    motion_rates`), so ``M_mm = W_m^T M_q W_m`` and ``(A^-T tau - C [V_m; 0] - G)_m = W_m^T f``
    with ``f = tau - A^T (C [V_m; 0] + G)``, one recursion (:meth:`Builder.bias_forces`); then
    ``eta_f = (A^-T (f - M_q W_m dV_m))_f``, one solve with ``A^T``. The cost is ``M_q`` (the
    composite-rigid-body algorithm) and ``m`` columns of ``A^-1`` where the dense route solves
    ``A^T`` on all ``n`` columns of ``M_q`` twice: cheaper when ``m`` is small against ``n`` (a
    robot standing on its feet, arms holding an object)."""
    m, n = b.m, b.n
    w_m, mw, mass = motion_block(b, a)
    f = np.array([x - y for x, y in zip(tau, b.bias_forces(a, qd_all, eta_m))], dtype=object)
    dv = b.g.solve_spd(mass, product(w_m.T, f), MOTION_BLOCK)
    eta_f = []
    if n > m:
        rest = f - product(mw, np.array(list(dv), dtype=object))
        eta_f = list(b.t.solve_task(a, rest, transpose=True)[m:])
    return list(dv), eta_f, qd_all, None


def motion_block(b: Builder, a) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(W_m, M_q W_m, M_mm = W_m^T M_q W_m)`` of the joint-space route (the same nodes on every
    call in one graph, so a Jacobian reuses the primal's factorisation of ``M_mm``)."""
    w_m = b.motion_rates(a)
    mw = product(b.mass_in_joint_space(), w_m)
    return w_m, mw, projected_mass(w_m, mw)


#: how forward dynamics is traced: ``auto`` traces every route that applies (the articulated-body
#: one on a tree) and keeps the one with fewer operations (scalar operations plus the library
#: solves' flops)
METHODS = ("auto", "articulated-body", "null-space", "joint-space", "dense")


@dataclass
class ChosenFunction(Function):
    """A traced function with the route chosen at generation time (``metadata``, in ``ops.json``)."""

    metadata: dict = field(default_factory=dict)


def traced_counts(fn: Function) -> dict:
    """The counts of ``fn``'s live statements, as ``ops.json`` has them (``total``, ``solve_flops``, ...)."""
    return fn.graph.count(fn.graph.live([arr.flat for _, arr in fn.outputs]))


def library_flops(ops: dict) -> int:
    """The flops of an ``ops.json`` entry's library loops: its dense solves' (``solve_flops``) and
    its banded products' (``product_flops``, :mod:`symgen.codegen.graph_products`)."""
    return ops["solve_flops"] + ops.get("product_flops", 0)


def traced_cost(fn: Function) -> int:
    """Operations of ``fn`` as ``ops.json`` counts them: ``total`` (mul + add) plus its library
    loops' flops (:func:`library_flops`)."""
    ops = traced_counts(fn)
    return ops["total"] + library_flops(ops)


def _choose(model, trace, method: str) -> ChosenFunction:
    """``trace(route)`` for each route ``method`` allows (``auto``: all that apply); the cheapest
    by :func:`traced_cost` is kept (the dense one on a tie) and recorded with every cost."""
    if method not in METHODS:
        raise CodegenError(f"unknown forward-dynamics method {method!r}; choose from {', '.join(METHODS)}")
    routes = {}
    if method in ("auto", "articulated-body"):
        if not aba.applies(model):
            if method == "articulated-body":
                raise CodegenError(f"scene {model.scene.name!r}: the articulated-body method needs a tree "
                                   "without constraints whose motion coordinates span every joint rate")
        else:
            try:
                routes["articulated-body"] = trace("articulated-body")
            except aba.SingularArticulatedInertia:
                if method == "articulated-body":
                    raise
    if method in ("auto", "null-space"):
        if null_space.applies(model):
            routes["null-space"] = trace("null-space")
        elif method == "null-space":
            raise CodegenError(f"scene {model.scene.name!r}: the null-space method needs motion given on joints "
                               "and exactly n_c coordinates outside it")
    if method in ("auto", "joint-space"):
        routes["joint-space"] = trace("joint-space")
    if method in ("auto", "dense"):
        routes["dense"] = trace("dense")
    costs = {name: traced_cost(fn) for name, fn in routes.items()}
    best = min(sorted(routes, key=lambda name: name != "dense"), key=costs.get)
    return ChosenFunction(**vars(routes[best]), metadata={"method": best, "method_costs": costs})


def _forward_dynamics(model, method="auto") -> Function:
    return _choose(model, lambda route: _forward_dynamics_by(model, route), method)


def _forward_dynamics_by(model, method) -> Function:
    b = Builder(model)
    dv, eta_f, _, _ = _forward(b, method)
    outputs = [("dV_m", dv, "task acceleration (m)")]
    if b.n > b.m:
        outputs.append(("eta_f", eta_f, "constraint forces (n - m)"))
    doc = {"dense": "Simulation right-hand side from model (32): solves M_mm dV_m = ([J_m; J_f]^-T tau - C [V_m; 0] "
                    "- G)_m, then eta_f.",
           "joint-space": "Simulation right-hand side from model (32) through the joint space: M_mm = W_m^T M_q W_m "
                          "with W_m = [J_m; J_f]^-1 [I; 0], M_mm dV_m = W_m^T (tau - [J_m; J_f]^T (C [V_m; 0] + G)), "
                          "then eta_f.",
           "null-space": "Simulation right-hand side from model (32) through the null space of the loop closures, "
                         "V_m the independent rates: qd_all = W V_m with W = [1; -T_d^-1 T_m], M_mm = W^T M_tree W, "
                         "M_mm dV_m = W^T (tau_all - RNEA(qd_all, qdd_0)), then eta_f from the rows of T_d.",
           "articulated-body": "Simulation right-hand side from model (32), by the articulated-body algorithm (O(N)): "
                               "qdd = ABA(q, qd, tau - xi - D_m^T eta_m), dV_m = J_m qdd + dJ_m/dt qd."}[method]
    return b.finish("forward_dynamics", doc, outputs)


def _dynamics_terms(model) -> Function:
    """``M``, ``C [V_m; 0]`` and ``G`` of (32) at one state in one pass: the kinematics, the
    ``[J_m; J_f]`` factorisation and eq. (10) are computed once for all three (a model-based
    controller's or a simulator's call), where three separate calls would repeat them."""
    b = Builder(model)
    v_m = b.arg("V_m", b.m, "task velocity (eq. 17)")
    eta_m = b.arg("eta_m", eta_m_size(model), "contact forces (eq. 16)") if eta_m_size(model) else None
    a, qd_all = b.task_rates(v_m)
    return b.finish("dynamics_terms", "M, C [V_m; 0] and G of model (32) at one state, sharing the kinematics.",
                    [("M", b.mass(a), "mass matrix in space O (n x n)"),
                     ("c", b.coriolis(a, qd_all), "Coriolis and centripetal forces in space O (n)"),
                     ("G", b.gravity(a, qd_all, eta_m), "gravity and friction forces in space O (n)")])


def _state_derivative(model, method="auto") -> Function:
    def trace(route):
        b = Builder(model)
        dv, _, qd_all, _ = _forward(b, route)
        return b.finish("state_derivative", "The simulation's right-hand side in one pass: dV_m of "
                        "forward_dynamics and qd_all of joint_rates, sharing [J_m; J_f]^-1 [V_m; 0] and eq. (10).",
                        [("dV_m", dv, "task acceleration (m)"),
                         ("qd_all", qd_all, "rates of every joint coordinate, dependent ones included, "
                                            "in scene order (N_all)")])
    return _choose(model, trace, method)


def _joint_rates(model) -> Function:
    b = Builder(model)
    v_m = b.arg("V_m", b.m, "task velocity (eq. 17)")
    _, qd_all = b.task_rates(v_m)
    return b.finish("joint_rates", "Rates of all joint coordinates: qd_all = P [J_m; J_f]^-1 [V_m; 0] "
                    "(eqs. 10, 18); spherical joints as the angular velocity in the child frame.",
                    [("qd_all", qd_all, "rates of every joint coordinate, dependent ones included, "
                                        "in scene order (N_all)")])


@dataclass
class ControlFunction(Function):
    """A traced controller function with its generation-time choices: ``metadata`` (written to
    ``ops.json``), and its dense reference -- ``reference_inputs(state)`` adds the controller's
    own inputs to a state of :func:`symgen.codegen.reference.reference_states`,
    ``reference(state)`` gives the outputs (:mod:`symgen.codegen.vdc_trace`)."""

    metadata: dict = field(default_factory=dict)
    reference_inputs: object = None
    reference: object = None


def _controller(model, name, trace, doc, uncertain, gain, contact) -> Function:
    from functools import partial

    from ..control import recursive as vdc
    from . import vdc_trace

    spec = vdc.control_spec(model, uncertain, gain, contact)
    b = Builder(model, null_space_rows=False)
    fn = b.finish(name, f"{doc} {vdc_trace.parameter_doc(spec)}", trace(b, spec))
    return ControlFunction(**vars(fn), metadata=spec.metadata(),
                           reference_inputs=partial(vdc_trace.reference_inputs, model, spec),
                           reference=partial(vdc_trace.reference_outputs, model, spec, name))


def _control(model, uncertain=None, gain=1.0, contact=None) -> Function:
    from .vdc_trace import trace_control

    doc = ("Adaptive control law (34): tau = T_S^T Y_r P_hat_r + Y_m P_hat_m + J_f^T eta_fr + K_A e, "
           "e = [J_m; J_f]^-1 [V_mr - V_m; 0], by recursion over the tree (O(N)).")
    return _controller(model, "control", trace_control, doc, uncertain, gain, contact)


def _adaptation(model, uncertain=None, contact=None) -> Function:
    from .vdc_trace import trace_adaptation

    doc = ("Adaptation signal of eq. (38): s = Y^T e, Y = [T_S^T Y_r, Y_m], e = [J_m; J_f]^-1 [V_mr - V_m; 0], "
           "one entry per uncertain parameter (the projection kappa and the gains rho stay in the caller).")
    return _controller(model, "adaptation", trace_adaptation, doc, uncertain, 1.0, contact)


def _forward_all_joints(b: Builder, method: str = "dense"):
    """Forward dynamics (32), then ``(qd_all, qdd_all)``: ``qdd = A^-1 ([dV_m; 0] - dA/dt qd)``
    completed by eq. (11) differentiated (the recursion gives ``qdd_all`` directly)."""
    dv, _, qd_all, qdd_all = _forward(b, method)
    if qdd_all is not None:
        return qd_all, qdd_all
    return qd_all, b.task_accelerations(b.t.task_matrix(), qd_all, dv)


def _joint_accelerations(model, method="auto") -> Function:
    def trace(route):
        b = Builder(model)
        qd_all, qdd_all = _forward_all_joints(b, route)
        doc = "every joint coordinate, dependent ones included, in scene order (N_all)"
        return b.finish("joint_accelerations", "Forward dynamics (32) in joint terms: the rates and "
                        "accelerations of every joint, qd_all = P qd and qdd_all = P qdd + dP/dt qd (eqs. 10-11).",
                        [("qd_all", qd_all, "rates of " + doc), ("qdd_all", qdd_all, "accelerations of " + doc)])
    return _choose(model, trace, method)


def _loop_forces(model) -> Function:
    """``W^T lam = (tau_tree - tau_all + D_m,all^T eta_m)[q_u1, q_a1]`` with ``tau_tree`` from the
    recursion over all joints (:mod:`symgen.steps.loop_forces`)."""
    b = Builder(model, null_space_rows=False)          # W^T lam: the multipliers of the model's rows
    t, part = b.t, model.partition
    qd_all, qdd_all = _forward_all_joints(b)
    tau_tree = rnea(*t.force_frames, qd_all, qdd_all, gravity=has_gravity(model), graph=b.g, tag="_all",
                    inertias=t.joint_force_inertias)
    if has_friction(model):
        tau_tree = [x + y for x, y in zip(tau_tree, joint_friction(t.tree, t.consts, qd_all, t.field.sign))]
    if has_springs(model):
        tau_tree = t.add_springs(tau_tree)
    residual = np.array(tau_tree, dtype=object)
    for k, node in zip(part.independent, b.g.input("tau", b.n)):
        residual[k] = residual[k] - node
    if eta_m_size(model):
        rows = steps.contact_rows(t.field, t.kinematics(), model.scene.contact_forces).v
        residual = residual + rows.T @ np.array(b.g.input("eta_m", eta_m_size(model)), dtype=object)
    lam = steps.closure_multipliers(t.field, t.blocks, part, residual)
    return b.finish("loop_forces", "Force of every loop-closure constraint under tau (forward dynamics): "
                    "the wrench on frame A's body at A's origin, A's axes, the listed components of each "
                    "constraint in scene order; the Lagrange multipliers of M qdd + h = tau + T^T lam.",
                    [("lam", list(lam), "constraint forces and moments (n_c)")])
