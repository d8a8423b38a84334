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
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np
import sympy as sp

from .math.fields import Field, make_field
from .errors import ConstraintError, SingularConfigurationError, StateError
from .math.jet import Jet
from .scene.declaration import Scene
from .math.configuration import Configuration, ConfigurationLike, as_configuration
from .math.scalar import FieldVector
from .kinematics import constraint_matrix, tree_kinematics
from .conditioning import check_loop_condition
from .model_solves import check_length, field_vector, finite_result, required, solve_forward, solve_inverse
from .steps import (FORCE_NAMES, Counts, Maps, Partition, SubsystemTerms, all_rates, check_full_row_rank,
                    choose_partition, TASK_MATRIX, coriolis_congruence, counts_from, evaluate_maps, jet_names,
                    joint_force, mass_congruence, subsystem_terms, task_gravity, task_matrix_at, velocity_product)
from .steps.pipeline import joint_rate_maps
from .steps.task_space import motion_rows
from .tree import Tree, build_tree

if TYPE_CHECKING:
    from .motion import JointMotion

#: [J_m; J_f] at the reference configuration must be better conditioned than this
MAX_TASK_CONDITION = 1e10
#: the functions whose meaning needs closed loops (forward and inverse dynamics, joint motion,
#: loop forces) refuse a float configuration whose closure residual exceeds this (m or rad)
CLOSURE_TOL = 1e-6


