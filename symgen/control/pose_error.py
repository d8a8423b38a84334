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

The required acceleration ``dV_r = d/dt V_r`` (the ``dV_mr`` of eqs. 34-36) is exact for any
actual twist ``V = [v; w]`` of B (:func:`required_twist_rate`). With ``w_d' = R_BD w_d``,
``v_d' = R_BD v_d - w_d' x e_p`` (the rows of ``V_d'``) and the relative angular velocity
``dw = w_d' - w`` (``d/dt R_BD = dw^ R_BD``)::

    d/dt e_p  = (v_d' - v) + dw x e_p
    d/dt e_o  = J_l^-1(e_o) dw,   J_l^-1(phi) = 1 - phi^/2 + (1/a^2 - (1 + cos a)/(2 a sin a)) phi^2,  a = |phi|
    d/dt w_d' = R_BD dw_d + dw x w_d'
    d/dt v_d' = R_BD dv_d + dw x (R_BD v_d) - (d/dt w_d') x e_p - w_d' x d/dt e_p

(``J_l^-1`` is the inverse left Jacobian of the rotation exponential: ``d/dt log R = J_l^-1 u``
when ``dR/dt = u^ R``.) Replacing ``d/dt e`` by ``V_d' - V`` and ``d/dt V_d'`` by ``dV_d`` is right
only at ``e = 0``; a task on a few components (``vx, vy`` of a planar pin, a tool sliding on a
plane) leaves the other components' error free, so ``R_BD`` stays far from ``1`` and that
approximation breaks the ``dV/dt <= 0`` of Section 4.
"""
from __future__ import annotations

import numpy as np

from ..math.spatial import rot_log
from .errors import ControlInputError
from .gains import check_positive_definite, gain_matrix

#: largest ``max|R^T R - 1|`` accepted for a rotation matrix (an integrator's drift is far below)
ROTATION_TOLERANCE = 1e-6
#: rotation angle (rad) below which :func:`log_rate_matrix` uses its Taylor series
SMALL_ANGLE = 1e-4


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


def log_rate_matrix(phi) -> np.ndarray:
    """``J_l^-1(phi)``: ``d/dt log R = J_l^-1(log R) u`` for ``dR/dt = u^ R`` (module docstring);
    a Taylor series below :data:`SMALL_ANGLE` rad, finite up to the half-turn."""
    phi = _vector(phi, 3, "phi")
    a = float(np.linalg.norm(phi))
    k = np.array([[0.0, -phi[2], phi[1]], [phi[2], 0.0, -phi[0]], [-phi[1], phi[0], 0.0]])
    if a < SMALL_ANGLE:
        c = 1.0 / 12.0 + a * a / 720.0
    else:
        c = 1.0 / (a * a) - (1.0 + np.cos(a)) / (2.0 * a * np.sin(a))
    return np.eye(3) - 0.5 * k + c * (k @ k)


def required_twist_rate(r, p, r_d, p_d, v, v_d, dv_d, gain) -> tuple[np.ndarray, np.ndarray]:
    """``(V_r, dV_r)``: the required twist of :func:`required_twist` and its exact time derivative
    (module docstring) for B's actual twist ``v`` = ``[v; w]`` and D's twist ``v_d`` with its
    derivative ``dv_d`` (D's axes); ``gain`` as in :func:`required_twist`."""
    lam = np.asarray(check_positive_definite(gain_matrix(gain, 6, "Lambda"), "Lambda"), dtype=float)
    v, dv_d = _vector(v, 6, "V"), _vector(dv_d, 6, "dV_d")
    e = pose_error(r, p, r_d, p_d)
    v_dp = desired_twist_in_frame(r, p, r_d, p_d, v_d)
    r_bd = np.asarray(r, float).T @ np.asarray(r_d, float)
    e_p, w_dp = e[:3], v_dp[3:]
    dw = w_dp - v[3:]
    de_p = (v_dp[:3] - v[:3]) + np.cross(dw, e_p)
    de_o = log_rate_matrix(e[3:]) @ dw
    dw_dp = r_bd @ dv_d[3:] + np.cross(dw, w_dp)
    dv_dp = r_bd @ dv_d[:3] + np.cross(dw, r_bd @ np.asarray(v_d, float)[:3]) - np.cross(dw_dp, e_p) \
        - np.cross(w_dp, de_p)
    de = np.concatenate([de_p, de_o])
    return v_dp + lam @ e, np.concatenate([dv_dp, dw_dp]) + lam @ de


def required_twist(r, p, r_d, p_d, v_d, gain) -> np.ndarray:
    """``V_r = V_d' + Lambda e`` (module docstring); ``gain`` is a scalar, 6 diagonal entries or a
    symmetric positive definite 6 x 6 ``Lambda`` (checked, :class:`GainMatrixError`)."""
    lam = check_positive_definite(gain_matrix(gain, 6, "Lambda"), "Lambda")
    lam = np.asarray(lam, dtype=float)
    return desired_twist_in_frame(r, p, r_d, p_d, v_d) + lam @ pose_error(r, p, r_d, p_d)
