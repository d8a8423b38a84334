"""The robot's regressors of Section 4, stacked from the subsystems' through the step pipeline.

    X_r  = T_S [J_m; J_f]^-1 [V_mr; 0]                                            (36)
    Y_r P_r = M_S dX_r/dt + C_S X_r + G_S      (row blocks Y_1j, Y_3i, Y_alpha)    (35)
    Y_m P_m = D_m^T eta_m                                                        (37)
    Y = [T_S^T Y_r, Y_m]

``T_S`` and ``[J_m; J_f]^-1`` are the maps of Steps 10-11 (:mod:`symgen.steps`) at the actual
configuration, with time derivatives along the actual motion; ``C_S`` carries the actual angular
velocities. Everything runs in any field. Forming ``Y`` densely is ``O(n_S p)``: the reference
and the inspection route; generated code applies the same sums recursively.
"""
from __future__ import annotations

import numpy as np

from .parameters import ParameterSet
from .regressor import Y_1j, Y_3i, Y_alpha


def required_velocity(data, v_mr, dv_mr) -> tuple[np.ndarray, np.ndarray]:
    """Eq. (36): ``X_r = B [V_mr; 0]`` and ``dX_r/dt = dB/dt [V_mr; 0] + B [dV_mr; 0]`` with
    ``B = T_S [J_m; J_f]^-1`` of the model data ``data`` (its derivative along the actual motion)."""
    fld, b = data.field, data.B
    n, m = b.shape[1], len(data.V_m)
    pad = fld.zeros((n - m,))
    v = np.concatenate([np.asarray(v_mr, dtype=fld.dtype), pad])
    dv = np.concatenate([np.asarray(dv_mr, dtype=fld.dtype), pad])
    return b.v @ v, b.d @ v + b.v @ dv


def subsystem_regressor(model, data, params: ParameterSet, x_r, dx_r, *, gravity: bool = True) -> np.ndarray:
    """``Y_r`` of eq. (35), ``n_S x p``: joint rows ``[qdd_r, qd, sign(qd)]`` (friction at the actual
    rate), spherical rows ``[w, w/|w|]``, and a ``Y_alpha`` block per massive body with its actual
    angular velocity, required twist and gravity in its own axes. Columns in ``params`` order."""
    fld, maps = data.field, data.maps
    space, kin = maps.velocity.space, maps.kin
    y = fld.zeros((space.size, len(params)))
    for joint in model.tree.joints:
        cols, rows = params.owner_indices(joint.name), list(joint.coords)
        if joint.kind.dof == 1:
            y[np.ix_(rows, cols)] = Y_1j(dx_r[rows[0]], data.X[rows[0]], fld)
        elif joint.kind.dof == 3:
            y[np.ix_(rows, cols)] = Y_3i(data.X[rows], fld)
    g_world = kin.const.gravity if gravity else fld.zeros((3,))
    for k, b in enumerate(space.bodies):
        rows = space.body_rows(k)
        cols = params.owner_indices(model.tree.bodies[b].name)
        g_body = kin.rot[b].v.T @ g_world
        y[rows, cols] = Y_alpha(data.X[rows][3:], x_r[rows], dx_r[rows], g_body, fld)
    return y


def joint_regressor(data, y_r) -> np.ndarray:
    """``T_S^T Y_r`` (``n x p``): the regressor in the general joint space A (eq. 30)."""
    return data.maps.T_S.v.T @ y_r
