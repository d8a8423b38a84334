"""Analytic partial derivatives of the tree's joint forces, in the spirit of Carpentier and Mansard
(*Analytical derivatives of rigid body dynamics algorithms*, RSS 2018), on any field.

``tau = T_S^T (M_S dX + C_S X + G_S)`` of :mod:`symgen.dynamics.rnea` (eqs. 21-25) differentiated
in closed form, every quantity carried in the axes of the world at its origin (so a twist or a
wrench of one body and of another are added or dotted without a transform). Per body ``k`` with
parent ``l`` and joint columns ``S_k`` (the motion subspace ``Z_k`` in world axes)::

    v_k = v_l + S_k qd_k              a_k = a_l + S_k qdd_k + v_k x (S_k qd_k)    (a_world = [-g; 0])
    h_k = I_k v_k                     f_k = I_k a_k + v_k x* h_k
    B_k u = I_k (v_k x u) - v_k x* (I_k u) - u x* h_k                               (6 x 6)

and the composites over each subtree ``F_k``, ``I^c_k``, ``B^c_k``, so that ``tau_j = S_j^T F_j``.
A coordinate ``i`` moves the subtree of its joint by the screw ``s`` (a column of ``S_i``): every
quantity fixed in that subtree turns as ``s x``; what the derivation adds is the change of the
velocities and accelerations *relative* to the parent ``l`` of ``i``. With

    u = s x v_l,        w = s x a_l - u x v_l,        y = s x (v_l + v_i),

and ``S_j^T (s x* F) + (s x S_j)^T F = 0`` (power is invariant), for ``i`` an ancestor of ``j``
or ``j`` itself::

    d tau_j / d q_i  =  S_j^T (B^c_j u - I^c_j w)
    d tau_j / d qd_i = -S_j^T (B^c_j s + I^c_j y)
    M_ji             =  S_j^T I^c_j s

and for ``j`` a strict ancestor of ``i``, whose axis the coordinate does not move::

    d tau_j / d q_i  =  S_j^T (s x* F_i - I^c_i w + B^c_i u)
    d tau_j / d qd_i = -S_j^T (B^c_i s + I^c_i y)

Entries of unrelated coordinates (neither an ancestor of the other) are zero. The work is ``O(N)``
six-vectors and ``6 x 6`` composites and one or two six-vector dot products per entry
(``S_j^T B^c_j`` and ``I^c_j S_j`` formed once per column), where a forward walk of the recursion
carries a tangent through every body per coordinate: fewer operations on long chains, more on
short ones (:mod:`symgen.codegen.dynamics_derivatives` traces both and keeps the cheaper).

Revolute and prismatic joints (one column each); the joint's motion ``q_i`` moves its child along
``S_i`` as :mod:`symgen.codegen.tangent` defines the columns of ``d / dq``. Friction, springs and
rotor inertias are added by the caller, as for :func:`~symgen.dynamics.rnea.rnea`.
"""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from ..errors import SymgenError
from ..kinematics import ConstantCache
from ..tree import WORLD_INDEX, Tree
from .algebra import Rows, Transform, Vector, add, cross, cross_force, cross_motion, dot, matmul3, rotate, scale, sub
from .algebra import apply_inertia as matvec        # any 6 x 6 rows times a six-vector
from .grouping import OriginInertia, is_empty, origin_inertias, placed


class UnsupportedJoint(SymgenError):
    """A joint the closed form does not cover (more than one coordinate: spherical, free), named."""


@dataclass(frozen=True)
class RneaDerivatives:
    """``d tau_all / d q_all``, ``d tau_all / d qd_all`` and ``M`` (``N_all x N_all`` nested lists of
    field numbers and ``0``), without friction, springs and rotor inertias."""

    dtau_dq: Rows
    dtau_dqd: Rows
    mass: Rows


def variation(body: OriginInertia, v: Sequence[Any], momentum: Sequence[Any]) -> Rows:
    """``B`` (6 x 6 rows) with ``B u = I (v x u) - v x* (I u) - u x* h`` for the momentum
    ``h = I v`` (module docstring), column by column on the unit twists."""
    cols = []
    for c in range(6):
        e = tuple(int(i == c) for i in range(6))
        col = sub(sub(body.times(cross_motion(v, e)), cross_force(v, body.times(e))),
                  cross_force(e, momentum))
        cols.append(col)
    return [[cols[c][r] for c in range(6)] for r in range(6)]


