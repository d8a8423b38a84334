"""``forward_dynamics_derivatives`` and ``state_derivative_jacobian``: the Jacobians of model (32)'s
forward dynamics and of the simulation's right-hand side, generated.

What ``q`` means. The derivatives with respect to ``q`` are the plain partials with respect to
every entry of the generated code's position input -- one angle or displacement per joint, the
dependent joints of closed chains included -- as the simulation state ``x = [q; V_m]`` holds it
(:mod:`symgen.simulation.state`); a spherical joint's unit quaternion has instead three columns,
its rotation turned in the child frame, ``R exp(hat(delta))`` (:mod:`symgen.codegen.tangent`;
Pinocchio's convention for ``computeABADerivatives``), so ``d / dq`` has one column per
coordinate of ``qd_all`` (scene order). The functions are those the generated code evaluates at any
``q``: eq. (10) completes the rates from the positions given, without re-closing the loops.
This is the Jacobian an implicit integrator of ``dx/dt = f(x)`` needs. The derivative *along the
constraint manifold* with respect to the independent coordinates is this one times the tangent
``dq/dq_ind``: for loops closed by passive joints, ``P`` of eq. (10) (a revolute or prismatic
position's rate is its joint rate), as ``inverse_dynamics_derivatives`` does inside
(:mod:`symgen.codegen.dynamics_derivatives`); the tests check that product against differences
taken with the loops re-closed at every step.

Two routes, traced and the cheaper kept (operations plus library-solve flops, :func:`traced_cost`;
``ops.json`` records ``method`` and ``method_costs``):

* ``graph``: the primal (``forward_dynamics``'s dense route, or the articulated-body recursion
  for a tree) differentiated in its own graph (:func:`symgen.codegen.derivatives.differentiate`);
* ``implicit``: the implicit-function theorem on (32). With ``y = (dV_m, eta_f)`` the solution,
  ``tau_ID(q, V_m, y) = A^T (M [dV_m; 0] + C [V_m; 0] + G + [0; eta_f]) = tau``, evaluated by the
  recursion (``task_inverse_dynamics``), and ``A^-T d tau_ID / dy = [[M_mm, 0], [M_fm, 1]]``, so

      Z = A^-T [-d tau_ID/dq, -d tau_ID/dV_m, 1]     (y held at the solution)
      d dV_m = M_mm^-1 Z_m,     d eta_f = Z_f - M_fm d dV_m.

  ``M_mm^-1`` reuses the primal's factorisation (the straight-line LDL^T is the same nodes); for a
  tree with motion given on joints it is applied instead by the articulated-body recursion at zero
  velocity without gravity, one ``O(N)`` pass per column over the primal's articulated inertias
  (``O(N^2)`` in all, where the dense solve is ``O(N^3)``).

Refused (:func:`check_supported`): spherical joints in ``state_derivative_jacobian``, whose state
``x`` holds the quaternion itself (its rate is not a coordinate of ``qd_all``). Derivatives with
respect to ``eta_m`` are not generated (it is an input, held).
"""
from __future__ import annotations

import numpy as np

from ..dynamics.aba import articulated_body
from ..errors import CodegenError
from . import aba
from .builder import Builder, Function, eta_m_size, has_friction, has_gravity, has_springs
from .derivatives import differentiate
from .functions import ChosenFunction, _forward, traced_cost
from .tangent import q_directions, tangent_layout
from .trace import position_layout

#: how the Jacobians are traced: ``auto`` keeps the cheaper of the applicable routes
ROUTES = ("graph-dense", "graph-articulated-body", "implicit-dense", "implicit-articulated-body")


def check_supported(model, name: str) -> None:
    """A :class:`CodegenError` naming the first spherical joint of ``model`` (for
    ``state_derivative_jacobian``, whose state holds the quaternion)."""
    for joint, kind, _, size in position_layout(model):
        if size != 1:
            raise CodegenError(f"joint {joint!r} ({kind}): {name} handles revolute and prismatic joints only; "
                               "a spherical joint's unit-quaternion position needs derivatives along the "
                               "rotation (dR = R w^), which are not generated")


