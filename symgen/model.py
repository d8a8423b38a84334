"""Model (32) of a general constrained robot, and its joint-space form.

:func:`derive` turns a :class:`~symgen.scene.Scene` into a :class:`Model`: the constant
description (tree, counts, partition, coordinate names). :meth:`Model.evaluate` computes, at one
state and in one field (``float``, ``exact``, ``symbolic``), every quantity of the twelve steps
and the model

    M [dV_m; 0] + C [V_m; 0] + G = [J_m; J_f]^-T tau - [0; eta_f]                (32)

    M = B^T M_S B,   C = B^T M_S dB/dt + B^T C_S B,   G = B^T G_S + A^-T D_m^T eta_m
    with B = T_S [J_m; J_f]^-1 and A = [J_m; J_f],

along with the joint-space form ``M_q qdd + C_q qd + G_q = tau - J_f^T eta_f - D_m^T eta_m``
(``M_q = T_S^T M_S T_S``, ``C_q = T_S^T (M_S dT_S/dt + C_S T_S)``, ``G_q = T_S^T G_S``).
"""
from __future__ import annotations

import copy
import numbers
from dataclasses import dataclass

import numpy as np
import sympy as sp

from .arith import Field, make_field
from .errors import ConstraintError, NonFiniteResultError, SingularConfigurationError, StateError
from .jet import Jet
from .scene import Scene
from .state import Configuration, as_configuration
from .kinematics import constraint_matrix, tree_kinematics
from .steps import (FORCE_NAMES, Counts, Maps, Partition, all_accelerations, all_rates, check_full_row_rank,
                    choose_partition, closure_multipliers, counts_from, evaluate_maps, jet_names, joint_space_model,
                    rate_bias, subsystem_terms, task_space_model, tree_forces)
from .tree import Tree, build_tree

#: [J_m; J_f] at the reference configuration must be better conditioned than this
MAX_TASK_CONDITION = 1e10
#: the functions whose meaning needs closed loops (forward and inverse dynamics, joint motion,
#: loop forces) refuse a float configuration whose closure residual exceeds this (m or rad)
CLOSURE_TOL = 1e-6


@dataclass(frozen=True)
class ModelData:
    """Everything computed at one state (a Pinocchio-style ``Data``): the maps of Steps 4-11,
    the subsystem terms of Step 12, model (32) and the joint-space form."""

    field: Field
    maps: Maps
    qd: np.ndarray            # eq. (14)
    V_m: np.ndarray           # eq. (17)
    X: np.ndarray             # velocity in S, eq. (25)
    M_S: np.ndarray
    C_S: np.ndarray
    G_S: np.ndarray           # eq. (24)
    M: np.ndarray
    C: np.ndarray
    G: np.ndarray             # eq. (32)
    M_q: np.ndarray
    C_q: np.ndarray
    G_q: np.ndarray           # joint space
    B: Jet                    # T_S [J_m; J_f]^-1 with its time derivative
    eta_m: np.ndarray

    def quantities(self) -> dict[str, np.ndarray]:
        """Named values of every step, for inspection (``sympy.Matrix(value)`` to pretty-print)."""
        out = {name: jet.v for name, jet in jet_names(self.maps).items()}
        out.update(qd=self.qd, V_m=self.V_m, X=self.X,
                   M_S=self.M_S, C_S=self.C_S, G_S=self.G_S, M=self.M, C=self.C, G=self.G,
                   M_q=self.M_q, C_q=self.C_q, G_q=self.G_q)
        return out


