"""Walk the step functions of Section 3.1 on the paper's §3.2 and §3.3 robots (and a four-bar),
checking each returned quantity against a hand-derived value, a finite difference of positions,
or an identity the paper states."""
from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

import symgen
from symgen import steps
from symgen.math.fields import ExactField, FloatField
from symgen.closure import closure_residual, random_consistent_states
from symgen.kinematics import tree_kinematics
from symgen.proofs import random_exact_state
from symgen.math.configuration import Configuration

#: central differences with this step agree with exact derivatives to about h^2
FD_STEP = 1e-6
FD_TOL = 1e-7
SCENES = ("arm_on_plane", "multi_arm:h=2", "four_bar")


@pytest.fixture(scope="module", params=SCENES)
def model(request):
    return symgen.derive(symgen.load(request.param))


def _exact_maps(model, seed=0):
    config, _ = random_exact_state(model, np.random.default_rng(seed))
    return steps.evaluate_maps(model, config, ExactField(model.tree.parameters))


def _shifted(config: Configuration, model, qd_all, h) -> Configuration:
    """Revolute-only scenes: every joint angle moved by ``h qd_all``."""
    pos = dict(config.positions)
    for j in model.tree.joints:
        if j.coords:
            pos[j.name] = pos[j.name] + h * qd_all[j.coords[0]]
    return Configuration(pos)


def test_counts_of_the_papers_examples():
    """Steps 1, 2 and 8 as printed in §3.2 (n_c = 6 + 0 - 3 = 3) and §3.3 (m = 6, n_c = 6(h-1))."""
    arm = symgen.derive(symgen.load("arm_on_plane")).counts
    assert (arm.n1a, arm.n1u, arm.n3a, arm.n3u, arm.m, arm.nc, arm.np, arm.n) == (6, 0, 0, 0, 3, 3, 0, 6)
    for h in (2, 3):
        c = symgen.derive(symgen.load(f"multi_arm:h={h}")).counts
        assert (c.n1a, c.m, c.nc, c.np, c.n) == (6 * h, 6, 6 * (h - 1), 0, 6 * h)
    bar = symgen.derive(symgen.load("four_bar")).counts
    assert (bar.n1a, bar.n1u, bar.m, bar.nc, bar.np, bar.n) == (1, 3, 1, 3, 3, 1)


def test_assign_frames_puts_every_one_dof_axis_on_z(model):
    """Step 3: the tree's joint motion subspace is e6 for every revolute joint (Z of §3.2)."""
    tree = steps.assign_frames(model.scene)
    kin = tree_kinematics(tree, FloatField(tree.parameters), model.reference)
    for z in kin.motion_subspace:
        if z.shape[1] == 1:
            assert list(z[:, 0]) == [0, 0, 0, 0, 0, 1]


@pytest.mark.parametrize("name", ["multi_arm:h=2", "four_bar"])
def test_constraint_matrix_is_minus_the_rate_of_the_closure_residual(name):
    """Step 4 (eq. 6): T qd_all = -d/dt r(q), with r from the frames' positions alone. (Welds
    only: their frames coincide on the manifold, where the residual's rate is exactly -T qd_all;
    a plane contact's frames are apart in the plane.)"""
    model = symgen.derive(symgen.load(name))
    config = random_consistent_states(model, 1, seed=3)[0][0]
    fld = FloatField(model.tree.parameters)
    cm = steps.constraint_matrix(tree_kinematics(model.tree, fld, config), model.scene.constraints.values(),
                                 model.partition)
    qd_all = np.random.default_rng(4).normal(size=model.tree.n_coords)
    rate = (closure_residual(model, _shifted(config, model, qd_all, FD_STEP))
            - closure_residual(model, _shifted(config, model, qd_all, -FD_STEP))) / (2 * FD_STEP)
    np.testing.assert_allclose(cm.T.v @ qd_all, -rate, atol=FD_TOL)
    assert cm.T_a.shape[1] + cm.T_u.shape[1] == model.tree.n_coords


