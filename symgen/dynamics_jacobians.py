"""Jacobians of forward dynamics (32) and of the simulation's right-hand side from the dense model,
in extended precision: the independent reference of the generated ``forward_dynamics_derivatives``
and ``state_derivative_jacobian``, and what :meth:`symgen.model.Model.forward_dynamics_derivatives`
and :meth:`~symgen.model.Model.state_derivative_jacobian` return.

No tracing and no recursion: the dense model (:meth:`symgen.model.Model.evaluate`, ``O(n_S^2)``
matrices) is solved for ``(dV_m, eta_f)`` (:func:`symgen.model_solves.solve_forward`) and
``qd_all = P Omega V_m`` (eqs. 10, 18, 20) at shifted arguments, in an
:class:`~symgen.math.fields.MpField` (50 digits by default):

* ``q`` and ``V_m``: central differences with step ``h = 10^-(dps/2 - 5)`` (``1e-20`` at 50
  digits); truncation ``O(h^2)`` and rounding ``10^-dps / h`` are both about ``10^-(dps/2 - 10)``,
  far below float64's resolution;
* ``tau``: exact, since (32) is linear in ``tau``: ``solve(e_k) - solve(0)`` at one evaluation.

``q`` means every joint position, one per 1-DOF joint in scene order, the dependent joints of
closed chains included, moved one at a time *without* re-closing the loops: the plain partials of
the functions of ``q`` that eqs. (10), (18) and (32) define at any configuration, as the
simulation state ``x = [q; V_m]`` holds it. (Along the manifold, multiply by ``dq/dq_ind``: ``P``
of eq. (10) for loops closed by passive joints.) A spherical joint's rotation is instead turned
in its child frame, ``R exp(+-h e_k)`` (Rodrigues' formula in the field,
:func:`symgen.closure.field_rot_exp`): three columns per spherical joint, the convention of the
generated code (:mod:`symgen.codegen.tangent`) and of Pinocchio. :func:`state_jacobian` refuses
spherical joints (its state holds the quaternion; the generated ``state_derivative_jacobian``'s
reference in the quaternion entries is :mod:`symgen.codegen.state_jacobian_reference`).
"""
from __future__ import annotations

from typing import Any

import numpy as np

from .closure import field_rot_exp
from .errors import StateError
from .math.configuration import Configuration, as_configuration
from .math.fields import MpField
from .model_solves import field_vector, solve_forward

#: precision of the differences when the caller gives no field
DEFAULT_DPS = 50


