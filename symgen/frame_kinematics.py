"""What a whole-body controller or an MPC asks of a model besides its dynamics: the pose, Jacobian
and drift ``J̇ q̇`` of a named frame, the centre of mass and its Jacobian, and the centroidal
momentum -- in any field (float, exact, mp, symbolic, and the code generator's traced nodes).

Conventions (the paper's, DESIGN.md section 2, and Pinocchio's names for the same things):

* a twist is ``[v; w]``: the velocity of the frame's origin, then the angular velocity;
* ``axes="world_aligned"``: in the world's axes (Pinocchio's ``LOCAL_WORLD_ALIGNED``): still the
  velocity of the frame's origin, not of the point of the body at the world's origin;
  ``axes="local"``: in the frame's own axes (Pinocchio's ``LOCAL``), ``diag(R_W_F^T, R_W_F^T)``
  times the world-aligned one, the frame's ``X_F`` of Section 3.2;
* the Jacobians are over the independent rates ``qd`` of eq. (14) (``Model.coordinate_names()``):
  ``J = J_all P`` with ``P`` of eq. (10), so on a closed chain ``J qd`` is the frame's twist when the
  dependent joints follow their loops; on a tree ``P = 1``;
* the drift is the frame's acceleration at ``qdd = 0`` as a *classical* acceleration: the
  acceleration of the frame's origin and the angular acceleration, ``d/dt(J_all) qd_all + J_all
  dP/dt qd`` (eq. 11 differentiated) for the world-aligned ``J_all`` (the time derivative of
  ``[dp_F/dt; w]``), rotated into the frame's axes for ``local``. It is Pinocchio's
  ``getFrameClassicalAcceleration`` at ``ddq = 0`` in ``LOCAL`` or ``LOCAL_WORLD_ALIGNED``; the
  frame's acceleration for joint accelerations ``qdd`` is ``J qdd + drift``;
* the centre of mass ``c = sum m_b c_b / sum m_b`` and its Jacobian ``J_c`` (``dc/dt = J_c qd``)
  are in world axes; the centroidal momentum ``h = [sum m_b v_b; sum (c_b - c) x m_b v_b + R_b I_b
  w_b]`` (``v_b`` the velocity of body ``b``'s centre of mass, ``I_b`` its inertia about it) is in
  world axes at the centre of mass: Pinocchio's ``computeCentroidalMomentum``. Rotor inertias
  (``I*`` of eq. 22) carry no momentum here, as in Pinocchio.

The field-generic functions take a :class:`~symgen.kinematics.TreeKinematics` (the world poses of
every body, with time derivatives where the drift needs them) and the joint transforms of
:mod:`symgen.dynamics.transforms`; the code generator runs the same functions on traced nodes
(:mod:`symgen.codegen.frame_functions`). The ``model_*`` functions are the
:class:`~symgen.model.Model` methods of the same names.
"""
from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np
import sympy as sp

from .dynamics.algebra import Transform, Vector, add, cross, rotate, scale, sub, subspace_columns
from .dynamics.transforms import configuration_transforms
from .dynamics.twists import body_twists
from .errors import StateError
from .kinematics import ConstantCache, TreeKinematics, constants, tree_kinematics
from .tree import WORLD_INDEX
from .math.configuration import as_configuration
from .math.jet import Jet, matmul
from .model_solves import check_length, field_vector, finite_result
from .steps import all_rates, constraint_blocks, constraint_matrix, rate_bias
from .steps.pipeline import DerivedModel, joint_rate_maps
from .steps.task_space import acceleration_bias

if TYPE_CHECKING:
    from .math.configuration import Configuration, ConfigurationLike
    from .math.fields import Field
    from .steps.structure import Counts
    from .tree import Tree


class Model(DerivedModel, Protocol):
    """What the ``model_*`` functions read of a :class:`symgen.model.Model` (which imports this
    module, so it is named by what is used): the steps' scene, tree and partition, the counts,
    fields by name and the closed-configuration check."""

    @property
    def counts(self) -> Counts: ...

    def field_of(self, field: str | Field) -> Field: ...

    def _closed(self, config: ConfigurationLike, field: str | Field, check: bool) -> Configuration: ...

#: the axes a frame's Jacobian and drift can be expressed in (Pinocchio's LOCAL, LOCAL_WORLD_ALIGNED)
AXES = ("local", "world_aligned")


