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

Three kinds of route, the first two on every primal route of ``forward_dynamics`` that applies
(dense, joint-space, articulated-body; the null-space primal of :mod:`symgen.codegen.null_space`
by the graph only), traced and the cheapest kept (operations plus library flops,
:func:`~symgen.codegen.functions.traced_cost`; ``ops.json`` records ``method`` and
``method_costs``) among those whose straight-line code stays within a budget (:func:`choose`):

* ``graph``: the primal differentiated in its own graph (:func:`symgen.codegen.derivatives.differentiate`);
* ``implicit``: the implicit-function theorem on (32). With ``y = (dV_m, eta_f)`` the solution,
  ``tau_ID(q, V_m, y) = A^T (M [dV_m; 0] + C [V_m; 0] + G + [0; eta_f]) = tau``, evaluated by the
  recursion (``task_inverse_dynamics``), and ``A^-T d tau_ID / dy = [[M_mm, 0], [M_fm, 1]]``, so

      Z = A^-T [-d tau_ID/dq, -d tau_ID/dV_m, 1]     (y held at the solution)
      d dV_m = M_mm^-1 Z_m,     d eta_f = Z_f - M_fm d dV_m.

  ``M_mm^-1`` reuses the primal's factorisation (the straight-line LDL^T is the same nodes); on
  the joint-space primal ``Z_m = W_m^T [...]`` and ``d eta_f = (A^-T ([...] - M_q W_m d dV_m))_f``
  (:func:`~symgen.codegen.functions.motion_block`); for a
  tree with motion given on joints it is applied instead by the articulated-body recursion at zero
  velocity without gravity, one ``O(N)`` pass per column over the primal's articulated inertias
  (``O(N^2)`` in all, where the dense solve is ``O(N^3)``);
* ``nested`` (dense primal; :func:`nested_applies`): the same theorem applied to the dependent
  rates and accelerations too, which ``tau_ID`` reads through ``A^-1`` (:func:`_nested`): their
  partials come from the task rows traced by the recursion with the rates held, not through the
  eliminations of ``A`` and the derivatives of its entries.

The explicit partials ``d tau_ID / d(q, V_m)`` are taken by the forward sweep, by the adjoint
sweep (suffix ``-reverse``) or, on a tree of one-coordinate joints with its motion on the joints
and no ``eta_m``, in closed form (suffix ``-analytic``: :mod:`symgen.dynamics.rnea_derivatives`
at the held accelerations, :func:`analytic_partials_apply`), whose mass entries are then the
dense and joint-space primals' ``M_q`` as well (:func:`_closed_form_mass`).