def _primal(b: Builder, primal: str):
    """``(dV_m, eta_f, qd_all, inputs, seeds)`` of forward dynamics by route ``primal``, with the
    columns ``q + V_m + tau`` that the Jacobians follow (``q`` by :func:`q_directions`)."""
    dv, eta_f, qd_all, _ = _forward(b, primal)
    g = b.g
    columns, seeds, _ = q_directions(b)
    inputs = columns + g.input("V_m", b.m) + g.input("tau", b.n)
    return list(dv), list(eta_f), qd_all, inputs, seeds


def _explicit_partials(b: Builder, dv, eta_f, qd_all, inputs, seeds) -> np.ndarray:
    """``d tau_ID / d(q, V_m)`` with ``(dV_m, eta_f)`` held at the solution (``n x (nq + m)``):
    ``tau_ID`` traced by the recursion as ``task_inverse_dynamics`` does."""
    a = b.t.task_matrix()
    qdd_all = b.task_accelerations(a, qd_all, dv)
    tau = b.t.joint_forces(qd_all, qdd_all, gravity=has_gravity(b.model),
                           friction_rates=qd_all if has_friction(b.model) else None, springs=has_springs(b.model))
    extra = a.T @ np.array([0] * b.m + list(eta_f), dtype=object)
    tau = [x + y for x, y in zip(tau, extra)]
    if eta_m_size(b.model):
        tau = [x + y for x, y in zip(tau, b.contact_term(b.g.input("eta_m", eta_m_size(b.model))))]
    nx = len(inputs) - b.n
    return differentiate(b.g, np.array(tau, dtype=object), inputs[:nx], held=dv + eta_f, seeds=seeds)


def _implicit(b: Builder, dv, eta_f, qd_all, inputs, seeds, by_recursion: bool):
    """``(d dV_m, d eta_f)`` by the implicit-function theorem (module docstring)."""
    g, m, n = b.g, b.m, b.n
    explicit = _explicit_partials(b, dv, eta_f, qd_all, inputs, seeds)
    rhs = np.concatenate([-explicit, np.array(np.eye(n, dtype=int), dtype=object)], axis=1)
    if by_recursion:                             # a tree, motion on joints: A a constant selection
        t = b.t
        coords = aba.motion_coordinates(b.model)
        zero = [0] * t.tree.n_coords
        cols = []
        for k in range(rhs.shape[1]):
            tau_all = list(zero)
            for j, coord in enumerate(t.part.independent):
                tau_all[coord] = rhs[j, k]
            qdd = articulated_body(t.tree, t.consts, t.transforms, zero, tau_all, gravity=False, graph=g)
            cols.append([qdd[c] for c in coords])
        return np.array(cols, dtype=object).T, np.empty((0, rhs.shape[1]), dtype=object)
    a = b.t.task_matrix()
    z = b.t.solve_task(a, rhs, transpose=True)
    mass = b.mass(a)
    d_dv = g.solve_spd(mass[:m, :m], z[:m], "M_mm, the motion block of M (eq. 32)")
    d_dv = np.asarray(d_dv, dtype=object).reshape(m, rhs.shape[1])
    if n == m:
        return d_dv, np.empty((0, rhs.shape[1]), dtype=object)
    return d_dv, np.asarray(z[m:] - mass[m:, :m] @ d_dv, dtype=object)


def _jacobians(b: Builder, route: str):
    """``(dv, eta_f, qd_all, d dV_m, d eta_f, inputs)`` by ``route`` (:data:`ROUTES`)."""
    kind, primal = route.split("-", 1)
    dv, eta_f, qd_all, inputs, seeds = _primal(b, primal)
    if kind == "graph":
        jac = differentiate(b.g, np.array(dv + eta_f, dtype=object), inputs, seeds=seeds)
        return dv, eta_f, qd_all, jac[:b.m], jac[b.m:], inputs
    d_dv, d_eta = _implicit(b, dv, eta_f, qd_all, inputs, seeds, primal == "articulated-body")
    return dv, eta_f, qd_all, d_dv, d_eta, inputs


