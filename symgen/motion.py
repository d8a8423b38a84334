"""The motion of every joint and the loop forces at one state, from one evaluation of model (32).

With ``A = [J_m; J_f]`` and the evaluated model: forward dynamics gives ``(dV_m, eta_f)`` from
``tau`` (or inverse dynamics ``tau`` from ``dV_m``, eq. 32); then ``qdd = A^-1 ([dV_m; 0] - dA/dt
qd)`` (eqs. 17-19 differentiated) and ``qdd_all = P qdd + dP/dt qd`` (eq. 11 differentiated); the
loop forces are the Lagrange multipliers of the spanning tree's equations
(:mod:`symgen.steps.loop_forces`).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol

import numpy as np

from .errors import StateError
from .model_solves import Evaluation, check_length, field_vector, finite_result, solve_forward, solve_inverse
from .steps import all_accelerations, all_rates, closure_multipliers, rate_bias, tree_forces
from .steps.pipeline import DerivedModel

if TYPE_CHECKING:
    from .math.configuration import Configuration, ConfigurationLike
    from .math.fields import Field
    from .math.scalar import FieldVector
    from .steps.structure import Counts


class MotionModel(DerivedModel, Protocol):
    """What :func:`joint_motion` reads of a :class:`symgen.model.Model` (which imports this module,
    so it is named by what is used): the steps' scene, tree and partition, the counts, the
    closed-configuration check and the evaluation of model (32)."""

    @property
    def counts(self) -> Counts: ...

    def _closed(self, config: ConfigurationLike, field: str | Field, check: bool) -> Configuration: ...

    def evaluate(self, config: ConfigurationLike, *, qd: FieldVector | None = None, V_m: FieldVector | None = None,
                 field: str | Field = "float", eta_m: FieldVector | None = None,
                 gravity: bool = True) -> Evaluation: ...


@dataclass(frozen=True)
class JointMotion:
    """One state's motion: rates and accelerations of every joint coordinate (eqs. 10-11), the
    task-space ``dV_m`` and constraint forces ``eta_f`` of model (32), the joint forces ``tau``
    and the loop forces ``lam`` (``None`` when not asked for)."""

    qd_all: np.ndarray
    qdd_all: np.ndarray
    dV_m: np.ndarray
    eta_f: np.ndarray
    tau: np.ndarray
    lam: np.ndarray | None


def joint_motion(model: MotionModel, config: ConfigurationLike, V_m: FieldVector, *, tau: FieldVector | None = None,
                 dV_m: FieldVector | None = None, eta_m: FieldVector | None = None,
                 eta_f: FieldVector | None = None, field: str | Field = "float", forces: bool = True) -> JointMotion:
    """:meth:`symgen.model.Model.motion`: exactly one of ``tau`` (forward dynamics) and ``dV_m``
    (given motion, with ``eta_f`` when the scene has constraint forces) must be given."""
    if (tau is None) == (dV_m is None):
        raise StateError("give exactly one of tau (forward dynamics) and dV_m (given motion)")
    d = model.evaluate(model._closed(config, field, True), V_m=V_m, eta_m=eta_m, field=field)
    fld, n, m = d.field, model.counts.n, model.counts.m
    if tau is not None:
        check_length("tau", tau, n)
        tau = field_vector(fld, tau)
        dV_m, eta_f = solve_forward(d, tau)
    else:
        check_length("dV_m", dV_m, m)
        check_length("eta_f", eta_f, n - m)
        dV_m = field_vector(fld, dV_m)
        eta_f = fld.zeros((n - m,)) if eta_f is None else field_vector(fld, eta_f)
        tau = solve_inverse(d, dV_m, eta_f)
    return motion_of_solution(model, d, dV_m, eta_f, tau, forces)


def motion_of_solution(model: MotionModel, d: Evaluation, dV_m: np.ndarray, eta_f: np.ndarray, tau: np.ndarray,
                       forces: bool = True) -> JointMotion:
    """The :class:`JointMotion` of an evaluation ``d`` of model (32) and a solution of it
    (``dV_m, eta_f, tau`` in ``d``'s field, as :func:`~symgen.model_solves.solve_forward` or
    :func:`~symgen.model_solves.solve_inverse` returns them): eqs. (17)-(19) and (11)
    differentiated for the joint accelerations, the loop forces with ``forces``. What
    :func:`joint_motion` does after its solve, for a caller that holds both already."""
    fld, n, m = d.field, model.counts.n, model.counts.m
    maps = d.maps
    qd_all = all_rates(maps.rates, d.qd)
    rest = fld.zeros((n - m,))
    qdd = maps.A_inv.v @ np.concatenate([dV_m, rest]) + maps.A_inv.d @ np.concatenate([d.V_m, rest])
    bias = rate_bias(fld, maps.constraints, maps.blocks, model.partition, qd_all)
    qdd_all = finite_result("joint_accelerations", "qdd_all", all_accelerations(maps.rates, qdd, bias))
    lam = None
    if forces:
        tau_tree = tree_forces(fld, maps.kin, qd_all, qdd_all)
        tau_all = fld.zeros((model.tree.n_coords,))
        tau_all[list(model.partition.independent)] = tau
        residual = tau_tree - tau_all + maps.contact.D_m_all.v.T @ d.eta_m
        lam = finite_result("loop_forces", "lam", closure_multipliers(fld, maps.blocks, model.partition, residual))
    return JointMotion(qd_all, qdd_all, finite_result("motion", "dV_m", dV_m), eta_f,
                       finite_result("motion", "tau", tau), lam)
