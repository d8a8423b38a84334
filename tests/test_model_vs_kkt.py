"""Model (32) against an independent Lagrange-multiplier (KKT) solve of the unconstrained tree.

For every built-in constrained scene, at 10 random consistent states (loops closed, qd in the
constraint null space), the task accelerations dV_m and the constraint forces eta_f from the
forward dynamics of (32) must equal those of ``tests/reference/tree_dynamics.py`` (world-frame
spatial algebra, its own recursion, its own constraint rows) to 1e-9 relative.
"""
import numpy as np
import pytest

from symgen.io.builtin import get_scene
from symgen.closure import random_consistent_states
from symgen.model import derive
from tests.reference import tree_dynamics as ref

STATES = 10
REL_TOL = 1e-9
#: a closed state must satisfy the reference's own position residuals to this
CLOSURE_TOL = 1e-10

SCENES = ["arm_on_plane", "multi_arm:h=2", "multi_arm:h=3", "four_bar", "five_bar", "stewart", "chain:n=4"]


def _close(a, b, tol=REL_TOL):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return np.linalg.norm(a - b) <= tol * max(1.0, np.linalg.norm(b))


def _states(model, seed):
    return random_consistent_states(model, STATES, seed=seed, spread=0.2)


@pytest.fixture(scope="module", params=SCENES)
def scene_and_model(request):
    scene = get_scene(request.param)
    return scene, derive(scene)


def test_random_states_are_consistent_for_the_reference(scene_and_model):
    scene, model = scene_and_model
    for cfg, v_m in _states(model, seed=1):
        assert np.max(np.abs(ref.constraint_residual(scene, cfg)), initial=0.0) < CLOSURE_TOL
        d = model.evaluate(cfg, V_m=v_m)
        qd_all = d.maps.P.v @ d.qd
        k, _ = ref.constraint_rows(scene, cfg, qd_all)
        assert np.linalg.norm(k @ qd_all) <= 1e-10 * max(1.0, np.linalg.norm(qd_all))


def test_forward_dynamics_matches_lagrange_multiplier_solve(scene_and_model):
    scene, model = scene_and_model
    rng = np.random.default_rng(2)
    part = model.partition
    for cfg, v_m in _states(model, seed=3):
        tau = np.concatenate([rng.uniform(-5, 5, len(part.actuated)), np.zeros(len(part.u2))])
        eta_m = rng.uniform(-2, 2, model.counts.m) if scene.contact_forces else None
        dv, eta_f = model.forward_dynamics(cfg, v_m, tau, eta_m)

        d = model.evaluate(cfg, V_m=v_m, eta_m=eta_m)
        qd_all = d.maps.P.v @ d.qd
        tau_all = np.zeros(model.tree.n_coords)
        tau_all[list(part.actuated)] = tau[: len(part.actuated)]
        qdd_all, lam = ref.kkt(scene, cfg, qd_all, tau_all, eta_m)

        assert _close(dv, ref.task_acceleration(scene, cfg, qd_all, qdd_all))
        # generalized constraint forces on the independent coordinates: J_f^T eta_f = -P^T K^T lam
        k, _ = ref.constraint_rows(scene, cfg, qd_all)
        assert _close(d.maps.J_f.v.T @ eta_f, -(d.maps.P.v.T @ (k.T @ lam)))
        if model.counts.np == 0 and scene.constraint_forces == "operational":
            # eta_f are the constraint forces the robot exerts, in the constraints' own axes
            assert _close(eta_f, -lam)


def test_inverse_dynamics_inverts_forward_dynamics(scene_and_model):
    scene, model = scene_and_model
    rng = np.random.default_rng(4)
    for cfg, v_m in _states(model, seed=5)[:3]:
        tau = rng.uniform(-5, 5, model.counts.n)
        tau[len(model.partition.actuated):] = 0.0
        dv, eta_f = model.forward_dynamics(cfg, v_m, tau)
        assert _close(model.inverse_dynamics(cfg, v_m, dv, eta_f), tau, 1e-8)