@dataclass(frozen=True)
class Model:
    """The constant result of the derivation: structure, counts, partition, reference configuration.
    Immutable: a changed scene is derived again."""

    scene: Scene
    tree: Tree
    counts: Counts
    partition: Partition
    reference: Configuration

    # ------------------------------------------------------------------ evaluation
    def evaluate(self, config: Configuration, *, qd=None, V_m=None, field: str | Field = "float",
                 eta_m=None, gravity: bool = True) -> ModelData:
        """All quantities at ``config`` with velocity ``qd`` (eq. 14) or ``V_m`` (then
        ``qd = Omega V_m``, eq. 20). ``O(n_S^2)`` work and memory: a reference evaluator, not the
        linear-time generated code. ``config``: a :class:`Configuration`, a mapping joint ->
        position or a flat array in scene order (:func:`~symgen.state.as_configuration`)."""
        fld = make_field(field, self.tree.parameters) if isinstance(field, str) else field
        config = fld.configuration(as_configuration(config, self.scene, "config"), self.tree)
        _check_length("qd", qd, self.counts.n)
        _check_length("V_m", V_m, self.counts.m)
        _check_length("eta_m", eta_m, len(self.scene.contact_forces.components) if self.scene.contact_forces else 0)
        first = evaluate_maps(self, config, fld)                 # values: Omega and P
        qd_v = self._joint_rates(first, fld, qd, V_m)
        maps = evaluate_maps(self, config, fld, all_rates(first.rates, qd_v))   # with d/dt along qd
        v_m = maps.J_m.v @ qd_v if V_m is None else np.asarray(V_m, dtype=fld.dtype)
        x = maps.T_S.v @ qd_v
        terms = subsystem_terms(fld, maps.kin, maps.velocity.space, x, gravity=gravity)
        eta = fld.zeros((maps.D_m.shape[0],)) if eta_m is None else np.asarray(eta_m, dtype=fld.dtype)
        task, b = task_space_model(terms, maps.velocity, maps.inverse, maps.contact, eta)
        joint = joint_space_model(terms, maps.velocity)
        for name, value in (("M", task.M), ("C", task.C), ("G", task.G), ("M_q", joint.M), ("C_q", joint.C),
                            ("G_q", joint.G)):
            _finite("evaluate", name, value)
        return ModelData(fld, maps, qd_v, v_m, x, terms.M_S, terms.C_S, terms.G_S, task.M, task.C, task.G,
                         joint.M, joint.C, joint.G, b, eta)

    def _joint_rates(self, maps: Maps, fld, qd, V_m) -> np.ndarray:
        """``qd`` of eq. (14): as given, from ``V_m`` by eq. (20) (``qd = Omega V_m``), or zero."""
        if V_m is not None:
            return maps.Omega.v @ np.asarray(V_m, dtype=fld.dtype)
        if qd is not None:
            return np.asarray(qd, dtype=fld.dtype)
        return fld.zeros((self.counts.n,))

    def forward_dynamics(self, config: Configuration, V_m, tau, eta_m=None, *, field: str | Field = "float",
                         check_closure: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """Solve (32) for ``(dV_m, eta_f)`` given ``tau``, in ``field`` (float by default; the
        float inputs are taken at their exact values). ``O(n^3)`` reference solve. ``config`` as
        in :meth:`evaluate`; its loops must be closed to :data:`CLOSURE_TOL` unless
        ``check_closure=False``. A non-finite result raises :class:`NonFiniteResultError`."""
        config = self._closed(config, field, check_closure)
        _check_length("tau", _required("tau", tau), self.counts.n)
        dv, eta_f = solve_forward(self.evaluate(config, V_m=V_m, eta_m=eta_m, field=field), tau)
        return _finite("forward_dynamics", "dV_m", dv), _finite("forward_dynamics", "eta_f", eta_f)

    def inverse_dynamics(self, config: Configuration, V_m, dV_m, eta_f=None, eta_m=None, *,
                         field: str | Field = "float", check_closure: bool = True) -> np.ndarray:
        """``tau = [J_m; J_f]^T (M [dV_m; 0] + C [V_m; 0] + G + [0; eta_f])``, in ``field``
        (float by default). ``config`` as in :meth:`forward_dynamics`."""
        config = self._closed(config, field, check_closure)
        _check_length("dV_m", _required("dV_m", dV_m), self.counts.m)
        _check_length("eta_f", eta_f, self.counts.n - self.counts.m)
        tau = solve_inverse(self.evaluate(config, V_m=V_m, eta_m=eta_m, field=field), dV_m, eta_f)
        return _finite("inverse_dynamics", "tau", tau)

    def _closed(self, config, field, check: bool) -> Configuration:
        """``config`` as a :class:`Configuration`; with ``check`` (float field), refused with a
        :class:`StateError` naming the constraint if a loop is open by more than :data:`CLOSURE_TOL`."""
        config = as_configuration(config, self.scene, "config")
        if check and self.scene.constraints and field == "float":
            from .closure import closure_residual

            res = closure_residual(self, config.as_float())
            if res.size and not np.max(np.abs(res)) <= CLOSURE_TOL:
                worst = int(np.argmax(np.abs(res))) if np.all(np.isfinite(res)) else 0
                raise StateError(f"config: constraint {_constraint_of_row(self.scene, worst)!r} is open by "
                                 f"{np.max(np.abs(res)):.3g} (more than {CLOSURE_TOL:g}); close the loops first "
                                 "(symgen.closure.solve_closure) or pass check_closure=False: the equations of "
                                 "motion hold only on closed configurations")
        return config

    # ------------------------------------------------------------------ symbols
    def symbolic_configuration(self) -> Configuration:
        """Symbols for every joint position: ``c_<j>, s_<j>`` (revolute), ``d_<j>`` (prismatic),
        ``R_<j>_<ab>`` (spherical)."""
        return Configuration({j.name: j.kind.symbolic_position(j.name)
                              for j in self.scene.joints.values() if j.kind.dof})

    def symbolic_velocity(self) -> list[sp.Symbol]:
        """Symbols ``qd_<coordinate>`` for ``qd`` of eq. (14)."""
        return [sp.Symbol("qd_" + self.tree.coordinates[c].label.replace(".", "_"), real=True)
                for c in self.partition.independent]

    def coordinate_names(self) -> list[str]:
        return [self.tree.coordinates[c].label for c in self.partition.independent]

    # ------------------------------------------------------------------ every joint, every loop
    def all_coordinate_names(self) -> list[str]:
        """Labels of ``qd_all``, the rates of every joint coordinate: scene (declaration) order,
        one entry per revolute or prismatic joint, three per spherical joint (``name.wx``,
        ``name.wy``, ``name.wz``: its angular velocity in the child frame), none for fixed joints.
        Dependent joints (``q_u1, q_a1`` of eq. 8) are included."""
        return [c.label for c in self.tree.coordinates]

    def constraint_force_names(self) -> list[str]:
        """Labels of :meth:`loop_forces`: ``<constraint>.<fx|fy|fz|mx|my|mz>`` in the order of the
        scene's constraints and of each constraint's components."""
        return [f"{con.name}.{FORCE_NAMES[c]}" for con in self.scene.constraints.values() for c in con.components]

    def joint_rates(self, config: Configuration, V_m, *, field: str | Field = "float") -> np.ndarray:
        """``qd_all = P Omega V_m`` (eqs. 10, 14, 20): the rates of every joint coordinate, in the
        order of :meth:`all_coordinate_names`, in ``field`` (float by default). ``O(n_S^2)``."""
        _check_length("V_m", V_m, self.counts.m)
        fld = make_field(field, self.tree.parameters) if isinstance(field, str) else field
        maps = evaluate_maps(self, fld.configuration(as_configuration(config, self.scene, "config"), self.tree), fld)
        return _finite("joint_rates", "qd_all", all_rates(maps.rates, maps.Omega.v @ field_vector(fld, V_m)))

    def joint_accelerations(self, config: Configuration, V_m, tau=None, eta_m=None, *, dV_m=None,
                            field: str | Field = "float") -> np.ndarray:
        """``qdd_all``, the accelerations of every joint coordinate (dependent ones included, in the
        order of :meth:`all_coordinate_names`), under ``tau`` (forward dynamics, eq. 32) or for a
        given ``dV_m`` (then ``tau`` is not needed). In ``field`` (float by default), ``O(n_S^2 + n^3)``.

        ``qdd = [J_m; J_f]^-1 ([dV_m; 0] - d[J_m; J_f]/dt qd)`` (eqs. 17-19 differentiated), then
        eq. (11) differentiated: ``qdd_all = P qdd + dP/dt qd``."""
        if (tau is None) == (dV_m is None):
            raise StateError("give exactly one of tau (forward dynamics) and dV_m (given motion)")
        qdd_all = self._all_joint_motion(config, V_m, eta_m, tau=tau, dV_m=dV_m, field=field)[3]
        return _finite("joint_accelerations", "qdd_all", qdd_all)

    def loop_forces(self, config: Configuration, V_m, tau=None, eta_m=None, *, dV_m=None, eta_f=None,
                    field: str | Field = "float") -> np.ndarray:
        """``lam``: the force of every loop-closure constraint, component by component, in the order
        of :meth:`constraint_force_names` (in ``field``, float by default; ``O(n_S^2 + n^3)``).

        Component ``k`` of a constraint between frames A and B is the force (``vx, vy, vz`` ->
        ``f_x, f_y, f_z``) or moment about A's origin (``wx, wy, wz`` -> ``m_x, m_y, m_z``) that
        the constraint exerts on the body of frame A, in A's axes; the body of B receives the
        opposite. These are the Lagrange multipliers of ``M qdd + h = tau + T^T lam``
        (:mod:`symgen.steps.loop_forces` derives them from eqs. 9, 12 and 25-31). Where model (32)
        has ``eta_f``: ``eta_f = -T_c^-T T_a1^T lam`` (``-lam`` for ``constraint_forces:
        operational``).

        Forward dynamics: give ``tau`` (and ``eta_m``). Inverse dynamics: give ``dV_m`` (and
        ``eta_f``, ``eta_m``); ``tau`` then follows from :meth:`inverse_dynamics`."""
        if (tau is None) == (dV_m is None):
            raise StateError("give exactly one of tau (forward dynamics) and dV_m (inverse dynamics)")
        d, tau, qd_all, qdd_all = self._all_joint_motion(config, V_m, eta_m, tau=tau, dV_m=dV_m, eta_f=eta_f,
                                                         field=field)
        tau_tree = tree_forces(d.field, d.maps.kin, qd_all, qdd_all)
        tau_all = d.field.zeros((self.tree.n_coords,))
        tau_all[list(self.partition.independent)] = tau
        residual = tau_tree - tau_all + d.maps.contact.D_m_all.v.T @ d.eta_m
        return _finite("loop_forces", "lam", closure_multipliers(d.field, d.maps.blocks, self.partition, residual))

    def _all_joint_motion(self, config, V_m, eta_m=None, *, tau=None, dV_m=None, eta_f=None, field="float"):
        """``(data, tau, qd_all, qdd_all)`` from one evaluation in ``field``: the motion under
        ``tau`` (forward dynamics), or the motion ``dV_m`` and the ``tau`` it needs (inverse dynamics)."""
        d = self.evaluate(self._closed(config, field, True), V_m=V_m, eta_m=eta_m, field=field)
        fld = d.field
        if tau is not None:
            _check_length("tau", tau, self.counts.n)
            tau = field_vector(fld, tau)
            dV_m, _ = solve_forward(d, tau)
        else:
            _check_length("dV_m", dV_m, self.counts.m)
            _check_length("eta_f", eta_f, self.counts.n - self.counts.m)
            dV_m = field_vector(fld, dV_m)
            tau = solve_inverse(d, dV_m, eta_f)
        maps, n, m = d.maps, self.counts.n, self.counts.m
        qd_all = all_rates(maps.rates, d.qd)
        rest = fld.zeros((n - m,))
        qdd = maps.A_inv.v @ np.concatenate([dV_m, rest]) + maps.A_inv.d @ np.concatenate([d.V_m, rest])
        bias = rate_bias(fld, maps.constraints, maps.blocks, self.partition, qd_all)
        return d, tau, qd_all, all_accelerations(maps.rates, qdd, bias)


def solve_forward(data: ModelData, tau, extra_g=None) -> tuple[np.ndarray, np.ndarray]:
    """Model (32) solved for ``(dV_m, eta_f)`` at evaluated ``data``, in its field: ``M_mm dV_m =
    (A^-T tau - C [V_m; 0] - G)_m``, then ``eta_f`` from the remaining rows. ``extra_g`` (n) is
    added to ``G`` (e.g. contact forces ``A^-T D_m^T eta_m`` found after the evaluation)."""
    fld, m = data.field, len(data.V_m)
    g = data.G if extra_g is None else data.G + extra_g
    rhs = data.maps.A_inv.v.T @ field_vector(fld, tau) - data.C[:, :m] @ data.V_m - g
    what = "the motion block of M (eq. 32)"
    if fld.dtype is float:
        cond = np.linalg.cond(data.M[:m, :m])
        if not np.isfinite(cond) or cond > 1e14:
            raise SingularConfigurationError(what, float(cond))
        dv = np.linalg.solve(data.M[:m, :m], rhs[:m])
    else:
        dv = fld.solve(data.M[:m, :m], rhs[:m], what)
    return dv, rhs[m:] - data.M[m:, :m] @ dv


def solve_inverse(data: ModelData, dV_m, eta_f=None) -> np.ndarray:
    """``tau = [J_m; J_f]^T (M [dV_m; 0] + C [V_m; 0] + G + [0; eta_f])`` of model (32) at
    evaluated ``data``, in its field."""
    fld, m, n = data.field, len(data.V_m), data.M.shape[0]
    ef = fld.zeros((n - m,)) if eta_f is None else field_vector(fld, eta_f)
    lhs = data.M[:, :m] @ field_vector(fld, dV_m) + data.C[:, :m] @ data.V_m + data.G \
        + np.concatenate([fld.zeros((m,)), ef])
    return data.maps.A.v.T @ lhs


def field_vector(fld: Field, values) -> np.ndarray:
    """A vector of numbers (floats taken at their exact binary value) as an array of ``fld``."""
    if fld.dtype is float:
        return np.asarray(values, dtype=float)
    return np.array([fld.const(v) for v in np.asarray(values, dtype=object).ravel()], dtype=object)


def _check_length(name: str, value, expected: int) -> None:
    """``value`` (if given) has ``expected`` entries, and none is NaN or infinite."""
    if value is None:
        return
    try:
        shape = np.shape(value)
    except ValueError:                       # a ragged nesting
        shape = None
    if shape != (expected,):
        raise StateError(f"{name} must have shape ({expected},), got {'a ragged sequence' if shape is None else shape}")
    for k, v in enumerate(np.asarray(value, dtype=object)):
        if isinstance(v, (bool, np.bool_)) or not isinstance(v, (numbers.Real, sp.Basic)):
            raise StateError(f"{name}[{k}] must be a real number, got {type(v).__name__}")
        if isinstance(v, (float, np.floating)) and not np.isfinite(v):
            raise StateError(f"{name}[{k}] is {float(v)} (not finite)")


def _required(name: str, value):
    if value is None:
        raise StateError(f"{name} is required")
    return value


def _finite(function: str, output: str, values: np.ndarray) -> np.ndarray:
    """``values`` unchanged, or :class:`NonFiniteResultError` naming the function and output
    when a float entry is NaN or infinite (an input near overflow)."""
    arr = np.asarray(values)
    if arr.dtype.kind == "f" and not np.all(np.isfinite(arr)):
        raise NonFiniteResultError(f"{function}: the result {output} is not finite (an input near overflow?)")
    return values


def reference_configuration(scene: Scene) -> Configuration:
    """The scene's ``q0`` as a float configuration."""
    return Configuration({j.name: j.kind.reference_position(j.q0, scene.value_of)
                          for j in scene.joints.values() if j.kind.dof})


def derive(scene: Scene, *, check_reference: bool = True) -> Model:
    """Steps 1-8 and the structural checks; returns the :class:`Model` (cheap: no symbolics).

    Raises typed errors for redundant constraints, an impossible partition, an inconsistent
    reference configuration, or a singular ``[J_m; J_f]`` at the reference configuration.
    """
    scene.validate()
    scene = copy.deepcopy(scene)        # the model keeps its own copy: later edits need a new derive
    tree = build_tree(scene)
    ref = reference_configuration(scene)
    fld = make_field("float", tree.parameters)
    kin = tree_kinematics(tree, fld, ref)
    t = constraint_matrix(kin, scene.constraints.values()).v
    if check_reference:     # an open loop first: at a stretched q0 its rows also look redundant
        from .task_frames import check_weighted_frames

        _check_closed(scene, tree, ref)
        check_weighted_frames(scene, tree, ref)
    check_full_row_rank(t, scene.constraints.values())
    part = choose_partition(t, tree)
    counts = counts_from(tree, part, t.shape[0])
    model = Model(scene, tree, counts, part, ref)
    if check_reference:
        try:
            maps = evaluate_maps(model, ref, fld)
        except SingularConfigurationError as exc:
            raise SingularConfigurationError(f"{exc.what} at the reference configuration", exc.condition,
                                             "choose another q0 or other task coordinates") from None
        cond = np.linalg.cond(maps.A.v) if maps.A.v.size else 1.0
        if not np.isfinite(cond) or cond > MAX_TASK_CONDITION:
            raise SingularConfigurationError("[J_m; J_f] (eq. 18) at the reference configuration", float(cond),
                                             "choose another q0 or other motion coordinates")
    return model


def _check_closed(scene: Scene, tree: Tree, ref: Configuration) -> None:
    """The reference configuration must close every loop (position residuals below 1e-8)."""
    from .closure import tree_residual

    res = tree_residual(tree, scene.constraints.values(), ref)
    if res.size and np.max(np.abs(res)) > 1e-8:
        worst = int(np.argmax(np.abs(res)))
        raise ConstraintError(f"constraint {_constraint_of_row(scene, worst)!r}",
                              f"is violated by {np.max(np.abs(res)):.3g} at the reference configuration "
                              "(q0); give joint positions that close the loop")


def _constraint_of_row(scene: Scene, row: int) -> str:
    for con in scene.constraints.values():
        if row < con.dim:
            return con.name
        row -= con.dim
    return "?"
