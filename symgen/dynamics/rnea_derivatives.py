"""Analytic partial derivatives of the tree's joint forces, in the spirit of Carpentier and Mansard
(*Analytical derivatives of rigid body dynamics algorithms*, RSS 2018), on any field.

``tau = T_S^T (M_S dX + C_S X + G_S)`` of :mod:`symgen.dynamics.rnea` (eqs. 21-25) differentiated
in closed form, every quantity carried in the axes of the world at its origin (so a twist or a
wrench of one body and of another are added or dotted without a transform). Per body ``k`` with
parent ``l`` and joint columns ``S_k`` (the motion subspace ``Z_k`` in world axes)::

    v_k = v_l + S_k qd_k              a_k = a_l + S_k qdd_k + v_k x (S_k qd_k)    (a_world = [-g; 0])
    h_k = I_k v_k                     f_k = I_k a_k + v_k x* h_k
    B_k u = I_k (v_k x u) - v_k x* (I_k u) - u x* h_k                               (6 x 6)

(``B_k`` has twelve free numbers and ignores the linear part of ``u``: :class:`Variation`)

and the composites over each subtree ``F_k``, ``I^c_k``, ``B^c_k``, so that ``tau_j = S_j^T F_j``.
A coordinate ``i`` moves the subtree of its joint by the screw ``s`` (a column of ``S_i``): every
quantity fixed in that subtree turns as ``s x``; what the derivation adds is the change of the
velocities and accelerations *relative* to the parent ``l`` of ``i``. With

    u = s x v_l,        w = s x a_l - u x v_l,        y = s x (v_l + v_i) = 2 u

(``v_i = v_l + s qd_i`` and ``s x s = 0``; for the same reason ``v_k x (S_k qd_k) = -qd_k u``),

and ``S_j^T (s x* F) + (s x S_j)^T F = 0`` (power is invariant), for ``i`` an ancestor of ``j``
or ``j`` itself::

    d tau_j / d q_i  =  S_j^T (B^c_j u - I^c_j w)
    d tau_j / d qd_i = -S_j^T (B^c_j s + I^c_j y)
    M_ji             =  S_j^T I^c_j s

and for ``j`` a strict ancestor of ``i``, whose axis the coordinate does not move::

    d tau_j / d q_i  =  S_j^T (s x* F_i - I^c_i w + B^c_i u)
    d tau_j / d qd_i = -S_j^T (B^c_i s + I^c_i y)

Entries of unrelated coordinates (neither an ancestor of the other) are zero. The work is ``O(N)``
six-vectors and composites and one or two six-vector dot products per entry
(``S_j^T B^c_j``, whose linear part is zero, and ``I^c_j S_j`` formed once per column), where a forward walk of the recursion
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


@dataclass(frozen=True)
class Variation:
    """The ``6 x 6`` variation ``B u = I (v x u) - v x* (I u) - u x* h`` of a body (module
    docstring), or a sum of them over a subtree, in the form every such ``B`` has::

        B = [[0, hat(l)],
             [0, Q     ]]

    ``B`` ignores the linear part of ``u``: with ``I = [[m 1, -hat(c)], [hat(c), J]]`` (first
    moment ``c``, rotational inertia ``J`` about the origin) and ``v = [v_o; w]``, ``l`` is twice
    the linear momentum ``m v_o + w x c`` and ``Q = hat(c) hat(v_o) + hat(v_o) hat(c) + J hat(w)
    - hat(w) J + hat(h_n)`` (``h_n`` the angular momentum). Twelve numbers instead of 36, so a
    subtree's sum costs twelve additions and ``B u``, ``B^T x`` one cross product and one ``3 x 3``
    product each."""

    linear: Vector
    block: Rows

    def times(self, u: Sequence[Any]) -> Vector:
        """``B u = [l x u_w; Q u_w]``."""
        w = u[3:]
        return cross(self.linear, w) + tuple(dot(row, w) for row in self.block)

    def transpose_times(self, x: Sequence[Any]) -> Vector:
        """``B^T x = [0; x_v x l + Q^T x_w]``."""
        turned = cross(x[:3], self.linear)
        return (0, 0, 0) + tuple(turned[c] + dot([self.block[r][c] for r in range(3)], x[3:]) for c in range(3))

    def __add__(self, other: Variation) -> Variation:
        return Variation(add(self.linear, other.linear),
                         [[a + b for a, b in zip(ra, rb)] for ra, rb in zip(self.block, other.block)])


def variation(body: OriginInertia, v: Sequence[Any], momentum: Sequence[Any]) -> Variation:
    """:class:`Variation` of ``body`` moving with the twist ``v``; ``momentum`` must be ``I v``
    (``body.times(v)``) and ``body.inertia`` symmetric, as every :class:`OriginInertia` is."""
    c, j = body.first_moment, body.inertia
    v_o, w = v[:3], v[3:]
    c_v = [[c[r] * v_o[k] for k in range(3)] for r in range(3)]       # c v_o^T
    along = c_v[0][0] + c_v[1][1] + c_v[2][2]
    # K = J hat(w); for a symmetric J, J hat(w) - hat(w) J = K + K^T
    k = [[j[r][1] * w[2] - j[r][2] * w[1], j[r][2] * w[0] - j[r][0] * w[2], j[r][0] * w[1] - j[r][1] * w[0]]
         for r in range(3)]
    h = momentum[3:]
    spin = ((0, -h[2], h[1]), (h[2], 0, -h[0]), (-h[1], h[0], 0))       # hat(h_n)
    block = [[2 * (c_v[r][r] + k[r][r] - along) if r == q
              else c_v[r][q] + c_v[q][r] + k[r][q] + k[q][r] + spin[r][q] for q in range(3)] for r in range(3)]
    return Variation(tuple(2 * x for x in momentum[:3]), block)


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
    carries nothing), ``columns[i] = (u, -w, -s, -y, g_q, g_qd)`` with ``g_q = s x* F_i - I^c_i w +
    B^c_i u`` and ``g_qd = -(B^c_i s + I^c_i y)`` (``None`` where nothing moves with ``i``; the
    signs are the entries', so that no negation is left to the products), the
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
    comp: list[tuple[OriginInertia, Variation] | None] = [None] * nb
    parent_vel, parent_acc, turn = [zero6] * n, [zero6] * n, [zero6] * n
    for k, joint in enumerate(tree.joints):
        c = joint.child
        v_l, a_l = (zero6, a_world) if joint.parent == WORLD_INDEX else (vel[joint.parent], acc[joint.parent])
        (coord,) = joint.coords or (None,)              # world_columns refused more than one
        v, a = v_l, a_l
        if coord is not None:
            s = s_col[coord]
            parent_vel[coord], parent_acc[coord] = v_l, a_l
            turn[coord] = u = cross_motion(s, v_l)       # u = s x v_l, and v x (s qd) = -qd u
            v = add(v_l, scale(qd_all[coord], s))
            a = sub(add(a_l, scale(qdd_all[coord], s)), scale(qd_all[coord], u))
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
        comp[l] = below_c if above is None else (above[0] + below_c[0], above[1] + below_c[1])

    body_of = {coord: joint.child for joint in tree.joints for coord in joint.coords}
    ancestors = ancestor_coordinates(tree)
    below = [[c for c in range(n) if c == i or i in ancestors[c]] for i in range(n)]
    rows: list[tuple[Vector, Vector] | None] = []
    for j in range(n):
        cj = comp[body_of[j]]
        rows.append(None if cj is None else (cj[1].transpose_times(s_col[j]), cj[0].times(s_col[j])))
    columns: list[tuple[Vector, ...] | None] = []
    for i in range(n):                                  # column i: the coordinate moved
        s, b_i, ci = s_col[i], body_of[i], comp[body_of[i]]
        if ci is None:
            columns.append(None)                        # nothing moves with it
            continue
        ic, bc = ci
        u = turn[i]
        minus_w = sub(cross_motion(u, parent_vel[i]), cross_motion(s, parent_acc[i]))
        minus_s = tuple(-x for x in s)
        minus_y = tuple(-2 * x for x in u)              # y = s x (v_l + v_l + s qd) = 2 u
        g_q = add(add(cross_force(s, force[b_i]), ic.times(minus_w)), bc.times(u))
        g_qd = add(bc.times(minus_s), ic.times(minus_y))
        columns.append((u, minus_w, minus_s, minus_y, g_q, g_qd))
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
        u, minus_w, minus_s, minus_y, g_q, g_qd = column
        for j in f.ancestors[i]:                        # strict ancestors: their axes stay put
            dq[j][i] = dot(s_col[j], g_q)
            dqd[j][i] = dot(s_col[j], g_qd)
        for j in f.below[i]:                            # i itself and the coordinates below it
            row = f.rows[j]
            if row is None:
                continue
            beta, iota = row                            # B^c_j^T S_j, I^c_j S_j
            dq[j][i] = dot(beta, u) + dot(iota, minus_w)
            dqd[j][i] = dot(beta, minus_s) + dot(iota, minus_y)
            mass[j][i] = mass[i][j] = dot(iota, s_col[i])
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

