"""An independent reference: the Lagrange-multiplier, index-reduced DAE of the open tree.

Nothing here uses model (32), the maps of Steps 5-11 (``P``, ``Omega``, ``T_S``) or the generated
code. On *all* joint coordinates ``q`` (revolute and prismatic joints only) of the spanning tree:

    M(q) = sum_b J_b^T M_b J_b + diag(rotor inertias)              (J_b: body Jacobian, [v; w])
    h(q, qd) = dM/dt qd - 1/2 [qd^T (dM/dq_k) qd]_k                (Lagrange's equations)
    g(q) = dU/dq,  U = -sum_b m_b gravity . c_b + sum_j k_j (q_j - q_spring,j)^2 / 2
                                                                    (c_b: world centre of mass)

with ``dM/dq_k`` and ``dc_b/dq_k`` taken exactly by one jet pass along each unit rate ``e_k``
(:func:`symgen.kinematics.tree_kinematics`), ``M_b`` the body's spatial inertia about its frame
origin written out below, and the constraints ``T qd = 0`` of eq. (6)
(:func:`symgen.kinematics.constraint_matrix`) differentiated once (index 1):

    [ M  T^T ] [ qdd ]   [ E tau - D^T eta_m - h - g - xi ]
    [ T   0  ] [ mu  ] = [ -dT/dt qd - 2 alpha T qd + beta^2 r(q) ]

``E`` places ``tau`` on the independent coordinates (eq. 14), ``D`` is the contact-force map of
eq. (16) over all coordinates, ``xi`` the joint friction of eq. (22) on every joint. The last row
is Baumgarte's stabilization ``s'' + 2 alpha s' + beta^2 s = 0`` of ``s = -r`` (``r`` the position
residual of :func:`symgen.closure.closure_residual`, whose rate is ``-T qd``), gains stated by the
caller. The drift of a run is measured with :func:`~symgen.closure.closure_residual` itself.
"""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from ..closure import closure_residual, kinematics_residual
from ..kinematics import constants, constraint_matrix, tree_kinematics
from ..steps import contact_rows, motion_rows
from ..math.configuration import Configuration
from .errors import SimulationError, SimulationInputError
from .forcing import CheckedForce

#: default Baumgarte gains (1/s) of the DAE reference: critically damped, time constant 0.1 s
ALPHA = 10.0
BETA = 10.0


def spatial_inertia(mass: float, com, inertia) -> np.ndarray:
    """A rigid body's 6x6 inertia about its frame origin for twists ``[v; w]``:
    ``[[m 1, -m c^], [m c^, I_c - m c^ c^]]`` (parallel-axis theorem)."""
    c = np.asarray(com, dtype=float)
    ch = np.array([[0.0, -c[2], c[1]], [c[2], 0.0, -c[0]], [-c[1], c[0], 0.0]])
    out = np.zeros((6, 6))
    out[:3, :3] = mass * np.eye(3)
    out[:3, 3:] = -mass * ch
    out[3:, :3] = mass * ch
    out[3:, 3:] = np.asarray(inertia, dtype=float) - mass * ch @ ch
    return out


