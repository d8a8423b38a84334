"""Traced building blocks shared by the generated functions: positions, loop closure (eqs. 10-11),
the task maps ``[J_m; J_f]`` (eqs. 12, 17-18) and their time derivatives, and the projection
``P^T`` of joint forces onto the independent coordinates.

One :class:`Tracer` records one generated function. Every block is computed on first use and
cached, so a function only contains what it needs.
"""
from __future__ import annotations

import weakref
from contextlib import contextmanager
from contextvars import ContextVar
from functools import cached_property
from typing import NamedTuple

import numpy as np

from .. import steps
from ..dynamics.algebra import add, force_to_parent
from ..dynamics.grouping import grouped_inertias, origin_inertias
from ..dynamics.origins import axial_origins
from ..dynamics.rnea import joint_friction, joint_springs, rnea
from ..dynamics.transforms import joint_rotation, joint_transforms
from ..dynamics.twists import body_drifts, body_twists, constraint_drift, motion_drift
from ..errors import CodegenError
from ..scene.joint_kinds import joint_kind
from ..kinematics import ConstantCache, constants, tree_kinematics
from ..math.spatial import COMPONENTS, matrix_to_quat, quaternion_matrix
from ..math.configuration import Configuration, CosSin
from ..tree import WORLD_INDEX, Tree
from .arms import arm_structure, solve_arms
from .graph import Graph
from .loop_rows import loop_drift, loop_rows
from .parameters import current as current_parameters, traced_parameters
from .trace_field import TraceField


def position_layout(model) -> list[tuple[str, str, int, int]]:
    """``(joint, type, offset, size)`` of each joint's entries in the position input ``q``:
    an angle (revolute), a displacement (prismatic) or a unit quaternion ``w, x, y, z``
    (spherical), in scene declaration order; fixed joints have none."""
    out, offset = [], 0
    for j in model.scene.joints.values():
        size = j.kind.position_size
        if size:
            out.append((j.name, j.kind, offset, size))
            offset += size
    return out


def position_vector(model, config) -> np.ndarray:
    """The generated code's ``q`` (angles, displacements, unit quaternions) of a configuration."""
    out = []
    for name, kind, _, _ in position_layout(model):
        value = config.positions[name]
        if joint_kind(kind).position_is_rotation:
            out.extend(float(v) for v in matrix_to_quat(np.asarray(value, dtype=float)))
        else:
            out.append(float(value))
    return np.array(out)


_RATES_BY_SOLVE: ContextVar[bool] = ContextVar("rates_by_solve", default=False)

def per_model(store: dict, model, key, compute):
    """``store[key]``, computed by ``compute()`` on first use and dropped when ``model`` is
    collected: a choice made once per model (the route of ``M_q``, whether grouping pays) that
    every function traced from it reuses, where keying by ``id`` alone could outlive the model."""
    if key not in store:
        store[key] = compute()
        weakref.finalize(model, store.pop, key, None)
    return store[key]


def has_gravity(model) -> bool:
    return any(g != 0 for g in model.tree.gravity)


class ForceFrames(NamedTuple):
    """The body frames the recursions of the joint forces read (:attr:`Tracer.force_frames`): the
    first three arguments of :func:`~symgen.dynamics.rnea.rnea`, :func:`~symgen.dynamics.crba.tree_mass_matrix`,
    :func:`~symgen.dynamics.aba.articulated_body` and the closed-form partials."""

    tree: Tree
    consts: ConstantCache
    transforms: list


#: ``{id(model): (axial, grouped)}``: the choice of :func:`force_frames_choice` for a model (:func:`per_model`)
_FORCE_FRAMES: dict[int, tuple[bool, bool]] = {}
#: ``{id(model): Tree}``: the model's tree with its origins moved (:func:`~symgen.dynamics.origins.axial_origins`)
_AXIAL_TREES: dict[int, Tree] = {}


