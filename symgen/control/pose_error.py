"""Required task velocity with pose feedback: ``V_r = V_d' + Lambda e`` (feeds ``V_mr`` of eq. 34).

Frames and conventions (DESIGN.md sections 2-3, float arithmetic): the current frame B has pose
``(R, p) = (R_WB, p_WB)`` and twist ``V = [v; w]`` in its own axes (``dp/dt = R v``,
``dR/dt = R w^``); the desired frame D has pose ``(R_d, p_d)`` and twist ``V_d = [v_d; w_d]`` in
D's own axes. The pose error is the pose of D seen from B, ``T_BD = T_B^-1 T_D``::

    R_BD = R^T R_d,           p_BD = R^T (p_d - p)
    e    = [e_p; e_o] = [p_BD; log(R_BD)]             (rotation vector, in B's axes)

``log`` is the rotation logarithm (:func:`symgen.math.spatial.rot_log`, angle in ``[0, pi]``): no
Euler angles, no singular orientation other than the half-turn ``|e_o| = pi`` where the
direction of the shortest rotation is ambiguous. The feedforward ``V_d'`` is the twist B would
have if it moved rigidly with D (the velocity map of :mod:`symgen.math.spatial` with
``p_DB = R_d^T (p - p_d) = -R_BD^T p_BD``)::

    V_d' = [R_BD (v_d + w_d x p_DB); R_BD w_d]
    V_r  = V_d' + Lambda e

Tracking ``V = V_r`` exactly gives ``d/dt R_BD = -((Lambda e)_o)^ R_BD`` and
``d/dt e_p = -(Lambda e)_o x e_p - (Lambda e)_p`` whatever ``V_d`` is, hence
``d/dt |e|^2 / 2 = -e^T Lambda e < 0`` for every symmetric positive definite ``Lambda`` while
``|e_o| < pi``; with ``Lambda = diag(l_p 1_3, l_o 1_3)`` the errors decay exactly as
``|e_p(t)| = exp(-l_p t) |e_p(0)|`` and ``|e_o(t)| = exp(-l_o t) |e_o(0)|``.
"""
from __future__ import annotations

import numpy as np

from ..math.spatial import rot_log
from .errors import ControlInputError
from .gains import check_positive_definite, gain_matrix

#: largest ``max|R^T R - 1|`` accepted for a rotation matrix (an integrator's drift is far below)
ROTATION_TOLERANCE = 1e-6


def _rotation(r, name: str) -> np.ndarray:
    r = np.asarray(r, dtype=float)
    if r.shape != (3, 3):
        raise ControlInputError(f"{name} must be a 3x3 rotation matrix, got shape {r.shape}")
    if not np.all(np.isfinite(r)) or np.abs(r.T @ r - np.eye(3)).max() > ROTATION_TOLERANCE \
            or np.linalg.det(r) <= 0:
        raise ControlInputError(f"{name} is not a rotation matrix (R^T R != 1 or det <= 0)")
    return r


def _vector(x, n: int, name: str) -> np.ndarray:
    x = np.asarray(x, dtype=float)
    if x.shape != (n,) or not np.all(np.isfinite(x)):
        raise ControlInputError(f"{name} must be {n} finite numbers, got shape {x.shape}")
    return x


def pose_error(r, p, r_d, p_d) -> np.ndarray:
    """``e = [R^T (p_d - p); log(R^T R_d)]`` (6), in the current frame's axes."""
    r, r_d = _rotation(r, "R"), _rotation(r_d, "R_d")
    p, p_d = _vector(p, 3, "p"), _vector(p_d, 3, "p_d")
    return np.concatenate([r.T @ (p_d - p), rot_log(r.T @ r_d)])


def desired_twist_in_frame(r, p, r_d, p_d, v_d) -> np.ndarray:
    """``V_d' = [R_BD (v_d + w_d x p_DB); R_BD w_d]``: D's twist carried rigidly to frame B."""
    r, r_d = _rotation(r, "R"), _rotation(r_d, "R_d")
    p, p_d, v_d = _vector(p, 3, "p"), _vector(p_d, 3, "p_d"), _vector(v_d, 6, "V_d")
    r_bd = r.T @ r_d
    p_db = r_d.T @ (p - p_d)
    return np.concatenate([r_bd @ (v_d[:3] + np.cross(v_d[3:], p_db)), r_bd @ v_d[3:]])


def required_twist(r, p, r_d, p_d, v_d, gain) -> np.ndarray:
    """``V_r = V_d' + Lambda e`` (module docstring); ``gain`` is a scalar, 6 diagonal entries or a
    symmetric positive definite 6 x 6 ``Lambda`` (checked, :class:`GainMatrixError`)."""
    lam = check_positive_definite(gain_matrix(gain, 6, "Lambda"), "Lambda")
    lam = np.asarray(lam, dtype=float)
    return desired_twist_in_frame(r, p, r_d, p_d, v_d) + lam @ pose_error(r, p, r_d, p_d)
