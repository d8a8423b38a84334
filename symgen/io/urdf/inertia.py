"""Mass properties of links, moved between frames and merged across fixed joints, exactly.

A URDF ``<inertial>`` gives a mass ``m``, the centre of mass ``c`` and the rotational inertia
``I_c`` about the centre of mass, in the inertial frame. A fixed joint welds a child link to its
parent, and symgen's scene has one body for both. With every link's properties expressed in the
body frame, through the rotation ``R`` and translation ``p`` of the link in that frame,

    c' = p + R c,        I' = R I_c R^T                        (change of frame)

the merged body has

    m = sum m_i,   c = sum m_i c_i / m,
    I_c = sum [ I_i + m_i (|d_i|^2 1 - d_i d_i^T) ],   d_i = c_i - c     (parallel axis)

Every number stays an exact SymPy rational (the rotations are rational, see
:mod:`symgen.io.urdf.rotations`), so the scene receives exact constants.
"""
from __future__ import annotations

from dataclasses import dataclass

import mpmath
import numpy as np
import sympy as sp

from ...math.numbers import DPS
from .rotations import rational_rotation

def _skew_square(d: sp.Matrix) -> sp.Matrix:
    """``|d|^2 1 - d d^T``: the parallel-axis term per unit mass."""
    return (d.T * d)[0, 0] * sp.eye(3) - d * d.T


@dataclass(frozen=True)
class MassProperties:
    """Mass, centre of mass and rotational inertia about the centre of mass, in one frame."""

    mass: sp.Expr
    com: sp.ImmutableMatrix        # 3 x 1
    inertia: sp.ImmutableMatrix    # 3 x 3, about com

    @staticmethod
    def zero() -> "MassProperties":
        return MassProperties(sp.Integer(0), sp.ImmutableMatrix([0, 0, 0]), sp.ImmutableMatrix(sp.zeros(3)))

    @staticmethod
    def from_urdf(mass, values: dict) -> "MassProperties":
        """From a URDF ``<mass>`` and ``<inertia>`` (``ixx .. iyz``) in the inertial frame."""
        v = {k: sp.Rational(x) for k, x in values.items()}
        inertia = sp.ImmutableMatrix([[v["ixx"], v["ixy"], v["ixz"]], [v["ixy"], v["iyy"], v["iyz"]],
                                      [v["ixz"], v["iyz"], v["izz"]]])
        return MassProperties(sp.Rational(mass), sp.ImmutableMatrix([0, 0, 0]), inertia)

    @property
    def is_zero(self) -> bool:
        return self.mass == 0 and all(x == 0 for x in self.inertia)

    def transformed(self, rotation, translation) -> "MassProperties":
        """The same body seen from a frame in which this frame has pose ``(R, p)``."""
        r, p = sp.Matrix(rotation), sp.Matrix(translation)
        return MassProperties(self.mass, sp.ImmutableMatrix(p + r * sp.Matrix(self.com)),
                              sp.ImmutableMatrix(r * sp.Matrix(self.inertia) * r.T))

    def inertia_about(self, point) -> sp.Matrix:
        """Rotational inertia about ``point`` (parallel-axis theorem)."""
        return sp.Matrix(self.inertia) + self.mass * _skew_square(sp.Matrix(self.com) - sp.Matrix(point))

    def __add__(self, other: "MassProperties") -> "MassProperties":
        """Two bodies welded together (both expressed in the same frame)."""
        mass = self.mass + other.mass
        if mass == 0:
            return MassProperties(mass, sp.ImmutableMatrix([0, 0, 0]),
                                  sp.ImmutableMatrix(sp.Matrix(self.inertia) + sp.Matrix(other.inertia)))
        com = (self.mass * sp.Matrix(self.com) + other.mass * sp.Matrix(other.com)) / mass
        return MassProperties(mass, sp.ImmutableMatrix(com),
                              sp.ImmutableMatrix(self.inertia_about(com) + other.inertia_about(com)))

    def scene_arguments(self) -> dict:
        """Keyword arguments of :meth:`symgen.scene.Scene.add_body`."""
        i = self.inertia
        return dict(mass=self.mass, com=list(self.com),
                    inertia=[i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2]])


def repaired_inertia(inertia) -> sp.ImmutableMatrix:
    """The nearest rotational inertia of a rigid body to ``inertia`` (3x3, exact), exactly.

    The principal axes are taken from the eigenvectors, rounded to an exactly orthonormal rational
    rotation ``R`` (:func:`~symgen.io.urdf.rotations.rational_rotation`); the principal moments
    ``a <= b <= c`` are the diagonal of ``R^T I R``. Negative moments are raised to zero; then, if
    ``a + b < c``, the three are moved by a third of the excess ``e = c - a - b`` onto the boundary
    plane (``a + e/3, b + e/3, c - e/3``: the Euclidean projection onto ``a + b = c``, which keeps
    the order and the signs). The result ``R diag(a, b, c) R^T`` is rational, so it is positive
    semi-definite and obeys the triangle inequality exactly, not within a tolerance.
    """
    matrix = sp.Matrix(inertia)
    _, vectors = np.linalg.eigh(np.array(matrix, dtype=float))
    if np.linalg.det(vectors) < 0:
        vectors[:, 0] = -vectors[:, 0]
    with mpmath.workdps(DPS):
        rotation = sp.Matrix(rational_rotation(mpmath.matrix(vectors.tolist())))
    moments = [max(sp.Integer(0), v) for v in (rotation.T * matrix * rotation).diagonal()]
    order = sorted(range(3), key=lambda k: moments[k])
    a, b, c = (moments[k] for k in order)
    excess = c - a - b
    if excess > 0:
        a, b, c = a + excess / 3, b + excess / 3, c - excess / 3
    clipped = [sp.Integer(0)] * 3
    for k, v in zip(order, (a, b, c)):
        clipped[k] = v
    return sp.ImmutableMatrix(rotation * sp.diag(*clipped) * rotation.T)