def _tmatvec(rows: Rows, x: Sequence[Any]) -> Vector:
    """``B^T x``."""
    return tuple(dot([rows[r][c] for r in range(6)], x) for c in range(6))


def _add_rows(a: Rows, b: Rows) -> Rows:
    return [[x + y for x, y in zip(ra, rb)] for ra, rb in zip(a, b)]


def world_columns(tree: Tree, transforms: Sequence[Transform]) -> tuple[list[Any], list[Vector]]:
    """``(poses, S)``: each body's world pose ``(R, p)`` (indexed like ``tree.bodies``; ``None`` for
    the world) and each tree coordinate's column ``S_i`` (``[v; w]`` in world axes at the world's
    origin). Raises :class:`UnsupportedJoint` for a joint of more than one coordinate."""
    poses: list[Any] = [None] * len(tree.bodies)
    columns: list[Vector] = [(0,) * 6] * tree.n_coords
    for k, joint in enumerate(tree.joints):
        if joint.kind.dof > 1:
            raise UnsupportedJoint(f"joint {joint.name!r}: {joint.kind.dof} coordinates")
        r_pc, p_pc = transforms[k]
        if joint.parent == WORLD_INDEX:
            r, p = [list(row) for row in r_pc], tuple(p_pc)
        else:
            r_l, p_l = poses[joint.parent]
            r, p = matmul3(r_l, r_pc), add(p_l, rotate(r_l, p_pc))
        poses[joint.child] = (r, p)
        if joint.kind.dof == 1:
            z = (r[0][2], r[1][2], r[2][2])
            columns[joint.coords[0]] = cross(p, z) + z if joint.kind.rotates else z + (0, 0, 0)
    return poses, columns


@dataclass(frozen=True)
class EntryFactors:
    """What every entry of :class:`RneaDerivatives` is a dot product of (module docstring), per
    tree coordinate: ``rows[j] = (B^c_j^T S_j, I^c_j S_j)`` (``None`` where the subtree of ``j``
    carries nothing), ``columns[i] = (s, u, w, y, g_q, g_qd)`` with ``g_q = s x* F_i - I^c_i w +
    B^c_i u`` and ``g_qd = -(B^c_i s + I^c_i y)`` (``None`` where nothing moves with ``i``), the
    strict ``ancestors`` of each coordinate and the coordinates ``below`` it (itself included);
    ``axes[j] = S_j``."""

    axes: list[Vector]
    columns: list[tuple[Vector, ...] | None]
    rows: list[tuple[Vector, Vector] | None]
    ancestors: list[list[int]]
    below: list[list[int]]


