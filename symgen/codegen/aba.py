"""The articulated-body route of the code generator: forward dynamics of model (32) for a tree by
:func:`symgen.dynamics.aba.articulated_body` on traced scalars (``O(N)`` operations where the dense
route forms ``M_q`` and factors it), with the task map, joint friction and contact wrench around it.
"""
from __future__ import annotations

from ..dynamics.aba import SingularArticulatedInertia, articulated_body
from ..dynamics.algebra import dot, force_to_parent
from ..math.spatial import COMPONENTS
from ..tree import WORLD_INDEX

__all__ = ["SingularArticulatedInertia", "applies", "motion_coordinates", "contact_wrenches", "tree_forward"]


def applies(model) -> bool:
    """The recursion replaces the dense route for a tree (``n_c = 0``) whose every coordinate is
    independent (``P`` a permutation, eq. 10) and whose task rows are all motion rows (``n = m``)."""
    c = model.counts
    return c.nc == 0 and c.n == c.m == model.tree.n_coords == len(set(model.partition.independent))


def motion_coordinates(model):
    """With motion given on joints, the tree coordinate of each entry of ``V_m`` (``J_m`` is then a
    constant selection, eq. 17, and ``V_m``, ``dV_m`` are rates and accelerations of those
    coordinates); ``None`` for motion on frames (alone or mixed with joint rates)."""
    motion = model.scene.motion
    if not motion.on_joints:
        return None
    return [model.tree.coordinate_index(label) for label in motion.joints]


def contact_wrenches(tracer, eta_m) -> dict:
    """``D_m^T eta_m`` (eq. 16) as a wrench on the contact frame's body: ``S^T eta_m`` in the frame's
    axes at its origin, moved to the body's origin (``J_F^T W = J_b^T (^b U_F W)``)."""
    cf = tracer.model.scene.contact_forces
    frames = tracer.force_frames          # the recursion's body origins (the frame re-expressed there)
    frame = frames.tree.frames[cf.frame]
    if frame.body == WORLD_INDEX:
        return {}
    wrench = [0] * 6
    for name, value in zip(cf.components, eta_m):
        wrench[COMPONENTS.index(name)] = value
    r_f, p_f = frames.consts.frame[cf.frame]
    return {frame.body: force_to_parent(r_f.tolist(), tuple(p_f), tuple(wrench))}


def tree_forward(tracer, v_m, tau, eta_m, *, task_rates, gravity: bool, friction: bool, springs: bool = False):
    """``(dV_m, qd_all, qdd_all)`` of model (32) for a tree: ``qd_all`` from ``V_m`` (directly for
    motion on joints, else ``task_rates(V_m) -> (A, qd_all)``, a solve with ``A = J_m``); the joint
    forces ``tau`` (independent order) less the joint friction ``xi`` (eqs. 22-23) and the joint
    springs (if ``springs``), with the contact
    wrench of ``eta_m`` (or ``None``), drive the recursion; ``dV_m = J_m qdd + dJ_m/dt qd`` (eq. 17)."""
    t = tracer
    tree, independent = t.tree, t.part.independent
    coords = motion_coordinates(t.model)
    if coords is not None:
        task, qd_all = None, [0] * tree.n_coords
        for coord, value in zip(coords, v_m):
            qd_all[coord] = value
    else:
        task, qd_all = task_rates(v_m)
    tau_all = t.applied_forces(tau, qd_all, friction=friction, springs=springs)
    wrenches = contact_wrenches(t, eta_m) if eta_m is not None else None
    qdd_all = articulated_body(*t.force_frames, qd_all, tau_all, gravity=gravity, wrenches=wrenches, graph=t.g)
    if task is None:
        return [qdd_all[c] for c in coords], qd_all, qdd_all
    qdd = [qdd_all[c] for c in independent]
    bias, _ = t.rate_bias(qd_all, kinematics=False)
    rows = t.task_bias_of_rates(qd_all, bias)
    return [dot(task[i], qdd) + rows[i] for i in range(t.m)], qd_all, qdd_all
