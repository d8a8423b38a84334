"""The directions along which the generated derivatives move ``q``: one per velocity coordinate.

A revolute or prismatic joint's position is one entry of ``q`` and its direction is that entry's
plain partial. A spherical joint's position is a unit quaternion ``(w, x, y, z)`` -- four numbers
for three degrees of freedom -- so its four partials are not a derivative of the motion. Its three
directions are instead the turns of the child frame about its own axes:

    R(q (+) delta) = R(q) exp(hat(delta)),   d/d delta_k R = R hat(e_k)   (at delta = 0),

the same convention as the joint's rate, the angular velocity ``w`` of the child in its own frame
(eq. 21 of the paper, ``dR/dt = R hat(w)``), and as Pinocchio's ``integrate(q, v)`` for its
spherical and free-flyer joints. So ``d f / d q`` has one column per coordinate of ``qd_all`` of
the joint (``N_all`` columns where ``q`` has ``N_all + (number of spherical joints)`` entries), and
a spherical joint's three columns are its rotation's partials seeded as ``R hat(e_k)`` -- whose
column ``j`` is ``R (e_k x e_j)``, a permutation of ``R``'s columns with signs: no operation -- into
the forward-mode walk (:func:`symgen.codegen.derivatives.differentiate`), which follows them
through every product as it follows an input's.

The generated code forms ``R`` from the quaternion without dividing by ``|q|^2``; the directions
are those of the unit quaternion the caller passes (the code assumes ``|q| = 1``).
"""
from __future__ import annotations

import numpy as np

from ..math.spatial import quaternion_product  # noqa: F401  (re-exported: the ambient map's users)
from .graph import Node
from .trace import position_layout


def tangent_layout(model) -> list[tuple[str, int, int]]:
    """``(joint, offset, size)`` of each joint's columns in ``d / dq``: scene order (as ``q``), one
    column per 1-DOF joint and three per spherical joint."""
    out, offset = [], 0
    for name, kind, _, size in position_layout(model):
        width = 1 if size == 1 else 3
        out.append((name, offset, width))
        offset += width
    return out


def coordinate_columns(model) -> list[int]:
    """The ``d / dq`` column of each coordinate of ``qd_all`` (a spherical joint's component
    ``k`` is its turn about the child's axis ``k``)."""
    offset = {name: off for name, off, _ in tangent_layout(model)}
    return [offset[c.joint] + c.component for c in model.tree.coordinates]


def q_directions(b) -> tuple[list[Node | None], dict[Node, dict[int, Node]], int]:
    """``(columns, seeds, count)`` for :func:`~symgen.codegen.derivatives.differentiate` with the
    ``q`` directions first: ``columns`` holds a 1-DOF joint's input node and ``None`` for each of a
    spherical joint's three columns; ``seeds`` gives the traced rotation entries of a spherical
    joint (``b.t.config``, a :class:`~symgen.codegen.builder.Builder`'s) their partials
    ``R hat(e_k)`` in those columns; ``count`` the number of columns."""
    g = b.g
    q = g.input("q", b.inputs[0].size) if position_layout(b.model) else []
    columns: list[Node | None] = []
    seeds: dict[Node, dict[int, Node]] = {}
    for (name, kind, off, size), (_, col, _) in zip(position_layout(b.model), tangent_layout(b.model)):
        if size == 1:
            columns.append(q[off])
            continue
        columns.extend([None, None, None])
        rot = b.t.config.positions[name]
        for i in range(3):
            for j in range(3):
                part = {}
                for k in range(3):
                    # (R hat(e_k))_ij = sum_l R_il (e_k x e_j)_l: one entry of R, signed
                    for l, c in enumerate(_cross_unit(k, j)):
                        if c:
                            part[col + k] = g._node(rot[i][l]) if c > 0 else g.neg(rot[i][l])
                seeds[g._node(rot[i][j])] = part
    return columns, seeds, len(columns)


def _cross_unit(k: int, j: int) -> list[int]:
    """``e_k x e_j`` as integers."""
    a = [1 if i == k else 0 for i in range(3)]
    b = [1 if i == j else 0 for i in range(3)]
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def ambient_map(b) -> np.ndarray:
    """``d delta / d q`` at a unit ``q``: the ``(columns x len(q))`` object array taking the
    directions of :func:`q_directions` to the entries of ``q`` themselves, the state's ambient
    coordinates (:func:`symgen.codegen.forward_derivatives` ``state_derivative_jacobian``).

    A 1-DOF joint's column is its entry's. A spherical joint's quaternion ``p = (w, v)`` stands
    for the rotation of ``p / |p|`` (the simulation normalises before every evaluation); moving it
    by ``dp`` turns the child frame by ``delta = 2 vec(p* (x) dp)`` (``p (+) dp = p (x) (1, delta/2)``
    to first order, the radial part of ``dp`` dropping out), so its block is
    ``2 [-v | w 1 - hat(v)]`` (3 x 4), whose rows are orthogonal to ``p``."""
    nq = b.inputs[0].size
    q = b.g.input("q", nq) if nq else []
    out = np.full((sum(w for *_, w in tangent_layout(b.model)), nq), b.g.const(0), dtype=object)
    for (name, kind, off, size), (_, col, _) in zip(position_layout(b.model), tangent_layout(b.model)):
        if size == 1:
            out[col, off] = b.g.const(1)
            continue
        w, x, y, z = (b.g.mul(2, e) for e in q[off:off + 4])
        out[col:col + 3, off:off + 4] = [[-x, w, z, -y], [-y, -z, w, x], [-z, y, -x, w]]
    return out
