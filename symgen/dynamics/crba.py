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
``[f; m]`` wrenches, body axes at the body frame's origin).
"""
from __future__ import annotations

from collections.abc import Sequence

from ..kinematics import ConstantCache
from ..tree import WORLD_INDEX, Tree
from .algebra import Rows, Transform, body_inertia, force_to_parent, inertia_to_parent, subspace_columns


def composite_inertias(tree: Tree, consts: ConstantCache, transforms: Sequence[Transform]) -> list[Rows | None]:
    """``I^c`` per body (6x6 nested lists): the body's spatial inertia plus its subtree's, inward."""
    comp: list[Rows | None] = [None if body.massless else body_inertia(consts.mass[b], consts.com[b], consts.inertia[b])
            for b, body in enumerate(tree.bodies)]
    for k in reversed(range(len(tree.joints))):
        joint = tree.joints[k]
        child, parent = comp[joint.child], joint.parent
        if child is None or parent == WORLD_INDEX:
            continue
        moved = inertia_to_parent(*transforms[k], child)
        above = comp[parent]
        comp[parent] = moved if above is None else [[x + y for x, y in zip(rp, rc)] for rp, rc in zip(above, moved)]
    return comp


def tree_mass_matrix(tree: Tree, consts: ConstantCache, transforms: Sequence[Transform]) -> Rows:
    """``M_q`` (``N_all x N_all`` nested lists of field numbers and ``0``) by the composite-rigid-body
    algorithm of the module docstring; symmetric entries share one node."""
    n = tree.n_coords
    mass: Rows = [[0] * n for _ in range(n)]
    comp = composite_inertias(tree, consts, transforms)
    joint_of = {joint.child: k for k, joint in enumerate(tree.joints)}
    for k, joint in enumerate(tree.joints):
        inertia = comp[joint.child]
        cols = subspace_columns(joint)
        for col, coord in zip(cols, joint.coords):
            if inertia is not None:
                force = tuple(inertia[i][col] for i in range(6))          # I^c S, one column
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
