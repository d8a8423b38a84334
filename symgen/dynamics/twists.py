"""The twist of every body of the tree, by the outward recursion of Section 3.2, in any field, and
its drift: the time derivative of the Jacobian along the motion, applied to the rates.

``X_c = ^P U_C^T X_p + Z_j qd_j`` per tree joint (the rows of ``T_S*``): each body's ``[v; w]``,
velocity of its frame's origin and angular velocity, in its own axes. The articulated-body pass
(:mod:`symgen.dynamics.aba`) runs the same two steps, :func:`~symgen.dynamics.algebra.motion_to_child`
and :func:`~symgen.dynamics.algebra.joint_twist`; this is the pass alone, for the consumers that
need velocities only (the centroidal momentum of :mod:`symgen.frame_kinematics`).

Differentiating ``J_c = ^P U_C^T J_p + Z_j E_j`` along the rates gives the *drift*
``beta_c = dJ_c/dt qd_all`` (the body's ``dX_c/dt`` at ``qdd_all = 0``, its own axes)::

    beta_c = ^P U_C^T beta_p + X_c x (Z_j qd_j)

since ``d(^P U_C^T)/dt X_p = (X_c - Z_j qd_j) x X_c`` (``x``: the cross product of twists). It
is what the velocity-product terms of eq. (11) need of the tree, as vectors: the jets of
:mod:`symgen.kinematics` carry the derivative of every Jacobian column instead.
"""
from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Any

from ..kinematics import TreeKinematics
from ..math.spatial import COMPONENTS
from ..tree import WORLD_INDEX, Tree
from .algebra import Transform, Vector, add, cross_motion, joint_twist, motion_to_child, sub

if TYPE_CHECKING:
    from ..scene.elements import Constraint, Motion


def body_twists(tree: Tree, transforms: Sequence[Transform], qd_all: Sequence[Any]) -> list[Vector]:
    """``[v; w]`` of every body (indexed like ``tree.bodies``) in its own axes, for the rates
    ``qd_all`` of every tree coordinate; ``transforms[k]`` is ``(R_PC, p_PC)`` of tree joint ``k``.
    ``O(N)``."""
    zero6: Vector = (0,) * 6
    out: list[Vector] = [zero6] * len(tree.bodies)
    for k, joint in enumerate(tree.joints):
        r, p = transforms[k]
        parent = zero6 if joint.parent == WORLD_INDEX else motion_to_child(r, p, out[joint.parent])
        out[joint.child] = add(parent, joint_twist(joint, qd_all))
    return out


def body_drifts(tree: Tree, transforms: Sequence[Transform], qd_all: Sequence[Any],
                twists: Sequence[Vector], qdd_all: Sequence[Any] | None = None) -> list[Vector]:
    """``beta_b = dJ_b/dt qd_all`` of every body (module docstring), in its own axes, from the
    twists ``twists`` of :func:`body_twists` for the same rates. ``O(N)``; zero at the root
    bodies (the world does not move). With the accelerations ``qdd_all`` of every coordinate,
    the bodies' accelerations ``dX_b/dt = J_b qdd_all + beta_b`` instead (each joint adds
    ``Z_j qdd_j`` as well)."""
    zero6: Vector = (0,) * 6
    out: list[Vector] = [zero6] * len(tree.bodies)
    for k, joint in enumerate(tree.joints):
        r, p = transforms[k]
        parent = zero6 if joint.parent == WORLD_INDEX else motion_to_child(r, p, out[joint.parent])
        out[joint.child] = add(parent, cross_motion(twists[joint.child], joint_twist(joint, qd_all)))
        if qdd_all is not None:
            out[joint.child] = add(out[joint.child], joint_twist(joint, qdd_all))
    return out


def _frame_motion(kin: TreeKinematics, name: str, twists: Sequence[Vector],
                  drifts: Sequence[Vector]) -> tuple[Vector, Vector]:
    """Twist and drift of frame ``name`` in its own axes: its body's, moved by the constant
    ``^B U_F^T`` of the frame's placement (both zero for a frame on the world)."""
    frame = kin.tree.frames[name]
    if frame.body == WORLD_INDEX:
        return (0,) * 6, (0,) * 6
    r_f, p_f = kin.const.frame[name]
    r, p = r_f.tolist(), tuple(p_f)
    return motion_to_child(r, p, twists[frame.body]), motion_to_child(r, p, drifts[frame.body])


def constraint_drift(kin: TreeKinematics, constraints: Iterable[Constraint], twists: Sequence[Vector],
                     drifts: Sequence[Vector]) -> list[Any]:
    """``dT/dt qd_all``, one entry per row of ``T`` (eq. 6, rows as
    :func:`symgen.kinematics.constraint_matrix` stacks them), from the body twists and drifts
    for ``qd_all`` and the poses of ``kin`` (no time derivatives needed). A frame constraint's
    rows are the components of ``X_A - ^A X_B`` with ``^A X_B = ^B U_A^T X_B``; differentiated,

        beta_A - ^B U_A^T beta_B - (^A X_B) x X_A,

    as ``d(^B U_A^T)/dt X_B = (^A X_B) x X_A`` (the relative twist of the two frames is
    ``X_B - ^B U_A X_A`` in B's axes). A joint coupling's row is constant: zero."""
    out: list[Any] = []
    for con in constraints:
        if con.is_coupling:
            out.append(0)
            continue
        x_a, beta_a = _frame_motion(kin, con.frame_a, twists, drifts)
        x_b, beta_b = _frame_motion(kin, con.frame_b, twists, drifts)
        rotation, position = kin.relative_pose(con.frame_a, con.frame_b)
        r_ba, p_ba = rotation.v.tolist(), tuple(position.v)
        x_b_in_a = motion_to_child(r_ba, p_ba, x_b)
        rel = sub(sub(beta_a, motion_to_child(r_ba, p_ba, beta_b)), cross_motion(x_b_in_a, x_a))
        out.extend(rel[COMPONENTS.index(c)] for c in con.components)
    return out


def motion_drift(kin: TreeKinematics, motion: Motion, twists: Sequence[Vector], drifts: Sequence[Vector]) -> list[Any]:
    """``dJ_m_all/dt qd_all``: the rows of :func:`symgen.steps.motion_rows` (eq. 17 over every
    joint coordinate) differentiated along the rates of ``twists`` and ``drifts`` -- each frame's
    drift in its own axes (the body's, moved by the frame's constant placement), weighted by its
    ``gamma`` and summed (Section 3.3), then zeros for the constant rows of the motion joints."""
    out: list[Any] = []
    if motion.frames:
        total: list[Any] | None = None
        for frame, gamma in motion.frames:
            _, beta = _frame_motion(kin, frame, twists, drifts)
            weight = kin.field.const(gamma)
            term = [beta[COMPONENTS.index(c)] * weight for c in motion.components]
            total = term if total is None else [a + b for a, b in zip(total, term)]
        out.extend(total or [])
    out.extend([0] * len(motion.joints))
    return out
