"""``inverse_dynamics_derivatives``: the Jacobians of joint-space inverse dynamics, generated.

``tau(q, qd, qdd) = M_q qdd + C_q qd + G_q`` is traced exactly as ``inverse_dynamics``
(:meth:`symgen.codegen.builder.Builder.joint_space_forces`), then differentiated in its own graph by
:func:`symgen.codegen.derivatives.differentiate` (forward mode, sparse, folded and shared) or by
the adjoint sweep (:mod:`symgen.codegen.reverse`); on a tree of revolute and prismatic joints the
partials are also traced in closed form (:mod:`symgen.dynamics.rnea_derivatives`: ``O(N)``
recursions and a six-vector product per entry, fewer operations than either sweep on long or
general chains). The cheapest of the three is kept (:data:`ROUTES`). Through the sweeps:

* ``dtau_dqd`` and ``M = dtau/dqdd`` are the plain partials (``tau`` is linear in ``qdd``, so the
  second is ``M_q`` of eq. (30));
* ``dtau_dq`` is the derivative along the independent coordinates, one column per coordinate:
  a 1-DOF joint's position moved by its entry of ``q``, a spherical joint's rotation turned in its
  child frame, ``R exp(hat(delta))`` (:mod:`symgen.codegen.tangent`; Pinocchio's convention for
  ``computeRNEADerivatives``). On a tree every coordinate is
  independent (``P`` of eq. (10) is a constant selection) and it is the plain partial. On a closed
  chain whose loops close through passive joints (``q_u1``) the traced ``tau`` reads every joint position, the dependent ones included; moving the
  independent coordinates along the constraint manifold moves all positions at the rate
  ``dq_all/dq = P`` (eq. 10; a revolute or prismatic position's rate is its joint rate, a
  spherical joint's the angular velocity in its child frame, the same direction as its columns),
  so ``dtau_dq = (d tau / d q_all) P`` by the chain rule, with ``P`` the traced one. Where the loops
  close through actuated joints only (``q_u1`` empty: ``arm_on_plane``, ``multi_arm``)
  ``inverse_dynamics`` is over every coordinate (the closure is carried by ``eta_f``), ``P = 1``
  and the partials are plain.

Refused (:func:`check_supported`): loops closed by passive and actuated dependent joints at once.
"""
from __future__ import annotations

import numpy as np

from ..dynamics.rnea_derivatives import (EntryFactors, UnsupportedJoint, ancestor_coordinates, entry_factors,
                                         rnea_derivatives)
from ..errors import CodegenError
from .builder import Builder, Function
from .derivatives import differentiate
from .functions import ChosenFunction, traced_cost
from .node_product import node_matmul
from .reverse import ReverseUnsupported, differentiate_reverse
from .tangent import coordinate_columns, q_directions
from .trace import has_gravity


def check_supported(model, function: str = "inverse_dynamics_derivatives") -> None:
    """A :class:`CodegenError` naming the loop closures of a scene whose dependent coordinates
    are both passive (``q_u1``) and actuated (``q_a1``): there ``P`` of eq. (10) solves only part
    of the closure and the direction ``P e_i`` leaves the manifold, so no derivative along it is
    defined."""
    part = model.partition
    if part.u1 and part.a1:
        joints = sorted({model.tree.coordinates[c].joint for c in part.a1})
        raise CodegenError(f"scene {model.scene.name!r}: {function} needs the loops closed "
                           f"by passive joints only or by actuated joints only; actuated joint(s) "
                           f"{', '.join(joints)} are dependent beside passive ones, where eq. (10) does not "
                           "follow the constraint manifold")


#: the routes ``inverse_dynamics_derivatives`` traces, the cheapest kept (``ops.json``: ``method``):
#: the recursion's graph differentiated by either sweep, or the closed-form partials of
#: :mod:`symgen.dynamics.rnea_derivatives` (a tree of one-coordinate joints)
ROUTES = ("forward", "reverse", "analytic")


def _inverse_dynamics_derivatives(model) -> Function:
    """Every route of :data:`ROUTES` that applies traced, the cheapest by :func:`traced_cost` kept
    (the first on a tie) and recorded with every cost; the reverse sweep where the graph holds a
    library solve (a closed chain's) and the analytic route off a tree of revolute and prismatic
    joints are not traced."""
    check_supported(model)
    traced = {}
    for route in ROUTES:
        try:
            traced[route] = _traced_analytic(model) if route == "analytic" else _traced(model, route)
        except (ReverseUnsupported, UnsupportedJoint):
            continue
    costs = {route: traced_cost(fn) for route, fn in traced.items()}
    best = min(traced, key=lambda k: (costs[k], ROUTES.index(k)))
    return ChosenFunction(**vars(traced[best]), metadata={"method": best, "method_costs": costs})


