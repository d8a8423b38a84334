"""Pinocchio's RNEA and ABA derivatives on a free-flyer root, mapped to symgen's coordinates.

Derived here from the two conventions (not from symgen's code). With ``R`` the base's rotation,
symgen's base rates are ``[pd (world); w (body)]`` and Pinocchio's ``v = B [pd; w]``,
``B = diag(R^T, 1, 1...)``; Pinocchio's ``a = dv/dt`` is ``B qdd - c``, ``c_lin = w x u`` with
``u = R^T pd``, that is ``a_lin = R^T pdd - w x u``; forces map by ``f_sym = B^T f_pin``.
Both take ``d/dq`` along a child-frame perturbation of the rotation, ``R exp(hat(d))``; a
translation ``dp`` (world) is Pinocchio's ``R^T dp`` (its ``integrate`` moves the base in its own
axes), so the ``q`` directions map by ``B`` too. At first order in ``d`` (``R^T -> exp(-hat d) R^T``):

* ``d(R^T x)/d d = hat(R^T x)`` for any fixed world vector ``x``, and ``d(R y)/d d = -R hat(y)``.

Inverse dynamics ``tau_s(q, qd, qdd) = B^T tau_p(q, B qd, a_p)``:

* ``dtau_s/dqdd = B^T M B``;
* ``dtau_s/dqd = B^T (dtau_p/dv B + M da_p/dqd)``, ``da_p,lin/dpd = -hat(w) R^T``,
  ``da_p,lin/dw = hat(u)``;
* ``dtau_s/dq = B^T (dtau_p/dq B + dtau_p/dv dv_p/dq + M da_p/dq) + d(B^T)/dq tau_p``, on the base's
  rotation columns: ``dv_p,lin = hat(u)``, ``da_p,lin = hat(R^T pdd) - hat(w) hat(u)``, and
  ``d(B^T)/dq tau_p`` has the linear rows ``-R hat(tau_p,lin)``.

Forward dynamics ``qdd_s(q, qd, tau_s) = B^T (a_p(q, B qd, B tau_s) + c)``, ``c_lin = hat(w) u``:

* ``d/dtau = B^T Minv B``; ``d/dqd = B^T (da/dv B + dc/dqd)``, ``dc_lin/dpd = hat(w) R^T``,
  ``dc_lin/dw = -hat(u)``;
* ``d/dq = B^T (da/dq B + da/dv dv_p/dq + Minv dtau_p/dq + dc/dq) + d(B^T)/dq (a_p + c)``, on the
  rotation columns: ``dv_p,lin = hat(u)``, ``dtau_p,lin = hat(R^T tau_s,lin)``, ``dc_lin = hat(w) hat(u)``,
  and the linear rows of the last term ``-R hat((a_p + c)_lin)``.
"""
from __future__ import annotations

import numpy as np


def hat(x) -> np.ndarray:
    return np.array([[0, -x[2], x[1]], [x[2], 0, -x[0]], [-x[1], x[0], 0]], dtype=float)


def _b(rot, n) -> np.ndarray:
    b = np.eye(n)
    b[:3, :3] = rot.T
    return b


def rnea_derivatives(pin, pmodel, q, rot, qd, qdd, drop=None):
    """``(dtau_dq, dtau_dqd, M)`` in symgen's coordinates (base first: ``pd`` world, ``w`` body),
    from Pinocchio's ``computeRNEADerivatives``; ``qd``, ``qdd`` symgen's, Pinocchio's velocity order
    (``drop``: ``"force_turn"`` or ``"velocity_turn"`` leaves that term out, a planted error)."""
    n = pmodel.nv
    b = _b(rot, n)
    w, u = qd[3:6], rot.T @ qd[:3]
    v = b @ qd
    a = b @ qdd
    a[:3] -= np.cross(w, u)
    data = pmodel.createData()
    d_q, d_v, _ = (np.asarray(x).copy() for x in pin.computeRNEADerivatives(pmodel, data, q, v, a))
    mass = np.triu(data.M) + np.triu(data.M, 1).T
    tau_p = np.asarray(pin.rnea(pmodel, pmodel.createData(), q, v, a)).copy()
    da_dqd = np.zeros((n, n))
    da_dqd[:3, :3], da_dqd[:3, 3:6] = -hat(w) @ rot.T, hat(u)
    dv_dq, da_dq = np.zeros((n, n)), np.zeros((n, n))
    dv_dq[:3, 3:6] = 0 if drop == "velocity_turn" else hat(u)
    da_dq[:3, 3:6] = hat(rot.T @ qdd[:3]) - hat(w) @ hat(u)
    dbt = np.zeros((n, n))
    dbt[:3, 3:6] = 0 if drop == "force_turn" else -rot @ hat(tau_p[:3])
    dtau_dq = b.T @ (d_q @ b + d_v @ dv_dq + mass @ da_dq) + dbt
    dtau_dqd = b.T @ (d_v @ b + mass @ da_dqd)
    return dtau_dq, dtau_dqd, b.T @ mass @ b


def aba_derivatives(pin, pmodel, q, rot, qd, tau, drop=None):
    """``(dqdd_dq, dqdd_dqd, dqdd_dtau)`` in symgen's coordinates from Pinocchio's
    ``computeABADerivatives``; ``qd``, ``tau`` symgen's, in Pinocchio's velocity order (``drop``: as
    :func:`rnea_derivatives`)."""
    n = pmodel.nv
    b = _b(rot, n)
    w, u = qd[3:6], rot.T @ qd[:3]
    v, tau_p = b @ qd, b @ tau
    data = pmodel.createData()
    d_q, d_v, minv = (np.asarray(x).copy() for x in pin.computeABADerivatives(pmodel, data, q, v, tau_p))
    minv = np.triu(minv) + np.triu(minv, 1).T     # Pinocchio fills the upper triangle
    a = np.asarray(pin.aba(pmodel, pmodel.createData(), q, v, tau_p)).copy()
    c = np.zeros(n)
    c[:3] = np.cross(w, u)
    dc_dqd = np.zeros((n, n))
    dc_dqd[:3, :3], dc_dqd[:3, 3:6] = hat(w) @ rot.T, -hat(u)
    dv_dq, dtau_dq, dc_dq = np.zeros((n, n)), np.zeros((n, n)), np.zeros((n, n))
    dv_dq[:3, 3:6] = 0 if drop == "velocity_turn" else hat(u)
    dtau_dq[:3, 3:6] = hat(rot.T @ tau[:3])
    dc_dq[:3, 3:6] = hat(w) @ hat(u)
    dbt = np.zeros((n, n))
    dbt[:3, 3:6] = 0 if drop == "force_turn" else -rot @ hat((a + c)[:3])
    d_dq = b.T @ (d_q @ b + d_v @ dv_dq + minv @ dtau_dq + dc_dq) + dbt
    return d_dq, b.T @ (d_v @ b + dc_dqd), b.T @ minv @ b
