"""Recursive Newton-Euler over the spanning tree: ``T_S^T (M_S dX + C_S X + G_S)`` applied, never
formed (DESIGN.md section 4).

Field-generic (:mod:`symgen.dynamics.algebra`): the evaluator, the exact proofs and the code
generator's tracer run this same function; ``consts.field.is_zero`` tells a structural zero.

Outward pass, per body ``c`` with parent ``p`` across joint ``j`` (``R = R_PC``, ``p = p_PC``)::

    w_c  = R^T w_p + Z_j qd_j                                    (rows of T_S*, Section 3.2)
    dw_c = R^T dw_p + Z_j qdd_j + w_c x (Z_j qd_j)
    a_c  = R^T (a_p + K_p p)   [+ 2 w_c x (e3 qd_j) + e3 qdd_j for a prismatic joint]

where ``a`` is the classical acceleration of the frame origin with gravity folded in
(``a_world = -g``) and ``K = hat(dw) + hat(w)^2`` maps a body-fixed offset to its relative
acceleration. Per body, about its frame origin (eq. 21; :mod:`symgen.dynamics.grouping`)::

    f = m a + K h                          n = I_O dw + w x (I_O w) + h x a

with the first moment ``h = m r`` (``r`` the centre of mass) and ``I_O`` the inertia about the
origin; the parameters may be grouped (:func:`symgen.dynamics.grouping.grouped_inertias`), which
changes the link forces and leaves every ``tau`` as it is. This is ``M_a dX + C_a X + G_a`` of eq. (21) written with the origin's classical acceleration
``a = dv + w x v`` in place of ``dv``: the linear velocity ``v`` then never appears (the
Luh-Walker-Paul arrangement). Inward pass: ``f_p += R f_c``, ``n_p += R n_c + p x (R f_c)``, and
``tau_j = Z_j^T F_c + I*_j qdd_j + xi_j`` (eqs. 22-23).
"""
from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

from ..kinematics import ConstantCache
from ..tree import WORLD_INDEX, Tree
from .algebra import Labeller, Transform, Vector, add, cross, euler_moment, offset_acceleration, rotate, rotate_t, scale
from .grouping import OriginInertia, is_empty, origin_inertias


def _label(graph: Labeller | None, values: Vector, prefix: str) -> None:
    if graph is not None:
        for comp, v in zip("xyz", values):
            graph.label(v, f"{prefix}_{comp}")