def test_constraint_blocks_solve_eq_9_exactly(model):
    """Step 6: [T_u1, T_a1] [[T11, T12], [T21, T22]] = [T_a2, T_u2], exactly."""
    maps = _exact_maps(model)
    part = model.partition
    lhs = maps.W.v @ np.block([[maps.T11.v, maps.T12.v], [maps.T21.v, maps.T22.v]])
    rhs = np.hstack([maps.constraints.columns(part.a2).v, maps.constraints.columns(part.u2).v])
    assert (lhs == rhs).all()


def test_operational_constraint_map_is_the_constraint_rows(model):
    """Step 7 with T_c = T_a1 (§3.2, §3.3): J_f = T_a on the actuated joints (no passive ones)."""
    maps = _exact_maps(model)
    if model.counts.nc == model.counts.np:
        assert maps.J_f.shape == (0, model.counts.n)
        return
    assert (maps.J_f.v == maps.T_a.v).all()


def test_rate_map_meets_every_constraint_when_all_are_passive():
    """Step 8 (eq. 10): for the four-bar (n_p = n_c) every qd_all = P qd satisfies T qd_all = 0."""
    maps = _exact_maps(symgen.derive(symgen.load("four_bar")))
    assert (maps.T.v @ maps.P.v == 0).all()


def test_rate_map_is_the_identity_on_the_independent_rates(model):
    maps = _exact_maps(model)
    part = model.partition
    assert (maps.P.v[list(part.independent), :] == np.eye(model.counts.n, dtype=object)).all()


def test_inverse_task_map_block_identities(model):
    """Step 10, eq. (18): J_m Omega = 1, J_f Omega = 0, J_m Psi = 0, J_f Psi = 1, exactly."""
    maps = _exact_maps(model)
    m, n = model.counts.m, model.counts.n
    assert (maps.J_m.v @ maps.Omega.v == np.eye(m, dtype=object)).all()
    assert (maps.J_f.v @ maps.Omega.v == 0).all()
    assert (maps.J_m.v @ maps.Psi.v == 0).all()
    assert (maps.J_f.v @ maps.Psi.v == np.eye(n - m, dtype=object)).all()


def test_multi_arm_task_map_is_the_gamma_weighted_tool_jacobians():
    """Step 10 of §3.3: J_m = sum gamma_i J_i P, here with gamma = 1/2 for two arms."""
    model = symgen.derive(symgen.load("multi_arm:h=2"))
    maps = _exact_maps(model)
    frames = [f for f, _ in model.scene.motion.frames]
    total = sum(steps.frame_rows(maps.kin, f, model.scene.motion.components).v for f in frames) / 2
    assert all(g == symgen.load("multi_arm:h=2").motion.frames[0][1] for _, g in model.scene.motion.frames)
    assert (total @ maps.P.v == maps.J_m.v).all()


def test_task_map_refuses_a_motion_with_neither_joints_nor_frames():
    """Step 10 needs V_m: a Motion record without joints and frames (only components) is a typed
    SceneError naming the motion, not a map of ``None``."""
    from symgen.errors import SceneError
    from symgen.scene.elements import Motion

    model = symgen.derive(symgen.load("multi_arm:h=2"))
    maps = _exact_maps(model)
    empty = Motion(components=model.scene.motion.components)
    with pytest.raises(SceneError, match="motion"):
        steps.task_map(ExactField(), maps.kin, empty, maps.P)


def test_contact_map_of_the_arm_on_plane_is_the_tangential_twist():
    """Step 9 of §3.2: D_m takes the object's in-plane twist components (vx, vy, wz)."""
    model = symgen.derive(symgen.load("arm_on_plane"))
    maps = _exact_maps(model)
    cf = model.scene.contact_forces
    assert tuple(cf.components) == ("vx", "vy", "wz")
    assert (maps.D_m.v == steps.frame_rows(maps.kin, cf.frame, cf.components).v @ maps.P.v).all()