def force_frames_costs(model) -> dict[tuple[bool, bool], int]:
    """``{(axial, grouped): operations}`` of the joint forces (``inverse_dynamics``'s recursion:
    rates, accelerations, gravity) with the body origins moved along the joint axes or as given
    (:func:`~symgen.dynamics.origins.axial_origins`) and with the grouped parameters or the bodies'
    own (:func:`~symgen.dynamics.grouping.grouped_inertias`), traced in one probe graph and counted;
    without the ``axial`` keys where no joint's translation has an axial part. The inertial
    parameters are folded, as every choice is made for them (run-time parameters keep the tree and
    the bodies as given)."""
    with traced_parameters(None):
        probe = Tracer(model)
    n = probe.tree.n_coords
    qd, qdd = probe.g.input("qd", n), probe.g.input("qdd", n)
    gravity = has_gravity(model)
    moved = probe.axial_tree
    cost = {}
    for axial in (False, True) if moved is not probe.tree else (False,):
        frames = probe.frames_of(moved if axial else probe.tree)
        for grouped in (False, True):
            inertias = (grouped_inertias if grouped else origin_inertias)(frames.tree, frames.consts)
            tau = rnea(*frames, qd, qdd, gravity=gravity, inertias=inertias)
            cost[axial, grouped] = probe.g.count(probe.g.live([tau]))["total"]
    return cost


def force_frames_choice(model) -> tuple[bool, bool]:
    """``(axial, grouped)`` of the fewest operations in :func:`force_frames_costs`, the tree and
    the bodies as given on a tie. On the Panda: 701 operations as given, 605 grouped, 675 with
    the origins moved and 588 grouped so; the grouped part of a body moved through general
    rotations can instead fill a sparse parent (the UR5 holding a payload: 446 as given, 457
    grouped, 449 grouped with the origins moved: kept as given), and moving an offset onto a joint
    that had none can cost more than it saves."""
    cost = force_frames_costs(model)
    return min(cost, key=lambda key: (cost[key], key))


def task_motion_applies(model) -> bool:
    """Whether :meth:`Tracer.task_motion` applies: every tree coordinate independent (``P`` a
    selection, eq. 10), the rows of ``J_f`` those of ``T`` (operational constraint forces, or none)
    and no joint coupling among the constraints."""
    scene = model.scene
    constraints = list(scene.constraints.values())
    return (not model.partition.u1 and not any(c.is_coupling for c in constraints)
            and (not constraints or scene.constraint_forces == "operational"))


@contextmanager
def rates_by_solve():
    """Tracers made inside complete rates and project forces by solves with ``W``
    (:func:`symgen.steps.rates_by_solve`) instead of through ``P``: cheaper when a function maps
    few vectors, dearer when it needs ``P`` whole anyway (the generator keeps the cheaper)."""
    token = _RATES_BY_SOLVE.set(True)
    try:
        yield
    finally:
        _RATES_BY_SOLVE.reset(token)


#: perturbations of ``q0`` (besides ``q0`` itself) at which static pivot orders are tested
PIVOT_SAMPLES = 3


def sample_positions(model, count: int = PIVOT_SAMPLES, spread: float = 0.2, seed: int = 0) -> np.ndarray:
    """``q0`` and ``count`` deterministic perturbations of it, as rows of the generated code's ``q``
    (angles and displacements moved by up to ``spread``, quaternions perturbed and renormalised).
    They need not close the loops: they choose and test the static pivot orders of
    :mod:`symgen.codegen.sparse_lu`, whose entries are functions of ``q`` alone."""
    q0 = position_vector(model, model.reference)
    rng = np.random.default_rng(seed)
    rows = [q0]
    for _ in range(count):
        q = q0 + rng.uniform(-spread, spread, q0.shape)
        for _, kind, off, size in position_layout(model):
            if size == 4:
                q[off:off + 4] /= np.linalg.norm(q[off:off + 4])
        rows.append(q)
    return np.array(rows)