def rnea(tree: Tree, consts: ConstantCache, transforms: Sequence[Transform], qd_all: Sequence[Any],
         qdd_all: Sequence[Any], *, gravity: bool, graph: Labeller | None = None, tag: str = "",
         inertias: Sequence[OriginInertia] | None = None, wrenches: dict[int, Vector] | None = None) -> list[Any]:
    """Joint forces ``tau_all`` (one per tree coordinate) for rates ``qd_all`` and accelerations
    ``qdd_all`` (sequences indexed by coordinate; ``0`` entries fold away). ``transforms[k]`` is
    ``(R_PC, p_PC)`` of tree joint ``k``; ``consts`` the body constants; ``inertias`` the bodies'
    parameters about their origins (default :func:`~symgen.dynamics.grouping.origin_inertias`; the
    grouped ones give the same ``tau``). Friction is added apart (:func:`joint_friction`).
    ``wrenches``: body index -> ``W = [f; n]`` about the body's origin in its axes, added to the
    body's force before the inward pass, so ``tau_all`` gains ``J^T W`` (eq. 30) in the same pass."""
    if inertias is None:
        inertias = origin_inertias(tree, consts)
    is_zero = consts.field.is_zero
    zero: Vector = (0, 0, 0)
    g_up = tuple(-x for x in consts.gravity) if gravity else zero
    nb = len(tree.bodies)
    w: list[Vector] = [zero] * nb
    dw: list[Vector] = [zero] * nb
    acc: list[Vector] = [zero] * nb
    force, moment = [zero] * nb, [zero] * nb
    for k, joint in enumerate(tree.joints):
        r, p = transforms[k]
        if joint.parent == WORLD_INDEX:
            wp, dwp, ap = zero, zero, g_up
        else:
            wp, dwp, ap = w[joint.parent], dw[joint.parent], acc[joint.parent]
        rates = [qd_all[c] for c in joint.coords]
        accels = [qdd_all[c] for c in joint.coords]
        wc, dwc = rotate_t(r, wp), rotate_t(r, dwp)
        ac = rotate_t(r, add(ap, offset_acceleration(wp, dwp, p)))
        if joint.kind.rotates:
            rel, rel_acc = joint.kind.angular(rates), joint.kind.angular(accels)     # Z_w qd, Z_w qdd
            wc = add(wc, rel)
            dwc = add(add(dwc, rel_acc), cross(wc, rel))
        elif joint.kind.translates:
            ac = add(add(ac, scale(2, cross(wc, joint.kind.linear(rates)))), joint.kind.linear(accels))
        name = tree.bodies[joint.child].name + tag
        _label(graph, wc, f"w_{name}")
        _label(graph, dwc, f"dw_{name}")
        _label(graph, ac, f"a_{name}")
        w[joint.child], dw[joint.child], acc[joint.child] = wc, dwc, ac
        b = joint.child
        body = inertias[b]
        if not is_empty(body, is_zero):
            h = body.first_moment
            f = add(scale(body.mass, ac), offset_acceleration(wc, dwc, h))
            n = add(euler_moment(body.inertia, wc, dwc, is_zero), cross(h, ac))
            force[b], moment[b] = f, n

    for b, wrench in (wrenches or {}).items():
        force[b], moment[b] = add(force[b], tuple(wrench[:3])), add(moment[b], tuple(wrench[3:]))
    tau: list[Any] = [0] * tree.n_coords
    for k in reversed(range(len(tree.joints))):
        joint = tree.joints[k]
        c = joint.child
        name = tree.bodies[c].name + tag
        _label(graph, force[c], f"f_{name}")
        _label(graph, moment[c], f"n_{name}")
        for coord, value in zip(joint.coords, joint.kind.transmitted(force[c], moment[c])):   # Z_j^T F_c
            tau[coord] = value
        for coord in joint.coords:
            tau[coord] = tau[coord] + consts.rotor[k] * qdd_all[coord]
        if joint.parent != WORLD_INDEX:
            r, p = transforms[k]
            rf = rotate(r, force[c])
            force[joint.parent] = add(force[joint.parent], rf)
            moment[joint.parent] = add(moment[joint.parent], add(rotate(r, moment[c]), cross(p, rf)))
    return tau


def joint_springs(tree: Tree, consts: ConstantCache, positions: dict[str, Any],
                  graph: Labeller | None = None) -> dict[int, Any]:
    """The passive spring force ``k (q - q_spring)`` of every 1-DOF joint with a stiffness ``k``,
    by coordinate index (joints without a spring are absent). Like gravity it is a potential term
    of ``G`` (the joint rows of ``G_S``, eqs. 22 and 24), with potential ``k (q - q_spring)^2 / 2``.
    ``positions``: the configuration's joint positions (angles, ``CosSin`` pairs that carry their
    angle, displacements)."""
    out: dict[int, Any] = {}
    field = consts.field
    for k, joint in enumerate(tree.joints):
        if field.is_zero(consts.stiffness[k]):
            continue
        q = joint.kind.coordinate(joint.name, positions[joint.name], field)
        term = consts.stiffness[k] * (q - consts.springref[k])
        out[joint.coords[0]] = term
        if graph is not None:
            graph.label(term, f"spring_{tree.coordinates[joint.coords[0]].label.replace('.', '_')}")
    return out


def joint_friction(tree: Tree, consts: ConstantCache, qd_all: Sequence[Any], sign: Callable[[Any], Any],
                   graph: Labeller | None = None) -> list[Any]:
    """``xi`` of eq. (22) per coordinate: ``b qd + c sign(qd)``; spherical joints viscous only."""
    xi: list[Any] = [0] * tree.n_coords
    for k, joint in enumerate(tree.joints):
        b, c = consts.viscous[k], consts.coulomb[k]
        for coord in joint.coords:
            term = b * qd_all[coord]
            if not consts.field.is_zero(c):
                term = term + c * sign(qd_all[coord])
            xi[coord] = term
            if graph is not None:
                graph.label(term, f"xi_{tree.coordinates[coord].label.replace('.', '_')}")
    return xi
