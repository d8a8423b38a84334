"""Forward dynamics (32) by the null space of the loop closures, when ``V_m`` are joint rates.

Model (32) is solved in the joint space of eq. (10), whose independent coordinates Step 5 picks
among the actuated joints (``q_a``, ``q_u2``). When the motion coordinates are themselves rates of
tree coordinates -- a robot standing on its feet, ``V_m`` its floating base's twist -- and the
remaining ``n_c`` coordinates ``q_d`` are exactly as many as the constraint rows, the motion
coordinates can serve as the independent set instead. Eq. (6) over all coordinates,
``T_m V_m + T_d qd_d = 0``, then gives every rate from ``V_m``::

    qd_all = W V_m,    W = [1; X],    X = -T_d^-1 T_m          (eq. 10 with V_m independent)

and, differentiated, ``qdd_all = W dV_m + qdd_0`` with ``qdd_0 = [0; -T_d^-1 dT/dt qd_all]``.
Projecting ``M qdd_all + h = tau_all + T^T lam`` (:mod:`symgen.steps.loop_forces`) on ``W``
(``T W = 0``) leaves the motion block of (32)::

    M_mm dV_m = W^T (tau_all - tau_0),   M_mm = W^T M_tree W,   tau_0 = RNEA(qd_all, qdd_0)

(``tau_0`` with gravity, friction and springs, one recursion), and the rows ``q_d`` give the loop
forces, ``T_d^T lam = (M_tree W dV_m)_d - (tau_all - tau_0)_d``; then ``eta_f = -T_c^-T T_a1^T lam``
(eq. 12; ``-lam`` for ``constraint_forces: operational``). ``T_d`` is block diagonal when each
contact closes through its own leg (3 x 3 per point foot, 6 x 6 per sole): the straight-line
elimination of :mod:`symgen.codegen.sparse_lu` solves leg by leg, and the products with ``W`` and
``M_tree`` (no entries between two legs) skip their structural zeros. Neither ``[J_m; J_f]`` nor
``M_q = P^T M_tree P`` is formed. The route is offered to the chooser of
:func:`symgen.codegen.functions._choose`, which keeps it where it costs fewer operations.
"""
from __future__ import annotations

import numpy as np

from .. import steps
from ..dynamics.rnea import rnea
from ..math.jet import matmul as product
from .aba import motion_coordinates
from .builder import MOTION_BLOCK, projected_mass
from .trace import has_gravity

#: what a failed solve with ``T_d`` names (the run-time pivot check of a singular leg)
DEPENDENT_BLOCK = "T_d, the constraint rows on the coordinates outside V_m (eq. 6)"


def dependent_coordinates(model) -> list[int] | None:
    """The tree coordinates outside ``V_m``, or ``None`` where the route does not apply: motion
    not given on joints, no constraints, or not exactly ``n_c`` coordinates left for them."""
    coords = motion_coordinates(model)
    if coords is None or not model.counts.nc or len(set(coords)) != len(coords):
        return None
    chosen = set(coords)
    rest = [c for c in range(model.tree.n_coords) if c not in chosen]
    return rest if len(rest) == model.counts.nc else None


def applies(model) -> bool:
    return dependent_coordinates(model) is not None


def forward(b, v_m, tau, eta_m, *, friction: bool, springs: bool):
    """``(dV_m, eta_f, qd_all, qdd_all)`` of model (32) by the null-space route (module docstring),
    on the builder ``b`` (its tracer ``b.t`` and graph ``b.g``)."""
    t, g, m, n = b.t, b.g, b.m, b.n
    model = b.model
    coords, dep = motion_coordinates(model), dependent_coordinates(model)
    n_all = t.tree.n_coords
    rows = t.closure.T.v                                   # eq. (6) over all coordinates, n_c x N
    t_m, t_d = rows[:, coords], rows[:, dep]
    x = -np.asarray(g.solve(t_d, t_m, DEPENDENT_BLOCK), dtype=object).reshape(len(dep), m)
    w = np.empty((n_all, m), dtype=object)
    for i, c in enumerate(coords):
        w[c] = [g.const(int(i == k)) for k in range(m)]
    w[dep] = x
    qd_all = list(product(w, np.array(list(v_m), dtype=object)))
    drift = np.array(t.constraint_drift(qd_all), dtype=object)
    qdd_0 = [0] * n_all
    for c, value in zip(dep, -np.asarray(g.solve(t_d, drift, DEPENDENT_BLOCK), dtype=object)):
        qdd_0[c] = value
    tau_0 = rnea(*t.force_frames, qd_all, qdd_0, gravity=has_gravity(model), graph=g, inertias=t.joint_force_inertias)
    applied = t.applied_forces(tau, qd_all, friction=friction, springs=springs)
    if eta_m is not None:
        d_m = steps.contact_rows(t.field, t.kinematics(), model.scene.contact_forces).v
        applied = [a - y for a, y in zip(applied, d_m.T @ np.array(list(eta_m), dtype=object))]
    f = np.array([a - y for a, y in zip(applied, tau_0)], dtype=object)   # tau_all - tau_0, per coordinate
    mw = product(b.tree_mass_matrix(), w)
    dv = list(g.solve_spd(projected_mass(w, mw), product(w.T, f), MOTION_BLOCK))
    dv_arr = np.array(dv, dtype=object)
    qdd_all = [q + y for q, y in zip(product(w, dv_arr), qdd_0)]
    eta_f = []
    if n > m:
        residual = product(mw[dep], dv_arr) - f[dep]
        lam = np.asarray(g.solve(t_d.T, residual, DEPENDENT_BLOCK), dtype=object)
        if model.scene.constraint_forces == "operational":
            eta_f = list(-lam)
        else:                                             # T_c = 1 (eq. 12): -T_a1^T lam
            eta_f = list(-product(rows[:, list(model.partition.a1)].T, lam))
    return dv, eta_f, qd_all, qdd_all