# ------------------------------------------------------------------ checks
def check_frame(tree: Tree, name: str, error: type[Exception] = StateError) -> None:
    """``name`` is a frame of the scene, else ``error`` naming it and listing the frames."""
    if name not in tree.frames:
        known = ", ".join(sorted(tree.frames)) or "none"
        raise error(f"no frame {name!r} in the scene; its frames: {known}")


def check_axes(axes: str, error: type[Exception] = StateError) -> None:
    if axes not in AXES:
        raise error(f"axes must be one of {', '.join(AXES)}, got {axes!r}")


def total_mass(tree: Tree) -> sp.Expr:
    """``sum m_b``, or :class:`StateError` when the scene has no mass (no centre of mass)."""
    total = sp.Add(*[b.mass for b in tree.bodies if not b.massless])
    if total == 0:
        raise StateError("the scene has no mass: its centre of mass and centroidal momentum are undefined")
    return total


# ------------------------------------------------------------------ field-generic
def _path(tree: Tree, body: int) -> list[int]:
    """The tree joints from the root to ``body``, root first."""
    joint_of = {joint.child: k for k, joint in enumerate(tree.joints)}
    out: list[int] = []
    while body != WORLD_INDEX:
        out.append(joint_of[body])
        body = tree.joints[out[-1]].parent
    return out[::-1]


def _cross_jet(a: Jet, b: Jet) -> Jet:
    """``a x b`` of two 3-vector jets (``d(a x b) = da x b + a x db``)."""
    return Jet(np.array(cross(a.v, b.v), dtype=object),
               np.array(add(cross(a.d, b.v), cross(a.v, b.d)), dtype=object))


def frame_jacobian_world(kin: TreeKinematics, name: str, point: Jet | None = None) -> Jet:
    """``J`` (``6 x N_all``) of frame ``name`` in world-aligned axes at its origin (or at the world
    point ``point``, a 3-vector jet, moving with the frame's body), with its time
    derivative: column by column from the world poses of :func:`~symgen.kinematics.tree_kinematics`.
    A joint's motion ``Z_j`` selects one axis ``e`` of its child ``c`` per coordinate
    (:func:`~symgen.dynamics.algebra.subspace_columns`): about it, ``[w x (p_F - p_c); w]`` with
    ``w = R_W_c e``; along it, ``[R_W_c e; 0]``. Columns of joints off the frame's branch are zero.
    ``O(N)``, where the body Jacobians of :class:`~symgen.kinematics.BodyJacobians` (the rows of
    ``T_S*``) form every ancestor's ``6 x N_all`` block."""
    field, tree = kin.field, kin.tree
    value, rate = field.zeros((6, tree.n_coords)), field.zeros((6, tree.n_coords))
    body = tree.frames[name].body
    if body == WORLD_INDEX:
        return Jet(value, rate)
    p_f = kin.frame_pose(name)[1] if point is None else point
    for k in _path(tree, body):
        joint = tree.joints[k]
        rot = kin.rot[joint.child]
        lever = p_f - kin.pos[joint.child]
        for coord, axis in zip(joint.coords, subspace_columns(joint)):
            e = rot[:, axis % 3]
            rows = [0, 1, 2] if axis < 3 else [3, 4, 5]
            value[rows, coord], rate[rows, coord] = e.v, e.d
            if axis >= 3:
                v = _cross_jet(e, lever)
                value[:3, coord], rate[:3, coord] = v.v, v.d
    return Jet(value, rate)


