"""Body inertias as the joint forces see them: about each body frame's origin, with the part of a
revolute link that its joint cannot turn carried by the parent.

**About the origin.** Newton-Euler of a body (eq. 21) about its frame origin ``O`` rather than its
centre of mass ``c`` reads, with ``a`` the origin's classical acceleration (gravity folded in)::

    f = m a + K h                     n = I_O dw + w x (I_O w) + h x a

with the first moment ``h = m c``, ``I_O = I_c + m (|c|^2 1 - c c^T)`` (parallel axes) and
``K = hat(dw) + hat(w)^2``. It is linear in ``(m, h, I_O)``: a sum of bodies is the sum of their
parameters, and a zero parameter is a folded term.

**Grouping** (Khalil and Dombre, *Modeling, Identification and Control of Robots*, 2002, the
grouping rules of the base inertial parameters for a revolute joint). A revolute joint turns its
child about the child's ``z`` through ``O`` (:mod:`symgen.tree` puts every 1-DOF joint axis on
``z``). The part ``(m_s, h_s, I_s) = (m, (0, 0, h_z), diag(I_yy, I_yy, 0))`` of the child is
unchanged by that rotation, so it moves with the parent as if fixed in it, and its spatial inertia
annihilates the joint axis (``S^T I_s = 0``: its ``zz`` entry and the ``z`` row of ``hat(h_s)`` are
zero), so it adds nothing to ``tau_j`` by itself. Moving it into the parent, through the joint's
fixed placement ``(R_0, p_0)``, therefore leaves every joint force unchanged: ``tau`` of
:func:`symgen.dynamics.rnea.rnea`, and with it ``M_q``, ``C_q qd``, ``G_q`` and their derivatives,
not the link forces. Done leaf to root; at the fixed base the part is dropped (the world carries
it). The child keeps ``m = 0``, ``h = (h_x, h_y, 0)`` and ``I_O - diag(I_yy, I_yy, 0)``: three of
its ten parameters are structural zeros.
"""
from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from ..kinematics import ConstantCache
from ..tree import WORLD_INDEX, Tree
from .algebra import cross, dot, matmul3, rotate

Vector = tuple[Any, Any, Any]
Rows = tuple[Vector, Vector, Vector]


def _vector(entry: Callable[[int], Any]) -> Vector:
    return entry(0), entry(1), entry(2)


def _rows(entry: Callable[[int, int], Any]) -> Rows:
    return _vector(lambda j: entry(0, j)), _vector(lambda j: entry(1, j)), _vector(lambda j: entry(2, j))


@dataclass(frozen=True)
class OriginInertia:
    """A body's inertial parameters about its frame origin, in its frame (module docstring)."""

    mass: Any
    first_moment: Vector
    inertia: Rows

    def times(self, twist: Sequence[Any]) -> tuple[Any, ...]:
        """The wrench ``I X`` of the spatial inertia ``[[m 1, -hat(h)], [hat(h), I_O]]`` and a twist
        ``X = [v; w]``: ``[m v - h x w; h x v + I_O w]``."""
        v, w = twist[:3], twist[3:]
        h = self.first_moment
        return (tuple(self.mass * v[i] - x for i, x in enumerate(cross(h, w)))
                + tuple(x + dot(self.inertia[i], w) for i, x in enumerate(cross(h, v))))

    def __add__(self, other: OriginInertia) -> OriginInertia:
        return OriginInertia(self.mass + other.mass,
                             _vector(lambda i: self.first_moment[i] + other.first_moment[i]),
                             _rows(lambda i, j: self.inertia[i][j] + other.inertia[i][j]))


def origin_inertias(tree: Tree, consts: ConstantCache) -> list[OriginInertia]:
    """Every body's ``(m, h, I_O)`` from its mass, centre of mass and inertia about it."""
    out = []
    for b in range(len(tree.bodies)):
        m, c, ic = consts.mass[b], list(consts.com[b]), consts.inertia[b]
        cc = c[0] * c[0] + c[1] * c[1] + c[2] * c[2]
        out.append(OriginInertia(m, _vector(lambda i: m * c[i]),
                                 _rows(lambda i, j: ic[i][j] + m * ((cc if i == j else 0) - c[i] * c[j]))))
    return out


def is_empty(body: OriginInertia, is_zero: Callable[[Any], bool]) -> bool:
    """Every one of the ten parameters is a structural zero (a massless link, or one grouped away)."""
    return (is_zero(body.mass) and all(is_zero(x) for x in body.first_moment)
            and all(is_zero(x) for row in body.inertia for x in row))


def placed(part: OriginInertia, r: Sequence[Sequence[Any]], p: Sequence[Any]) -> OriginInertia:
    """``part`` (given in a child frame) expressed in the parent frame, the child's origin at ``p``
    and its axes ``r`` (columns) there: ``h' = R h + m p``,
    ``I' = R I R^T + m (|p|^2 1 - p p^T) + 2 (p . u) 1 - u p^T - p u^T`` with ``u = R h``. Each
    symmetric entry is computed once (``R I R^T`` from the upper triangle of ``R I``)."""
    m = part.mass
    u = rotate(r, part.first_moment)
    ri = matmul3(r, part.inertia)
    pp, pu = dot(p, p), dot(p, u)
    upper = {}
    for i in range(3):
        for j in range(i, 3):
            upper[i, j] = (dot(ri[i], r[j])
                           + m * ((pp if i == j else 0) - p[i] * p[j])
                           + ((2 * pu) if i == j else 0) - u[i] * p[j] - p[i] * u[j])
    inertia = _rows(lambda i, j: upper[min(i, j), max(i, j)])
    return OriginInertia(m, _vector(lambda i: u[i] + m * p[i]), inertia)


def grouped_inertias(tree: Tree, consts: ConstantCache) -> list[OriginInertia]:
    """:func:`origin_inertias` with each revolute link's unturnable part moved into its parent,
    leaf to root (module docstring). The joint forces of :func:`symgen.dynamics.rnea.rnea` are
    the same with these as with :func:`origin_inertias`; the link forces are not."""
    out = origin_inertias(tree, consts)
    zero = 0
    for k in reversed(range(len(tree.joints))):
        joint = tree.joints[k]
        if not (joint.kind.rotates and not joint.kind.translates and len(joint.coords) == 1):
            continue                                  # revolute joints only (axis z, through O)
        b = joint.child
        body = out[b]
        yy = body.inertia[1][1]
        (ixx, ixy, ixz), (_, _, iyz), (_, _, izz) = body.inertia
        out[b] = OriginInertia(zero, (body.first_moment[0], body.first_moment[1], zero),
                               ((ixx - yy, ixy, ixz), (ixy, zero, iyz), (ixz, iyz, izz)))
        if joint.parent != WORLD_INDEX:
            part = OriginInertia(body.mass, (zero, zero, body.first_moment[2]),
                                 ((yy, zero, zero), (zero, yy, zero), (zero, zero, zero)))
            out[joint.parent] = out[joint.parent] + placed(part, consts.joint_rot[k].tolist(),
                                                            tuple(consts.joint_trans[k]))
    return out
