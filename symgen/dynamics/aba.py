"""Forward dynamics of a tree by the articulated-body algorithm (Featherstone, *Rigid Body Dynamics
Algorithms*, ch. 7), on any field (:mod:`symgen.dynamics.algebra`): ``O(N)`` operations
where the dense route forms ``M_q`` (``O(N^2)``) and factors it (``O(N^3)``).

Body-frame spatial vectors in symgen's order (DESIGN.md): twists ``X = [v; w]``, wrenches
``F = [f; m]``. Across tree joint ``k`` with ``(R, p) = (R_PC, p_PC)`` (the same transforms as
:mod:`symgen.dynamics.rnea`), a motion vector of the parent maps to the child as
``w_c = R^T w_p``, ``v_c = R^T (v_p - p x w_p)``, and a wrench of the child to the parent as
``f_p = R f_c``, ``m_p = R m_c + p x (R f_c)``. The joint's motion subspace ``S`` picks entries
(``e3`` prismatic, ``e6`` revolute, ``[0; 1_3]`` spherical, none for a fixed joint).

Three passes (RBDA Table 7.1), with ``I*`` the rotor inertia of eq. (22) added to ``D``:

1. outward: ``v_i = X_i v_p + S qd_i``, ``c_i = v_i x (S qd_i)``, ``I^A_i = I_i``,
   ``p^A_i = v_i x* (I_i v_i)``;
2. inward: ``U = I^A S``, ``D = S^T U + I*``, ``u = tau - S^T p^A``,
   ``I^a = I^A - U D^-1 U^T``, ``p^a = p^A + I^a c + U D^-1 u``, added to the parent through
   ``X^T I^a X`` and ``X^T p^a``;
3. outward: ``a' = X a_p + c``, ``qdd = D^-1 (u - U^T a')``, ``a = a' + S qdd``, from
   ``a_world = [-g; 0]`` (gravity as a base acceleration).

Spatial (not classical) accelerations throughout. A 3x3 ``D`` (spherical joint) is factored as
``L diag(d) L^T`` in scalars. With ``I* = 0`` the rows and columns of ``I^a`` along ``S`` are zero
and ``U D^-1`` is the identity there; both are written in, not computed. A pivot that is the
constant zero (a subtree without mass or rotor inertia) raises :class:`SingularArticulatedInertia`:
the code generator then keeps the dense route.
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from ..errors import SymgenError
from ..kinematics import ConstantCache
from ..tree import WORLD_INDEX, Tree
from .algebra import (IsZero, Labeller, Matrix, Rows, Transform, Vector, add, apply_inertia, body_inertia,
                      cross_force, cross_motion, dot, force_to_parent, inertia_to_parent, joint_twist,
                      motion_to_child, subspace_columns)


class SingularArticulatedInertia(SymgenError):
    """An articulated-body pivot ``D_i`` is identically singular (named joint)."""


class _Pivot:
    """``D = L diag(d) L^T`` of a symmetric 1x1 or 3x3 pivot, written out in scalars."""

    def __init__(self, d: Matrix, name: str, is_zero: IsZero):
        k = len(d)
        self.k = k
        self.low: Rows = [[0] * k for _ in range(k)]
        self.inv: list[Any] = [None] * k
        unscaled: Rows = [[None] * k for _ in range(k)]          # L diag(d), column by column
        for j in range(k):
            for i in range(j, k):
                unscaled[i][j] = d[i][j] - dot(self.low[i][:j], unscaled[j][:j])
            if is_zero(unscaled[j][j]):
                raise SingularArticulatedInertia(f"joint {name!r}: its articulated inertia D is singular "
                                                 "(the subtree has no mass or rotor inertia along the joint)")
            self.inv[j] = 1 / unscaled[j][j]
            for i in range(j + 1, k):
                self.low[i][j] = unscaled[i][j] * self.inv[j]

    def solve(self, rhs: Sequence[Any]) -> list[Any]:
        k = self.k
        y = list(rhs)
        for i in range(k):
            for s in range(i):
                y[i] = y[i] - self.low[i][s] * y[s]
        y = [y[i] * self.inv[i] for i in range(k)]
        for i in reversed(range(k)):
            for s in range(i + 1, k):
                y[i] = y[i] - self.low[s][i] * y[s]
        return y


def _label(graph: Labeller | None, values: Vector, prefix: str) -> None:
    if graph is not None:
        for comp, v in zip(("vx", "vy", "vz", "wx", "wy", "wz"), values):
            graph.label(v, f"{prefix}_{comp}")


@dataclass
class _Passes:
    """What the three passes hand on, per body (``vel``, ``bias_acc``, ``ia``, ``pa``) and per joint
    (``pivots``, ``gains`` ``U D^-1``, ``drive`` ``u``)."""

    vel: list[Any]
    bias_acc: list[Any]
    ia: list[Any]
    pa: list[Any]
    pivots: list[Any]
    gains: list[Any]
    drive: list[Any]


def _outward(tree: Tree, consts: ConstantCache, transforms: Sequence[Transform], qd_all: Sequence[Any],
             wrenches: Mapping[int, Vector] | None, graph: Labeller | None) -> _Passes:
    """Pass 1: body velocities, velocity-product accelerations ``c = v x S qd``, rigid-body
    inertias ``I^A = I`` and bias forces ``p^A = v x* I v (+ F_b)``."""
    zero6: Vector = (0,) * 6
    nb, nj = len(tree.bodies), len(tree.joints)
    out = _Passes([None] * nb, [None] * nb, [None] * nb, [zero6] * nb, [None] * nj, [None] * nj, [None] * nj)
    for k, joint in enumerate(tree.joints):
        r, p = transforms[k]
        b = joint.child
        v = zero6 if joint.parent == WORLD_INDEX else motion_to_child(r, p, out.vel[joint.parent])
        sq = joint_twist(joint, qd_all)
        v = add(v, sq)
        out.vel[b] = v
        out.bias_acc[b] = cross_motion(v, sq)
        _label(graph, v, f"V_{tree.bodies[b].name}")
        body = tree.bodies[b]
        if body.massless:
            out.ia[b] = [[0] * 6 for _ in range(6)]
        else:
            out.ia[b] = body_inertia(consts.mass[b], consts.com[b], consts.inertia[b])
            out.pa[b] = cross_force(v, apply_inertia(out.ia[b], v))
        if wrenches and b in wrenches:
            out.pa[b] = add(out.pa[b], wrenches[b])
    return out


def _inward(tree: Tree, consts: ConstantCache, transforms: Sequence[Transform], tau_all: Sequence[Any],
            out: _Passes) -> None:
    """Pass 2: the joint-space pivots ``D = S^T I^A S`` (+ rotor), gains ``U D^-1`` and drives
    ``u = tau - S^T p^A``; each articulated inertia and bias force moved to the parent."""
    for k in reversed(range(len(tree.joints))):
        joint = tree.joints[k]
        b = joint.child
        cols = subspace_columns(joint)
        big, bias = out.ia[b], out.pa[b]
        rotor = consts.rotor[k]
        pivot = _Pivot([[big[i][j] + (rotor if i == j else 0) for j in cols] for i in cols], joint.name,
                       consts.field.is_zero)
        u = [tau_all[coord] - bias[col] for col, coord in zip(cols, joint.coords)]
        exact = consts.field.is_zero(rotor)                          # U D^-1 = 1 on the joint's rows
        w: list[Any] = []
        for i in range(6):
            if exact and i in cols:
                w.append([1 if cols[s] == i else 0 for s in range(len(cols))])
            else:
                w.append(pivot.solve([big[i][j] for j in cols]) if cols else [])
        out.pivots[k], out.gains[k], out.drive[k] = pivot, w, u
        if joint.parent == WORLD_INDEX:
            continue
        art: Rows = [[None] * 6 for _ in range(6)]
        for i in range(6):
            for j in range(i, 6):
                if exact and (i in cols or j in cols):
                    value = 0
                else:
                    value = big[i][j] - dot(w[i], [big[j][c] for c in cols])
                art[i][j] = art[j][i] = value
        c = out.bias_acc[b]
        pa_b = [bias[i] + dot(art[i], c) + dot(w[i], u) for i in range(6)]
        if exact:                                       # p^a = tau along S
            for col, coord in zip(cols, joint.coords):
                pa_b[col] = tau_all[coord]
        r, p = transforms[k]
        par = joint.parent
        out.ia[par] = [[x + y for x, y in zip(rp, rc)] for rp, rc in zip(out.ia[par], inertia_to_parent(r, p, art))]
        out.pa[par] = add(out.pa[par], force_to_parent(r, p, tuple(pa_b)))


def _accelerations(tree: Tree, transforms: Sequence[Transform], base: Vector, out: _Passes,
                   graph: Labeller | None) -> list[Any]:
    """Pass 3: outward again, ``qdd = D^-1 (u - U^T a')`` and the body accelerations."""
    qdd_all: list[Any] = [0] * tree.n_coords
    acc: list[Any] = [None] * len(tree.bodies)
    for k, joint in enumerate(tree.joints):
        r, p = transforms[k]
        b = joint.child
        ap = base if joint.parent == WORLD_INDEX else acc[joint.parent]
        a = add(motion_to_child(r, p, ap), out.bias_acc[b])
        cols = subspace_columns(joint)
        if cols:
            w, u, pivot = out.gains[k], out.drive[k], out.pivots[k]
            if pivot.k == 1:
                qdd = [u[0] * pivot.inv[0] - dot([w[i][0] for i in range(6)], a)]
            else:
                qdd = pivot.solve([u[s] - dot([out.ia[b][i][cols[s]] for i in range(6)], a)
                                   for s in range(len(cols))])
            moved = list(a)
            for col, coord, value in zip(cols, joint.coords, qdd):
                qdd_all[coord] = value
                moved[col] = moved[col] + value
                if graph is not None:
                    graph.label(value, f"qdd_{tree.coordinates[coord].label.replace('.', '_')}")
            a = tuple(moved)
        acc[b] = a
    return qdd_all


def articulated_body(tree: Tree, consts: ConstantCache, transforms: Sequence[Transform], qd_all: Sequence[Any],
                     tau_all: Sequence[Any], *, gravity: bool, wrenches: Mapping[int, Vector] | None = None,
                     graph: Labeller | None = None) -> list[Any]:
    """``qdd_all`` (one per tree coordinate) of ``M_q qdd + c(q, qd) + g(q) + sum J_b^T F_b = tau_all``
    by the three passes of the module docstring; ``wrenches`` maps a body to a wrench ``F_b`` in its
    axes at its origin (added to ``p^A``); ``tau_all`` already carries the joint friction."""
    base = tuple(-x for x in consts.gravity) + (0, 0, 0) if gravity else (0,) * 6
    passes = _outward(tree, consts, transforms, qd_all, wrenches, graph)
    _inward(tree, consts, transforms, tau_all, passes)
    return _accelerations(tree, transforms, base, passes, graph)
