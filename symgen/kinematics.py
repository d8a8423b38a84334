"""Tree kinematics at one configuration, with time derivatives (jets).

For the spanning tree of :mod:`symgen.tree` this computes, in any field:

* each body's world pose ``(R_W_b, p_W_b)`` and the force transform ``^P U_C`` across each joint;
* each body's velocity Jacobian ``J_b`` (6 x N_all) from the outward recursion
  ``J_C = ^P U_C^T J_P + Z_j E_j`` -- the rows of ``T_S*`` in Section 3.2;
* frame Jacobians and the constraint matrix ``T = [T_a, T_u]`` of eq. (6).

With joint rates ``qd_all`` supplied, every quantity is a :class:`~symgen.math.jet.Jet` carrying its
exact time derivative along that motion (DESIGN.md section 5); without, derivatives are zero.
"""
from __future__ import annotations

import weakref
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from .math.jet import Jet, vstack
from .math.scalar import FieldVector, Scalar
from .math.spatial import COMPONENTS, force_transform
from .math.configuration import Configuration
from .tree import WORLD_INDEX, Tree

if TYPE_CHECKING:
    from .math.fields import Field
    from .scene.elements import Constraint


class ConstantCache:
    """Scene constants of a tree converted once per field.

    Its ``field`` (a :class:`~symgen.math.fields.Field`) and the constants are left unannotated:
    typed, they would show that :mod:`symgen.dynamics` hands these NumPy arrays to its tuple
    algebra, whose signatures say ``Sequence``, and reads ``field`` from a weak reference that
    may be ``None`` -- to be settled in :mod:`symgen.dynamics` first."""

    def __init__(self, tree: Tree, field):
        self._field = weakref.ref(field)     # the cache of :func:`constants` must not keep it alive
        self.joint_rot = [field.array(j.rotation.tolist()) for j in tree.joints]
        self.joint_trans = [field.array(list(j.translation)) for j in tree.joints]
        self.frame = {name: (field.array(f.rotation.tolist()), field.array(list(f.translation)))
                      for name, f in tree.frames.items()}
        self.mass = [field.const(b.mass) for b in tree.bodies]
        self.com = [field.array(list(b.com)) for b in tree.bodies]
        self.inertia = [field.array(b.inertia.tolist()) for b in tree.bodies]
        self.gravity = field.array(list(tree.gravity))
        self.rotor = [field.const(j.rotor_inertia) for j in tree.joints]
        self.viscous = [field.const(j.viscous) for j in tree.joints]
        self.coulomb = [field.const(j.coulomb) for j in tree.joints]
        self.stiffness = [field.const(j.stiffness) for j in tree.joints]
        self.springref = [field.const(j.springref) for j in tree.joints]

    @property
    def field(self):
        """The field these constants are numbers of."""
        return self._field()


#: per field, the tree its constants were converted for and the :class:`ConstantCache`; weakly
#: keyed so that the cache never writes into a field nor keeps one alive
_CONSTANTS: weakref.WeakKeyDictionary[Field, tuple[Tree, ConstantCache]] = weakref.WeakKeyDictionary()


def constants(tree: Tree, field: Field) -> ConstantCache:
    """The scene constants of ``tree`` in ``field``, converted once per (field, tree)."""
    cached = _CONSTANTS.get(field)
    if cached is None or cached[0] is not tree:
        cached = (tree, ConstantCache(tree, field))
        _CONSTANTS[field] = cached
    return cached[1]


@dataclass
class TreeKinematics:
    """Kinematic quantities of every body at one configuration (all jets)."""

    field: Field
    tree: Tree
    const: ConstantCache
    rot: list[Jet]            # R_W_b
    pos: list[Jet]            # p_W_b
    transform: list[Jet]      # ^P U_C across each tree joint (indexed like tree.joints)
    jacobian: BodyJacobians   # J_b, 6 x N_all, computed on first use
    motion_subspace: list[np.ndarray]  # Z_j as 6 x dof arrays
    positions: dict = field(default_factory=dict)   # the configuration's joint positions (springs)

    def frame_pose(self, name: str) -> tuple[Jet, Jet]:
        f = self.tree.frames[name]
        r_f, p_f = self.const.frame[name]
        if f.body == WORLD_INDEX:
            return Jet.const(r_f, self.field), Jet.const(p_f, self.field)
        r_b, p_b = self.rot[f.body], self.pos[f.body]
        return r_b @ r_f, p_b + r_b @ p_f

    def relative_pose(self, frame_a: str, frame_b: str) -> tuple[Jet, Jet]:
        """``(R_BA, p_BA)``: frame A's pose in frame B's axes, ``^B U_A`` of a frame constraint
        (eq. 6): the rotation ``R_B^T R_A`` and the position ``R_B^T (p_A - p_B)``."""
        r_a, p_a = self.frame_pose(frame_a)
        r_b, p_b = self.frame_pose(frame_b)
        return r_b.T @ r_a, r_b.T @ (p_a - p_b)

    def frame_jacobian(self, name: str) -> Jet:
        """``J_F`` with ``X_F = J_F qd_all`` (twist of the frame in its own axes)."""
        f = self.tree.frames[name]
        n = self.tree.n_coords
        if f.body == WORLD_INDEX:
            return Jet.const(self.field.zeros((6, n)), self.field)
        r_f, p_f = self.const.frame[name]
        u = force_transform(Jet.const(r_f, self.field), Jet.const(p_f, self.field), self.field)
        return u.T @ self.jacobian[f.body]