class Tracer:
    """Records one function of ``model`` into a fresh :class:`Graph`."""

    def __init__(self, model):
        self.model = model
        self.tree = model.tree
        self.part = model.partition
        self.g = Graph()
        self.g.samples = {"q": sample_positions(model)} if position_layout(model) else None
        self.parameters = current_parameters()
        inputs = {}
        if self.parameters:
            inputs = dict(zip(self.parameters.symbols, self.g.input("p", len(self.parameters))))
            if self.g.samples is not None:
                count = len(self.g.samples["q"])
                self.g.samples["p"] = np.tile(np.array(self.parameters.defaults), (count, 1))
        self.field = TraceField(self.g, self.tree.parameters, inputs)
        self.consts = constants(self.tree, self.field)
        self.n, self.m = model.counts.n, model.counts.m
        self.by_solve = _RATES_BY_SOLVE.get() and bool(self.part.u1)
        #: eq. (6) traced by :mod:`symgen.codegen.loop_rows` (:meth:`use_null_space_rows`)
        self.null_space_rows = False
        self._kin0 = None
        self._body_motion: dict = {}
        self.config, self.motion, self.transforms = self._positions()

    # ---------------------------------------------------------------- positions
    def _positions(self):
        g = self.g
        layout = position_layout(self.model)
        q = g.input("q", sum(size for *_, size in layout)) if layout else []
        pos = {}
        for name, kind, off, _size in layout:
            if kind.position_is_angle:
                c, s = g.func("cos", q[off]), g.func("sin", q[off])
                g.label(c, f"c_{name}")
                g.label(s, f"s_{name}")
                pos[name] = CosSin(c, s, q[off])
            elif kind.translates:
                pos[name] = q[off]
            else:
                rot = quaternion_matrix(*q[off:off + 4])
                for i in range(3):
                    for k in range(3):
                        g.label(rot[i][k], f"R_{name}_{i + 1}{k + 1}")
                pos[name] = rot
        motion = {j.name: joint_rotation(j.kind, pos[j.name]) if j.kind.rotates else pos[j.name]
                  for j in self.tree.joints if j.kind.rotates or j.kind.translates}
        return Configuration(pos), motion, joint_transforms(self.tree, self.consts, motion)

    # ---------------------------------------------------------------- Steps 4-10 on traced numbers
    def kinematics(self, qd_all=None):
        """Reference kinematics (jets) recorded into the graph; without rates, cached."""
        if qd_all is None:
            if self._kin0 is None:
                self._kin0 = tree_kinematics(self.tree, self.field, self.config)
            return self._kin0
        return tree_kinematics(self.tree, self.field, self.config, np.array(qd_all, dtype=object))

    def _constraints(self, kin):
        return steps.constraint_matrix(kin, self.model.scene.constraints.values(), self.part)

    @cached_property
    def closure(self) -> steps.ConstraintMatrix:
        """Step 4 (eq. 6) at the configuration, traced once for every block that reads it; with
        :attr:`null_space_rows`, the welds' rows in world axes (:mod:`symgen.codegen.loop_rows`)."""
        if not self.null_space_rows:
            return self._constraints(self.kinematics())
        t = loop_rows(self.kinematics(), self.model.scene.constraints.values())
        return steps.ConstraintMatrix(t, t[:, list(self.part.actuated)], t[:, list(self.part.unactuated)])

    def use_null_space_rows(self) -> None:
        """From now on trace eq. (6) by :func:`~symgen.codegen.loop_rows.loop_rows`: for a function
        that reads only the null space of ``T`` (rates, accelerations, ``P^T``), before anything
        has read :attr:`closure`; the rows of the model otherwise."""
        if "closure" not in vars(self):
            self.null_space_rows = True

    def frames_of(self, tree: Tree) -> ForceFrames:
        """``tree`` (the model's, or another placement of its bodies) with its constants and its
        joints' transforms at this tracer's positions."""
        if tree is self.tree:
            return ForceFrames(tree, self.consts, self.transforms)
        consts = ConstantCache(tree, self.field)
        return ForceFrames(tree, consts, joint_transforms(tree, consts, self.motion))

    @cached_property
    def axial_tree(self) -> Tree:
        """The model's tree with each body's origin moved along its joint's axis
        (:func:`~symgen.dynamics.origins.axial_origins`; the tree itself where no joint's
        translation has an axial part), made once per model."""
        return per_model(_AXIAL_TREES, self.model, id(self.model), lambda: axial_origins(self.tree))

    @cached_property
    def force_choice(self) -> tuple[bool, bool]:
        """``(axial, grouped)`` of the joint-force recursions: :func:`force_frames_choice`, made once
        per model; ``(False, False)`` with run-time parameters (the grouping and the moved centres of
        mass would cost operations on every call)."""
        if self.parameters:
            return False, False
        return per_model(_FORCE_FRAMES, self.model, id(self.model), lambda: force_frames_choice(self.model))

    @cached_property
    def force_frames(self) -> ForceFrames:
        """The tree, constants and transforms the recursions of the joint forces read (``tau``,
        ``M``, the articulated-body accelerations and their derivatives, none of which depends on
        where along its joint's axis a body's origin is): the origins moved (:attr:`axial_tree`)
        where that makes the recursion cheaper for this model (:attr:`force_choice`), the model's
        tree otherwise. Every function that reads a named frame or a body twist uses the model's
        tree, except the contact wrench the articulated-body recursion applies, which is placed on
        its frame in these (:func:`symgen.codegen.aba.contact_wrenches`)."""
        return self.frames_of(self.axial_tree if self.force_choice[0] else self.tree)

    @cached_property
    def joint_force_inertias(self) -> list:
        """The body parameters the recursion of the joint forces reads, in :attr:`force_frames`:
        grouped (:func:`~symgen.dynamics.grouping.grouped_inertias`, the same ``tau`` with three
        structural zeros per revolute link) where the grouping makes the recursion cheaper for this
        model (:attr:`force_choice`); about the origins otherwise."""
        frames = self.force_frames
        return (grouped_inertias if self.force_choice[1] else origin_inertias)(frames.tree, frames.consts)

    @cached_property
    def blocks(self) -> steps.ConstraintBlocks:
        """Step 6 (eq. 9): one factorisation of ``[T_u1, T_a1]``, several right-hand sides."""
        return steps.constraint_blocks(self.field, self.closure, self.part)

    @cached_property
    def rates(self) -> steps.RateMap:
        """Step 8: ``P`` (eq. 10); its constant zeros and ones fold away in every product."""
        return steps.rate_map(self.field, self.blocks, self.part)

    def complete_rates(self, qd):
        """``qd_all = P qd`` (eq. 10); inside :func:`rates_by_solve`, by one solve with ``W``
        (:func:`symgen.steps.rates_by_solve`), so ``P`` is formed only where a function needs it."""
        if not self.by_solve:
            return list(steps.all_rates(self.rates, qd))
        return list(steps.rates_by_solve(self.field, self.closure, self.blocks, self.part, qd))

    def rate_bias(self, qd_all, *, kinematics: bool = True):
        """``(dP/dt qd, kin)``: the accelerations at ``qdd = 0`` (eq. 11) and the kinematics with
        derivatives along ``qd_all`` (``None`` when nothing needs them, or without
        ``kinematics``: the bias itself needs none, :meth:`constraint_drift`)."""
        scene = self.model.scene
        kin = None
        if kinematics and (self.part.u1 or scene.constraints or scene.motion.frames or scene.contact_forces):
            kin = self.kinematics(qd_all)
        if not self.part.u1:
            return [0] * self.tree.n_coords, kin
        return list(steps.rate_bias_of_drift(self.field, self.constraint_drift(qd_all), self.blocks, self.part)), kin

    def body_motion(self, qd_all):
        """``(twists, drifts)`` of every body for the rates ``qd_all``
        (:func:`symgen.dynamics.twists.body_drifts`), traced once per rate vector."""
        key = tuple(id(x) for x in qd_all)
        found = self._body_motion.get(key)
        if found is None:
            twists = body_twists(self.tree, self.transforms, qd_all)
            found = (qd_all, twists, body_drifts(self.tree, self.transforms, qd_all, twists))
            self._body_motion[key] = found
        return found[1], found[2]

    def constraint_drift(self, qd_all):
        """``dT/dt qd_all`` (eq. 6 differentiated) by the outward recursion of the body twists and
        their drifts (:func:`symgen.dynamics.twists.constraint_drift`): vectors, where the jets of
        ``T`` carry the derivative of every column."""
        drift = loop_drift if self.null_space_rows else constraint_drift
        return drift(self.kinematics(), self.model.scene.constraints.values(), *self.body_motion(qd_all))

    def accelerations_of_rates(self, qdd, qd_all):
        """``qdd_all = P qdd + dP/dt qd`` (eq. 11) from the completed rates ``qd_all``: inside
        :func:`rates_by_solve`, the constraints' drift joins the right-hand side of the one solve
        with ``W`` (:func:`symgen.steps.rates_by_solve`); through ``P``, :meth:`rate_bias` first."""
        if not self.part.u1:
            return self.complete_accelerations(qdd, [0] * self.tree.n_coords)
        if not self.by_solve:
            return self.complete_accelerations(qdd, self.rate_bias(qd_all, kinematics=False)[0])
        return list(steps.rates_by_solve(self.field, self.closure, self.blocks, self.part, qdd,
                                         drift=self.constraint_drift(qd_all)))

    def complete_accelerations(self, qdd, bias):
        """``qdd_all = P qdd + dP/dt qd`` (eq. 11), by a solve as :meth:`complete_rates`."""
        if not self.by_solve:
            return list(steps.all_accelerations(self.rates, qdd, bias))
        return list(steps.rates_by_solve(self.field, self.closure, self.blocks, self.part, qdd, bias))

    def project(self, tau_all):
        """``P^T tau_all``: joint forces on the independent coordinates (inside
        :func:`rates_by_solve`, one transposed solve with ``W``)."""
        if not self.by_solve:
            return list(steps.project(self.rates, tau_all))
        return list(steps.project_by_solve(self.field, self.closure, self.blocks, self.part, tau_all))

    def p_full(self):
        """``P`` (N_all x n) as an array of nodes."""
        return self.rates.P.v

    @cached_property
    def constraint(self) -> steps.ConstraintMap:
        """Step 7 (eq. 12), for either choice of ``T_c``."""
        return steps.constraint_map(self.field, self.closure, self.blocks, self.rates.P,
                                    self.part, self.model.scene.constraint_forces)

    @cached_property
    def arms(self):
        """The per-arm block structure of ``[J_m; J_f]`` (:mod:`symgen.codegen.arms`), or ``None``."""
        return arm_structure(self)

    def task_matrix(self):
        """``A = [J_m; J_f]`` (n x n, eq. 18) at the configuration (Step 10)."""
        task = steps.task_map(self.field, self.kinematics(), self.model.scene.motion, self.rates.P)
        return steps.task_matrix(self.field, task, self.constraint).v

    def task_bias(self, qd_all, bias, kin):
        """``dA/dt qd`` (n): the task rows' accelerations at ``qdd = 0``. The rows of ``J_f = T P``
        (operational ``T_c``) take the constraint rows' bias; those of ``J_f = [1, T21, T22] =
        E2 W^-1 T P`` (``T_c = 1``) take ``E2 W^-1 (dT/dt qd_all + T dP/dt qd)``: ``d(W^-1)/dt``
        multiplies ``T P qd = 0`` on admissible velocities and drops out."""
        rows = steps.motion_rows(self.field, kin or self.kinematics(), self.model.scene.motion)
        out = list(steps.acceleration_bias(rows, qd_all, bias))
        if self.n > self.m:
            t_bias = steps.acceleration_bias(self._constraints(kin).T, qd_all, bias)
            if self.model.scene.constraint_forces != "operational":
                t_bias = self.g.solve(self.blocks.W.v, t_bias, "[T_u1, T_a1] (eq. 9)")[self.model.counts.np:]
            out += list(t_bias)
        return out

    def task_bias_of_rates(self, qd_all, bias):
        """:meth:`task_bias` for derivatives along the rates ``qd_all`` themselves: the rows' drift
        by the outward recursion (:func:`symgen.dynamics.twists.motion_drift`,
        :func:`~symgen.dynamics.twists.constraint_drift`) plus the rows times ``bias = dP/dt qd``,
        where :func:`symgen.steps.acceleration_bias` reads the jets of every row."""
        kin = self.kinematics()
        twists, drifts = self.body_motion(qd_all)
        motion = self.model.scene.motion
        rows = steps.motion_rows(self.field, kin, motion).v
        bias_v = np.array(bias, dtype=object)
        out = [d + x for d, x in zip(motion_drift(kin, motion, twists, drifts), rows @ bias_v)]
        if self.n > self.m:
            if self.null_space_rows:
                raise CodegenError("the task bias of the constraint rows needs the rows of the model")
            drift = constraint_drift(kin, self.model.scene.constraints.values(), twists, drifts)
            t_bias = np.array([d + x for d, x in zip(drift, self.closure.T.v @ bias_v)], dtype=object)
            if self.model.scene.constraint_forces != "operational":
                t_bias = self.g.solve(self.blocks.W.v, t_bias, "[T_u1, T_a1] (eq. 9)")[self.model.counts.np:]
            out += list(t_bias)
        return out

    def _require_task_motion(self, what: str) -> None:
        """The guard of :meth:`task_motion` and :meth:`constraint_wrenches` (``what``: theirs)."""
        if not task_motion_applies(self.model):
            raise CodegenError(f"scene {self.model.scene.name!r}: {what} by recursion need every coordinate "
                               "independent, operational constraint forces and no joint coupling")
        if self.n > self.m and self.null_space_rows:
            raise CodegenError(f"scene {self.model.scene.name!r}: {what} by recursion need the rows of T "
                               "(eq. 6) in the constraints' frames, not the loop rows this function traces")

    def task_motion(self, qd_all, qdd_all=None) -> list:
        """``A qd`` (eq. 18) for the rates ``qd_all`` of every tree coordinate -- or, with their
        accelerations ``qdd_all``, ``A qdd + dA/dt qd`` -- by the outward recursion of the body
        twists (and accelerations, :func:`symgen.dynamics.twists.body_drifts`) instead of the
        rows' entries: the frames' twists weighted by their ``gamma`` (eq. 17), the constraints'
        relative twists (eq. 6), the motion joints' rates. Differentiated in ``q`` with the rates
        held, it costs ``O(N)`` per column where the rows' entries carry every column's dependence
        (:mod:`symgen.codegen.forward_derivatives`, the nested routes). Only where ``A``'s rows are
        those of the tree (:func:`task_motion_applies`)."""
        self._require_task_motion("the task rows")
        scene = self.model.scene
        kin = self.kinematics()
        twists, _ = self.body_motion(qd_all)
        if qdd_all is None:     # the drifts are linear in their last argument: zero twists leave J x
            first, second, rates = [(0,) * 6] * len(twists), twists, qd_all
        else:
            first, second, rates = twists, body_drifts(self.tree, self.transforms, qd_all, twists, qdd_all), qdd_all
        joints = scene.motion.joints
        out = motion_drift(kin, scene.motion, first, second)[:self.m - len(joints)]
        out += [rates[self.tree.coordinate_index(name)] for name in joints]
        if self.n > self.m:
            out += constraint_drift(kin, scene.constraints.values(), first, second)
        return out

    def constraint_wrenches(self, eta_f) -> dict:
        """The wrenches the constraint forces ``eta_f`` put on the bodies, body index -> ``[f; n]``
        about the origin of the body in :attr:`force_frames` (where :meth:`joint_forces` runs), in
        its axes: with them the recursion's joint forces gain ``J_f^T eta_f = A^T [0; eta_f]``
        (eq. 18) in the same inward pass, instead of through ``A``'s entries. A frame constraint's
        rows are components of ``X_A - ^A X_B`` (eq. 6), so its ``eta`` (on those components, in
        A's axes) acts on A, and moved to B (``^B U_A eta``) acts negated on B. Where
        :meth:`task_motion` applies."""
        self._require_task_motion("the constraint forces")
        kin, frames = self.kinematics(), self.force_frames
        wrenches: dict = {}

        def put(name, wrench):
            body = frames.tree.frames[name].body
            if body != WORLD_INDEX:
                r_f, p_f = frames.consts.frame[name]
                moved = force_to_parent(r_f.tolist(), tuple(p_f), tuple(wrench))
                wrenches[body] = add(wrenches[body], moved) if body in wrenches else moved

        values = iter(eta_f)
        for con in self.model.scene.constraints.values():
            wrench = [0] * 6
            for component in con.components:
                wrench[COMPONENTS.index(component)] = next(values)
            r_ba, p_ba = kin.relative_pose(con.frame_a, con.frame_b)
            on_b = force_to_parent(r_ba.v.tolist(), tuple(p_ba.v), tuple(wrench))
            put(con.frame_a, wrench)
            put(con.frame_b, tuple(-x for x in on_b))
        return wrenches

    def contact_map(self):
        """``D_m`` (eq. 16) as an array of nodes, or ``None`` without contact forces."""
        cf = self.model.scene.contact_forces
        if cf is None:
            return None
        return steps.contact_map(self.field, self.kinematics(), cf, self.rates.P).D_m.v

    def solve(self, a, b, what):
        return self.g.solve(a, np.array(b, dtype=object), what)

    def solve_task(self, a, b, *, transpose: bool = False):
        """``A^-1 b`` or ``A^-T b`` for ``A = [J_m; J_f]``: through the per-arm blocks when the scene
        has them (:mod:`symgen.codegen.arms`), else one dense library solve."""
        b = np.array(b, dtype=object)
        structure = self.arms
        if structure is not None:
            cols = [solve_arms(self, structure, b[:, k] if b.ndim == 2 else b, transpose)
                    for k in range(b.shape[1] if b.ndim == 2 else 1)]
            return np.array(cols, dtype=object).T if b.ndim == 2 else np.array(cols[0], dtype=object)
        if transpose:
            return self.g.solve(a.T, b, "[J_m; J_f]^T (eq. 18)")
        return self.g.solve(a, b, "[J_m; J_f] (eq. 18)")

    # ---------------------------------------------------------------- dynamics
    def joint_forces(self, qd_all, qdd_all, *, gravity: bool, friction_rates=None, tag: str = "",
                     springs: bool = False, wrenches: dict | None = None):
        """``P^T (T_S^T (M_S dX + C_S X + G_S))`` by recursion (eqs. 21-25): velocity products
        from ``qd_all``, joint friction ``xi`` from ``friction_rates`` (``None``: left out), the
        joint springs ``k (q - q_spring)`` if ``springs``, ``J^T W`` of the body wrenches
        ``wrenches`` (in :attr:`force_frames`, e.g. :meth:`constraint_wrenches`)."""
        tau = rnea(*self.force_frames, qd_all, qdd_all, gravity=gravity, graph=self.g, tag=tag,
                   inertias=self.joint_force_inertias, wrenches=wrenches)
        if friction_rates is not None:
            tau = [a + b for a, b in zip(tau, self.friction(friction_rates))]
        if springs:
            tau = self.add_springs(tau)
        return self.project(tau)

    def friction(self, qd_all) -> list:
        """The joint friction ``xi`` (eqs. 22-23) per tree coordinate at the rates ``qd_all``."""
        for k, joint in enumerate(self.tree.joints):
            if joint.kind.position_is_rotation and not self.field.is_zero(self.consts.coulomb[k]):
                raise CodegenError(f"joint {joint.name!r}: Coulomb friction on a spherical joint "
                                   "is not supported by the code generator")
        return joint_friction(self.tree, self.consts, qd_all, self.field.sign, self.g)

    def applied_forces(self, tau, qd_all, *, friction: bool, springs: bool) -> list:
        """The forces that drive the tree, per tree coordinate: the actuator forces ``tau`` (in the
        order of ``qd``, eq. 14; zero on the dependent coordinates) less the joint friction (if
        ``friction``) and the joint springs (if ``springs``)."""
        tau_all = [0] * self.tree.n_coords
        for j, coord in enumerate(self.part.independent):
            tau_all[coord] = tau[j]
        if friction:
            tau_all = [x - y for x, y in zip(tau_all, self.friction(qd_all))]
        if springs:
            tau_all = self.add_springs(tau_all, sign=-1)
        return tau_all

    def add_springs(self, tau, sign: int = 1):
        """``tau`` (per tree coordinate) plus ``sign`` times the joint springs ``k (q - q_spring)``."""
        tau = list(tau)
        for coord, term in joint_springs(self.tree, self.consts, self.config.positions, self.g).items():
            tau[coord] = tau[coord] + term if sign > 0 else tau[coord] - term
        return tau
