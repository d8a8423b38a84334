"""The identification regressor: Section 4's ``Y`` with the required motion equal to the actual one.

With ``V_mr = V_m`` and ``dV_mr = dV_m``, eq. (36) gives ``X_r = X`` and eqs. (34)-(37) are the
inverse dynamics of model (32) written linearly in the parameters (:func:`symgen.control.law.regressor`)::

    Y P = T_S^T (M_S dX + C_S X + G_S) + D_m^T eta_m = tau - J_f^T eta_f            (A = [J_m; J_f])

because ``A^T M = T_S^T M_S B`` (``B = T_S A^-1``): ``Y`` is already the regressor of the joint
forces ``tau`` on the independent coordinates (eq. 14). ``P = [P_r; P_m]``: 10 per massive body
(``m, h, I_o`` in the body's internal frame), ``[I*, b, c]`` per 1-DOF joint, and the contact law's
``P_m`` (eq. 37) when the contact forces ``eta_m`` are not measured.

What one sample contributes (its *channels*):

* ``eta_f`` measured, or no ``eta_f`` (``n = m``): the ``n`` rows ``Y P = tau - J_f^T eta_f``;
* ``eta_f`` not measured (``n > m``): the ``m`` rows ``Omega^T Y P = Omega^T tau``, since
  ``Omega^T J_f^T = (J_f Omega)^T = 0`` (eq. 18): the constraint forces drop out.

Measured ``eta_m`` are moved to the left (``- D_m^T eta_m``) and ``P_m`` is left out.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..control.contact import ContactLaw, contact_velocity
from ..control.law import default_parameters, regressor
from ..control.parameters import ParameterSet
from .states import State, check_one_dof


@dataclass(frozen=True)
class Problem:
    """What is identified on a scene and from which measurements."""

    model: object
    params: ParameterSet
    contact: ContactLaw | None      # the law whose P_m is identified (eta_m not measured)
    eta_f_measured: bool
    eta_m_measured: bool

    @property
    def projected(self) -> bool:
        """True when the rows are ``Omega^T`` of the joint forces (``eta_f`` unknown, ``n > m``)."""
        return not self.eta_f_measured and self.model.counts.n > self.model.counts.m

    @property
    def channels(self) -> list[str]:
        """Names of one sample's rows: the coordinates of ``qd``, or the motion coordinates (``V_m``)."""
        return motion_names(self.model) if self.projected else self.model.coordinate_names()


def motion_names(model) -> list[str]:
    """``V_m``'s components: ``frame.component`` (``task.component`` for several weighted frames),
    then joint names (:meth:`~symgen.scene.elements.Motion.labels`)."""
    return model.scene.motion.labels()


def make_problem(model, *, eta_f_measured: bool = False, eta_m_measured: bool = False,
                 contact: ContactLaw | None = None) -> Problem:
    """The problem on ``model``: every parameter of ``P_r`` with the scene's values as prior, plus
    ``P_m`` of ``contact`` (default: the scene's contact components with zero prior) unless
    ``eta_m`` is measured."""
    check_one_dof(model)
    law = None
    if model.scene.contact_forces is not None and not eta_m_measured:
        law = contact or ContactLaw.for_scene(model.scene)
    return Problem(model, default_parameters(model, law), law, eta_f_measured, eta_m_measured)


def evaluate_state(model, state: State):
    """Model data at ``state`` and ``dV_m = (A qdd + dA/dt qd)_m`` (eq. 17 differentiated)."""
    data = model.evaluate(state.config, qd=state.qd)
    dv = data.maps.A.v @ state.qdd + data.maps.A.d @ state.qd
    return data, dv[:model.counts.m]


def sample_rows(problem: Problem, state: State, data=None, dv_m=None):
    """``(W, T)``: this sample's regressor rows (channels x parameters) and the map ``T`` that takes
    the measured joint forces ``tau`` to the same rows (identity, or ``Omega^T``)."""
    model = problem.model
    if data is None:
        data, dv_m = evaluate_state(model, state)
    y, _, _ = regressor(model, data, problem.params, data.V_m, dv_m, contact=problem.contact)
    y = np.asarray(y, float)
    if problem.projected:
        omega_t = np.asarray(data.maps.Omega.v, float).T
        return omega_t @ y, omega_t
    return y, np.eye(model.counts.n)


def measured_side(problem: Problem, data, t_map, tau, eta_f=None, eta_m=None) -> np.ndarray:
    """The rows' right-hand side: ``T (tau - J_f^T eta_f - D_m^T eta_m)`` with the measured forces."""
    rhs = np.asarray(tau, float).copy()
    if eta_f is not None and not problem.projected and len(eta_f):
        rhs -= np.asarray(data.maps.J_f.v, float).T @ np.asarray(eta_f, float)
    if eta_m is not None and problem.eta_m_measured:
        rhs -= np.asarray(data.maps.D_m.v, float).T @ np.asarray(eta_m, float)
    return t_map @ rhs


def stacked_regressor(problem: Problem, states) -> np.ndarray:
    """``W``: the rows of every state stacked (``len(states) * channels`` x parameters)."""
    return np.vstack([sample_rows(problem, s)[0] for s in states])


def true_forces(problem: Problem, state: State, *, eta_f=None, law: ContactLaw | None = None):
    """``(tau, eta_m)``: the joint forces model (32) needs for ``state`` with the scene's parameters
    (inverse dynamics, the reference for simulated data), the contact forces of ``law`` at the
    state's contact velocity, and the constraint forces ``eta_f`` (zero if not given)."""
    model = problem.model
    data, dv = evaluate_state(model, state)
    eta_m = None
    if law is not None:
        eta_m = np.asarray(law.forces(contact_velocity(data), data.field), float)
    tau = model.inverse_dynamics(state.config, data.V_m, dv, eta_f, eta_m)
    return np.asarray(tau, float), eta_m