def tree_kinematics(tree: Tree, field: Field, config: Configuration,
                    qd_all: FieldVector | None = None) -> TreeKinematics:
    """Outward pass over the tree: poses, joint transforms and body Jacobians (with jets)."""
    const = constants(tree, field)
    n = tree.n_coords
    rates = field.zeros((n,)) if qd_all is None else np.asarray(qd_all, dtype=field.dtype)
    rot, pos, transform, subspaces = [None] * len(tree.bodies), [None] * len(tree.bodies), [], []
    for k, joint in enumerate(tree.joints):
        value = joint.kind.position(joint.name, config.positions)
        r_m, p_m = joint.kind.motion(value, rates[list(joint.coords)], field)   # child w.r.t. joint frame
        subspace = joint.kind.motion_subspace(field)                            # Z_j
        r_c = Jet.const(const.joint_rot[k], field)
        p_c = Jet.const(const.joint_trans[k], field)
        r_rel = r_c @ r_m                  # R_P_C
        p_rel = p_c + r_c @ p_m            # p_P_C
        if joint.parent == WORLD_INDEX:
            rot[joint.child], pos[joint.child] = r_rel, p_rel
        else:
            r_p, p_p = rot[joint.parent], pos[joint.parent]
            rot[joint.child], pos[joint.child] = r_p @ r_rel, p_p + r_p @ p_rel
        transform.append(force_transform(r_rel, p_rel, field))    # ^P U_C
        subspaces.append(subspace)
    jac = BodyJacobians(tree, field, transform, subspaces)
    return TreeKinematics(field, tree, const, rot, pos, transform, jac, subspaces, dict(config.positions))


class BodyJacobians:
    """``J_b`` (6 x N_all) per body, indexed like ``tree.bodies``, from the outward recursion
    ``J_C = ^P U_C^T J_P + Z_j E_j`` (rows of ``T_S*``, Section 3.2). Each is computed on first
    use, with its ancestors: a caller that reads no Jacobian (motion given on joints, no
    constraint) pays for none, one that reads the tool's pays for its branch only."""

    def __init__(self, tree: Tree, field: Field, transform: list[Jet], subspaces: list[np.ndarray]) -> None:
        self.tree, self.field = tree, field
        self.transform, self.subspaces = transform, subspaces
        self.joint_of = {joint.child: k for k, joint in enumerate(tree.joints)}
        self._done: dict[int, Jet] = {}

    def __len__(self) -> int:
        return len(self.tree.bodies)

    def __getitem__(self, body: int) -> Jet:
        pending = []
        while body not in self._done and body != WORLD_INDEX:
            pending.append(body)
            body = self.tree.joints[self.joint_of[body]].parent
        for b in reversed(pending):          # root side first
            k = self.joint_of[b]
            joint = self.tree.joints[k]
            e = self.field.zeros((6, self.tree.n_coords))
            for col, c in enumerate(joint.coords):
                e[:, c] = self.subspaces[k][:, col]
            if joint.parent == WORLD_INDEX:
                self._done[b] = Jet.const(e, self.field)
            else:
                self._done[b] = self.transform[k].T @ self._done[joint.parent] + e
        return self._done[pending[0] if pending else body]


def coupling_row(tree: Tree, field: Field, con: Constraint) -> np.ndarray:
    """The one row (1 x N_all) of ``T`` (eq. 6) of a joint coupling ``sum_i c_i q_i = offset``:
    ``c_i`` at each coupled joint's column. It is constant, so its time derivative (the drift term
    of the accelerations, eq. 11) is zero."""
    row = field.zeros((1, tree.n_coords))
    for joint, coefficient in con.terms:
        row[0, tree.coordinate_of(joint)] = field.const(coefficient)
    return row


def coupling_residual(tree: Tree, field: Field, con: Constraint, positions) -> Scalar:
    """The position residual ``offset - sum_i c_i q_i`` of a joint coupling (zero when it holds;
    its time derivative is ``-T qd_all``, like a frame constraint's), in ``field`` from the joint
    positions ``positions`` (joint name -> number)."""
    total = field.const(con.offset)
    for joint, coefficient in con.terms:
        total = total - field.const(coefficient) * positions[joint]
    return total


def constraint_matrix(kin: TreeKinematics, constraints: Iterable[Constraint]) -> Jet:
    """``T`` of eq. (6) over all joint coordinates: for each constraint (frames A, B), the
    selected components of ``X_A - ^B U_A^T X_B`` (relative twist, A's axes)."""
    field, rows = kin.field, []
    for con in constraints:
        if con.is_coupling:
            rows.append(Jet.const(coupling_row(kin.tree, field, con), field))
            continue
        j_a = kin.frame_jacobian(con.frame_a)
        j_b = kin.frame_jacobian(con.frame_b)
        r_ba, p_ba = kin.relative_pose(con.frame_a, con.frame_b)
        u_ba = force_transform(r_ba, p_ba, field)
        rel = j_a - u_ba.T @ j_b
        sel = [COMPONENTS.index(c) for c in con.components]
        rows.append(rel[sel, :])
    return vstack(rows, kin.tree.n_coords, field)
