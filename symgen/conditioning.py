"""How close a loop may come to its dead point before the model's velocity terms lose every digit.

Near a singular configuration of a loop (a *dead point*: the loop-closure block
``W = [T_u1, T_a1]`` of eq. (9) nearly singular), a configuration given in floating point is off
the constraint manifold by its rounding, about ``u |q|`` (``u = 2^-53``). Positions and
velocities then carry a relative error of about ``cond(W) u``, as any solve with ``W`` does; but
the terms built from the time derivatives of the maps -- ``dP/dt`` (eq. 11 differentiated), the
Coriolis terms ``C`` of model (32) and everything that uses them (forward and inverse dynamics, the
joint accelerations, the loop forces, the controller) -- differentiate through ``W`` a second time
and carry about ``cond(W)^2 u``. On the four-bar's flat configurations ``q = [t, -t, t - pi,
pi - t]`` the error of ``dV_m`` measured against the 50-digit value on the manifold grows like
``cond(W)^2`` (``benchmarks/dead_point.md``).

So those functions refuse a state where ``cond(W) > MAX_LOOP_CONDITION``: above ``u^-1/2`` the
bound ``cond(W)^2 u`` passes 1 and the result could have no correct digit. Functions of positions
alone, or linear in the velocities without their derivatives (``M``, ``G``, the joint rates), keep
the general limit of the solves (``cond <= 1e12``: they lose ``cond u``).
"""
from __future__ import annotations

import numpy as np

from .errors import SingularConfigurationError

#: largest condition estimate of ``W = [T_u1, T_a1]`` (eq. 9) for outputs built from the maps' time
#: derivatives: ``1e8 ~ u^-1/2`` with ``u = 2^-53``
MAX_LOOP_CONDITION = 1e8
#: how solves with ``W`` are named (:func:`symgen.steps.constraints.constraint_blocks`)
LOOP_MATRIX = "[T_u1, T_a1]"


def check_loop_condition(w: np.ndarray) -> None:
    """Raise :class:`SingularConfigurationError` when ``cond(W)`` (2-norm, float) exceeds
    :data:`MAX_LOOP_CONDITION`; nothing for a scene without loops. (The dense evaluator skips the
    check in a float field made with ``max_condition=inf``, which never refuses a solve.)"""
    if w.size == 0:
        return
    cond = float(np.linalg.cond(np.asarray(w, dtype=float)))
    if not cond <= MAX_LOOP_CONDITION:
        raise SingularConfigurationError(
            f"{LOOP_MATRIX} (eq. 9)", cond,
            f"the loop is within the rounding of a dead point: above {MAX_LOOP_CONDITION:g} the velocity "
            "terms (dP/dt, C of model 32) could have no correct digit; move away from it or evaluate in the "
            "'mp' field at exactly closed positions")