def analytic_applies(model) -> bool:
    """The closed-form partials cover a tree (no loop closure) of one-coordinate joints."""
    return (not model.scene.constraints and not model.partition.u1 and not model.partition.a1
            and all(j.kind.dof == 1 for j in model.tree.joints if j.kind.dof))


def closed_form_partials(b: Builder, qd_all, qdd_all) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(d tau/dq_all, d tau/dqd_all, M)`` (``N_all x N_all`` arrays of nodes, tree coordinates)
    of the joint forces ``inverse_dynamics`` traces: :func:`~symgen.dynamics.rnea_derivatives.rnea_derivatives`
    on the tracer's transforms and body parameters, plus what the model adds to the recursion --
    the viscous friction's ``b`` on the diagonal of ``d tau/dqd`` (Coulomb friction's sign has no
    derivative off ``qd = 0``), the springs' ``k`` on that of ``d tau/dq`` and the rotor inertias
    on that of ``M`` (zero constants fold away).

    The ancestor-pair entries are straight-line dot products, or, where the tree has at least
    :data:`LOOPED_PAIRS` of them (:func:`loops_entries`), five banded library products
    (:func:`looped_entries`)."""
    if not analytic_applies(b.model):
        raise UnsupportedJoint(f"scene {b.model.scene.name!r}: not a tree of one-coordinate joints")
    t = b.t
    args = (*t.force_frames, qd_all, qdd_all)
    kwargs = dict(gravity=has_gravity(b.model), inertias=t.joint_force_inertias)
    if loops_entries(t.tree):
        dq, dqd, mass = looped_entries(b.g, entry_factors(*args, **kwargs))
    else:
        d = rnea_derivatives(*args, **kwargs)
        dq, dqd, mass = (np.array(x, dtype=object) for x in (d.dtau_dq, d.dtau_dqd, d.mass))
    for c, (stiffness, viscous, rotor) in diagonal_terms(t).items():
        dqd[c, c] = dqd[c, c] + viscous
        dq[c, c] = dq[c, c] + stiffness
        mass[c, c] = mass[c, c] + rotor
    return dq, dqd, mass


def diagonal_terms(t) -> dict[int, tuple]:
    """Per tree coordinate, ``(k, b, J)``: what the model adds to the diagonals of ``d tau/dq``,
    ``d tau/dqd`` and ``M`` beside the recursion (a joint spring's stiffness, viscous friction,
    rotor inertia; zero constants where there is none)."""
    consts = t.consts
    return {c: (consts.stiffness[k], consts.viscous[k], consts.rotor[k])
            for k, joint in enumerate(t.tree.joints) for c in joint.coords}


#: fewest ancestor pairs (a coordinate and one at or below it) whose closed-form entries are
#: computed by library products rather than straight-line dot products (:func:`loops_entries`):
#: ``chain:n=12``'s 78, from where ``benchmarks/closed_form_products.md`` times the products faster
#: and the closed form with them still counts fewer operations than the reverse sweep (below, the
#: products' flops would hand ``chain:n=10`` and ``chain:n=11`` to the reverse sweep, which no
#: benchmark times against them)
LOOPED_PAIRS = 78


def loops_entries(tree) -> bool:
    """Whether the closed form's entries go to library products: at least :data:`LOOPED_PAIRS`
    ancestor pairs (``benchmarks/closed_form_products.md`` times both ways)."""
    return ancestor_pairs(tree) >= LOOPED_PAIRS


def ancestor_pairs(tree) -> int:
    """The pairs of a coordinate and one at or below it (``N (N + 1) / 2`` on a chain): the
    closed form's entries on and below the diagonal of each output, each a dot product."""
    return sum(len(above) + 1 for above in ancestor_coordinates(tree))


def _cover(rows) -> tuple[int, int]:
    """The smallest range ``(lo, hi)`` holding ``rows`` (``(0, 0)`` when there are none)."""
    rows = list(rows)
    return (min(rows), max(rows) + 1) if rows else (0, 0)


