"""Spatial algebra in the paper's conventions (DESIGN.md section 2).

A frame velocity is ``X = [v; w]`` (linear velocity of the frame origin, then angular velocity),
a force ``F = [f; m]``. ``U_B_A`` stands for the paper's ``^B U_A``: it maps a force from frame A
to frame B, ``F_B = U_B_A F_A``, with ``U_B_A = [[R, 0], [hat(p) R, R]]``, ``R = R_BA``,
``p = p_BA``; velocities map the other way, ``X_A = U_B_A^T X_B``.

The generic helpers (:func:`hat`, :func:`force_transform`) work on NumPy arrays of any field and
on :class:`~symgen.math.jet.Jet` s. The ``exact_*`` helpers build constant rotations as exact SymPy
matrices for scene placements; :func:`box_inertia` and friends exact (``Fraction``) inertias of
simple solids, so a body built from them obeys the triangle inequality by construction. Poses
``(R, p)`` derived at 50 digits (:mod:`symgen.reference_kinematics`) are composed with
:func:`relative_pose` and handed back exact by :func:`pose_to_exact`.
"""
from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from fractions import Fraction
from typing import TYPE_CHECKING, Any, Protocol, TypeAlias

import mpmath
import numpy as np
import sympy as sp

from .jet import Jet, block
from .numbers import DPS, to_exact
from .scalar import Scalar

if TYPE_CHECKING:
    from .fields import Field


class EntryIndexed(Protocol):
    """A matrix read entry by entry, ``r[i, j]``: a NumPy array, a SymPy or an mpmath matrix."""

    def __getitem__(self, index: tuple[int, int], /) -> Scalar: ...


#: a pose ``(R, p)`` as 50-digit mpmath matrices (3x3 and 3x1)
MpPose: TypeAlias = "tuple[mpmath.matrix, mpmath.matrix]"
#: a mass or length of a simple solid: a decimal string, a float (read by its ``repr``, so ``0.1``
#: is 1/10), an int or a Fraction
Size: TypeAlias = "str | float | Fraction"

AXIS_NAMES = {"x": 0, "y": 1, "z": 2}
#: component names of a frame velocity / force, in the paper's order
COMPONENTS = ("vx", "vy", "vz", "wx", "wy", "wz")


def hat(p: np.ndarray | Sequence[Scalar], field: Field) -> np.ndarray:
    """Cross-product matrix: ``hat(p) @ x == cross(p, x)``."""
    z = field.zero
    return np.array([[z, -p[2], p[1]], [p[2], z, -p[0]], [-p[1], p[0], z]], dtype=field.dtype)


def quaternion_matrix(w: Any, x: Any, y: Any, z: Any) -> list[list[Any]]:
    """``|p|^2 R(p)`` of a quaternion ``p = (w, x, y, z)`` in any field: the homogeneous rotation
    matrix, so ``R(p)`` itself after dividing by ``|p|^2`` (the same rotation for any ``|p| > 0``)."""
    return [[w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z]]


def quaternion_product(a: Sequence[Any], b: Sequence[Any]) -> list[Any]:
    """Hamilton product ``a (x) b`` of quaternions ``(w, x, y, z)`` in any field (numbers, traced
    nodes)."""
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return [aw * bw - ax * bx - ay * by - az * bz, aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw]


def hat_jet(p: Jet, field: Field) -> Jet:
    return Jet(hat(p.v, field), hat(p.d, field))


def force_transform(r: Jet, p: Jet, field: Field) -> Jet:
    """``^B U_A`` from ``R = R_BA`` and ``p = p_BA`` (both jets)."""
    zero = Jet.const(field.zeros((3, 3)), field)
    return block([[r, zero], [hat_jet(p, field) @ r, r]])


