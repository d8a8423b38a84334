"""Loop-closure rows for the traced routes that read only the null space of ``T`` (eq. 6): the
rates and accelerations of every joint (eqs. 10-11) and the projection ``P^T`` of the joint
forces -- what ``inverse_dynamics`` and its derivatives are made of.

Those routes are unchanged when a constraint's rows are multiplied by any invertible matrix
``S_k``: ``S T qd_all = 0`` has the solutions of ``T qd_all = 0``, ``S T qdd_all = -S dT/dt
qd_all`` the solutions of eq. (11) differentiated, and ``P^T = [1, -(W^-1 T_a2)^T]`` on the
independent columns is the same for ``S W`` and ``S T_a2``. A weld (all six components of
``X_A - ^B U_A^T X_B``, A's axes) is written here with ``S_k = diag(R_W_A, 1)``: its linear rows
are those of the world-aligned Jacobians of the two frames at A's origin, ``J_A - J_B(o_A)``,
whose columns are a joint's axis and its moment arm
(:func:`symgen.frame_kinematics.frame_jacobian_world`); its angular rows stay in A's axes, where a
spherical joint at A has the columns ``R_W_A^T R_W_A``, the identity to rounding, as in the
model's rows: the straight-line elimination's static order then stays sound far from ``q0`` (with
the angular rows in world axes too, the Stewart platform's forward dynamics refused a state at
1e-3 from its dead point, where the model's rows answer). That avoids carrying every column of B's branch into A's axes through ``^B U_A``
(the 6 x 6 transport of eq. 6): on the Stewart platform each of five legs would carry the six
columns of the first. The other constraints keep their rows of
:func:`symgen.kinematics.constraint_matrix`.

The drift of the weld rows, ``S_k dT/dt qd_all``, is the two bodies' drifts
(:func:`symgen.dynamics.twists.body_drifts`) moved to ``o_A`` in world axes, the angular part
turned into A's axes; the term ``(^A X_B) x X_A`` of
:func:`symgen.dynamics.twists.constraint_drift` vanishes because the rates are the completed
``qd_all`` of eq. (10), which keep the weld (``X_A = ^B U_A^T X_B``).
Functions that read ``T`` itself (the operational ``J_f = T P`` of eq. 12, the loop forces) keep
the rows of the model.
"""
from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any

from ..dynamics.algebra import Vector, add, cross, rotate, rotate_t, sub
from ..dynamics.twists import constraint_drift
from ..frame_kinematics import frame_jacobian_world
from ..kinematics import TreeKinematics
from ..kinematics import constraint_matrix as model_rows
from ..math.jet import Jet, vstack
from ..math.spatial import COMPONENTS
from ..tree import WORLD_INDEX


def is_weld(con) -> bool:
    """A frame constraint on all six components of the relative twist."""
    return not con.is_coupling and set(con.components) == set(COMPONENTS)


def loop_rows(kin: TreeKinematics, constraints: Iterable) -> Jet:
    """``S T`` (module docstring): each weld's six rows as ``J_A - J_B(o_A)``, linear rows in world
    axes, angular rows in A's (components in the order ``vx vy vz wx wy wz``), the other
    constraints' rows as the model's."""
    rows = []
    for con in constraints:
        if not is_weld(con):
            rows.append(model_rows(kin, [con]))
            continue
        r_a, o_a = kin.frame_pose(con.frame_a)
        j_a = frame_jacobian_world(kin, con.frame_a)
        j_b = frame_jacobian_world(kin, con.frame_b, point=o_a)
        angular = r_a.T @ j_a[3:]
        _own_columns(kin, con.frame_a, angular)
        rows += [(j_a - j_b)[:3], angular - r_a.T @ j_b[3:]]
    return vstack(rows, kin.tree.n_coords, kin.field)


def _own_columns(kin: TreeKinematics, frame: str, angular: Jet) -> None:
    """In ``angular`` (A's angular rows in A's axes), the columns of the joint that carries A's
    body: ``R_W_A^T R_W_c Z_w = r_f^T Z_w`` with ``r_f`` A's constant placement on the body, written
    as the constants they are (a spherical joint's identity) instead of a product of rotations."""
    body = kin.tree.frames[frame].body
    if body == WORLD_INDEX:
        return
    k = next(i for i, joint in enumerate(kin.tree.joints) if joint.child == body)
    joint, r_f = kin.tree.joints[k], kin.const.frame[frame][0]
    subspace = kin.motion_subspace[k]
    for col, coord in enumerate(joint.coords):
        angular.v[:, coord] = r_f.T @ subspace[3:, col]


def _at(kin: TreeKinematics, body: int, vector: Vector, point: Sequence[Any]) -> Vector:
    """A motion vector ``[v; w]`` of ``body`` (its axes, its origin) in world axes at ``point``."""
    if body == WORLD_INDEX:
        return (0,) * 6
    r, origin = kin.rot[body].v, kin.pos[body].v
    w = rotate(r, vector[3:])
    return add(rotate(r, vector[:3]), cross(w, sub(point, origin))) + w


def loop_drift(kin: TreeKinematics, constraints: Iterable, twists: Sequence[Vector],
               drifts: Sequence[Vector]) -> list[Any]:
    """``S dT/dt qd_all`` for the rows of :func:`loop_rows`, from the body twists and drifts of
    rates ``qd_all`` that keep the welds (module docstring)."""
    out: list[Any] = []
    for con in constraints:
        if not is_weld(con):
            out.extend(constraint_drift(kin, [con], twists, drifts))
            continue
        r_a, o_a = (x.v for x in kin.frame_pose(con.frame_a))
        body_a, body_b = kin.tree.frames[con.frame_a].body, kin.tree.frames[con.frame_b].body
        rel = sub(_at(kin, body_a, drifts[body_a] if body_a != WORLD_INDEX else (), o_a),
                  _at(kin, body_b, drifts[body_b] if body_b != WORLD_INDEX else (), o_a))
        out.extend(rel[:3] + rotate_t(r_a.tolist(), rel[3:]))
    return out