class ModelData:
    """Everything computed at one state (a Pinocchio-style ``Data``): the maps of Steps 4-11,
    the subsystem terms of Step 12, model (32) and the joint-space form.

    The maps and the subsystem terms are computed by :meth:`Model.evaluate`; each matrix of
    model (32) and of the joint-space form is formed when it is first read (in the float field,
    at once), each once. What the solves of (32) need -- ``M``, ``G`` and the velocity product
    ``c = C [V_m; 0]`` -- costs one congruence ``B^T M_S B`` of the six, so a 50-digit reference
    solve does not pay for the others."""

    def __init__(self, field: Field, maps: Maps, qd: np.ndarray, V_m: np.ndarray, X: np.ndarray,
                 terms: SubsystemTerms, eta_m: np.ndarray) -> None:
        self.field, self.maps = field, maps
        self.qd = qd              # eq. (14)
        self.V_m = V_m            # eq. (17)
        self.X = X                # velocity in S, eq. (25)
        self.terms = terms
        self.eta_m = eta_m
        self.M_S, self.C_S, self.G_S = terms.M_S, terms.C_S, terms.G_S   # eqs. (21)-(24)

    def _checked(self, name: str, values: np.ndarray) -> np.ndarray:
        return finite_result("evaluate", name, values)

    @cached_property
    def B(self) -> Jet:
        """``T_S [J_m; J_f]^-1`` with its time derivative (eq. 32)."""
        return self.maps.T_S @ self.maps.A_inv

    @cached_property
    def M(self) -> np.ndarray:
        """``B^T M_S B`` of eq. (32)."""
        return self._checked("M", mass_congruence(self.terms, self.B.v, rounds=self.field.rounds))

    @cached_property
    def C(self) -> np.ndarray:
        """``B^T M_S dB/dt + B^T C_S B`` of eq. (32)."""
        return self._checked("C", coriolis_congruence(self.terms, self.B))

    @cached_property
    def G(self) -> np.ndarray:
        """``B^T G_S + A^-T D_m^T eta_m`` of eq. (32)."""
        return self._checked("G", task_gravity(self.terms, self.B, self.maps.inverse, self.maps.contact, self.eta_m))

    @cached_property
    def c(self) -> np.ndarray:
        """``C [V_m; 0]``, the velocity product of eq. (32), by products of vectors (``C`` not formed)."""
        v0 = np.concatenate([self.V_m, self.field.zeros((self.B.shape[1] - len(self.V_m),))])
        return self._checked("c", velocity_product(self.terms, self.B, v0))

    @cached_property
    def M_q(self) -> np.ndarray:
        """``T_S^T M_S T_S`` of the joint-space form."""
        return self._checked("M_q", mass_congruence(self.terms, self.maps.T_S.v, rounds=self.field.rounds))

    @cached_property
    def C_q(self) -> np.ndarray:
        """``T_S^T (M_S dT_S/dt + C_S T_S)`` of the joint-space form."""
        return self._checked("C_q", coriolis_congruence(self.terms, self.maps.T_S))

    @cached_property
    def G_q(self) -> np.ndarray:
        """``T_S^T G_S`` of the joint-space form."""
        return self._checked("G_q", self.maps.T_S.v.T @ self.G_S)

    def joint_force(self, qdd: FieldVector) -> np.ndarray:
        """``M_q qdd + C_q qd + G_q`` at this state's ``qd`` (the left side of the joint-space
        form, eqs. 28-31 with ``B = T_S``), by products of vectors: ``O(n_S n)``, no matrix formed."""
        qdd_v = field_vector(self.field, qdd)
        return self._checked("tau", joint_force(self.terms, self.maps.T_S, self.qd, qdd_v))

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
    @cached_property
    def float_field(self) -> Field:
        """This model's float field, made once, so that the scene's constants are converted to
        floats once (:func:`~symgen.kinematics.constants` keeps them per field)."""
        return make_field("float", self.tree.parameters)

    def field_of(self, field: str | Field) -> Field:
        """``field`` as a :class:`~symgen.math.fields.Field`: a name makes a new field, except
        ``"float"``, which is :attr:`float_field` (a float field holds no state of a computation;
        the exact and mp fields do)."""
        if not isinstance(field, str):
            return field
        return self.float_field if field == "float" else make_field(field, self.tree.parameters)

    def evaluate(self, config: ConfigurationLike, *, qd: FieldVector | None = None, V_m: FieldVector | None = None,
                 field: str | Field = "float", eta_m: FieldVector | None = None, gravity: bool = True) -> ModelData:
        """All quantities at ``config`` with velocity ``qd`` (eq. 14) or ``V_m`` (then
        ``qd = Omega V_m``, eq. 20). ``O(n_S^2)`` work and memory: a reference evaluator, not the
        linear-time generated code. ``config``: a :class:`Configuration`, a mapping joint ->
        position or a flat array in scene order (:func:`~symgen.math.configuration.as_configuration`)."""
        fld = self.field_of(field)
        config = fld.configuration(as_configuration(config, self.scene, "config"), self.tree)
        check_length("qd", qd, self.counts.n)
        check_length("V_m", V_m, self.counts.m)
        check_length("eta_m", eta_m, len(self.scene.contact_forces.components) if self.scene.contact_forces else 0)
        qd_v, qd_all = self._joint_rates(config, fld, qd, V_m)
        maps = evaluate_maps(self, config, fld, qd_all)          # Steps 4-11 with d/dt along qd_all
        if qd_all is not None and fld.dtype is float and np.isfinite(fld.max_condition):
            check_loop_condition(maps.W.v, maps.A.v if self.counts.nc else None)  # dP/dt, C lose cond^2 u
        v_m = maps.J_m.v @ qd_v if V_m is None else np.asarray(V_m, dtype=fld.dtype)
        x = maps.T_S.v @ qd_v
        terms = subsystem_terms(fld, maps.kin, maps.velocity.space, x, gravity=gravity)
        eta = fld.zeros((maps.D_m.shape[0],)) if eta_m is None else np.asarray(eta_m, dtype=fld.dtype)
        data = ModelData(fld, maps, qd_v, v_m, x, terms, eta)
        if fld.dtype is float:                 # cheap in floats: formed and checked at once
            for name in ("M", "C", "G", "M_q", "C_q", "G_q"):
                getattr(data, name)
        return data

    def _joint_rates(self, config: Configuration, fld: Field, qd: FieldVector | None,
                     V_m: FieldVector | None) -> tuple[np.ndarray, np.ndarray | None]:
        """``qd`` of eq. (14) -- as given, from ``V_m`` by eq. (20) (``qd = Omega V_m``), or zero --
        and the rates of every joint, ``P qd`` (eq. 10; ``None`` at rest). ``P`` and ``Omega`` come
        from the value-only steps they need (:func:`~symgen.steps.pipeline.joint_rate_maps`)."""
        if V_m is None and qd is None:
            return fld.zeros((self.counts.n,)), None
        rates, omega = joint_rate_maps(self, config, fld, with_task=V_m is not None)
        qd_v = omega.v @ np.asarray(V_m, dtype=fld.dtype) if omega is not None else np.asarray(qd, dtype=fld.dtype)
        return qd_v, all_rates(rates, qd_v)

    def forward_dynamics(self, config: ConfigurationLike, V_m: FieldVector, tau: FieldVector,
                         eta_m: FieldVector | None = None, *, field: str | Field = "float",
                         check_closure: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """Solve (32) for ``(dV_m, eta_f)`` given ``tau``, in ``field`` (float by default; the
        float inputs are taken at their exact values). ``O(n^3)`` reference solve. ``config`` as
        in :meth:`evaluate`; its loops must be closed to :data:`CLOSURE_TOL` unless
        ``check_closure=False``. A non-finite result raises :class:`NonFiniteResultError`."""
        config = self._closed(config, field, check_closure)
        check_length("tau", required("tau", tau), self.counts.n)
        dv, eta_f = solve_forward(self.evaluate(config, V_m=V_m, eta_m=eta_m, field=field), tau)
        return finite_result("forward_dynamics", "dV_m", dv), finite_result("forward_dynamics", "eta_f", eta_f)

    def forward_dynamics_derivatives(self, config: ConfigurationLike, V_m: FieldVector, tau: FieldVector,
                                     eta_m: FieldVector | None = None, *,
                                     field: str | Field = "mp") -> dict[str, np.ndarray]:
        """Jacobians of :meth:`forward_dynamics`: ``ddV_m_dq``, ``ddV_m_dV_m``, ``ddV_m_dtau`` and, when
        ``n > m``, ``deta_f_dq``, ``deta_f_dV_m``, ``deta_f_dtau`` (the generated
        ``forward_dynamics_derivatives``'s outputs, same shapes and column order), as numbers of
        ``field`` -- an extended-precision ``mp`` field (default 50 digits): central differences of
        the dense model (32) with step ``10^-(dps/2 - 5)`` in ``q`` and ``V_m``, exact in ``tau``
        (:func:`symgen.dynamics_jacobians.jacobians`). ``q`` is every joint position in scene
        order, moved one at a time without re-closing the loops (see there); a spherical (or free)
        joint has three columns, its rotation turned in the child frame, ``R exp(hat(d))`` -- the
        directions of its rates ``w`` (eq. 21) and Pinocchio's ``integrate`` -- so ``ddV_m_dq`` is
        ``m x (nq - number of spherical joints)`` for a ``q`` of ``nq`` entries. ``config`` as in
        :meth:`evaluate` (quaternions or rotation matrices). Cost ``2 (n_d + m) + 1`` evaluations
        of the dense model (``n_d`` columns of ``q``)."""
        from .dynamics_jacobians import jacobians

        return jacobians(self, config, V_m, tau, eta_m, field)

    def state_derivative_jacobian(self, config: ConfigurationLike, V_m: FieldVector, tau: FieldVector,
                                  eta_m: FieldVector | None = None, *,
                                  field: str | Field = "mp") -> dict[str, np.ndarray]:
        """``dxdot_dx`` and ``dxdot_dtau`` of the simulation's right-hand side (the generated
        ``state_derivative_jacobian``'s outputs, same shapes and layout), in ``field`` (an ``mp``
        field, 50 digits by default). The state is ``x = [q; V_m]`` with ``q`` the generated code's
        positions: one entry per 1-DOF joint and a spherical (or free) joint's quaternion
        ``p = (w, x, y, z)``, four entries, in scene order; and::

            dx/dt = [qd_all at 1-DOF joints;  1/2 (p / |p|) (x) (0, w) per spherical joint;  dV_m]

        with ``w`` the joint's rates, the angular velocity in its child frame (eq. 21), ``qd_all = P Omega
        V_m`` (eqs. 10, 18, 20), ``dV_m`` from (32). The partials are taken in the entries of ``x``
        themselves (a quaternion's four moved off the unit sphere, so a radial change moves
        nothing), by 50-digit central differences of the dense model, exact in ``tau``
        (:func:`symgen.dynamics_jacobians.state_jacobian`, the generated function's reference).
        ``config``: the flat ``q`` (its quaternions taken as they are) or a mapping / Configuration
        (a rotation matrix read as its quaternion with ``w >= 0``, the one the generated ``q``
        holds): :func:`symgen.dynamics_jacobians.state_positions`. Cost ``2 (nq + m) + 1``
        evaluations of the dense model."""
        from .dynamics_jacobians import state_jacobian

        return state_jacobian(self, config, V_m, tau, eta_m, field)

    def inverse_dynamics(self, config: ConfigurationLike, V_m: FieldVector, dV_m: FieldVector,
                         eta_f: FieldVector | None = None, eta_m: FieldVector | None = None, *,
                         field: str | Field = "float", check_closure: bool = True) -> np.ndarray:
        """``tau = [J_m; J_f]^T (M [dV_m; 0] + C [V_m; 0] + G + [0; eta_f])``, in ``field``
        (float by default). ``config`` as in :meth:`forward_dynamics`."""
        config = self._closed(config, field, check_closure)
        check_length("dV_m", required("dV_m", dV_m), self.counts.m)
        check_length("eta_f", eta_f, self.counts.n - self.counts.m)
        tau = solve_inverse(self.evaluate(config, V_m=V_m, eta_m=eta_m, field=field), dV_m, eta_f)
        return finite_result("inverse_dynamics", "tau", tau)

    def _closed(self, config: ConfigurationLike, field: str | Field, check: bool) -> Configuration:
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

    def joint_rates(self, config: ConfigurationLike, V_m: FieldVector, *, field: str | Field = "float") -> np.ndarray:
        """``qd_all = P Omega V_m`` (eqs. 10, 14, 20): the rates of every joint coordinate, in the
        order of :meth:`all_coordinate_names`, in ``field`` (float by default). ``O(n_S^2)``."""
        check_length("V_m", V_m, self.counts.m)
        fld = self.field_of(field)
        cfg = fld.configuration(as_configuration(config, self.scene, "config"), self.tree)
        rates, omega = joint_rate_maps(self, cfg, fld, with_task=True)
        return finite_result("joint_rates", "qd_all", all_rates(rates, omega.v @ field_vector(fld, V_m)))

    def motion(self, config: ConfigurationLike, V_m: FieldVector, tau: FieldVector | None = None,
               eta_m: FieldVector | None = None, *, dV_m: FieldVector | None = None, eta_f: FieldVector | None = None,
               field: str | Field = "float", loop_forces: bool = True) -> JointMotion:
        """Everything about the motion at one state from one evaluation of model (32): a
        :class:`~symgen.motion.JointMotion` with ``qd_all``, ``qdd_all`` (every joint, in the order
        of :meth:`all_coordinate_names`), ``dV_m``, ``eta_f``, ``tau`` and the loop forces ``lam``
        (:meth:`loop_forces`). Forward dynamics: give ``tau`` (and ``eta_m``); given motion: give
        ``dV_m`` (and ``eta_f``). In ``field`` (float by default), ``O(n_S^2 + n^3)``."""
        from .motion import joint_motion

        return joint_motion(self, config, V_m, tau=tau, dV_m=dV_m, eta_m=eta_m, eta_f=eta_f, field=field,
                            forces=loop_forces)

    def joint_accelerations(self, config: ConfigurationLike, V_m: FieldVector, tau: FieldVector | None = None,
                            eta_m: FieldVector | None = None, *, dV_m: FieldVector | None = None,
                            field: str | Field = "float") -> np.ndarray:
        """``qdd_all``, the accelerations of every joint coordinate (dependent ones included, in the
        order of :meth:`all_coordinate_names`), under ``tau`` (forward dynamics, eq. 32) or for a
        given ``dV_m`` (then ``tau`` is not needed): :meth:`motion`'s ``qdd_all``.

        ``qdd = [J_m; J_f]^-1 ([dV_m; 0] - d[J_m; J_f]/dt qd)`` (eqs. 17-19 differentiated), then
        eq. (11) differentiated: ``qdd_all = P qdd + dP/dt qd``."""
        return self.motion(config, V_m, tau, eta_m, dV_m=dV_m, field=field, loop_forces=False).qdd_all

    def loop_forces(self, config: ConfigurationLike, V_m: FieldVector, tau: FieldVector | None = None,
                    eta_m: FieldVector | None = None, *, dV_m: FieldVector | None = None,
                    eta_f: FieldVector | None = None, field: str | Field = "float") -> np.ndarray:
        """``lam``: the force of every loop-closure constraint, component by component, in the order
        of :meth:`constraint_force_names` (:meth:`motion`'s ``lam``).

        Component ``k`` of a constraint between frames A and B is the force (``vx, vy, vz`` ->
        ``f_x, f_y, f_z``) or moment about A's origin (``wx, wy, wz`` -> ``m_x, m_y, m_z``) that
        the constraint exerts on the body of frame A, in A's axes; the body of B receives the
        opposite. These are the Lagrange multipliers of ``M qdd + h = tau + T^T lam``
        (:mod:`symgen.steps.loop_forces` derives them from eqs. 9, 12 and 25-31). Where model (32)
        has ``eta_f``: ``eta_f = -T_c^-T T_a1^T lam`` (``-lam`` for ``constraint_forces:
        operational``).

        Forward dynamics: give ``tau`` (and ``eta_m``). Inverse dynamics: give ``dV_m`` (and
        ``eta_f``, ``eta_m``); ``tau`` then follows from :meth:`inverse_dynamics`."""
        return self.motion(config, V_m, tau, eta_m, dV_m=dV_m, eta_f=eta_f, field=field).lam

    def constraint_wrenches(self, config: ConfigurationLike, V_m, tau=None, eta_m=None, *, dV_m=None, eta_f=None,
                            axes: str = "A") -> dict[str, np.ndarray]:
        """The :meth:`loop_forces` of each constraint as one wrench ``[f; m]`` (its missing
        components zero) on the body of frame A, moment about A's origin, in A's axes or, with
        ``axes="world"`` or ``axes="B"``, in the world's or frame B's (:mod:`symgen.constraint_wrenches`).
        Float."""
        from .constraint_wrenches import constraint_wrenches

        lam = self.loop_forces(config, V_m, tau, eta_m, dV_m=dV_m, eta_f=eta_f)
        return constraint_wrenches(self, config, lam, axes)

    def task_rates(self, config: ConfigurationLike, qd_all, qdd_all=None) -> tuple[np.ndarray, np.ndarray | None]:
        """``(V_m, dV_m)`` from the rates (and accelerations) of every joint coordinate, in the order
        of :meth:`all_coordinate_names`: ``V_m = J_m_all qd_all`` (eq. 17 over all coordinates) and
        ``dV_m = J_m_all qdd_all + dJ_m_all/dt qd_all`` (``None`` without ``qdd_all``), for every
        kind of task (joint rates, a frame's twist components, gamma-weighted frames). The inverse of
        :meth:`joint_rates` and :meth:`joint_accelerations` on states that meet the constraints.
        Float."""
        n_all = self.tree.n_coords
        check_length("qd_all", qd_all, n_all)
        check_length("qdd_all", qdd_all, n_all)
        fld = self.float_field
        cfg = fld.configuration(as_configuration(config, self.scene, "config"), self.tree)
        qd = np.asarray(qd_all, dtype=float)
        rows = motion_rows(fld, tree_kinematics(self.tree, fld, cfg, qd), self.scene.motion)   # J_m_all, eq. (17)
        v_m = finite_result("task_rates", "V_m", rows.v @ qd)
        if qdd_all is None:
            return v_m, None
        return v_m, finite_result("task_rates", "dV_m", rows.v @ np.asarray(qdd_all, dtype=float) + rows.d @ qd)

    def frame_pose(self, config: ConfigurationLike, name: str, *,
                   field: str | Field = "float") -> tuple[np.ndarray, np.ndarray]:
        """``(R_W_F, p_W_F)`` of the named frame ``F`` at ``config``: its axes and origin in the
        world, in ``field`` (floats by default). ``O(N)``.

        This and the methods below (:mod:`symgen.frame_kinematics`: conventions, and the functions
        the code generator traces) are what a whole-body controller asks of a model."""
        from .frame_kinematics import model_frame_pose

        return model_frame_pose(self, config, name, field=field)

    def frame_jacobian(self, config: ConfigurationLike, name: str, *, axes: str = "local",
                       field: str | Field = "float", check_closure: bool = True) -> np.ndarray:
        """``J`` (``6 x n``): the twist ``[v; w]`` of frame ``name`` is ``J qd`` (``qd`` of eq. 14),
        in the frame's axes (``axes="local"``) or the world's (``"world_aligned"``). ``O(N n)``."""
        from .frame_kinematics import model_frame_jacobian

        return model_frame_jacobian(self, config, name, axes=axes, field=field, check_closure=check_closure)

    def frame_drift(self, config: ConfigurationLike, qd: FieldVector, name: str, *, axes: str = "local",
                    field: str | Field = "float", check_closure: bool = True) -> np.ndarray:
        """``J̇ qd``: the classical acceleration ``[a; dw]`` of frame ``name``'s origin at ``qdd = 0``
        (Pinocchio's ``getFrameClassicalAcceleration``), in ``axes``. ``O(N n)``."""
        from .frame_kinematics import model_frame_drift

        return model_frame_drift(self, config, qd, name, axes=axes, field=field, check_closure=check_closure)

    def center_of_mass(self, config: ConfigurationLike, *, field: str | Field = "float") -> np.ndarray:
        """The centre of mass in world axes. ``O(N)``."""
        from .frame_kinematics import model_center_of_mass

        return model_center_of_mass(self, config, field=field)

    def com_jacobian(self, config: ConfigurationLike, *, field: str | Field = "float",
                     check_closure: bool = True) -> np.ndarray:
        """``J_c`` (``3 x n``, world axes): ``dc/dt = J_c qd``. ``O(N n)``."""
        from .frame_kinematics import model_com_jacobian

        return model_com_jacobian(self, config, field=field, check_closure=check_closure)

    def centroidal_momentum(self, config: ConfigurationLike, qd: FieldVector, *, field: str | Field = "float",
                            check_closure: bool = True) -> np.ndarray:
        """``h = [linear; angular]``: the momentum in world axes, the angular part about the centre
        of mass (Pinocchio's ``computeCentroidalMomentum``), at rates ``qd`` (eq. 14). ``O(N)``."""
        from .frame_kinematics import model_centroidal_momentum

        return model_centroidal_momentum(self, config, qd, field=field, check_closure=check_closure)


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

        check_closed(scene, tree, ref)
        check_weighted_frames(scene, tree, ref)
    check_full_row_rank(t, scene.constraints.values())
    part = choose_partition(t, tree)
    counts = counts_from(tree, part, t.shape[0])
    model = Model(scene, tree, counts, part, ref)
    if check_reference:
        try:
            maps = evaluate_maps(model, ref, fld)
        except SingularConfigurationError as exc:
            if exc.what == TASK_MATRIX:
                raise _singular_task(model, task_matrix_at(model, ref, fld).v, exc.condition) from None
            raise SingularConfigurationError(f"{exc.what} at the reference configuration", exc.condition,
                                             "choose another q0 or other task coordinates") from None
        cond = np.linalg.cond(maps.A.v) if maps.A.v.size else 1.0
        if not np.isfinite(cond) or cond > MAX_TASK_CONDITION:
            raise _singular_task(model, maps.A.v, float(cond))
    return model


def _singular_task(model: Model, a: np.ndarray, cond: float) -> SingularConfigurationError:
    """The error for a singular ``A = [J_m; J_f]`` at ``q0``, naming the motion entry to blame."""
    from .task_frames import singular_task_hint

    return SingularConfigurationError(f"{TASK_MATRIX} at the reference configuration", cond,
                                      singular_task_hint(model.scene.motion, a, MAX_TASK_CONDITION))


def check_closed(scene: Scene, tree: Tree, ref: Configuration) -> None:
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
