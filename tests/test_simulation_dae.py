"""The simulation (model 32 through the generated code) agrees with an independent Lagrange-
multiplier index-1 DAE of the open tree (:mod:`symgen.simulation.dae`) to 1e-8."""
from __future__ import annotations

import numpy as np
import pytest

from symgen.simulation import LagrangeDAE, StateLayout, builtin_model, dae_simulate, simulate
from symgen.simulation.errors import SimulationInputError

#: the issue's bound on the joint positions at t_end
AGREEMENT = 1e-8
#: both integrations run well below it
SIM_TOL, DAE_TOL = 1e-11, 1e-10


def _compare(model, x0, t_end, **forces):
    sim = simulate(model, t_end, "DOP853", rtol=SIM_TOL, atol=SIM_TOL, backend="c", x0=x0, energy=False, **forces)
    dae = dae_simulate(model, t_end, x0, rtol=DAE_TOL, atol=DAE_TOL, **forces)
    return sim, dae


def test_four_bar_agrees_with_the_dae():
    model = builtin_model("four_bar")
    x0 = StateLayout(model).initial_state(V_m=[0.5])

    def crank_torque(t, q, v_m):
        return np.array([0.02 * np.sin(3 * t) - 0.01 * v_m[0]])

    sim, dae = _compare(model, x0, 1.0, tau=crank_torque)
    assert np.max(np.abs(sim.q() - dae.q[-1])) < AGREEMENT
    assert np.max(np.abs(sim.q() - x0[:4])) > 0.3            # the crank really moved
    assert dae.drift < 1e-9


@pytest.mark.slow
def test_arm_on_plane_agrees_with_the_dae_with_torque_friction_and_contact_forces():
    """Joint friction (viscous, every joint), rotor inertia, a holding torque plus a sine, and a
    contact force eta_m = 0.5 V_m + a cosine (dissipative: eta_m is what the robot exerts)."""
    model = builtin_model("arm_on_plane")
    tau0 = model.inverse_dynamics(model.reference, np.zeros(3), np.zeros(3), eta_f=np.array([5.0, 0, 0]),
                                  eta_m=np.zeros(3))

    def arm_torque(t, q, v_m):
        return tau0 + 0.05 * np.sin(2 * t + np.arange(6))

    def sliding_friction(t, q, v_m):
        return 0.5 * v_m + np.array([0.2, -0.1, 0.05]) * np.cos(t)

    x0 = StateLayout(model).initial_state(V_m=[0.05, -0.03, 0.1])
    sim, dae = _compare(model, x0, 1.0, tau=arm_torque, eta_m=sliding_friction)
    assert np.max(np.abs(sim.q() - dae.q[-1])) < AGREEMENT
    assert np.max(np.abs(sim.q() - x0[:6])) > 0.03
    assert dae.drift < 1e-9


def test_open_chain_agrees_with_the_dae_under_gravity():
    model = builtin_model("chain:n=3")
    x0 = StateLayout(model).initial_state(V_m=[0.5, -0.5, 0.5])
    sim, dae = _compare(model, x0, 0.5)
    assert np.max(np.abs(sim.q() - dae.q[-1])) < AGREEMENT
    np.testing.assert_allclose(sim.V_m(), dae.qd[-1], atol=AGREEMENT)


def test_dae_conserves_energy_on_its_own():
    """A check of the DAE's Lagrangian bias that does not involve symgen's model at all."""
    model = builtin_model("chain:n=3")
    dae = LagrangeDAE(model)
    x0 = StateLayout(model).initial_state(V_m=[1.0, -1.0, 0.5])
    run = dae_simulate(model, 1.0, x0, rtol=1e-12, atol=1e-12)

    def energy(q, qd):
        mass, *_ = dae.terms(q, np.zeros_like(q))
        cfg = dae.configuration(q)
        from symgen.kinematics import tree_kinematics

        kin = tree_kinematics(dae.tree, dae.fld, cfg)
        potential = -sum(dae.masses[b] * dae.gravity @ (kin.pos[b].v + kin.rot[b].v @ dae.coms[b])
                         for b, _ in dae.body_inertia)
        return 0.5 * qd @ mass @ qd + potential

    e = np.array([energy(q, qd) for q, qd in zip(run.q, run.qd)])
    kinetic_scale = max(0.5 * qd @ dae.terms(q, qd)[0] @ qd for q, qd in zip(run.q, run.qd))
    assert np.max(np.abs(e - e[0])) / kinetic_scale < 1e-9


def test_dae_refuses_spherical_joints():
    with pytest.raises(SimulationInputError, match="joint 's1'"):
        LagrangeDAE(builtin_model("stewart"))


@pytest.mark.slow
def test_comparison_detects_a_wrong_contact_force_sign():
    """Negative control: the DAE with eta_m reversed disagrees far beyond the bound, so the
    agreement above is not blind to how eta_m enters (D_m^T eta_m on the left-hand side)."""
    model = builtin_model("arm_on_plane")
    tau0 = model.inverse_dynamics(model.reference, np.zeros(3), np.zeros(3), eta_f=np.array([5.0, 0, 0]),
                                  eta_m=np.zeros(3))
    push = np.array([0.2, -0.1, 0.05])
    x0 = StateLayout(model).initial_state(V_m=[0.05, -0.03, 0.1])
    sim = simulate(model, 0.3, "DOP853", rtol=SIM_TOL, atol=SIM_TOL, backend="c", x0=x0, energy=False,
                   tau=lambda t, q, v: tau0, eta_m=lambda t, q, v: push)
    flipped = dae_simulate(model, 0.3, x0, rtol=DAE_TOL, atol=DAE_TOL, tau=lambda t, q, v: tau0,
                           eta_m=lambda t, q, v: -push)
    assert np.max(np.abs(sim.q() - flipped.q[-1])) > 1e3 * AGREEMENT
