"""Rotation matrices written by other tools: checked, and snapped to exact rotations.

A scene may give a placement's ``rotation`` as a 3x3 matrix. Exact entries (integers, fractions,
``sqrt(3)/2``) must form an exact rotation (``R^T R = 1``, ``det R = 1``). Floating-point entries,
as exported by CAD tools, MuJoCo or Pinocchio, must be orthonormal to :data:`ORTHONORMAL_TOL`
(``max |R^T R - 1|`` and ``|det R - 1|``); they are then *snapped* to an exact rotation:

1. each entry is recognised as a small rational (denominator at most 100), or such a rational
   times ``sqrt(2)``, ``sqrt(3)`` or ``sqrt(6)`` (the entries of rotations by multiples of 15 degrees about coordinate axes and
   their products, e.g. ``0.8660254037844386 -> sqrt(3)/2``); if the recognised matrix is an exact
   rotation within :data:`ORTHONORMAL_TOL` of the given one, it is used;
2. otherwise the rotation's unit quaternion is rounded to rationals of denominator at most
   :data:`QUAT_DENOMINATOR` and turned exactly into a rotation (``symgen.math.spatial.exact_quat``):
   an exact rotation within about ``1e-12`` of the given matrix.

Either way the model is derived from an exact rotation, so every field (exact, symbolic, float)
sees the same robot.
"""
from __future__ import annotations

from collections.abc import Iterable
from fractions import Fraction
from typing import Any, cast

import numpy as np
import sympy as sp

from ..errors import SceneError
from .spatial import exact_quat, matrix_to_quat

#: a floating-point rotation matrix must satisfy max|R^T R - 1| and |det R - 1| below this
ORTHONORMAL_TOL = 1e-6
#: denominators of the rational quaternion of step 2
QUAT_DENOMINATOR = 10 ** 12
#: step 1 looks for rationals of at most this denominator (times the square roots below), within
#: ten times the matrix's own orthonormality error (at least 1e-10)
RECOGNISE_DENOMINATOR = 100
#: the square roots step 1 recognises
SURDS = (sp.sqrt(2), sp.sqrt(3), sp.sqrt(6))


def _is_float_entry(v: object) -> bool:
    return isinstance(v, (float, np.floating, sp.Float))


def _exact_rotation_check(element: str, r: sp.Matrix) -> sp.Matrix:
    gram = sp.simplify(r.T * r - sp.eye(3))
    det = sp.simplify(r.det() - 1)
    if any(v != 0 for v in gram) or det != 0:
        raise SceneError(element, "rotation must be a rotation matrix (R^T R = 1 and det R = +1); "
                                  f"got R^T R - 1 = {gram.tolist()}, det R - 1 = {det}")
    return r


def _recognise(x: float, tol: float) -> sp.Expr | None:
    """``x`` as a rational of denominator at most :data:`RECOGNISE_DENOMINATOR`, or such a rational
    times sqrt(2), sqrt(3) or sqrt(6), within ``tol`` (step 1); ``None`` if there is none."""
    for surd in (sp.Integer(1),) + SURDS:
        frac = Fraction(x / float(surd)).limit_denominator(RECOGNISE_DENOMINATOR)
        value = sp.Rational(frac.numerator, frac.denominator) * surd
        if abs(float(value) - x) <= tol:
            return value
    return None


def snap_rotation(element: str, matrix: object) -> sp.ImmutableMatrix:
    """An exact rotation from ``matrix`` (3x3, exact or float; see the module docstring).

    Raises:
        SceneError: not 3x3, not orthonormal within :data:`ORTHONORMAL_TOL`, or a reflection.
    """
    try:
        rows: list[list[Any]] | None = [list(r) for r in cast(Iterable[Iterable[Any]], matrix)]
    except TypeError:
        rows = None
    if rows is None or len(rows) != 3 or any(len(r) != 3 for r in rows):
        raise SceneError(element, "rotation must be a 3x3 matrix (three rows of three numbers)")
    if not any(_is_float_entry(v) for r in rows for v in r):
        return sp.ImmutableMatrix(_exact_rotation_check(element, sp.Matrix(rows)))
    f = np.array([[float(v) for v in r] for r in rows])
    err = float(np.max(np.abs(f.T @ f - np.eye(3))))
    det = float(np.linalg.det(f))
    if not np.isfinite(err) or err > ORTHONORMAL_TOL or abs(det - 1) > ORTHONORMAL_TOL:
        raise SceneError(element, f"rotation is not a rotation matrix within {ORTHONORMAL_TOL:g}: "
                                  f"max|R^T R - 1| = {err:.3g}, det R = {det:.6g}")
    entries = [_recognise(v, max(1e-10, 10 * err)) for v in f.flat]
    if all(e is not None for e in entries):
        r = sp.Matrix(3, 3, entries)
        if sp.simplify(r.T * r - sp.eye(3)) == sp.zeros(3) and sp.simplify(r.det()) == 1:
            return sp.ImmutableMatrix(r)
    # step 2: project onto SO(3) (polar factor), then a rational quaternion
    u, _, vt = np.linalg.svd(f)
    q = matrix_to_quat(u @ vt)
    fr = [Fraction(float(c)).limit_denominator(QUAT_DENOMINATOR) for c in q]
    r = exact_quat(*(sp.Rational(c.numerator, c.denominator) for c in fr))
    return sp.ImmutableMatrix(r)
