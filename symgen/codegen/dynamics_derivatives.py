"""``inverse_dynamics_derivatives``: the Jacobians of joint-space inverse dynamics, generated.

``tau(q, qd, qdd) = M_q qdd + C_q qd + G_q`` is traced exactly as ``inverse_dynamics``
(:meth:`symgen.codegen.builder.Builder.joint_space_forces`), then differentiated in its own graph by
:func:`symgen.codegen.derivatives.differentiate` (forward mode, sparse, folded and shared):

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

from ..errors import CodegenError
from .builder import Builder, Function
from .derivatives import differentiate
from .functions import ChosenFunction, traced_cost
from .node_product import node_matmul
from .reverse import ReverseUnsupported, differentiate_reverse
from .tangent import coordinate_columns, q_directions


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


#: the sweeps ``inverse_dynamics_derivatives`` traces, the cheaper kept (``ops.json``: ``method``)
SWEEPS = ("forward", "reverse")


def _inverse_dynamics_derivatives(model) -> Function:
    """Both sweeps traced (:data:`SWEEPS`), the cheaper by :func:`traced_cost` kept (forward on a
    tie) and recorded with both costs; the reverse one where the graph holds a library solve
    (a closed chain's) is not traced."""
    check_supported(model)
    traced = {}
    for sweep in SWEEPS:
        try:
            traced[sweep] = _traced(model, sweep)
        except ReverseUnsupported:
            continue
    costs = {sweep: traced_cost(fn) for sweep, fn in traced.items()}
    best = min(traced, key=lambda k: (costs[k], SWEEPS.index(k)))
    return ChosenFunction(**vars(traced[best]), metadata={"method": best, "method_costs": costs})


def _traced(model, sweep: str) -> Function:
    b = Builder(model)
    qd, qdd, tau = b.joint_space_forces()
    columns, seeds, nq = q_directions(b)
    n = b.n
    jacobian = differentiate if sweep == "forward" else differentiate_reverse
    jac = jacobian(b.g, tau, columns + list(qd) + list(qdd), seeds=seeds)
    d_q_all = jac[:, coordinate_columns(model)]                   # d tau / d q_all, N_all columns
    p = b.t.p_full()
    dtau_dq = node_matmul(d_q_all, p)                            # along eq. (10)
    if dtau_dq is None:
        dtau_dq = d_q_all @ p
    for k, v in np.ndenumerate(dtau_dq):
        b.g.label(v, f"dtau_dq_{k[0]}_{k[1]}")
    return b.finish("inverse_dynamics_derivatives",
                    "Jacobians of inverse dynamics tau = M_q qdd + C_q qd + G_q: d tau/dq along the independent "
                    "coordinates (through P of eq. (10) on a closed chain; a spherical joint turned in its child frame, "
                    "R exp(hat(delta))), d tau/dqd and d tau/dqdd = M_q.",
                    [("dtau_dq", dtau_dq, "d tau / dq along the independent coordinates (n x n)"),
                     ("dtau_dqd", jac[:, nq:nq + n], "d tau / dqd (n x n)"),
                     ("M", jac[:, nq + n:], "d tau / dqdd = M_q, the joint-space mass matrix (n x n)")])
