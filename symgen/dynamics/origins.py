"""Body origins moved along the joint axes, for the recursions of the joint forces.

A one-coordinate joint ``k`` (revolute or prismatic, axis ``z`` of its child's frame,
:mod:`symgen.tree`) places its child at ``p_k`` in the parent with the constant rotation ``R_k``;
its motion, a turn about or a slide along the axis ``u = R_k e3``, commutes with a translation
along that axis. The axial part ``s = u . p_k`` of the placement can therefore be carried by the
child's frame instead: the child's origin moves along the axis to ``p_k - s u`` (in the child's
own axes, by ``-s e3``), and everything given in the child's frame gains ``s e3`` -- its centre of
mass, its named frames and the placements of its own joints. A joint's translation is then
``p_k - s u + s_P e3``, ``s_P`` its parent's own move along the parent's axis. On a chain placed by
modified Denavit-Hartenberg parameters, ``p_k = a e1 + d u = (a, -sin(alpha) d, cos(alpha) d)``,
every translation becomes ``(a, 0, d_P)``: two entries in the parent's axes where there were
three, so fewer products in each origin's acceleration ``K p`` and in each moment ``p x f``.

Only the body frames the recursions read move: a joint force ``tau_j = Z_j^T F_j`` is a moment
about the joint's axis (or a force along it), the same about any point of the axis, so ``tau``,
``M_q``, ``C_q qd``, ``G_q`` and their derivatives are unchanged; the link forces, twists and
accelerations are those of the moved origins, and every function that reads a named frame or a
body twist keeps the tree as the scene gives it (:class:`symgen.codegen.trace.Tracer`).
"""
from __future__ import annotations

from dataclasses import replace

import sympy as sp

from ..tree import WORLD_INDEX, Tree, TreeJoint


def _exact_number(x: sp.Expr) -> bool:
    return not sp.sympify(x).free_symbols


def axial_offset(joint: TreeJoint) -> sp.Expr:
    """``s = u . p_k``: the component of a one-coordinate joint's translation along its axis
    ``u = R_k e3`` (zero for other joints, and where the placement holds scene parameters)."""
    if not joint.kind.is_one_dof or not all(_exact_number(x) for x in [*joint.rotation, *joint.translation]):
        return sp.Integer(0)
    return sp.expand((joint.rotation[:, 2].T * joint.translation)[0])


def axial_origins(tree: Tree) -> Tree:
    """``tree`` with every one-coordinate joint's child origin moved along the joint's axis by the
    axial part of the joint's given translation (module docstring); ``tree`` itself when no joint's
    translation has one."""
    shift = {j.child: axial_offset(j) for j in tree.joints}
    if all(s == 0 for s in shift.values()):
        return tree
    shift[WORLD_INDEX] = sp.Integer(0)
    e3 = sp.ImmutableMatrix([0, 0, 1])
    joints = tuple(replace(j, translation=sp.ImmutableMatrix(sp.expand(
        j.translation - shift[j.child] * j.rotation[:, 2] + shift[j.parent] * e3))) for j in tree.joints)
    bodies = tuple(replace(b, com=sp.ImmutableMatrix(sp.expand(b.com + shift[b.index] * e3))) for b in tree.bodies)
    frames = {name: f if f.body == WORLD_INDEX else
              replace(f, translation=sp.ImmutableMatrix(sp.expand(f.translation + shift[f.body] * e3)))
              for name, f in tree.frames.items()}
    return replace(tree, joints=joints, bodies=bodies, frames=frames)