def looped_entries(g, f: EntryFactors) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(d tau/dq, d tau/dqd, M)`` of the closed form (:func:`~symgen.dynamics.rnea_derivatives.rnea_derivatives`)
    from its factors by five banded products (:mod:`symgen.codegen.graph_products`). Each product's
    column ``j`` is row ``j`` of its output (its rows the moved coordinates ``i``), so its result
    is laid out as the row-major output and the C target writes it there
    (:mod:`symgen.codegen.targets.c_products`); in depth-first coordinate order each column's rows
    are a contiguous range:

    * ``d tau_j/dq_i = [u_i; -w_i] . [B^c_j^T S_j; I^c_j S_j]`` and ``d tau_j/dqd_i = [-s_i; -y_i] . (same)``
      for ``i`` at or above ``j`` (at most nine terms each: ``B^c_j^T S_j`` has no linear part, so
      the product leaves out the three terms of ``u_i`` and ``s_i``'s linear parts);
    * ``d tau_j/dq_i = g_q_i . S_j`` and ``d tau_j/dqd_i = g_qd_i . S_j`` for ``i`` strictly below
      ``j`` (at most six terms);
    * ``M_ji = M_ij = S_i . I^c_j S_j`` for ``i`` at or above ``j`` (at most six terms; the C target
      copies the lower triangle into the upper one).

    A product leaves out any term that is zero in every row or column (a planar chain's).

    Entries no pair reaches (a subtree that carries nothing) stay structural zeros; rows a covering
    range computes beyond the wanted ones (a tree declared breadth first) are never read."""
    n = len(f.axes)
    row, lower_q, lower_qd, upper_q, upper_qd = triangle_factors(f)
    inertia = [r[1] if r is not None else (0,) * 6 for r in f.rows]
    at_or_above = [[] for _ in range(n)]           # j -> the moved coordinates i of its lower entries
    for i in range(n):
        if f.columns[i] is not None:
            for j in f.below[i]:
                if f.rows[j] is not None:
                    at_or_above[j].append(i)
    strictly_below = [[i for i in f.below[j] if i != j and f.columns[i] is not None] for j in range(n)]
    lower = [_cover(at_or_above[j]) for j in range(n)]
    by_row = np.array(row, dtype=object).T                      # 12 x n: column j the row factors of j
    by_axis = np.array(f.axes, dtype=object).T
    dq_lower = g.product(lower_q, by_row, lower, "closed-form d tau/dq at and above each torque's coordinate")
    dqd_lower = g.product(lower_qd, by_row, lower, "closed-form d tau/dqd at and above each torque's coordinate")
    dq_upper = g.product(upper_q, by_axis, [_cover(b) for b in strictly_below],
                         "closed-form d tau/dq below each torque's coordinate")
    dqd_upper = g.product(upper_qd, by_axis, [_cover(b) for b in strictly_below],
                          "closed-form d tau/dqd below each torque's coordinate")
    masses = g.product(list(f.axes), np.array(inertia, dtype=object).T, lower,
                       "closed-form M on and below the diagonal")
    dq, dqd, mass = (np.zeros((n, n), dtype=object) for _ in range(3))
    for j in range(n):
        for i in at_or_above[j]:
            dq[j, i], dqd[j, i] = dq_lower[i, j], dqd_lower[i, j]
            mass[j, i] = mass[i, j] = masses[i, j]
        for i in strictly_below[j]:
            dq[j, i], dqd[j, i] = dq_upper[i, j], dqd_upper[i, j]
    return dq, dqd, mass


def triangle_factors(f: EntryFactors) -> tuple[list, list, list, list, list]:
    """``(rows, lower_q, lower_qd, upper_q, upper_qd)``, per coordinate, the twelve-term vectors
    whose dot products are the closed form's entries (:func:`looped_entries`): torque ``j``'s
    ``rows[j] = [B^c_j^T S_j; I^c_j S_j]`` against the moved coordinate ``i``'s ``lower_q[i] =
    [u_i; -w_i]`` and ``lower_qd[i] = [-s_i; -y_i]`` for ``i`` at or above ``j``; ``S_j`` against
    the six-term ``upper_q[i] = g_q_i`` and ``upper_qd[i] = g_qd_i`` for ``i`` below ``j``. Zeros for
    a coordinate with nothing below it (no row) or nothing moving with it (no column)."""
    zero6 = (0,) * 6
    column = [c if c is not None else (zero6,) * 6 for c in f.columns]
    rows = [r[0] + r[1] if r is not None else zero6 * 2 for r in f.rows]
    return (rows, [c[0] + c[1] for c in column], [c[2] + c[3] for c in column], [c[4] for c in column],
            [c[5] for c in column])


def serial_chain(tree) -> bool:
    """Whether the coordinates form one path, each below all those before it (a serial chain
    declared root first): the closed form's ancestor pairs are then the lower triangle."""
    return all(above == list(range(c)) for c, above in enumerate(ancestor_coordinates(tree)))


def scanned_inverse_products(b: Builder, qd_all, qdd_all, inverse) -> tuple[np.ndarray, np.ndarray]:
    """``(-W d tau/dq, -W d tau/dqd)`` for the closed-form partials of a serial chain
    (:func:`serial_chain`) at ``qd_all, qdd_all`` and the symmetric ``n x n`` array of nodes
    ``inverse`` (``W = M^-1``: the forward-dynamics Jacobians), each by one scan product
    (:class:`~symgen.codegen.graph_products.ScanProduct`): torque ``j``'s entry for the coordinate
    ``i`` moved is ``row_j . column_i`` for ``j >= i`` and ``S_j . g_i`` for ``j < i``
    (:func:`looped_entries`), so the running sums over ``j`` stand for the products that form
    ``d tau/dq`` and multiply it by ``W``. The model's diagonal terms (springs, viscous friction:
    :func:`closed_form_partials`) are added as ``-k_i W[:, i]``."""
    g, t = b.g, b.t
    f = entry_factors(*t.force_frames, qd_all, qdd_all, gravity=has_gravity(b.model), inertias=t.joint_force_inertias)
    rows, lower_q, lower_qd, upper_q, upper_qd = triangle_factors(f)
    inverse = np.asarray(inverse, dtype=object)
    diagonal = diagonal_terms(t)
    out = []
    for lower, upper, which, what in ((lower_q, upper_q, 0, "d tau/dq"), (lower_qd, upper_qd, 1, "d tau/dqd")):
        x = g.scan_product(inverse, np.array(rows, dtype=object), [[g.neg(v) for v in c] for c in lower],
                           np.array(f.axes, dtype=object), [[g.neg(v) for v in c] for c in upper],
                           f"M^-1 times the closed-form {what}").T
        for c, terms in diagonal.items():                  # a zero constant folds away
            x[:, c] = [g.sub(v, g.mul(terms[which], w)) for v, w in zip(x[:, c], inverse[c, :])]
        out.append(x)
    return out[0], out[1]


def _traced_analytic(model) -> Function:
    """The closed-form route (:func:`closed_form_partials`), projected on the independent
    coordinates as ``P^T (.) P`` (a selection on a tree)."""
    b = Builder(model)
    _, _, qd_all, qdd_all = b.joint_space_rates()
    p = b.t.p_full()
    outs = [product_of_nodes(product_of_nodes(p.T, a), p) for a in closed_form_partials(b, qd_all, qdd_all)]
    for k, v in np.ndenumerate(outs[0]):
        b.g.label(v, f"dtau_dq_{k[0]}_{k[1]}")
    return b.finish("inverse_dynamics_derivatives", _DOC,
                    [("dtau_dq", outs[0], _OUTPUT_DOCS[0]), ("dtau_dqd", outs[1], _OUTPUT_DOCS[1]),
                     ("M", outs[2], _OUTPUT_DOCS[2])])


def product_of_nodes(a, b):
    """``a @ b`` of two arrays of nodes, by :func:`~symgen.codegen.node_product.node_matmul` where it applies."""
    out = node_matmul(a, b)
    return a @ b if out is None else out


_DOC = ("Jacobians of inverse dynamics tau = M_q qdd + C_q qd + G_q: d tau/dq along the independent "
        "coordinates (through P of eq. (10) on a closed chain; a spherical joint turned in its child frame, "
        "R exp(hat(delta))), d tau/dqd and d tau/dqdd = M_q.")
_OUTPUT_DOCS = ("d tau / dq along the independent coordinates (n x n)", "d tau / dqd (n x n)",
                "d tau / dqdd = M_q, the joint-space mass matrix (n x n)")


def _traced(model, sweep: str) -> Function:
    b = Builder(model)
    qd, qdd, tau = b.joint_space_forces()
    columns, seeds, nq = q_directions(b)
    n = b.n
    jacobian = differentiate if sweep == "forward" else differentiate_reverse
    jac = jacobian(b.g, tau, columns + list(qd) + list(qdd), seeds=seeds)
    d_q_all = jac[:, coordinate_columns(model)]                   # d tau / d q_all, N_all columns
    p = b.t.p_full()
    dtau_dq = product_of_nodes(d_q_all, p)                       # along eq. (10)
    for k, v in np.ndenumerate(dtau_dq):
        b.g.label(v, f"dtau_dq_{k[0]}_{k[1]}")
    return b.finish("inverse_dynamics_derivatives", _DOC,
                    [("dtau_dq", dtau_dq, _OUTPUT_DOCS[0]), ("dtau_dqd", jac[:, nq:nq + n], _OUTPUT_DOCS[1]),
                     ("M", jac[:, nq + n:], _OUTPUT_DOCS[2])])