def step_size(fld: MpField) -> Any:
    """The difference step ``10^-(dps // 2 - 5)`` of ``fld``."""
    return fld.const(10) ** -(fld.dps // 2 - 5)


def position_joints(model) -> list[str]:
    """The joints whose positions ``q`` holds, in scene order -- the order of the generated code's
    ``q``, which the spanning tree's own order need not follow (``multi_arm`` interleaves its arms)
    -- (1-DOF joints; a spherical joint raises a :class:`StateError` naming it)."""
    tree_joints = {joint.name: joint for joint in model.tree.joints}
    names = []
    for name in model.scene.joints:
        joint = tree_joints.get(name)
        if joint is None or not joint.coords:
            continue
        if joint.kind.position_is_rotation:
            raise StateError(f"joint {name!r}: the derivatives handle revolute and prismatic joints only; a "
                             "spherical joint's rotation has no partials in its quaternion entries (the generated "
                             "state_derivative_jacobian takes the state's quaternion entries)")
        names.append(name)
    return names


def tangent_directions(model) -> list[tuple[str, int | None]]:
    """The directions of ``d / dq`` in scene order: ``(joint, None)`` for a 1-DOF joint's
    position, ``(joint, k)`` for a spherical joint turned about its child frame's axis ``k``."""
    tree_joints = {joint.name: joint for joint in model.tree.joints}
    out: list[tuple[str, int | None]] = []
    for name in model.scene.joints:
        joint = tree_joints.get(name)
        if joint is None or not joint.coords:
            continue
        out.extend([(name, k) for k in range(3)] if joint.kind.position_is_rotation else [(name, None)])
    return out


def field_position(value: Any, fld: MpField) -> Any:
    """A joint position (a number, or a rotation matrix) in ``fld``, floats taken exactly."""
    if isinstance(value, np.ndarray):
        return np.array([[fld.const(v) for v in row] for row in value], dtype=object)
    return fld.const(value)


def moved_position(pos: dict, direction: tuple[str, int | None], step: Any, fld: MpField) -> dict:
    """``pos`` moved by ``step`` along ``direction`` (:func:`tangent_directions`): a 1-DOF
    position plus ``step``, a rotation ``R exp(step hat(e_k))``."""
    name, k = direction
    if k is None:
        return {**pos, name: pos[name] + step}
    w = [step if i == k else fld.zero for i in range(3)]
    return {**pos, name: pos[name] @ field_rot_exp(w, fld)}


def _field(model, field) -> MpField:
    if field is None:
        return MpField(model.tree.parameters, dps=DEFAULT_DPS)
    fld = model.field_of(field)
    if not isinstance(fld, MpField):
        raise StateError(f"field {getattr(fld, 'name', field)!r}: the derivatives are central differences in an "
                         "extended-precision field; use field='mp' or 'mp:D'")
    return fld


def _rates(data) -> np.ndarray:
    return data.maps.P.v @ data.maps.Omega.v @ data.V_m


def jacobians(model, config, V_m, tau, eta_m=None, field=None) -> dict[str, np.ndarray]:
    """The Jacobians at ``(config, V_m, tau[, eta_m])`` in ``field`` (an ``mp`` field; default 50
    digits), as field numbers: ``ddV_m_dq``, ``ddV_m_dV_m``, ``ddV_m_dtau`` and, when ``n > m``,
    ``deta_f_dq``, ``deta_f_dV_m``, ``deta_f_dtau``; ``dqd_all_dq``, ``dqd_all_dV_m`` (the rates of
    every joint coordinate); the ``q`` columns follow :func:`tangent_directions`. ``config``: a :class:`Configuration` or a mapping joint -> position
    (float inputs are taken at their exact values). Cost: ``2 (nq + m) + 1`` dense evaluations."""
    fld = _field(model, field)
    directions = tangent_directions(model)
    config = as_configuration(config, model.scene, "config")
    base = {name: field_position(config.positions[name], fld) for name, _ in directions}
    v_m, tau = field_vector(fld, V_m), field_vector(fld, tau)
    eta = field_vector(fld, eta_m) if eta_m is not None and len(eta_m) else None
    h = step_size(fld)

    def at(pos, v):
        d = model.evaluate(Configuration(pos), V_m=v, eta_m=eta, field=fld)
        dv, eta_f = solve_forward(d, tau)
        return np.concatenate([dv, eta_f, _rates(d)]), d

    cols_q = []
    for direction in directions:
        plus, minus = (at(moved_position(base, direction, s * h, fld), v_m)[0] for s in (1, -1))
        cols_q.append((plus - minus) / (2 * h))
    cols_v = []
    for i in range(len(v_m)):
        e = np.array([h if k == i else fld.zero for k in range(len(v_m))], dtype=object)
        cols_v.append((at(base, v_m + e)[0] - at(base, v_m - e)[0]) / (2 * h))
    _, data = at(base, v_m)
    n = model.counts.n
    zero = solve_forward(data, field_vector(fld, [0] * n))
    cols_t = []
    for k in range(n):
        dv, eta_f = solve_forward(data, field_vector(fld, [1 if j == k else 0 for j in range(n)]))
        cols_t.append(np.concatenate([dv - zero[0], eta_f - zero[1]]))
    d_q, d_v, d_t = (np.array(c, dtype=object).T.reshape(-1, len(c)) for c in (cols_q, cols_v, cols_t))
    m = model.counts.m
    out = {"ddV_m_dq": d_q[:m], "ddV_m_dV_m": d_v[:m], "ddV_m_dtau": d_t[:m]}
    if n > m:
        out.update(deta_f_dq=d_q[m:n], deta_f_dV_m=d_v[m:n], deta_f_dtau=d_t[m:n])
    out.update(dqd_all_dq=d_q[n:], dqd_all_dV_m=d_v[n:])
    return out


def state_jacobian(model, jac: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """``dxdot_dx`` and ``dxdot_dtau`` of ``x = [q; V_m]``, ``dx/dt = [qd_all at q's joints; dV_m]``
    (:mod:`symgen.simulation.state`), from the Jacobians of :func:`jacobians`."""
    first: dict[str, int] = {}
    for c, coord in enumerate(model.tree.coordinates):
        first.setdefault(coord.joint, c)
    rows = [first[name] for name in position_joints(model)]
    top = np.concatenate([jac["dqd_all_dq"][rows], jac["dqd_all_dV_m"][rows]], axis=1)
    bottom = np.concatenate([jac["ddV_m_dq"], jac["ddV_m_dV_m"]], axis=1)
    zero = np.array([[0] * model.counts.n] * len(rows), dtype=object).reshape(len(rows), model.counts.n)
    return {"dxdot_dx": np.concatenate([top, bottom], axis=0),
            "dxdot_dtau": np.concatenate([zero, jac["ddV_m_dtau"]], axis=0)}
