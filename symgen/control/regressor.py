"""Per-subsystem regressors ``Y_1j``, ``Y_3i``, ``Y_alpha`` of eq. (35), in any field.

Rigid body alpha (eq. 21), parameters ``P_alpha = [m, h, I_o]`` of
:mod:`symgen.control.parameters`, actual angular velocity ``omega``, required frame velocity
``X_r = [v_r; w_r]`` and its derivative ``dX_r`` (body-frame coordinates, DESIGN.md section 3),
gravity ``g_body = R_alphaW g`` (the gravity acceleration, e.g. ``R_alphaW (0, 0, -9.81)``, so
that symgen's ``G_alpha = M_alpha [-g_body; 0]``, :func:`symgen.subsystems.rigid_body_gravity`)::

    Y_alpha P_alpha = M_alpha dX_r + Cbar_alpha(omega) X_r + G_alpha                      (35)
    Cbar_alpha(omega) = [[m omega^,   -omega^ h^],
                         [h^ omega^,  I_o omega^ + omega^ I_o]]

``Cbar_alpha`` is symgen's ``C_alpha`` (:func:`symgen.subsystems.rigid_body_coriolis`) written
in the parameters: skew-symmetric and linear in ``P_alpha`` for every ``omega``, so eq. (35)
holds exactly with the actual ``omega`` and any required ``X_r``.

Joints, with ``qdd_r`` the required acceleration and the friction at the ACTUAL rate::

    Y_1j P_1j = I* qdd_r + b qd + c sign(qd),        P_1j = [I*, b, c]                   (22)
    Y_3i P_3i = b w + c w/|w|,                       P_3i = [b, c]                       (23)

The friction ``xi`` of eqs. (22)-(23) is a function of the actual motion, exactly as the plant
(:func:`symgen.subsystems.joint_friction`) computes it; with the true parameters the control
then cancels the plant's friction exactly (no ``b (qd_r - qd)`` residue) and ``s_k`` of
eq. (38) still adapts ``b`` and ``c`` linearly.

The ``required_*`` functions return ``Y P`` without forming ``Y`` (what generated code uses).
"""
from __future__ import annotations

import numpy as np

from ..math.spatial import hat

from .parameters import origin_inertia


def _cross(a, b, field) -> np.ndarray:
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]], dtype=field.dtype)


def _split(x_r, dx_r, g_body, field):
    """``v_r, w_r`` and the gravity-folded acceleration ``a = dX_r - [g_body; 0]``."""
    x_r = np.asarray(x_r, dtype=field.dtype)
    dx_r = np.asarray(dx_r, dtype=field.dtype)
    a_v = dx_r[:3] - np.asarray(g_body, dtype=field.dtype)
    return x_r[:3], x_r[3:], a_v, dx_r[3:]


def inertia_operator(x, field) -> np.ndarray:
    """``L(x)`` (3 x 6) with ``I_o x = L(x) [Ixx, Iyy, Izz, Ixy, Ixz, Iyz]``."""
    z = field.zero
    return np.array([[x[0], z, z, x[1], x[2], z],
                     [z, x[1], z, x[0], z, x[2]],
                     [z, z, x[2], z, x[0], x[1]]], dtype=field.dtype)


def Y_alpha(omega, x_r, dx_r, g_body, field) -> np.ndarray:  # noqa: N802 - the paper's name
    """The 6 x 10 rigid-body regressor of eq. (35) (module docstring)::

        u = a_v + omega x v_r,   z = a_w + omega x w_r,   (a_v, a_w) = dX_r - (g_body, 0)
        Y_alpha = [[u, a_w^ + omega^ w_r^, 0                       ],
                   [0, -u^,                L(z) + omega^ L(w_r)   ]]
    """
    omega = np.asarray(omega, dtype=field.dtype)
    v_r, w_r, a_v, a_w = _split(x_r, dx_r, g_body, field)
    u = a_v + _cross(omega, v_r, field)
    z = a_w + _cross(omega, w_r, field)
    oh = hat(omega, field)
    top = np.hstack([u.reshape(3, 1), hat(a_w, field) + oh @ hat(w_r, field), field.zeros((3, 6))])
    bottom = np.hstack([field.zeros((3, 1)), -hat(u, field),
                        inertia_operator(z, field) + oh @ inertia_operator(w_r, field)])
    return np.vstack([top, bottom])


def required_body_force(p_alpha, omega, x_r, dx_r, g_body, field) -> np.ndarray:
    """``Y_alpha P_alpha`` of eq. (35) computed directly from ``P_alpha`` (no 6 x 10 matrix)::

        f = m u + a_w x h + omega x (w_r x h)
        n = h x u + I_o z + omega x (I_o w_r)
    """
    omega = np.asarray(omega, dtype=field.dtype)
    v_r, w_r, a_v, a_w = _split(x_r, dx_r, g_body, field)
    m, h, io = p_alpha[0], np.asarray(p_alpha[1:4], dtype=field.dtype), origin_inertia(p_alpha, field)
    u = a_v + _cross(omega, v_r, field)
    z = a_w + _cross(omega, w_r, field)
    f = m * u + _cross(a_w, h, field) + _cross(omega, _cross(w_r, h, field), field)
    n = _cross(h, u, field) + io @ z + _cross(omega, io @ w_r, field)
    return np.concatenate([f, n])


def linear_coriolis(p_alpha, omega, field) -> np.ndarray:
    """``Cbar_alpha(omega)`` (6 x 6): skew-symmetric, linear in ``P_alpha``, and equal to
    symgen's ``C_alpha(omega)`` on every ``X`` whose angular part is ``omega`` (module docstring)."""
    oh = hat(np.asarray(omega, dtype=field.dtype), field)
    hh = hat(np.asarray(p_alpha[1:4], dtype=field.dtype), field)
    io = origin_inertia(p_alpha, field)
    top = np.hstack([p_alpha[0] * oh, -oh @ hh])
    return np.vstack([top, np.hstack([hh @ oh, io @ oh + oh @ io])])


def Y_1j(qdd_r, qd, field) -> np.ndarray:  # noqa: N802 - the paper's name
    """The 1 x 3 regressor of a 1-DOF joint, eq. (22): ``[qdd_r, qd, sign(qd)]``, friction at the
    actual rate ``qd``."""
    return np.array([[qdd_r, qd, field.sign(qd)]], dtype=field.dtype)


def required_joint_force(p_1j, qdd_r, qd, field):
    """``Y_1j P_1j = I* qdd_r + b qd + c sign(qd)`` (a scalar of the field)."""
    ir, b, c = p_1j
    return ir * qdd_r + b * qd + c * field.sign(qd)


def Y_3i(w, field) -> np.ndarray:  # noqa: N802 - the paper's name
    """The 3 x 2 regressor of a spherical joint, eq. (23): ``[w, w/|w|]`` at the actual relative
    angular velocity ``w`` (second column zero at ``w = 0``, like the plant's friction)."""
    w = np.asarray(w, dtype=field.dtype)
    norm = field.norm(w) if any(v != 0 for v in w) else None
    unit = field.zeros((3,)) if norm is None else np.array([v / norm for v in w], dtype=field.dtype)
    return np.stack([w, unit], axis=1)


def required_spherical_moment(p_3i, w, field) -> np.ndarray:
    """``Y_3i P_3i = b w + c w/|w|`` (3)."""
    return Y_3i(w, field) @ np.asarray(p_3i, dtype=field.dtype)