def applicable_routes(model) -> list[str]:
    """The routes of :data:`ROUTES` that apply to ``model``: the articulated-body ones for a tree
    (:func:`symgen.codegen.aba.applies`), the implicit one of them with motion given on joints."""
    routes = ["graph-dense", "implicit-dense"]
    if aba.applies(model):
        routes.insert(1, "graph-articulated-body")
        if aba.motion_coordinates(model) is not None:
            routes.append("implicit-articulated-body")
    return routes


def choose(model, trace, method: str = "auto") -> ChosenFunction:
    """``trace(route)`` for every applicable route (or the one ``method`` names); the cheapest by
    :func:`traced_cost` is kept (the first in :data:`ROUTES` order on a tie) and recorded."""
    routes = applicable_routes(model)
    if method != "auto":
        if method not in routes:
            raise CodegenError(f"scene {model.scene.name!r}: derivative route {method!r} does not apply; "
                               f"choose from auto, {', '.join(routes)}")
        routes = [method]
    traced = {}
    for route in routes:
        try:
            traced[route] = trace(route)
        except aba.SingularArticulatedInertia:
            if method != "auto":
                raise
    costs = {route: traced_cost(fn) for route, fn in traced.items()}
    best = min(traced, key=lambda r: (costs[r], ROUTES.index(r)))
    return ChosenFunction(**vars(traced[best]), metadata={"method": best, "method_costs": costs})


def _forward_dynamics_derivatives(model, method: str = "auto") -> Function:
    def trace(route):
        b = Builder(model)
        _, _, _, d_dv, d_eta, _ = _jacobians(b, route)
        nq, m = sum(w for *_, w in tangent_layout(model)), b.m
        outputs = [("ddV_m_dq", d_dv[:, :nq], "d dV_m / dq, every entry of q; a spherical joint's "
                    "rotation turned in its child frame, R exp(hat(delta)) (m x nq)"),
                   ("ddV_m_dV_m", d_dv[:, nq:nq + m], "d dV_m / dV_m (m x m)"),
                   ("ddV_m_dtau", d_dv[:, nq + m:], "d dV_m / dtau (m x n)")]
        if b.n > m:
            outputs += [("deta_f_dq", d_eta[:, :nq], "d eta_f / dq ((n - m) x nq)"),
                        ("deta_f_dV_m", d_eta[:, nq:nq + m], "d eta_f / dV_m ((n - m) x m)"),
                        ("deta_f_dtau", d_eta[:, nq + m:], "d eta_f / dtau ((n - m) x n)")]
        return b.finish("forward_dynamics_derivatives",
                        "Jacobians of forward dynamics (32): d dV_m and d eta_f with respect to q (plain partials "
                        "in every 1-DOF joint position; a spherical joint turned in its child frame, three columns), "
                        "V_m and tau; eta_m held.", outputs)
    return choose(model, trace, method)


def state_rows(model) -> list[int]:
    """For each entry of ``q``, the coordinate of ``qd_all`` that is its rate (1-DOF joints)."""
    first: dict[str, int] = {}
    for c, coord in enumerate(model.tree.coordinates):
        first.setdefault(coord.joint, c)
    return [first[name] for name, *_ in position_layout(model)]


def _state_derivative_jacobian(model, method: str = "auto") -> Function:
    check_supported(model, "state_derivative_jacobian")

    def trace(route):
        b = Builder(model)
        _, _, qd_all, d_dv, _, inputs = _jacobians(b, route)
        nq, m = b.inputs[0].size, b.m
        rates = [qd_all[c] for c in state_rows(model)]
        d_rates = differentiate(b.g, np.array(rates, dtype=object), inputs)   # 1-DOF joints: no seeds
        jac = np.concatenate([d_rates, d_dv], axis=0)
        return b.finish("state_derivative_jacobian",
                        "Jacobians of the simulation's right-hand side dx/dt = [dq/dt; dV_m/dt] for x = [q; V_m] "
                        "(state_derivative): d xdot / dx and d xdot / dtau; eta_m held.",
                        [("dxdot_dx", jac[:, :nq + m], "d xdot / dx, x = [q; V_m] ((nq + m) x (nq + m))"),
                         ("dxdot_dtau", jac[:, nq + m:], "d xdot / dtau ((nq + m) x n)")])
    return choose(model, trace, method)
