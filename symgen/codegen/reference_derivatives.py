"""The dense reference of ``inverse_dynamics_derivatives``: central differences of the dense
model's joint-space inverse dynamics (:meth:`symgen.model.Model.evaluate`,
``tau = M_q qdd + C_q qd + G_q``, eq. 30) in extended precision.

No tracing and no recursion: each difference quotient evaluates the ``O(n_S^2)`` dense model twice,
at 50 digits (or the given :class:`~symgen.math.fields.MpField`'s ``dps``) with a step of about
``10^-(dps/2 - 5)`` (``1e-20`` at 50 digits): the truncation error ``O(h^2)`` and the rounding
``10^-dps / h`` both stay far below float64's resolution.

On a closed chain with passive dependent joints (``q_u1``) the difference is taken *along the
constraint manifold*: the independent
coordinate is moved by ``+-h`` and the dependent ones re-solved at that precision by
:func:`symgen.closure.refine_closure` (which holds the independent ones), so the quotient is the
total derivative along eq. (10) -- an independent check of the generated chain rule through ``P``.
``M`` is the dense ``M_q`` itself. The base point is the state's ``q`` with its loops closed in
extended precision (the float ``q`` closes them to about 1e-16). Where the loops close through
actuated joints only, ``inverse_dynamics`` is over every coordinate and the differences are plain
partials at ``q`` as given. A spherical joint's coordinate ``k`` is its rotation turned in the
child frame, ``R exp(+-h e_k)`` (:func:`symgen.dynamics_jacobians.moved_position`), the direction
of the generated code's columns (:mod:`symgen.codegen.tangent`).
"""
from __future__ import annotations

import numpy as np

from ..closure import refine_closure
from ..dynamics_jacobians import moved_position
from ..math.configuration import Configuration
from ..math.fields import MpField
from ..model_solves import field_vector
from .dynamics_derivatives import check_supported
from .trace import position_layout

#: precision of the reference when the caller's field is ``float``
REFERENCE_DPS = 50


def step_size(fld: MpField):
    """The difference step ``10^-(dps // 2 - 5)`` of ``fld``."""
    return fld.const(10) ** -(fld.dps // 2 - 5)


def derivative_reference(model, state: dict, fld: MpField | None = None) -> dict[str, np.ndarray]:
    """``dtau_dq`` (along the independent coordinates), ``dtau_dqd`` and ``M`` at ``state`` (the
    float arrays ``q``, ``qd``, ``qdd`` of the generated code, taken exactly), in ``fld``."""
    check_supported(model)
    if fld is None:
        fld = MpField(model.tree.parameters, dps=REFERENCE_DPS)
    qd, qdd = field_vector(fld, state["qd"]), field_vector(fld, state["qdd"])
    closing = bool(model.partition.u1)        # else inverse_dynamics is over every coordinate
    base = field_positions(model, state["q"], fld)
    if closing:
        base = refine_closure(model, base, fld)
    h = step_size(fld)

    def tau(pos, rates):
        return model.evaluate(Configuration(pos), qd=rates, field=fld).joint_force(qdd)

    d_q = []
    for coord in model.partition.independent:
        c = model.tree.coordinates[coord]
        direction = (c.joint, None if c.kind.is_one_dof else c.component)
        moved = [moved_position(base, direction, s * h, fld) for s in (1, -1)]
        if closing:
            moved = [refine_closure(model, pos, fld) for pos in moved]
        d_q.append((tau(moved[0], qd) - tau(moved[1], qd)) / (2 * h))
    d_qd = []
    for i in range(model.counts.n):
        e = np.array([h if k == i else fld.zero for k in range(model.counts.n)], dtype=object)
        d_qd.append((tau(base, qd + e) - tau(base, qd - e)) / (2 * h))
    mass = model.evaluate(Configuration(base), qd=qd, field=fld).M_q
    return {"dtau_dq": np.array(d_q, dtype=object).T, "dtau_dqd": np.array(d_qd, dtype=object).T,
            "M": np.asarray(mass, dtype=object)}


def field_positions(model, q, fld: MpField) -> dict:
    """Joint -> position (an angle, a displacement or a rotation) in ``fld`` from the generated
    code's ``q`` (:func:`symgen.codegen.reference.field_configuration`)."""
    from .field_configuration import field_configuration

    rotations = field_configuration(model, q, fld).positions
    q = np.asarray(q, dtype=float)
    return {name: fld.const(q[off]) if size == 1 else rotations[name] for name, _, off, size in position_layout(model)}
