"""Exact rotations for URDF origins, axes and locked joints.

Every rotation handed to the scene is a matrix of exact rationals, so that placements compose
exactly, merged inertias stay rational, and the scene can be written to YAML and proved in exact
arithmetic. Two cases:

* **Multiples of pi/2.** An angle within ``snap`` of a multiple of pi/2 is taken as that
  multiple, so the rotation is a signed permutation matrix with exact zeros. The default
  :data:`SNAP` = 1e-14 rad only catches what a double cannot tell from pi/2
  (``1.5707963267948966``, ``3.141592653589793``), so the model is the file's robot to double
  precision. Files that round pi/2 to fewer digits (the UR5's ``1.57079632679``, 4.9e-12 rad
  off) keep their angle, unless a larger ``snap`` is asked for. ``snap=1e-9`` takes it as pi/2.
  The UR5 then has fewer operations in ``inverse_dynamics`` (348 instead of 357 when measured)
  and differs from Pinocchio on the same file by 3e-11 relative instead of 6e-16
  (``tests/test_urdf_examples.py``).
* **Any other angle.** The rotation is computed in 50-digit arithmetic from the exact angles,
  turned into a unit quaternion and rounded to the grid ``10**-20`` (the built-in scenes do the
  same, see :func:`symgen.math.numbers.to_exact`). The rational quaternion gives an exactly orthonormal
  rational matrix within about 1e-20 of the file's rotation, far below double precision.

The convention of ``rpy`` is URDF's: fixed axes, roll about x, then pitch about y, then yaw
about z, ``R = Rz(yaw) Ry(pitch) Rx(roll)``.
"""
from __future__ import annotations

from fractions import Fraction

import mpmath
import sympy as sp

from ...math.numbers import DPS, mp, to_exact
from ..scene_yaml_dump import rational_quat
from ...math.spatial import exact_quat, exact_rpy, mp_matrix_to_quat

#: angles closer than this to a multiple of pi/2 (rad) are taken as that multiple
SNAP = 1e-14


def snapped_angle(angle, snap: float = SNAP):
    """``k*pi/2`` (SymPy) when ``angle`` is within ``snap`` of it, else ``None``."""
    with mpmath.workdps(DPS):
        k = int(mpmath.nint(mp(angle) / (mpmath.pi / 2)))
        close = abs(mp(angle) - k * mpmath.pi / 2) <= snap
    return sp.Integer(k) * sp.pi / 2 if close else None


def _mp_rpy(angles) -> mpmath.matrix:
    r, p, y = angles
    cr, sr, cp, sp_, cy, sy = mpmath.cos(r), mpmath.sin(r), mpmath.cos(p), mpmath.sin(p), mpmath.cos(y), mpmath.sin(y)
    return mpmath.matrix([[cy * cp, cy * sp_ * sr - sy * cr, cy * sp_ * cr + sy * sr],
                          [sy * cp, sy * sp_ * sr + cy * cr, sy * sp_ * cr - cy * sr],
                          [-sp_, cp * sr, cp * cr]])


def rational_rotation(r_mp) -> sp.ImmutableMatrix:
    """An exactly orthonormal rational matrix within about 1e-20 of the mpmath rotation ``r_mp``."""
    quat = [sp.Rational(to_exact(v)) for v in mp_matrix_to_quat(r_mp)]
    return sp.ImmutableMatrix(exact_quat(*quat))


def rotation_from_rpy(rpy, snap: float = SNAP) -> sp.ImmutableMatrix:
    """The exact rational rotation of URDF angles ``rpy`` (see the module docstring)."""
    snapped = [snapped_angle(a, snap) if snap > 0 else (sp.Integer(0) if a == 0 else None) for a in rpy]
    if all(s is not None for s in snapped):
        return sp.ImmutableMatrix(exact_rpy(*snapped))
    with mpmath.workdps(DPS):
        angles = [mp(s if s is not None else a) for s, a in zip(snapped, rpy)]
        return rational_rotation(_mp_rpy(angles))


def axis_rotation(axis, angle, snap: float = SNAP) -> sp.ImmutableMatrix:
    """Rotation by ``angle`` about the (not necessarily unit) ``axis``, exact rational."""
    a = [sp.Rational(v) for v in axis]
    k = snapped_angle(angle, snap) if snap > 0 else None
    unit = [i for i, v in enumerate(a) if v != 0]
    if k is not None and len(unit) == 1:
        i, sign = unit[0], 1 if a[unit[0]] > 0 else -1
        rpy = [sp.Integer(0)] * 3
        rpy[i] = sign * k
        return sp.ImmutableMatrix(exact_rpy(*rpy))
    with mpmath.workdps(DPS):
        u = mpmath.matrix([mp(v) for v in a])
        u = u / mpmath.norm(u)
        t = mp(k if k is not None else angle)
        kx = mpmath.matrix([[0, -u[2], u[1]], [u[2], 0, -u[0]], [-u[1], u[0], 0]])
        return rational_rotation(mpmath.eye(3) + mpmath.sin(t) * kx + (1 - mpmath.cos(t)) * (kx * kx))


def unit_axis(axis) -> tuple:
    """The exact direction of a URDF axis, for a translation along it (rounded when not rational)."""
    a = [sp.Rational(v) for v in axis]
    norm2 = sum(v * v for v in a)
    root = sp.sqrt(norm2)
    if root.is_Rational:
        return tuple(v / root for v in a)
    with mpmath.workdps(DPS):
        n = mpmath.sqrt(mp(norm2))
        return tuple(sp.Rational(to_exact(mp(v) / n)) for v in a)


def axis_argument(axis):
    """The scene's ``axis`` argument: ``"x"``, ``"-y"``... for a coordinate axis (exact), else the
    rational vector (the scene normalises it and maps it to z exactly, see :mod:`symgen.tree`)."""
    a = [Fraction(v) for v in axis]
    nonzero = [i for i, v in enumerate(a) if v != 0]
    if len(nonzero) == 1:
        i = nonzero[0]
        return ("-" if a[i] < 0 else "") + "xyz"[i]
    return [sp.Rational(v) for v in a]


def quaternion_argument(rotation) -> list | None:
    """The scene's ``quat`` argument (integers, exact) of a rational rotation; ``None`` for 1."""
    r = sp.Matrix(rotation)
    if r == sp.eye(3):
        return None
    q = rational_quat(r)
    if sp.Matrix(exact_quat(*q)) != r:
        raise ValueError("not a rational rotation")
    return q
