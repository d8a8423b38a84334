"""The dense reference of ``state_derivative_jacobian`` for scenes with spherical (and so free)
joints: central differences, in extended precision, of the simulation's right-hand side in the
entries of its state ``x = [q; V_m]`` themselves, a quaternion's four included.

The right-hand side is the one the integrators call (:mod:`symgen.simulation.dynamics`), written
out again here on the dense model (:meth:`symgen.model.Model.evaluate`, no tracing): each
quaternion ``p`` is normalised, its rotation is ``R(p) / |p|^2`` (the same rotation), the model
(32) is solved for ``dV_m`` (:func:`symgen.model_solves.solve_forward`), every joint's rate is
``qd_all = P Omega V_m`` (eqs. 10, 18), and

    dq/dt = [a 1-DOF joint's rate;  1/2 (p / |p|) (x) (0, w) for a spherical joint],

``w`` its three rates (the angular velocity in the child frame). The four entries of ``p`` are
moved one at a time by ``+-h`` (``h = 10^-(dps/2 - 5)``, ``1e-20`` at 50 digits), *off* the unit
sphere, so the normalisation is differentiated by the differences themselves -- nothing of the
generated code's turn columns or of their map to the quaternion entries
(:func:`symgen.codegen.tangent.ambient_map`) is assumed. ``dxdot/dtau`` is exact ((32) is linear
in ``tau``). Cost: ``2 (nq + m) + 1`` dense evaluations.
"""
from __future__ import annotations

import numpy as np

from ..math.configuration import Configuration
from ..math.fields import MpField
from ..model_solves import field_vector, solve_forward
from .tangent import quaternion_product
from .trace import position_layout, quaternion_matrix


def _rhs(model, q, v_m, tau, eta, fld: MpField) -> tuple[np.ndarray, object]:
    """``(xdot, data)`` at the field numbers ``q`` (ambient: quaternions of any length), ``v_m``."""
    layout = position_layout(model)
    pos, units = {}, {}
    for name, _, off, size in layout:
        if size == 1:
            pos[name] = q[off]
            continue
        p = list(q[off:off + 4])
        norm2 = sum(e * e for e in p)
        pos[name] = np.array([[e / norm2 for e in row] for row in quaternion_matrix(*p)], dtype=object)
        units[name] = [e / fld.sqrt(norm2) for e in p]
    data = model.evaluate(Configuration(pos), V_m=v_m, eta_m=eta, field=fld)
    dv, _ = solve_forward(data, tau)
    rates = data.maps.P.v @ data.maps.Omega.v @ data.V_m
    first: dict[str, int] = {}
    for c, coord in enumerate(model.tree.coordinates):
        first.setdefault(coord.joint, c)
    qdot: list = []
    for name, _, _, size in layout:
        c = first[name]
        if size == 1:
            qdot.append(rates[c])
        else:
            half = [e / 2 for e in units[name]]
            qdot.extend(quaternion_product(half, [fld.zero] + list(rates[c:c + 3])))
    return np.concatenate([np.array(qdot, dtype=object), dv]), data


def state_jacobian_differences(model, state: dict, fld: MpField) -> dict[str, np.ndarray]:
    """``dxdot_dx`` and ``dxdot_dtau`` at ``state`` (the generated code's float ``q``, ``V_m``,
    ``tau``, ``eta_m``, taken exactly) as numbers of ``fld``."""
    q = [fld.const(v) for v in np.asarray(state["q"], dtype=float)]
    v_m, tau = field_vector(fld, state["V_m"]), field_vector(fld, state["tau"])
    eta_m = state.get("eta_m")
    eta = field_vector(fld, eta_m) if eta_m is not None and len(eta_m) else None
    h = fld.const(10) ** -(fld.dps // 2 - 5)
    x = q + list(v_m)
    nq = len(q)
    cols = []
    for k in range(len(x)):
        ends = []
        for s in (1, -1):
            y = list(x)
            y[k] = y[k] + s * h
            ends.append(_rhs(model, y[:nq], np.array(y[nq:], dtype=object), tau, eta, fld)[0])
        cols.append((ends[0] - ends[1]) / (2 * h))
    _, data = _rhs(model, q, v_m, tau, eta, fld)
    n = model.counts.n
    zero = solve_forward(data, field_vector(fld, [0] * n))[0]
    d_tau = [np.concatenate([[fld.zero] * nq, solve_forward(data, field_vector(fld, [int(j == k) for j in range(n)]))[0]
                             - zero]) for k in range(n)]
    return {"dxdot_dx": np.array(cols, dtype=object).T, "dxdot_dtau": np.array(d_tau, dtype=object).T.reshape(-1, n)}
