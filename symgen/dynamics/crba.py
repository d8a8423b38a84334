"""The joint-space mass matrix of a tree by the composite-rigid-body algorithm (Featherstone,
*Rigid Body Dynamics Algorithms*, ch. 6), on any field (:mod:`symgen.dynamics.algebra`).

``M_q`` is the matrix of ``T_S^T M_S T_S`` (eqs. 21-25) over every tree coordinate: the product
the recursion of :mod:`symgen.dynamics.rnea` applies column by column (``M_q e_k`` is the joint
force at ``qdd = e_k``, ``qd = 0``, no gravity). Column by column that costs a whole inward pass
per coordinate and re-derives the outward accelerations; the composite-rigid-body algorithm
instead forms, once, each subtree's spatial inertia ``I^c_i`` about its root body's origin, and
then carries ``F = I^c_i S_i`` (the wrench that accelerates the subtree along joint ``i``) inward
through the ancestors, reading one entry per ancestor coordinate::

    I^c_i = I_i + sum over children c of X_c^T I^c_c X_c
    M[i, i] = S_i^T I^c_i S_i + I*_i                       (I* the rotor inertia of eq. 22)
    F = I^c_i S_i;  for each ancestor joint a:  F <- X^T F,  M[a, i] = M[i, a] = S_a^T F

Same spatial conventions and transforms as :mod:`symgen.dynamics.aba` (``[v; w]`` twists,
``[f; m]`` wrenches, body axes at the body frame's origin). The composites are carried as the ten
parameters ``(m, h, I_O)`` of :mod:`symgen.dynamics.grouping`, not as 6x6 matrices, and may be the
grouped ones: a grouped part annihilates its joint's axis and moves with the parent, so every
entry of ``M_q`` is unchanged (the grouping's argument, at ``qd = 0``, unit ``qdd``).
"""
from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from ..kinematics import ConstantCache
from ..tree import WORLD_INDEX, Tree
from .algebra import Rows, Transform, cross, force_to_parent, scale, subspace_columns
from .grouping import OriginInertia, is_empty, origin_inertias, placed


def composite_inertias(tree: Tree, consts: ConstantCache, transforms: Sequence[Transform],
                       inertias: Sequence[OriginInertia] | None = None) -> list[OriginInertia | None]:
    """``I^c`` per body, inward, in the ten parameters about the body's origin
    (:class:`~symgen.dynamics.grouping.OriginInertia`: a rigid body's spatial inertia is
    ``[[m 1, -hat(h)], [hat(h), I_O]]``, so a sum of bodies is the sum of their parameters and
    moving one to the parent is :func:`~symgen.dynamics.grouping.placed`, a rotation and a shift of
    ten numbers where the 6x6 congruence re-derives the blocks ``m 1`` and ``hat(h)``). ``None``
    for a body whose subtree carries nothing. ``inertias`` as for :func:`symgen.dynamics.rnea.rnea`
    (default about the origins; the grouped ones give the same ``M_q``)."""
    if inertias is None:
        inertias = origin_inertias(tree, consts)
    is_zero = consts.field.is_zero
    comp: list[OriginInertia | None] = [None if is_empty(body, is_zero) else body for body in inertias]
    for k in reversed(range(len(tree.joints))):
        joint = tree.joints[k]
        child, parent = comp[joint.child], joint.parent
        if child is None or parent == WORLD_INDEX:
            continue
        moved = placed(child, *transforms[k])
        above = comp[parent]
        comp[parent] = moved if above is None else above + moved
    return comp


def inertia_column(body: OriginInertia, col: int) -> tuple[Any, ...]:
    """Column ``col`` of the spatial inertia ``[[m 1, -hat(h)], [hat(h), I_O]]``: the wrench
    ``[f; n]`` that the unit twist ``e_col`` (``[v; w]`` order) needs, ``[m e; h x e]`` for a
    translation and ``[e x h; I_O e]`` for a rotation."""
    m, h, inertia = body.mass, body.first_moment, body.inertia
    e = [int(i == col % 3) for i in range(3)]
    if col < 3:
        return scale(m, e) + cross(h, e)
    return cross(e, h) + tuple(inertia[i][col - 3] for i in range(3))


def tree_mass_matrix(tree: Tree, consts: ConstantCache, transforms: Sequence[Transform],
                     inertias: Sequence[OriginInertia] | None = None) -> Rows:
    """``M_q`` (``N_all x N_all`` nested lists of field numbers and ``0``) by the composite-rigid-body
    algorithm of the module docstring; symmetric entries share one node. ``inertias``: as for
    :func:`composite_inertias`."""
    n = tree.n_coords
    mass: Rows = [[0] * n for _ in range(n)]
    comp = composite_inertias(tree, consts, transforms, inertias)
    joint_of = {joint.child: k for k, joint in enumerate(tree.joints)}
    for k, joint in enumerate(tree.joints):
        inertia = comp[joint.child]
        cols = subspace_columns(joint)
        for col, coord in zip(cols, joint.coords):
            if inertia is not None:
                force = inertia_column(inertia, col)                           # I^c S, one column
                for col2, coord2 in zip(cols, joint.coords):
                    if coord2 >= coord:
                        mass[coord][coord2] = mass[coord2][coord] = force[col2]
                a = k
                while tree.joints[a].parent != WORLD_INDEX:
                    force = force_to_parent(*transforms[a], force)
                    a = joint_of[tree.joints[a].parent]
                    for col_a, coord_a in zip(subspace_columns(tree.joints[a]), tree.joints[a].coords):
                        mass[coord_a][coord] = mass[coord][coord_a] = force[col_a]
            mass[coord][coord] = mass[coord][coord] + consts.rotor[k]
    return mass
