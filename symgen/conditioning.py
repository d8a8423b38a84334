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

The same holds for ``A = [J_m; J_f]`` of eq. (18) in a scene with constraints: ``B = T_S A^-1``
and ``dB/dt`` differentiate through ``A``, and a rounded input is off the manifold too. On two
arms holding one object, with arm 1's wrist approaching its singularity, ``W`` stays near 7 while
``cond(A)`` grows like ``1/t`` and the error of ``dV_m`` like ``cond(A)^2 u``
(``benchmarks/dead_point.md``). So the limit holds ``max(cond W, cond A)`` there; in a scene
without constraints the input is exact and ``A`` keeps the general limit (an outstretched open arm
is answered to ``cond A = 1e12``).

The generated code estimates a condition number by the ratio of its LU pivots, which runs below the
2-norm condition number -- by up to 12.1 times on the built-ins' dead-point sweeps (the Stewart
platform; ``benchmarks/dead_point.md``). It holds its estimate to :data:`MAX_LOOP_ESTIMATE`, so
that what it answers is within ``cond^2 u < 1`` of the 50-digit value on the manifold.
"""
from __future__ import annotations

import numpy as np

from .errors import SingularConfigurationError

#: largest condition estimate of ``W = [T_u1, T_a1]`` (eq. 9) for outputs built from the maps' time
#: derivatives: ``1e8 ~ u^-1/2`` with ``u = 2^-53``
MAX_LOOP_CONDITION = 1e8
#: how much the generated code's pivot-ratio estimate may run below the 2-norm condition number
#: (measured at most 12.1 on the built-ins' dead-point sweeps, ``benchmarks/dead_point.md``)
LOOP_ESTIMATE_MARGIN = 100
#: the limit of the generated code's condition estimate for the solves held to the loop limit
MAX_LOOP_ESTIMATE = MAX_LOOP_CONDITION / LOOP_ESTIMATE_MARGIN
#: how solves with ``W`` are named (:func:`symgen.steps.constraints.constraint_blocks`)
LOOP_MATRIX = "[T_u1, T_a1]"
#: how solves with ``A = [J_m; J_f]`` or its blocks are named (eq. 18; :mod:`symgen.codegen.arms`)
TASK_MATRIX = "[J_m; J_f]"


def loop_limited(what: str, constrained: bool) -> bool:
    """Whether a solve named ``what`` in a function built from the maps' time derivatives is held
    to the loop limit: a solve with ``W``, or, in a scene with constraints, with ``A`` or one of its
    blocks (an arm's tool Jacobian, the object block: every name citing eq. 18)."""
    return what.startswith(LOOP_MATRIX) or (constrained and (TASK_MATRIX in what or "eq. 18" in what))


def check_loop_condition(w: np.ndarray, a: np.ndarray | None = None) -> None:
    """Raise :class:`SingularConfigurationError` when ``cond(W)`` -- or ``cond(A)``, when ``a`` is
    given (a scene with constraints) -- exceeds :data:`MAX_LOOP_CONDITION` (2-norm, float). (The
    dense evaluator skips the check in a float field made with ``max_condition=inf``, which never
    refuses a solve.)"""
    for matrix, name in ((w, f"{LOOP_MATRIX} (eq. 9)"), (a, f"{TASK_MATRIX} (eq. 18)")):
        if matrix is None or matrix.size == 0:
            continue
        cond = float(np.linalg.cond(np.asarray(matrix, dtype=float)))
        if not cond <= MAX_LOOP_CONDITION:
            where = ("the loop is within the rounding of a dead point" if matrix is w else
                     "the closed chain is within the rounding of a singular [J_m; J_f]")
            raise SingularConfigurationError(
                name, cond,
                f"{where}: above {MAX_LOOP_CONDITION:g} the velocity terms (dP/dt, C of model 32) could have "
                "no correct digit; move away from it or evaluate in the 'mp' field at exactly closed positions")