# ---------------------------------------------------------------------- exact constant rotations
def exact_rot(axis: int, angle: sp.Expr) -> sp.Matrix:
    """Rotation by ``angle`` about coordinate axis ``axis`` (0, 1, 2), exact."""
    c, s = sp.cos(angle), sp.sin(angle)
    if axis == 0:
        return sp.Matrix([[1, 0, 0], [0, c, -s], [0, s, c]])
    if axis == 1:
        return sp.Matrix([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    return sp.Matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def exact_rpy(roll: sp.Expr, pitch: sp.Expr, yaw: sp.Expr) -> sp.Matrix:
    """URDF convention: fixed-axis roll about x, then pitch about y, then yaw about z."""
    return exact_rot(2, yaw) * exact_rot(1, pitch) * exact_rot(0, roll)


def exact_quat(w: sp.Expr, x: sp.Expr, y: sp.Expr, z: sp.Expr) -> sp.Matrix:
    """Rotation matrix of the quaternion ``(w, x, y, z)``, normalised exactly."""
    return sp.Matrix(quaternion_matrix(w, x, y, z)) / (w * w + x * x + y * y + z * z)


def exact_align_z(axis: sp.Matrix) -> sp.Matrix:
    """A constant rotation ``A`` with ``A e3 = axis`` (unit), exact, identity for ``axis = e3``.

    Coordinate axes map to signed permutation matrices, so the paper's ``Z = e3 / e6`` joint
    frames cost nothing. Other axes use the rotation about ``e3 x axis``.
    """
    a = sp.Matrix(axis)
    a = a / sp.sqrt(sum(v * v for v in a))
    e3 = sp.Matrix([0, 0, 1])
    special = {
        (0, 0, 1): sp.eye(3),
        (0, 0, -1): exact_rot(0, sp.pi),
        (0, 1, 0): exact_rot(0, -sp.pi / 2),
        (0, -1, 0): exact_rot(0, sp.pi / 2),
        (1, 0, 0): exact_rot(1, sp.pi / 2),
        (-1, 0, 0): exact_rot(1, -sp.pi / 2),
    }
    key = tuple(sp.nsimplify(v) for v in a)
    if key in special:
        return special[key]
    k = e3.cross(a)
    s = sp.sqrt(sum(v * v for v in k))
    c = e3.dot(a)
    k = k / s
    kx = sp.Matrix([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return sp.simplify(sp.eye(3) + s * kx + (1 - c) * kx * kx)



# ------------------------------------------------------------------------- float helpers (numpy)
def rot_log(r: np.ndarray) -> np.ndarray:
    """Rotation vector of a rotation matrix (float), robust near 0 and pi."""
    cos = np.clip((np.trace(r) - 1.0) / 2.0, -1.0, 1.0)
    angle = np.arccos(cos)
    w = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]])
    out: np.ndarray
    if angle < 1e-7:
        out = 0.5 * w
    elif np.pi - angle < 1e-6:
        # axis from the symmetric part
        m = (r + np.eye(3)) / 2.0
        axis = m[:, np.argmax(np.diag(m))]
        axis = axis / np.linalg.norm(axis)
        out = angle * axis * (1.0 if axis @ w >= 0 else -1.0)
    else:
        out = angle / (2.0 * np.sin(angle)) * w
    return out


def rot_exp(w: np.ndarray) -> np.ndarray:
    """Rotation matrix of a rotation vector (float), Rodrigues."""
    angle = float(np.linalg.norm(w))
    k = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
    out: np.ndarray
    if angle < 1e-9:
        out = np.eye(3) + k + 0.5 * k @ k
    else:
        out = np.eye(3) + np.sin(angle) / angle * k + (1 - np.cos(angle)) / angle**2 * k @ k
    return out


def matrix_to_quat(r: EntryIndexed, sqrt: Callable[[Scalar], Scalar] = math.sqrt) -> list[Scalar]:
    """Unit quaternion ``[w, x, y, z]`` of a rotation matrix (Shepperd's method), ``w >= 0``.

    ``r`` is anything indexed as ``r[i, j]`` (a NumPy array, an mpmath matrix); ``sqrt`` matches
    its number type (``mpmath.sqrt`` for 50-digit builders)."""
    tr = r[0, 0] + r[1, 1] + r[2, 2]
    cands = [tr, r[0, 0], r[1, 1], r[2, 2]]
    k = max(range(4), key=lambda i: cands[i])
    if k == 0:
        s = 2 * sqrt(1 + tr)
        q = [s / 4, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s]
    elif k == 1:
        s = 2 * sqrt(1 + r[0, 0] - r[1, 1] - r[2, 2])
        q = [(r[2, 1] - r[1, 2]) / s, s / 4, (r[0, 1] + r[1, 0]) / s, (r[0, 2] + r[2, 0]) / s]
    elif k == 2:
        s = 2 * sqrt(1 + r[1, 1] - r[0, 0] - r[2, 2])
        q = [(r[0, 2] - r[2, 0]) / s, (r[0, 1] + r[1, 0]) / s, s / 4, (r[1, 2] + r[2, 1]) / s]
    else:
        s = 2 * sqrt(1 + r[2, 2] - r[0, 0] - r[1, 1])
        q = [(r[1, 0] - r[0, 1]) / s, (r[0, 2] + r[2, 0]) / s, (r[1, 2] + r[2, 1]) / s, s / 4]
    return q if q[0] >= 0 else [-v for v in q]


def mp_matrix_to_quat(r: mpmath.matrix) -> list[mpmath.mpf]:
    """Unit quaternion ``(w, x, y, z)`` of an mpmath rotation matrix, at ``DPS`` digits."""
    with mpmath.workdps(DPS):
        return matrix_to_quat(r, sqrt=mpmath.sqrt)


# ------------------------------------------------------------------ 50-digit poses (mpmath)
def relative_pose(pose_a: MpPose, pose_b: MpPose) -> MpPose:
    """Pose of b in a's frame: ``(R_a^T R_b, R_a^T (p_b - p_a))``."""
    (r_a, p_a), (r_b, p_b) = pose_a, pose_b
    with mpmath.workdps(DPS):
        return r_a.T * r_b, r_a.T * (p_b - p_a)


def pose_to_exact(pose: MpPose) -> dict[str, list[Fraction]]:
    """``xyz`` and ``quat`` keyword arguments (exact Fractions) for a placement ``(R, p)``."""
    r, p = pose
    return dict(xyz=[to_exact(p[i]) for i in range(3)], quat=[to_exact(v) for v in mp_matrix_to_quat(r)])


# --------------------------------------------------------- mass properties of simple solids
def _fraction(x: Size) -> Fraction:
    return Fraction(str(x)) if isinstance(x, (str, float)) else Fraction(x)


def box_inertia(mass: Size, sx: Size, sy: Size, sz: Size) -> list[Fraction]:
    """Principal inertias ``[ixx, iyy, izz]`` of a solid box with edge lengths ``sx, sy, sz``."""
    m, x, y, z = (_fraction(v) for v in (mass, sx, sy, sz))
    return [m * (y * y + z * z) / 12, m * (x * x + z * z) / 12, m * (x * x + y * y) / 12]


def bar_inertia(mass: Size, length: Size, width: Size, axis: str = "x") -> list[Fraction]:
    """A bar of square cross-section ``width`` x ``width`` and ``length`` along ``axis``."""
    sizes = {a: _fraction(width) for a in "xyz"}
    sizes[axis] = _fraction(length)
    return box_inertia(mass, sizes["x"], sizes["y"], sizes["z"])


def cylinder_inertia(mass: Size, length: Size, radius: Size, axis: str = "z") -> list[Fraction]:
    """A solid cylinder of ``radius`` and ``length`` along ``axis``."""
    m, h, r = _fraction(mass), _fraction(length), _fraction(radius)
    axial, transverse = m * r * r / 2, m * (3 * r * r + h * h) / 12
    return [axial if a == axis else transverse for a in "xyz"]