def entry_factors(tree: Tree, consts: ConstantCache, transforms: Sequence[Transform], qd_all: Sequence[Any],
                  qdd_all: Sequence[Any], *, gravity: bool,
                  inertias: Sequence[OriginInertia] | None = None) -> EntryFactors:
    """The ``O(N)`` passes of the module docstring (arguments of :func:`~symgen.dynamics.rnea.rnea`):
    every entry's factors, before the products."""
    if inertias is None:
        inertias = origin_inertias(tree, consts)
    is_zero = consts.field.is_zero
    poses, s_col = world_columns(tree, transforms)
    zero6: Vector = (0,) * 6
    nb, n = len(tree.bodies), tree.n_coords
    a_world = tuple(-x for x in consts.gravity) + (0, 0, 0) if gravity else zero6
    vel, acc = [zero6] * nb, [zero6] * nb
    force: list[Vector] = [zero6] * nb
    #: per body, its subtree's ``(I^c, B^c)``; ``None`` where the subtree carries nothing
    comp: list[tuple[OriginInertia, Rows] | None] = [None] * nb
    parent_vel, parent_acc = [zero6] * n, [zero6] * n
    for k, joint in enumerate(tree.joints):
        c = joint.child
        v_l, a_l = (zero6, a_world) if joint.parent == WORLD_INDEX else (vel[joint.parent], acc[joint.parent])
        v, a = v_l, a_l
        for coord in joint.coords:
            parent_vel[coord], parent_acc[coord] = v_l, a_l
            sq = scale(qd_all[coord], s_col[coord])
            v = add(v, sq)
            a = add(add(a, scale(qdd_all[coord], s_col[coord])), cross_motion(v, sq))
        vel[c], acc[c] = v, a
        if not is_empty(inertias[c], is_zero):
            body = placed(inertias[c], *poses[c])
            momentum = body.times(v)
            force[c] = add(body.times(a), cross_force(v, momentum))
            comp[c] = (body, variation(body, v, momentum))
    for k in reversed(range(len(tree.joints))):          # composites, leaf to root
        joint = tree.joints[k]
        c, l = joint.child, joint.parent
        below_c, above = comp[c], comp[l] if l != WORLD_INDEX else None
        if l == WORLD_INDEX or below_c is None:
            continue
        force[l] = add(force[l], force[c])
        comp[l] = below_c if above is None else (above[0] + below_c[0], _add_rows(above[1], below_c[1]))

    body_of = {coord: joint.child for joint in tree.joints for coord in joint.coords}
    ancestors = ancestor_coordinates(tree)
    below = [[c for c in range(n) if c == i or i in ancestors[c]] for i in range(n)]
    rows: list[tuple[Vector, Vector] | None] = []
    for j in range(n):
        cj = comp[body_of[j]]
        rows.append(None if cj is None else (_tmatvec(cj[1], s_col[j]), cj[0].times(s_col[j])))
    columns: list[tuple[Vector, ...] | None] = []
    for i in range(n):                                  # column i: the coordinate moved
        s, b_i, ci = s_col[i], body_of[i], comp[body_of[i]]
        if ci is None:
            columns.append(None)                        # nothing moves with it
            continue
        ic, bc = ci
        u = cross_motion(s, parent_vel[i])
        w = sub(cross_motion(s, parent_acc[i]), cross_motion(u, parent_vel[i]))
        y = cross_motion(s, add(parent_vel[i], vel[b_i]))
        g_q = add(sub(cross_force(s, force[b_i]), ic.times(w)), matvec(bc, u))
        g_qd = tuple(-x for x in add(matvec(bc, s), ic.times(y)))
        columns.append((s, u, w, y, g_q, g_qd))
    return EntryFactors(s_col, columns, rows, ancestors, below)


def rnea_derivatives(tree: Tree, consts: ConstantCache, transforms: Sequence[Transform], qd_all: Sequence[Any],
                     qdd_all: Sequence[Any], *, gravity: bool,
                     inertias: Sequence[OriginInertia] | None = None) -> RneaDerivatives:
    """The partials of :func:`~symgen.dynamics.rnea.rnea` (same arguments) by the formulas of the
    module docstring: ``O(N)`` passes (:func:`entry_factors`), then the entries of every ancestor pair."""
    f = entry_factors(tree, consts, transforms, qd_all, qdd_all, gravity=gravity, inertias=inertias)
    s_col, n = f.axes, tree.n_coords
    dq: Rows = [[0] * n for _ in range(n)]
    dqd: Rows = [[0] * n for _ in range(n)]
    mass: Rows = [[0] * n for _ in range(n)]
    for i, column in enumerate(f.columns):
        if column is None:
            continue
        s, u, w, y, g_q, g_qd = column
        for j in f.ancestors[i]:                        # strict ancestors: their axes stay put
            dq[j][i] = dot(s_col[j], g_q)
            dqd[j][i] = dot(s_col[j], g_qd)
        for j in f.below[i]:                            # i itself and the coordinates below it
            row = f.rows[j]
            if row is None:
                continue
            beta, iota = row                            # B^c_j^T S_j, I^c_j S_j
            dq[j][i] = dot(beta, u) - dot(iota, w)
            dqd[j][i] = -(dot(beta, s) + dot(iota, y))
            mass[j][i] = mass[i][j] = dot(iota, s)
    return RneaDerivatives(dq, dqd, mass)


def ancestor_coordinates(tree: Tree) -> list[list[int]]:
    """Per coordinate, the coordinates of the joints strictly above its joint (root first)."""
    joint_of_body = {joint.child: k for k, joint in enumerate(tree.joints)}
    out: list[list[int]] = [[] for _ in range(tree.n_coords)]
    for joint in tree.joints:
        above: list[int] = []
        body = joint.parent
        while body != WORLD_INDEX:
            k = joint_of_body[body]
            above = list(tree.joints[k].coords) + above
            body = tree.joints[k].parent
        for coord in joint.coords:
            out[coord] = above
    return out

