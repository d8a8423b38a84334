"""Jacobians of forward dynamics (32) and of the simulation's right-hand side from the dense model,
in extended precision: the independent reference of the generated ``forward_dynamics_derivatives``
and ``state_derivative_jacobian``, and what :meth:`symgen.model.Model.forward_dynamics_derivatives`
and :meth:`~symgen.model.Model.state_derivative_jacobian` return -- one function each for the
model API and the code generator's references (:mod:`symgen.codegen.reference`).

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
of eq. (10) for loops closed by passive joints.) Both Jacobians come from one function,
:func:`derivatives`, which differences one function of the state, ``[dV_m; eta_f; dq/dt]``
(:func:`_outputs`), and takes two conventions for a spherical joint:

* forward dynamics (:func:`jacobians`): its rotation turned in its child frame, ``R exp(+-h e_k)``
  (Rodrigues' formula in the field, :func:`symgen.closure.field_rot_exp`): three columns per
  spherical joint, the convention of the generated code (:mod:`symgen.codegen.tangent`) and of
  Pinocchio;
* the simulation's right-hand side (:func:`state_jacobian`): the four entries of its quaternion
  ``p`` in the state moved one at a time, *off* the unit sphere: the right-hand side reads
  ``p / |p|``, so the differences differentiate the normalisation themselves and nothing of the
  generated code's map from turns to quaternion entries
  (:func:`symgen.codegen.tangent.ambient_map`) is assumed.

A 1-DOF joint's and ``V_m``'s columns are the same differences in both.
"""
from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from .closure import field_rot_exp
from .errors import StateError
from .math.configuration import Configuration, ConfigurationLike, as_configuration
from .math.fields import MpField
from .math.spatial import matrix_to_quat, quaternion_matrix, quaternion_product
from .model_solves import check_length, field_vector, solve_forward

#: precision of the differences when the caller gives no field
DEFAULT_DPS = 50


