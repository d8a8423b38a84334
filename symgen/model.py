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

import numpy as np
import sympy as sp

from .arith import Field, make_field
from .errors import ConstraintError, SingularConfigurationError, StateError
from .jet import Jet
from .scene import Scene
from .state import Configuration, as_configuration
from .kinematics import constraint_matrix, tree_kinematics
from .steps import (Counts, Maps, Partition, all_rates, check_full_row_rank, choose_partition, counts_from,
                    evaluate_maps, jet_names, joint_space_model, subsystem_terms, task_space_model)
from .tree import Tree, build_tree

#: [J_m; J_f] at the reference configuration must be better conditioned than this
MAX_TASK_CONDITION = 1e10


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
        return ModelData(fld, maps, qd_v, v_m, x, terms.M_S, terms.C_S, terms.G_S, task.M, task.C, task.G,
                         joint.M, joint.C, joint.G, b, eta)

    def _joint_rates(self, maps: Maps, fld, qd, V_m) -> np.ndarray:
        """``qd`` of eq. (14): as given, from ``V_m`` by eq. (20) (``qd = Omega V_m``), or zero."""
        if V_m is not None:
            return maps.Omega.v @ np.asarray(V_m, dtype=fld.dtype)
        if qd is not None:
            return np.asarray(qd, dtype=fld.dtype)
        return fld.zeros((self.counts.n,))

    def forward_dynamics(self, config: Configuration, V_m, tau, eta_m=None) -> tuple[np.ndarray, np.ndarray]:
        """Solve (32) for ``(dV_m, eta_f)`` given ``tau`` (float). ``O(n^3)`` reference solve.
        ``config`` as in :meth:`evaluate`."""
        config = as_configuration(config, self.scene, "config")
        _check_length("tau", tau, self.counts.n)
        d = self.evaluate(config, V_m=V_m, eta_m=eta_m)
        m = self.counts.m
        rhs = d.maps.A_inv.v.T @ np.asarray(tau, float) - d.C[:, :m] @ d.V_m - d.G
        cond = np.linalg.cond(d.M[:m, :m])
        if not np.isfinite(cond) or cond > 1e14:
            raise SingularConfigurationError("the motion block of M (eq. 32)", float(cond))
        dv = np.linalg.solve(d.M[:m, :m], rhs[:m])
        eta_f = rhs[m:] - d.M[m:, :m] @ dv
        return dv, eta_f

    def inverse_dynamics(self, config: Configuration, V_m, dV_m, eta_f=None, eta_m=None) -> np.ndarray:
        """``tau = [J_m; J_f]^T (M [dV_m; 0] + C [V_m; 0] + G + [0; eta_f])`` (float).
        ``config`` as in :meth:`evaluate`."""
        d = self.evaluate(as_configuration(config, self.scene, "config"), V_m=V_m, eta_m=eta_m)
        m, n = self.counts.m, self.counts.n
        ef = np.zeros(n - m) if eta_f is None else np.asarray(eta_f, float)
        lhs = d.M[:, :m] @ np.asarray(dV_m, float) + d.C[:, :m] @ d.V_m + d.G + np.concatenate([np.zeros(m), ef])
        return d.maps.A.v.T @ lhs

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


def _check_length(name: str, value, expected: int) -> None:
    if value is not None and np.shape(value) != (expected,):
        raise StateError(f"{name} must have shape ({expected},), got {np.shape(value)}")


def reference_configuration(scene: Scene) -> Configuration:
    """The scene's ``q0`` as a float configuration."""
    return Configuration({j.name: j.kind.reference_position(j.q0, scene.value_of)
                          for j in scene.joints.values() if j.kind.dof})


def derive(scene: Scene, *, check_reference: bool = True) -> Model:
    """Steps 1-8 and the structural checks; returns the :class:`Model` (cheap: no symbolics).

    Raises typed errors for redundant constraints, an impossible partition, an inconsistent
    reference configuration, or a singular ``[J_m; J_f]`` at the reference configuration.
    """
    from .closure import closure_residual

    scene.validate()
    scene = copy.deepcopy(scene)        # the model keeps its own copy: later edits need a new derive
    tree = build_tree(scene)
    ref = reference_configuration(scene)
    fld = make_field("float", tree.parameters)
    kin = tree_kinematics(tree, fld, ref)
    t = constraint_matrix(kin, scene.constraints.values()).v
    check_full_row_rank(t, scene.constraints.values())
    part = choose_partition(t, tree)
    counts = counts_from(tree, part, t.shape[0])
    model = Model(scene, tree, counts, part, ref)
    if check_reference:
        res = closure_residual(model, ref)
        if res.size and np.max(np.abs(res)) > 1e-8:
            worst = int(np.argmax(np.abs(res)))
            raise ConstraintError(f"constraint {_constraint_of_row(scene, worst)!r}",
                                  f"is violated by {np.max(np.abs(res)):.3g} at the reference configuration "
                                  "(q0); give joint positions that close the loop")
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


def _constraint_of_row(scene: Scene, row: int) -> str:
    for con in scene.constraints.values():
        if row < con.dim:
            return con.name
        row -= con.dim
    return "?"