def local(r: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """``diag(R^T, R^T) rows`` for the 6 rows (or 6-vector) ``rows`` of world-aligned vectors."""
    return np.concatenate([matmul(r.T, rows[:3]), matmul(r.T, rows[3:])])


def frame_jacobian_all(kin: TreeKinematics, name: str, axes: str) -> np.ndarray:
    """``J_F`` over every tree coordinate (``6 x N_all``) in ``axes``."""
    jac = frame_jacobian_world(kin, name).v
    return jac if axes == "world_aligned" else local(kin.frame_pose(name)[0].v, jac)


def frame_drift(kin: TreeKinematics, name: str, qd_all: Sequence[Any], bias: Sequence[Any], axes: str) -> Vector:
    """The frame's classical acceleration ``[a; dw]`` at ``qdd = 0`` (module docstring): in world
    axes, ``d/dt(J qd_all) + J dP/dt qd`` of the world-aligned ``J`` -- the time derivative of
    ``[dp_F/dt; w]``; in local axes, that rotated by ``R_W_F^T``. ``kin`` carries time derivatives
    along ``qd_all``, ``bias = dP/dt qd`` (eq. 11)."""
    out = acceleration_bias(frame_jacobian_world(kin, name), qd_all, bias)
    if axes == "world_aligned":
        return tuple(out)
    return tuple(local(kin.frame_pose(name)[0].v, out))


def _com_world(kin: TreeKinematics, consts: ConstantCache, b: int) -> Vector:
    return add(kin.pos[b].v, rotate(kin.rot[b].v, consts.com[b]))


def center_of_mass(field: Field, kin: TreeKinematics) -> Vector:
    """``c = sum m_b c_b / sum m_b`` in world axes."""
    consts, tree = kin.const, kin.tree
    total: Vector = (0, 0, 0)
    for b, body in enumerate(tree.bodies):
        if not body.massless:
            total = add(total, scale(consts.mass[b], _com_world(kin, consts, b)))
    return scale(field.const(1 / total_mass(tree)), total)


def com_jacobian_all(field: Field, kin: TreeKinematics) -> np.ndarray:
    """``J_c`` over every tree coordinate (``3 x N_all``, world axes), column by column: with
    ``m_j`` and ``s_j`` the mass and first moment ``sum m_b c_b`` of the subtree a joint moves
    (one inward pass), a rotation about the world axis ``w`` moves the centre of mass at
    ``w x (s_j - m_j p_c) / sum m_b``, a translation along ``u`` at ``m_j u / sum m_b``. ``O(N)``."""
    consts, tree = kin.const, kin.tree
    mass: list[Any] = [0] * len(tree.bodies)
    moment: list[Vector] = [(0, 0, 0)] * len(tree.bodies)
    for b, body in enumerate(tree.bodies):
        if not body.massless:
            mass[b], moment[b] = consts.mass[b], scale(consts.mass[b], _com_world(kin, consts, b))
    for joint in reversed(tree.joints):                   # children before parents
        if joint.parent != WORLD_INDEX:
            mass[joint.parent] = mass[joint.parent] + mass[joint.child]
            moment[joint.parent] = add(moment[joint.parent], moment[joint.child])
    inv = field.const(1 / total_mass(tree))
    out = field.zeros((3, tree.n_coords))
    for joint in tree.joints:
        c = joint.child
        rot = kin.rot[c].v
        for coord, axis in zip(joint.coords, subspace_columns(joint)):
            e = tuple(rot[:, axis % 3])
            col = scale(mass[c], e) if axis < 3 else cross(e, sub(moment[c], scale(mass[c], kin.pos[c].v)))
            out[:, coord] = scale(inv, col)
    return out


def centroidal_momentum(field: Field, kin: TreeKinematics, transforms: Sequence[Transform],
                        qd_all: Sequence[Any]) -> Vector:
    """``h = [linear; angular about the centre of mass]`` in world axes (module docstring), from
    the body twists of :func:`~symgen.dynamics.twists.body_twists`. ``O(N)``."""
    consts, tree = kin.const, kin.tree
    twists = body_twists(tree, transforms, qd_all)
    linear: Vector = (0, 0, 0)
    angular: Vector = (0, 0, 0)             # about the world's origin first
    for b, body in enumerate(tree.bodies):
        if body.massless:
            continue
        r, c = kin.rot[b].v, consts.com[b]
        v, w = twists[b][:3], twists[b][3:]
        momentum = scale(consts.mass[b], rotate(r, add(v, cross(w, c))))
        linear = add(linear, momentum)
        spin = rotate(r, rotate(consts.inertia[b], w))
        angular = add(angular, add(cross(_com_world(kin, consts, b), momentum), spin))
    return linear + sub(angular, cross(center_of_mass(field, kin), linear))


# ------------------------------------------------------------------ the Model's methods
class _State:
    """One configuration of ``model`` in a field: its kinematics (with time derivatives along the
    rates when given), ``P`` (eq. 10), ``qd_all`` and ``dP/dt qd``."""

    def __init__(self, model: Model, config: ConfigurationLike, field: str | Field,
                 qd: Sequence[Any] | None = None, check_closure: bool = True) -> None:
        self.model = model
        fld = self.field = model.field_of(field)
        cfg = fld.configuration(model._closed(config, field, check_closure), model.tree)
        rates, _ = joint_rate_maps(model, cfg, fld, with_task=False)
        self.P = rates.P.v
        self.qd_all = None if qd is None else all_rates(rates, field_vector(fld, qd))
        self.kin = tree_kinematics(model.tree, fld, cfg, self.qd_all)
        self.transforms = configuration_transforms(model.tree, constants(model.tree, fld), fld, cfg)

    def bias(self) -> np.ndarray:
        """``dP/dt qd`` (eq. 11 at ``qdd = 0``)."""
        model, fld = self.model, self.field
        part = model.partition
        if not part.u1:
            return fld.zeros((model.tree.n_coords,))
        cm = constraint_matrix(self.kin, model.scene.constraints.values(), part)
        return rate_bias(fld, cm, constraint_blocks(fld, cm, part), part, self.qd_all)


def model_frame_pose(model: Model, config: ConfigurationLike, name: str, *,
                     field: str | Field = "float") -> tuple[np.ndarray, np.ndarray]:
    """``(R_W_F, p_W_F)``: the axes and origin of frame ``name`` in the world."""
    check_frame(model.tree, name)
    fld = model.field_of(field)
    cfg = fld.configuration(as_configuration(config, model.scene, "config"), model.tree)
    r, p = tree_kinematics(model.tree, fld, cfg).frame_pose(name)
    return finite_result("frame_pose", "R", r.v), finite_result("frame_pose", "p", p.v)


def model_frame_jacobian(model: Model, config: ConfigurationLike, name: str, *, axes: str = "local",
                         field: str | Field = "float", check_closure: bool = True) -> np.ndarray:
    """``J`` (``6 x n``) with ``[v; w] = J qd`` of frame ``name`` in ``axes``."""
    check_frame(model.tree, name)
    check_axes(axes)
    s = _State(model, config, field, check_closure=check_closure)
    return finite_result("frame_jacobian", "J", matmul(frame_jacobian_all(s.kin, name, axes), s.P))


def model_frame_drift(model: Model, config: ConfigurationLike, qd: Sequence[Any], name: str, *,
                      axes: str = "local", field: str | Field = "float", check_closure: bool = True) -> np.ndarray:
    """``J̇ qd``: the classical acceleration ``[a; dw]`` of frame ``name`` at ``qdd = 0``, in ``axes``."""
    check_frame(model.tree, name)
    check_axes(axes)
    check_length("qd", qd, model.counts.n)
    s = _State(model, config, field, qd, check_closure)
    out = frame_drift(s.kin, name, s.qd_all, s.bias(), axes)
    return finite_result("frame_drift", "a", np.array(out, dtype=s.field.dtype))


def model_center_of_mass(model: Model, config: ConfigurationLike, *, field: str | Field = "float") -> np.ndarray:
    """The centre of mass in world axes."""
    fld = model.field_of(field)
    cfg = fld.configuration(as_configuration(config, model.scene, "config"), model.tree)
    out = center_of_mass(fld, tree_kinematics(model.tree, fld, cfg))
    return finite_result("center_of_mass", "c", np.array(out, dtype=fld.dtype))


def model_com_jacobian(model: Model, config: ConfigurationLike, *, field: str | Field = "float",
                       check_closure: bool = True) -> np.ndarray:
    """``J_c`` (``3 x n``, world axes) with ``dc/dt = J_c qd``."""
    s = _State(model, config, field, check_closure=check_closure)
    return finite_result("com_jacobian", "J_c", matmul(com_jacobian_all(s.field, s.kin), s.P))


def model_centroidal_momentum(model: Model, config: ConfigurationLike, qd: Sequence[Any], *,
                              field: str | Field = "float", check_closure: bool = True) -> np.ndarray:
    """``h = [linear; angular]`` about the centre of mass, world axes, at rates ``qd`` (eq. 14)."""
    check_length("qd", qd, model.counts.n)
    s = _State(model, config, field, qd, check_closure)
    out = centroidal_momentum(s.field, s.kin, s.transforms, s.qd_all)
    return finite_result("centroidal_momentum", "h", np.array(out, dtype=s.field.dtype))