class LagrangeDAE:
    """The index-1 DAE of the open tree with stated Baumgarte gains (see module docstring)."""

    def __init__(self, model, *, tau=None, eta_m=None, alpha: float = ALPHA, beta: float = BETA):
        for j in model.tree.joints:
            if j.kind.position_is_rotation:
                raise SimulationInputError(f"joint {j.name!r}: the DAE reference handles revolute and prismatic "
                                           "joints only")
        self.model, self.tree = model, model.tree
        self.fld = model.float_field
        const = constants(self.tree, self.fld)
        self.n_all = self.tree.n_coords
        self.body_inertia = [(b.index, spatial_inertia(float(const.mass[b.index]), const.com[b.index],
                                                       const.inertia[b.index]))
                             for b in self.tree.bodies if not b.massless]
        self.masses = np.array(const.mass, dtype=float)
        self.coms = const.com
        self.gravity = np.asarray(const.gravity, dtype=float)
        self.rotor, self.viscous, self.coulomb = np.zeros(self.n_all), np.zeros(self.n_all), np.zeros(self.n_all)
        self.stiffness, self.springref = np.zeros(self.n_all), np.zeros(self.n_all)
        for k, j in enumerate(self.tree.joints):
            for c in j.coords:
                self.rotor[c], self.viscous[c], self.coulomb[c] = (float(const.rotor[k]), float(const.viscous[k]),
                                                                   float(const.coulomb[k]))
                self.stiffness[c], self.springref[c] = float(const.stiffness[k]), float(const.springref[k])
        self.independent = list(model.partition.independent)
        cf = model.scene.contact_forces
        self.tau = CheckedForce(tau, model.counts.n, "tau")
        self.eta_m = CheckedForce(eta_m, len(cf.components) if cf else 0, "eta_m")
        self.alpha, self.beta = float(alpha), float(beta)
        self.calls = 0

    def configuration(self, q) -> Configuration:
        return Configuration({j.name: float(q[j.coords[0]]) for j in self.tree.joints if j.coords})

    def motion_map(self, kin) -> np.ndarray:
        """``V_m = J qd`` over all coordinates: Step 10's motion rows (eq. 17 before ``P``)."""
        return motion_rows(self.fld, kin, self.model.scene.motion).v

    def contact_map(self, kin) -> np.ndarray:
        """``D_m`` over all coordinates: Step 9's contact rows (eq. 16 before ``P``)."""
        return contact_rows(self.fld, kin, self.model.scene.contact_forces).v

    def terms(self, q, qd):
        """``(M, h + g, T, dT/dt qd, kin)`` at ``(q, qd)``: one exact jet pass along each unit
        rate ``e_k`` (``dM/dq_k``, ``dc_b/dq_k``) and one along ``qd`` (``dT/dt``)."""
        cfg = self.configuration(q)
        constraints = self.model.scene.constraints.values()
        mass = np.diag(self.rotor)
        dmass, grad_u = [], np.zeros(self.n_all)
        for k in range(self.n_all):
            kin = tree_kinematics(self.tree, self.fld, cfg, np.eye(self.n_all)[k])
            dm = np.zeros((self.n_all, self.n_all))
            for b, m_b in self.body_inertia:
                jac = kin.jacobian[b]
                if k == 0:
                    mass = mass + jac.v.T @ m_b @ jac.v
                dm += jac.d.T @ m_b @ jac.v + jac.v.T @ m_b @ jac.d
                grad_u[k] -= self.masses[b] * self.gravity @ (kin.pos[b].d + kin.rot[b].d @ self.coms[b])
            dmass.append(dm)
        mdot = sum(qd[k] * dmass[k] for k in range(self.n_all))
        h = mdot @ qd - 0.5 * np.array([qd @ dmass[k] @ qd for k in range(self.n_all)])
        kin = tree_kinematics(self.tree, self.fld, cfg, qd)
        if constraints:
            t_jet = constraint_matrix(kin, constraints)
            t_mat, tdot_qd = t_jet.v, t_jet.d @ qd
        else:
            t_mat, tdot_qd = np.zeros((0, self.n_all)), np.zeros(0)
        grad_u += self.stiffness * (np.asarray(q, dtype=float) - self.springref)
        return mass, h + grad_u, t_mat, tdot_qd, kin

    def rhs(self, t, y) -> np.ndarray:
        self.calls += 1
        q, qd = y[: self.n_all], y[self.n_all:]
        mass, bias, t_mat, tdot_qd, kin = self.terms(q, qd)
        v_m = self.motion_map(kin) @ qd
        force = np.zeros(self.n_all)
        force[self.independent] = self.tau(t, q, v_m)
        force -= self.contact_map(kin).T @ self.eta_m(t, q, v_m) if self.eta_m.size else 0.0
        force -= bias + self.viscous * qd + self.coulomb * np.sign(qd)
        nc = t_mat.shape[0]
        kkt = np.block([[mass, t_mat.T], [t_mat, np.zeros((nc, nc))]])
        rhs = force
        if nc:
            r = self.residual(kin, q)
            rhs = np.concatenate([force, -tdot_qd - 2 * self.alpha * t_mat @ qd + self.beta ** 2 * r])
        return np.concatenate([qd, np.linalg.solve(kkt, rhs)[: self.n_all]])

    def residual(self, kin, q) -> np.ndarray:
        """Position residual of every constraint at positions ``q`` (:func:`symgen.closure.kinematics_residual`)."""
        return kinematics_residual(kin, self.model.scene.constraints.values(), self.configuration(q))

    def initial_rates(self, q, v_m) -> np.ndarray:
        """``qd`` with ``[J_m; T] qd = [V_m; 0]`` (all coordinates)."""
        kin = tree_kinematics(self.tree, self.fld, self.configuration(q))
        constraints = self.model.scene.constraints.values()
        t_mat = constraint_matrix(kin, constraints).v if constraints else np.zeros((0, self.n_all))
        a = np.vstack([self.motion_map(kin), t_mat])
        if a.shape[0] != self.n_all:
            raise SimulationInputError("the DAE reference needs m + n_c = N_all (no passive independent "
                                       "coordinates); this scene has n_p < n_c or u2 coordinates")
        return np.linalg.solve(a, np.concatenate([np.asarray(v_m, float), np.zeros(t_mat.shape[0])]))


@dataclass
class DAEResult:
    """Times, all-coordinate positions and rates, cost and drift of a DAE run."""

    times: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    rhs_calls: int
    wall_time: float
    drift: float


def dae_simulate(model, t_end: float, x0, *, tau=None, eta_m=None, rtol: float = 1e-12, atol: float = 1e-12,
                 method: str = "DOP853", alpha: float = ALPHA, beta: float = BETA) -> DAEResult:
    """Integrate :class:`LagrangeDAE` from the simulation state ``x0 = [q; V_m]`` (revolute and
    prismatic joints: ``q`` is indexed like the joint coordinates)."""
    dae = LagrangeDAE(model, tau=tau, eta_m=eta_m, alpha=alpha, beta=beta)
    x0 = np.asarray(x0, dtype=float)
    q0, v0 = x0[: dae.n_all], x0[dae.n_all:]
    y0 = np.concatenate([q0, dae.initial_rates(q0, v0)])
    start = time.perf_counter()
    sol = solve_ivp(dae.rhs, (0.0, float(t_end)), y0, method=method, rtol=rtol, atol=atol)
    wall = time.perf_counter() - start
    if sol.status != 0:
        raise SimulationError(f"DAE reference ({method}) failed: {sol.message}")
    q = sol.y[: dae.n_all].T
    drift = max(float(np.max(np.abs(closure_residual(model, dae.configuration(row))), initial=0.0)) for row in q)
    return DAEResult(sol.t, q, sol.y[dae.n_all:].T, dae.calls, wall, drift)