``state_derivative_jacobian`` is the Jacobian of the simulation's right-hand side
(:mod:`symgen.simulation.dynamics`) in the entries of its state ``x = [q; V_m]`` itself -- what
SciPy's ``Radau`` and ``BDF`` integrate -- so a spherical joint has four columns and four rows,
its quaternion's: the simulation normalises the quaternion ``p`` before each evaluation and moves
it at ``dp/dt = 1/2 p (x) (0, w)`` (:mod:`symgen.simulation.state`), and the Jacobian is that of
this map at a unit ``p``: the three turn columns mapped by ``d delta / d p = 2 [-v | w 1 - hat(v)]``
(:func:`~symgen.codegen.tangent.ambient_map`), so a radial change of ``p`` moves nothing but the
quaternion's own rate is differentiated with the normalisation (:func:`_ambient_rows`). At a
``p`` of length ``s`` the integrator's Jacobian is this one's quaternion columns divided by ``s``
(:mod:`symgen.simulation.jacobian`). Derivatives with respect to ``eta_m`` are not generated (it
is an input, held).
"""
from __future__ import annotations

import numpy as np

from ..dynamics.aba import articulated_body
from ..errors import CodegenError
from ..math.jet import matmul as product
from . import aba, null_space
from .builder import Builder, Function, eta_m_size, has_friction, has_gravity, has_springs
from .dynamics_derivatives import (analytic_applies, closed_form_partials, loops_entries, product_of_nodes,
                                   scanned_inverse_products, serial_chain)
from .derivatives import differentiate
from .reverse import ReverseUnsupported, differentiate_reverse
from .functions import MOTION_BLOCK, ChosenFunction, _forward, library_flops, motion_block, traced_counts
from .node_product import node_matmul
from .tangent import ambient_map, coordinate_columns, q_directions, quaternion_product, tangent_layout
from .trace import position_layout, task_motion_applies

#: how the Jacobians are traced: ``auto`` keeps the cheaper of the applicable routes
ROUTES = ("graph-dense", "graph-joint-space", "graph-articulated-body", "graph-null-space", "implicit-dense",
          "implicit-joint-space", "implicit-articulated-body", "implicit-dense-reverse", "implicit-joint-space-reverse",
          "implicit-articulated-body-reverse", "implicit-dense-analytic", "implicit-joint-space-analytic",
          "implicit-articulated-body-analytic", "nested-dense", "nested-dense-reverse")
#: the suffix of a route whose explicit partials are taken by the adjoint sweep (:mod:`symgen.codegen.reverse`)
REVERSE = "-reverse"
#: the suffix of a route whose explicit partials are the closed form of
#: :mod:`symgen.dynamics.rnea_derivatives` (a tree of one-coordinate joints, motion on joints)
ANALYTIC = "-analytic"
#: straight-line operations (mul + add) beyond which a route is kept only when no other is within:
#: at 9-11 bytes of machine code per operation (``-O3``, x86-64) such a function outgrows a core's
#: L2 cache (1-2 MB) and its instructions stream from L3 on every call. ``chain:n=32``'s
#: forward-dynamics Jacobians are the case: the articulated-body route is all straight line, the
#: joint-space one leaves its 32 x 32 ``M`` to the library LU's loops
#: (``benchmarks/derivative_ops.md`` and ``derivative_speed.md``).
STRAIGHT_LINE_BUDGET = 150_000


def _primal(b: Builder, primal: str):
    """``(dV_m, eta_f, qd_all, inputs, seeds)`` of forward dynamics by route ``primal``, with the
    columns ``q + V_m + tau`` that the Jacobians follow (``q`` by :func:`q_directions`)."""
    dv, eta_f, qd_all, _ = _forward(b, primal)
    g = b.g
    columns, seeds, _ = q_directions(b)
    inputs = columns + g.input("V_m", b.m) + g.input("tau", b.n)
    return list(dv), list(eta_f), qd_all, inputs, seeds


def _explicit_partials(b: Builder, dv, eta_f, qd_all, inputs, seeds, sweep=differentiate) -> np.ndarray:
    """``d tau_ID / d(q, V_m)`` with ``(dV_m, eta_f)`` held at the solution (``n x (nq + m)``):
    ``tau_ID`` traced by the recursion as ``task_inverse_dynamics`` does, differentiated by
    ``sweep`` (forward, or :func:`~symgen.codegen.reverse.differentiate_reverse`), or ``None`` for
    the closed form (:func:`_analytic_partials`)."""
    a = b.t.task_matrix()
    qdd_all = b.task_accelerations(a, qd_all, dv)
    if sweep is None:
        return _analytic_partials(b, qd_all, qdd_all)
    tau = _tau_id(b, eta_f, qd_all, qdd_all, a)
    nx = len(inputs) - b.n
    return sweep(b.g, np.array(tau, dtype=object), inputs[:nx], held=dv + eta_f, seeds=seeds)


def _tau_id(b: Builder, eta_f, qd_all, qdd_all, a, *, by_recursion: bool = False) -> list:
    """``tau_ID = A^T (M [dV_m; 0] + C [V_m; 0] + G + [0; eta_f])`` (module docstring) by the
    recursion at the rates ``qd_all`` and accelerations ``qdd_all`` (``dV_m``'s), the contact
    term ``D_m^T eta_m`` included; ``A^T [0; eta_f]`` by ``A``'s entries, or with ``by_recursion``
    as the constraints' wrenches on the bodies in the same recursion
    (:meth:`~symgen.codegen.trace.Tracer.constraint_wrenches`)."""
    wrenches = b.t.constraint_wrenches(eta_f) if by_recursion and eta_f else None
    tau = b.t.joint_forces(qd_all, qdd_all, gravity=has_gravity(b.model),
                           friction_rates=qd_all if has_friction(b.model) else None, springs=has_springs(b.model),
                           wrenches=wrenches)
    if wrenches is None:
        tau = [x + y for x, y in zip(tau, a.T @ np.array([0] * b.m + list(eta_f), dtype=object))]
    if eta_m_size(b.model):
        tau = [x + y for x, y in zip(tau, b.contact_term(b.g.input("eta_m", eta_m_size(b.model))))]
    return tau


def analytic_partials_apply(model) -> bool:
    """The closed-form partials stand for the traced ``tau_ID``: a tree of one-coordinate joints
    (:func:`~symgen.codegen.dynamics_derivatives.analytic_applies`) with its motion given on the
    joints (``V_m`` a selection of the rates) and no contact forces ``eta_m``."""
    return (analytic_applies(model) and aba.motion_coordinates(model) is not None
            and not eta_m_size(model))


def _analytic_partials(b: Builder, qd_all, qdd_all) -> np.ndarray:
    """``d tau_ID / d(q, V_m)`` (``n x (nq + m)``, rows and ``q`` columns as the sweeps give them)
    by :func:`~symgen.codegen.dynamics_derivatives.closed_form_partials` at the rates and the held
    accelerations; rows projected by ``P^T`` as ``tau_ID`` is, the ``V_m`` columns those of the
    rates of :func:`~symgen.codegen.aba.motion_coordinates`."""
    dq, dqd, _ = closed_form_partials(b, qd_all, qdd_all)
    p_t = b.t.p_full().T
    dq, dqd = product_of_nodes(p_t, dq), product_of_nodes(p_t, dqd)
    nq = len(coordinate_columns(b.model))
    out = np.empty((dq.shape[0], nq + b.m), dtype=object)
    for c, col in enumerate(coordinate_columns(b.model)):
        out[:, col] = dq[:, c]
    for j, c in enumerate(aba.motion_coordinates(b.model)):
        out[:, nq + j] = dqd[:, c]
    return out


def _implicit(b: Builder, dv, eta_f, qd_all, inputs, seeds, primal: str, sweep=differentiate):
    """``(d dV_m, d eta_f)`` by the implicit-function theorem (module docstring), ``M_mm^-1``
    applied as the ``primal`` route factors it."""
    g, m, n = b.g, b.m, b.n
    if sweep is None and primal == "joint-space":
        scanned = _scanned(b, dv, qd_all)
        if scanned is not None:
            return scanned
    explicit = _explicit_partials(b, dv, eta_f, qd_all, inputs, seeds, sweep)
    rhs = np.concatenate([-explicit, np.array(np.eye(n, dtype=int), dtype=object)], axis=1)
    if primal == "joint-space":                  # Z_m = W_m^T rhs; eta_f by one solve with A^T
        a = b.t.task_matrix()
        w_m, mw, mass = motion_block(b, a)
        rhs = _nodes(g, rhs)
        d_dv = g.solve_spd(mass, product(w_m.T, rhs), MOTION_BLOCK)
        d_dv = np.asarray(d_dv, dtype=object).reshape(m, rhs.shape[1])
        if n == m:
            if _is_identity(g, w_m):
                _mirror_inverse(d_dv[:, rhs.shape[1] - n:])
            return d_dv, np.empty((0, rhs.shape[1]), dtype=object)
        z = b.t.solve_task(a, rhs - product(mw, d_dv), transpose=True)
        return d_dv, np.asarray(z[m:], dtype=object)
    if primal == "articulated-body":             # a tree, motion on joints: A a constant selection
        t = b.t
        coords = aba.motion_coordinates(b.model)
        zero = [0] * t.tree.n_coords
        cols = []
        for k in range(rhs.shape[1]):
            tau_all = list(zero)
            for j, coord in enumerate(t.part.independent):
                tau_all[coord] = rhs[j, k]
            qdd = articulated_body(*t.force_frames, zero, tau_all, gravity=False, graph=g)
            cols.append([qdd[c] for c in coords])
        return np.array(cols, dtype=object).T, np.empty((0, rhs.shape[1]), dtype=object)
    a = b.t.task_matrix()
    return _dense_solution(b, b.mass(a), b.t.solve_task(a, rhs, transpose=True))


def _dense_solution(b: Builder, mass, z):
    """``(d dV_m, d eta_f)`` from ``Z`` (``n x k``) and ``M`` of (32): ``d dV_m = M_mm^-1 Z_m``,
    ``d eta_f = Z_f - M_fm d dV_m`` (module docstring; empty without constraint rows)."""
    g, m = b.g, b.m
    d_dv = np.asarray(g.solve_spd(mass[:m, :m], z[:m], MOTION_BLOCK), dtype=object).reshape(m, z.shape[1])
    if b.n == m:
        return d_dv, np.empty((0, z.shape[1]), dtype=object)
    return d_dv, np.asarray(z[m:] - mass[m:, :m] @ d_dv, dtype=object)


def _unit_seeds(g, qd_all, seeds: dict, first: int) -> dict:
    """``seeds`` plus one column per tree coordinate's rate, ``first`` on: ``qd_all``'s nodes
    taken as independent variables (the columns ``d / d qd_all``)."""
    out = dict(seeds or {})
    for c, node in enumerate(qd_all):
        out[node] = {first + c: g.const(1)}
    return out


def _nested(b: Builder, sweep=differentiate):
    """``(dv, eta_f, qd_all, d dV_m, d eta_f, inputs)`` by the implicit-function theorem applied to
    the rates and the accelerations as well as to (32), on the dense primal. ``tau_ID`` reads the
    rates ``qd_all = P A^-1 [V_m; 0]`` and the accelerations ``qdd_all = P A^-1 ([dV_m; 0] - dA/dt
    qd)`` (eqs. 10, 18; ``P`` a selection here); with ``s = A qd`` and ``r = A qdd + dA/dt qd``
    traced by the recursion (:meth:`~symgen.codegen.trace.Tracer.task_motion`) and differentiated
    with the rates held, no column goes through the eliminations of ``A`` (``x = (q, V_m)``)::

        d qd_all / dx = P A^-1 [-ds/dq, [1_m; 0]],
        dr/dx = [dr/dq, 0] + dr/dqd_all  d qd_all / dx              (qdd_all held),
        E = [dtau/dq, 0] + dtau/dqd_all  d qd_all / dx              (qdd_all, eta_f held),
        Z = A^-T [-E, 1] + [M dr/dx, 0],   then :func:`_dense_solution`,

    since ``tau_ID`` reads ``qdd_all`` through ``M_q`` and ``A^-T M_q A^-1 = M`` (32): the
    accelerations' partials need no solve. ``A^T [0; eta_f]`` is taken as the constraints' wrenches
    in the recursion of ``tau_ID`` (:meth:`~symgen.codegen.trace.Tracer.constraint_wrenches`).
    ``sweep`` takes the partials of ``tau_ID`` (forward or adjoint); those of ``s`` and ``r`` are
    forward, their columns sparse along the tree."""
    g, t, n, m = b.g, b.t, b.n, b.m
    dv, eta_f, qd_all, inputs, seeds = _primal(b, "dense")
    a = t.task_matrix()
    qdd_all = b.task_accelerations(a, qd_all, dv)
    nx = len(inputs) - n
    nq = nx - m
    ds = differentiate(g, np.array(t.task_motion(qd_all), dtype=object), inputs[:nq], held=qd_all, seeds=seeds)
    unit_v = np.array([[g.const(int(i < m and j == i)) for j in range(m)] for i in range(n)], dtype=object)
    d_qd = np.asarray(t.solve_task(a, np.concatenate([-ds, unit_v], axis=1)), dtype=object)
    d_qd_all = _nodes(g, np.array([t.complete_rates(list(d_qd[:, j])) for j in range(nx)], dtype=object).T)
    columns = list(inputs[:nq]) + [None] * len(qd_all)
    rate_seeds = _unit_seeds(g, qd_all, seeds, nq)

    def through_rates(partials):      # [d/dq, 0] + d/dqd_all d qd_all/dx
        chained = product(partials[:, nq:], d_qd_all)
        return _nodes(g, np.concatenate([partials[:, :nq], np.zeros((partials.shape[0], m), dtype=object)], axis=1)
                      + chained)

    d_r = differentiate(g, np.array(t.task_motion(qd_all, qdd_all), dtype=object), columns, held=qdd_all,
                        seeds=rate_seeds)
    tau = _tau_id(b, eta_f, qd_all, qdd_all, a, by_recursion=True)
    explicit = sweep(g, np.array(tau, dtype=object), columns, held=eta_f + list(qdd_all), seeds=rate_seeds)
    mass = _nodes(g, np.asarray(b.mass(a), dtype=object))
    rhs = np.concatenate([-through_rates(explicit), np.array(np.eye(n, dtype=int), dtype=object)], axis=1)
    z = np.asarray(t.solve_task(a, rhs, transpose=True), dtype=object)
    z[:, :nx] = z[:, :nx] + product(mass, through_rates(d_r))
    d_dv, d_eta = _dense_solution(b, mass, _nodes(g, z))
    return dv, eta_f, qd_all, d_dv, d_eta, inputs


def _nodes(g, array: np.ndarray) -> np.ndarray:
    """``array`` (2-D) with every entry a node of ``g`` (numbers as constants), for the products."""
    return np.array([[g._node(x) for x in row] for row in array], dtype=object).reshape(array.shape)


def nested_applies(model) -> bool:
    """The nested routes (:func:`_nested`) apply: ``A`` depends on ``q`` (frames in the motion, or
    constraints) and its rows are the tree's (:func:`~symgen.codegen.trace.task_motion_applies`)."""
    scene = model.scene
    return bool(scene.motion.frames or scene.constraints) and task_motion_applies(model)


def _scanned(b: Builder, dv, qd_all):
    """``(d dV_m, d eta_f)`` of the closed-form route on a serial chain (motion on every joint, in
    order) whose mass matrix goes to the library factor and whose closed form goes to library
    products (:func:`~symgen.codegen.dynamics_derivatives.loops_entries`), or ``None`` elsewhere:
    ``M^-1`` by the factor's solve with the identity (the ``d/d tau`` block), then ``-M^-1 d tau/dq``
    and ``-M^-1 d tau/dqd`` by two scan products on it
    (:func:`~symgen.codegen.dynamics_derivatives.scanned_inverse_products`) instead of forming the
    partials and multiplying (``O(n^2)`` per product where the ``n x n`` one is ``O(n^3)``)."""
    g, n, model = b.g, b.n, b.model
    if not (b.m == n and loops_entries(b.t.tree) and serial_chain(b.t.tree)
            and coordinate_columns(model) == list(range(n)) and aba.motion_coordinates(model) == list(range(n))):
        return None
    a = b.t.task_matrix()
    w_m, _, mass = motion_block(b, a)
    if not (_is_identity(g, w_m) and g.spd_in_library(mass, MOTION_BLOCK)):
        return None
    qdd_all = b.task_accelerations(a, qd_all, dv)
    eye = np.array([[g.const(int(r == c)) for c in range(n)] for r in range(n)], dtype=object)
    inverse = np.asarray(g.solve_spd(mass, eye, MOTION_BLOCK), dtype=object).reshape(n, n)
    d_q, d_qd = scanned_inverse_products(b, qd_all, qdd_all, inverse)
    d_tau = inverse.copy()
    _mirror_inverse(d_tau)
    return np.concatenate([d_q, d_qd, d_tau], axis=1), np.empty((0, 3 * n), dtype=object)


def _is_identity(g, w) -> bool:
    """Whether the array of nodes ``w`` is the constant identity (``W_m`` where the motion is given
    on the joint coordinates of the joint-space form: an open chain, the four- and five-bar)."""
    w = np.asarray(w, dtype=object)
    if w.ndim != 2 or w.shape[0] != w.shape[1]:
        return False
    nodes = [[g._node(v) for v in row] for row in w]
    return all(v.is_const and v.value == (i == j) for i, row in enumerate(nodes) for j, v in enumerate(row))


def _mirror_inverse(block: np.ndarray) -> None:
    """``block`` (a view) is ``M_mm^-1``, symmetric: its upper triangle is set to the lower one's
    nodes, so the back substitution of column ``k`` stops at row ``k`` (the rows above are dead
    and left out of the code) -- about half the operations of the inverse."""
    for i in range(block.shape[0]):
        for j in range(i + 1, block.shape[1]):
            block[i, j] = block[j, i]


def _closed_form_mass(b: Builder) -> None:
    """The primal's ``M_q`` on a route with the closed-form partials: the closed form's own mass
    entries (``M_ji = S_i . I^c_j S_j`` of :mod:`symgen.dynamics.rnea_derivatives`, on the composites
    its partials use), which depend on ``q`` only and are traced here at zero rates and
    accelerations -- the same nodes the partials make later at the solution, so the composites are
    shared and the composite-rigid-body algorithm is not traced."""
    zero = [0] * b.t.tree.n_coords
    b.use_tree_mass(closed_form_partials(b, zero, zero)[2])


def _jacobians(b: Builder, route: str):
    """``(dv, eta_f, qd_all, d dV_m, d eta_f, inputs)`` by ``route`` (:data:`ROUTES`)."""
    sweep = (differentiate_reverse if route.endswith(REVERSE) else None if route.endswith(ANALYTIC)
             else differentiate)
    kind, primal = route.removesuffix(REVERSE).removesuffix(ANALYTIC).split("-", 1)
    if kind == "nested":
        return _nested(b, sweep)
    if sweep is None and primal != "articulated-body":     # that primal reads no mass matrix
        _closed_form_mass(b)
    dv, eta_f, qd_all, inputs, seeds = _primal(b, primal)
    if kind == "graph":
        jac = differentiate(b.g, np.array(dv + eta_f, dtype=object), inputs, seeds=seeds)
        return dv, eta_f, qd_all, jac[:b.m], jac[b.m:], inputs
    d_dv, d_eta = _implicit(b, dv, eta_f, qd_all, inputs, seeds, primal, sweep)
    return dv, eta_f, qd_all, d_dv, d_eta, inputs


def applicable_routes(model) -> list[str]:
    """The routes of :data:`ROUTES` that apply to ``model``: the articulated-body ones for a tree
    (:func:`symgen.codegen.aba.applies`), the implicit one of them with motion given on joints; the
    graph one on the null-space primal where it applies (:func:`symgen.codegen.null_space.applies`);
    every implicit one also by the adjoint sweep, and in closed form where
    :func:`analytic_partials_apply`; the nested ones where :func:`nested_applies`."""
    routes = ["graph-dense", "graph-joint-space", "implicit-dense", "implicit-joint-space"]
    if null_space.applies(model):
        routes.insert(2, "graph-null-space")
    if aba.applies(model):
        routes.insert(2, "graph-articulated-body")
        if aba.motion_coordinates(model) is not None:
            routes.append("implicit-articulated-body")
    implicit = [r for r in routes if r.startswith("implicit")]
    return routes + [r + REVERSE for r in implicit] + (
        [r + ANALYTIC for r in implicit] if analytic_partials_apply(model) else []) + (
        ["nested-dense", "nested-dense" + REVERSE] if nested_applies(model) else [])


def cheapest(counts: dict[str, tuple[int, int]]) -> str:
    """The route to keep of ``{route: (straight-line operations, operations + library flops)}``:
    the lowest second count among the routes within :data:`STRAIGHT_LINE_BUDGET` if one is, among
    all otherwise; the first in :data:`ROUTES` order on a tie."""
    return min(counts, key=lambda r: (counts[r][0] > STRAIGHT_LINE_BUDGET, counts[r][1], ROUTES.index(r)))


def choose(model, trace, method: str = "auto") -> ChosenFunction:
    """``trace(route)`` for every applicable route (or the one ``method`` names); the cheapest by
    operations plus library flops (:func:`~symgen.codegen.functions.traced_cost`) is kept
    (the first in :data:`ROUTES` order on a tie) and recorded -- among the routes whose
    straight-line part is within :data:`STRAIGHT_LINE_BUDGET` when one is: a route that leaves
    more of its work to the library LU's loops (where a mass matrix is too large for the
    straight-line ``LDL^T``, :data:`~symgen.codegen.sparse_lu.LDLT_MAX`) can then win on time."""
    routes = applicable_routes(model)
    if method != "auto":
        if method not in routes:
            raise CodegenError(f"scene {model.scene.name!r}: derivative route {method!r} does not apply; "
                               f"choose from auto, {', '.join(routes)}")
        routes = [method]
    traced, counts = {}, {}
    for route in routes:
        try:
            traced[route] = trace(route)
        except (aba.SingularArticulatedInertia, ReverseUnsupported):
            if method != "auto":
                raise
            continue
        ops = traced_counts(traced[route])
        counts[route] = ops["total"], ops["total"] + library_flops(ops)
    best = cheapest(counts)
    return ChosenFunction(**vars(traced[best]), metadata={"method": best,
                                                          "method_costs": {r: c for r, (_, c) in counts.items()}})


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


def _ambient_rows(b: Builder, qd_all, d_dv, inputs) -> np.ndarray:
    """``d xdot / d(x, tau)`` with the ``q`` columns in the ambient entries of ``q``
    (:func:`~symgen.codegen.tangent.ambient_map`): a 1-DOF joint's row is its rate's, a spherical
    joint's four rows those of ``rho = 1/2 p (x) (0, w)`` of its normalised quaternion,

        d rho = 1/2 p (x) (0, dw) + 1/2 ((1 - p p^T) dp) (x) (0, w),

    the second term, in the joint's own four columns, being ``1/2 e_a (x) (0, w) - p_a rho``."""
    g = b.g
    columns, seeds, nt = q_directions(b)
    first = {name: c for c, name in reversed(list(enumerate(c.joint for c in b.model.tree.coordinates)))}
    layout = position_layout(b.model)
    coords = [first[name] + k for name, _, _, size in layout for k in range(1 if size == 1 else 3)]
    d_rates = differentiate(g, np.array([qd_all[c] for c in coords], dtype=object), inputs, seeds=seeds)

    def ambient(jac):
        return np.concatenate([node_matmul(jac[:, :nt], ambient_map(b)), jac[:, nt:]], axis=1)

    d_rates, d_dv = ambient(d_rates), ambient(d_dv)
    q = g.input("q", b.inputs[0].size)
    rows, r = [], 0
    for name, _, off, size in layout:
        if size == 1:
            rows.append(d_rates[r])
            r += 1
            continue
        p = q[off:off + 4]
        w = [qd_all[first[name] + k] for k in range(3)]
        half = [g.mul(0.5, e) for e in p]
        rho = quaternion_product(half, [0] + w)
        block = [quaternion_product(half, [0] + list(d_rates[r:r + 3, j])) for j in range(d_rates.shape[1])]
        for a in range(4):
            unit = [0.5 if i == a else 0 for i in range(4)]
            turn = quaternion_product(unit, [0] + w)
            block[off + a] = [x + t - p[a] * e for x, t, e in zip(block[off + a], turn, rho)]
        rows.extend(np.array(block, dtype=object).T)
        r += 3
    return np.concatenate([np.array(rows, dtype=object).reshape(len(rows), -1), d_dv], axis=0)


def _state_derivative_jacobian(model, method: str = "auto") -> Function:
    spherical = any(size != 1 for *_, size in position_layout(model))

    def trace(route):
        b = Builder(model)
        _, _, qd_all, d_dv, _, inputs = _jacobians(b, route)
        nq, m = b.inputs[0].size, b.m
        if spherical:
            jac = _ambient_rows(b, qd_all, d_dv, inputs)
        else:
            rates = [qd_all[c] for c in state_rows(model)]
            d_rates = differentiate(b.g, np.array(rates, dtype=object), inputs)   # 1-DOF joints: no seeds
            jac = np.concatenate([d_rates, d_dv], axis=0)
        return b.finish("state_derivative_jacobian",
                        "Jacobians of the simulation's right-hand side dx/dt = [dq/dt; dV_m/dt] for x = [q; V_m] "
                        "(state_derivative; a quaternion's rate 1/2 q (x) (0, w), normalised): d xdot / dx in the "
                        "entries of x (a quaternion's four, at unit length) and d xdot / dtau; eta_m held.",
                        [("dxdot_dx", jac[:, :nq + m], "d xdot / dx, x = [q; V_m] ((nq + m) x (nq + m))"),
                         ("dxdot_dtau", jac[:, nq + m:], "d xdot / dtau ((nq + m) x n)")])
    return choose(model, trace, method)