def step_size(fld: MpField) -> Any:
    """The difference step ``10^-(dps // 2 - 5)`` of ``fld``."""
    return fld.const(10) ** -(fld.dps // 2 - 5)


def field_position(value: Any, fld: MpField) -> Any:
    """A joint position (a number, or a rotation matrix) in ``fld``, floats taken exactly."""
    if isinstance(value, np.ndarray):
        return np.array([[fld.const(v) for v in row] for row in value], dtype=object)
    return fld.const(value)


def moved_position(pos: dict, direction: tuple[str, int | None], step: Any, fld: MpField) -> dict:
    """``pos`` moved by ``step`` along ``direction``: ``(joint, None)`` a 1-DOF position plus
    ``step``, ``(joint, k)`` a rotation turned about its child frame's axis ``k``,
    ``R exp(step hat(e_k))``."""
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


def state_layout(model) -> list[tuple[str, int, int]]:
    """``(joint, offset, size)`` of each joint's entries in the state's ``q``, in scene order -- the
    order of the generated code's ``q``, which the spanning tree's own order need not follow
    (``multi_arm`` interleaves its arms): one entry per 1-DOF joint, a spherical joint's quaternion
    ``(w, x, y, z)`` four, a fixed joint none."""
    out, offset = [], 0
    for joint in model.scene.joints.values():
        size = joint.kind.position_size
        if size:
            out.append((joint.name, offset, size))
            offset += size
    return out


def state_positions(model, config: ConfigurationLike, fld: MpField) -> list[Any]:
    """The state's ``q`` (:func:`state_layout`) in ``fld``, floats taken at their exact values.

    ``config`` is checked by :func:`~symgen.math.configuration.as_configuration` (a typed
    :class:`StateError` naming the joint or the layout). A flat array is the state itself: its
    entries are taken as they are, a quaternion of any non-zero length. In a mapping a spherical
    joint's quaternion is taken as given; a rotation matrix (or a :class:`Configuration`, which
    holds matrices) as its quaternion with ``w >= 0``
    (:func:`~symgen.math.spatial.matrix_to_quat`, in the field), the one
    :func:`symgen.codegen.trace.position_vector` writes into the generated code's ``q``."""
    checked = as_configuration(config, model.scene, "config")
    if not isinstance(config, (Configuration, Mapping)):
        return list(field_vector(fld, config))
    given = config.positions if isinstance(config, Configuration) else config
    q: list[Any] = []
    for name, _, size in state_layout(model):
        if size == 1:
            q.append(field_position(checked.positions[name], fld))
        elif np.shape(given[name]) == (4,):
            q.extend(field_vector(fld, given[name]))
        else:
            q.extend(matrix_to_quat(field_position(np.asarray(checked.positions[name]), fld), sqrt=fld.sqrt))
    return q


def _point(model, q: list[Any], fld: MpField) -> tuple[dict, dict]:
    """The positions (joint -> number or rotation) and the unit quaternions of the state's ``q``:
    a quaternion ``p`` of any non-zero length stands for the rotation ``R(p / |p|)``, its
    homogeneous matrix divided by ``|p|^2``."""
    pos, units = {}, {}
    for name, off, size in state_layout(model):
        if size == 1:
            pos[name] = q[off]
            continue
        p = list(q[off:off + 4])
        norm2 = sum(e * e for e in p)
        pos[name] = np.array([[e / norm2 for e in row] for row in quaternion_matrix(*p)], dtype=object)
        units[name] = [e / fld.sqrt(norm2) for e in p]
    return pos, units


def _outputs(model, point: tuple[dict, dict], v_m, tau, eta, fld: MpField) -> tuple[np.ndarray, Any]:
    """``[dV_m; eta_f; dq/dt]`` at ``point`` (:func:`_point`) and ``v_m``, and the evaluation:
    (32) solved (:func:`~symgen.model_solves.solve_forward`), every joint's rate
    ``qd_all = P Omega V_m`` (eqs. 10, 18, 20), and the state's position rates, the simulation's
    right-hand side (:mod:`symgen.simulation.state`)::

        dq/dt = [a 1-DOF joint's rate;  1/2 (p / |p|) (x) (0, w) for a spherical joint]

    with ``w`` its three rates (the angular velocity in the child frame, eq. 21's ``dR/dt = R hat(w)``)."""
    pos, units = point
    data = model.evaluate(Configuration(pos), V_m=v_m, eta_m=eta, field=fld)
    dv, eta_f = solve_forward(data, tau)
    rates = data.maps.P.v @ data.maps.Omega.v @ data.V_m
    first: dict[str, int] = {}
    for c, coord in enumerate(model.tree.coordinates):
        first.setdefault(coord.joint, c)
    qdot: list[Any] = []
    for name, _, size in state_layout(model):
        c = first[name]
        if size == 1:
            qdot.append(rates[c])
        else:
            half = [e / 2 for e in units[name]]
            qdot.extend(quaternion_product(half, [fld.zero] + list(rates[c:c + 3])))
    return np.concatenate([dv, eta_f, np.array(qdot, dtype=object)]), data


def _columns(cols: list, rows: int) -> np.ndarray:
    return np.array(cols, dtype=object).T.reshape(rows, len(cols))


def derivatives(model, config: ConfigurationLike, V_m, tau, eta_m=None, field=None, *, forward: bool = True,
                state: bool = False) -> dict[str, np.ndarray]:
    """The Jacobians at ``(config, V_m, tau[, eta_m])`` in ``field`` (an ``mp`` field; default 50
    digits), as field numbers, from one set of differences of :func:`_outputs`:

    * ``forward``: ``ddV_m_dq``, ``ddV_m_dV_m``, ``ddV_m_dtau`` and, when ``n > m``, ``deta_f_dq``,
      ``deta_f_dV_m``, ``deta_f_dtau`` (the generated ``forward_dynamics_derivatives``'s outputs):
      ``d/dq`` one column per 1-DOF joint and three per spherical joint, its rotation turned in
      the child frame (:func:`moved_position`), in scene order;
    * ``state``: ``dxdot_dx`` and ``dxdot_dtau`` of the simulation's right-hand side,
      ``x = [q; V_m]``, ``dx/dt = [dq/dt; dV_m]`` (the generated ``state_derivative_jacobian``'s
      outputs), in the entries of ``x`` themselves, a quaternion's four moved off the unit sphere.

    ``config``: read by :func:`state_positions` (a flat ``q``, a mapping, a :class:`Configuration`).
    A 1-DOF position's and ``V_m``'s columns are shared. Cost: ``2 (n_1 + 3 n_s [forward] + 4 n_s
    [state] + m) + 1`` dense evaluations (``n_1`` 1-DOF, ``n_s`` spherical joints)."""
    fld = _field(model, field)
    q = state_positions(model, config, fld)
    m, n, nq = model.counts.m, model.counts.n, len(q)
    check_length("V_m", V_m, m)
    check_length("tau", tau, n)
    v_m, tau = field_vector(fld, V_m), field_vector(fld, tau)
    eta = field_vector(fld, eta_m) if eta_m is not None and len(eta_m) else None
    h = step_size(fld)
    base = _point(model, q, fld)

    def difference(moved) -> np.ndarray:           # moved(s): (point, v_m) at +-h
        ends = [_outputs(model, *moved(s), tau, eta, fld)[0] for s in (1, -1)]
        return (ends[0] - ends[1]) / (2 * h)

    def entry(k):
        return lambda s: (_point(model, [e + s * h if i == k else e for i, e in enumerate(q)], fld), v_m)

    def turn(name, k):
        return lambda s: ((moved_position(base[0], (name, k), s * h, fld), base[1]), v_m)

    cols_q, cols_x = [], []              # d/dq along the turns (forward), in the entries (state)
    for name, off, size in state_layout(model):
        if size == 1:
            col = difference(entry(off))
            cols_q.append(col)
            cols_x.append(col)
            continue
        if forward:
            cols_q.extend(difference(turn(name, k)) for k in range(3))
        if state:
            cols_x.extend(difference(entry(off + i)) for i in range(4))
    unit = [np.array([h if k == i else fld.zero for k in range(m)], dtype=object) for i in range(m)]
    cols_v = [difference(lambda s, e=e: (base, v_m + s * e)) for e in unit]
    _, data = _outputs(model, base, v_m, tau, eta, fld)
    zero = np.concatenate(solve_forward(data, field_vector(fld, [0] * n)))
    cols_t = [np.concatenate(solve_forward(data, field_vector(fld, [int(j == k) for j in range(n)]))) - zero
              for k in range(n)]
    rows = n + nq
    d_v, d_t = _columns(cols_v, rows), _columns(cols_t, n)
    out: dict[str, np.ndarray] = {}
    if forward:
        d_q = _columns(cols_q, rows)
        out.update(ddV_m_dq=d_q[:m], ddV_m_dV_m=d_v[:m], ddV_m_dtau=d_t[:m])
        if n > m:
            out.update(deta_f_dq=d_q[m:n], deta_f_dV_m=d_v[m:n], deta_f_dtau=d_t[m:n])
    if state:
        order = list(range(n, rows)) + list(range(m))            # [dq/dt; dV_m]
        out["dxdot_dx"] = _columns(cols_x + cols_v, rows)[order]
        out["dxdot_dtau"] = np.concatenate([np.array([[fld.zero] * n] * nq, dtype=object).reshape(nq, n), d_t[:m]])
    return out


def jacobians(model, config: ConfigurationLike, V_m, tau, eta_m=None, field=None) -> dict[str, np.ndarray]:
    """:func:`derivatives` of forward dynamics (32) alone: what
    :meth:`symgen.model.Model.forward_dynamics_derivatives` returns and the generated
    ``forward_dynamics_derivatives``'s reference."""
    return derivatives(model, config, V_m, tau, eta_m, field, forward=True)


def state_jacobian(model, config: ConfigurationLike, V_m, tau, eta_m=None, field=None) -> dict[str, np.ndarray]:
    """:func:`derivatives` of the simulation's right-hand side alone: what
    :meth:`symgen.model.Model.state_derivative_jacobian` returns and the generated
    ``state_derivative_jacobian``'s reference. Cost ``2 (nq + m) + 1`` dense evaluations, ``nq``
    the entries of ``q``."""
    return derivatives(model, config, V_m, tau, eta_m, field, forward=False, state=True)