def test_velocity_map_matches_finite_differences_of_body_poses(model):
    """Step 11 (eq. 25): each body's rows of T_S qd are [R^T dp/dt; vee(R^T dR/dt)], the
    derivatives taken by central differences of the poses."""
    config = random_consistent_states(model, 1, seed=5)[0][0]
    fld = FloatField(model.tree.parameters)
    maps = steps.evaluate_maps(model, config, fld)
    qd = np.random.default_rng(6).normal(size=model.counts.n)
    qd_all = maps.P.v @ qd
    x = maps.T_S.v @ qd
    plus = tree_kinematics(model.tree, fld, _shifted(config, model, qd_all, FD_STEP))
    minus = tree_kinematics(model.tree, fld, _shifted(config, model, qd_all, -FD_STEP))
    space = maps.velocity.space
    for k, b in enumerate(space.bodies):
        r = maps.kin.rot[b].v
        dp = (plus.pos[b].v - minus.pos[b].v) / (2 * FD_STEP)
        dr = (plus.rot[b].v - minus.rot[b].v) / (2 * FD_STEP)
        w_hat = r.T @ dr
        twist = np.concatenate([r.T @ dp, [w_hat[2, 1], w_hat[0, 2], w_hat[1, 0]]])
        np.testing.assert_allclose(x[space.body_rows(k)], twist, atol=FD_TOL)
    np.testing.assert_allclose(x[: model.tree.n_coords], qd_all)


def test_subsystem_terms_are_block_diagonal_constant_and_skew(model):
    """Step 12 (eq. 24): M_S symmetric and independent of the velocity, C_S skew."""
    maps = _exact_maps(model)
    fld = maps.kin.field
    x1 = maps.T_S.v @ np.array([fld.const(k + 1) / 7 for k in range(model.counts.n)], dtype=object)
    t1 = steps.subsystem_terms(fld, maps.kin, maps.velocity.space, x1)
    t0 = steps.subsystem_terms(fld, maps.kin, maps.velocity.space, 0 * x1)
    assert (t1.M_S == t1.M_S.T).all() and (t1.M_S == t0.M_S).all()
    assert (t1.C_S + t1.C_S.T == 0).all()


def test_task_space_model_is_the_joint_space_model_seen_through_the_inverse_task_map(model):
    """Step 12, eq. (32): M = A^-T M_q A^-1 and G = A^-T G_q (no contact forces given)."""
    maps = _exact_maps(model)
    fld = maps.kin.field
    terms = steps.subsystem_terms(fld, maps.kin, maps.velocity.space, fld.zeros((maps.velocity.space.size,)))
    eta = fld.zeros((maps.D_m.shape[0],))
    task, _ = steps.task_space_model(terms, maps.velocity, maps.inverse, maps.contact, eta)
    joint = steps.joint_space_model(terms, maps.velocity)
    a_inv = maps.A_inv.v
    assert (task.M == a_inv.T @ joint.M @ a_inv).all()
    assert (task.G == a_inv.T @ joint.G).all()


def test_what_the_solves_read_is_formed_without_the_other_congruences(model):
    """``M``, ``G`` and ``c = C [V_m; 0]`` of eq. (32), read before ``C`` is formed, and the
    joint-space left side ``M_q qdd + C_q qd + G_q`` by products of vectors, equal the full
    congruences exactly (rational arithmetic: the same numbers, not close ones)."""
    rng = np.random.default_rng(3)
    config, v_m = random_exact_state(model, rng)
    cf = model.scene.contact_forces
    eta = [Fraction(int(k), 7) for k in rng.integers(-9, 10, len(cf.components))] if cf else None
    lean = model.evaluate(config, V_m=v_m, eta_m=eta, field="exact")
    full = model.evaluate(config, V_m=v_m, eta_m=eta, field="exact")
    M, G, c = lean.M, lean.G, lean.c
    assert "C" not in lean.__dict__ and "_task" not in lean.__dict__ and "M_q" not in lean.__dict__
    m = model.counts.m
    assert (M == full.M).all() and (G == full.G).all()
    assert (c == full.C[:, :m] @ full.V_m).all() and any(v != 0 for v in c)
    qdd = [Fraction(int(k), 5) for k in rng.integers(-5, 6, model.counts.n)]
    assert (lean.joint_force(qdd) == full.M_q @ np.array(qdd, dtype=object) + full.C_q @ full.qd + full.G_q).all()
