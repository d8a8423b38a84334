"""Frame poses and loop forces as wrenches (A's axes, the world's or B's), against independent
references: the 50-digit reference kinematics at q0, Pinocchio's frame placements at random states,
and Pinocchio's constraintDynamics multipliers in world-aligned axes."""
from __future__ import annotations

import numpy as np
import pytest

import symgen
from symgen.errors import StateError
from symgen.math.spatial import COMPONENTS
from symgen.reference_kinematics import reference_pose

TOL = 1e-9


@pytest.mark.parametrize("spec", ["four_bar", "arm_on_plane", "multi_arm:h=2"])
def test_frame_poses_at_q0_equal_the_50_digit_reference_kinematics(spec):
    model = symgen.derive(symgen.load(spec))
    for name in model.scene.frames:
        r, p = model.frame_pose(model.reference, name)
        r_ref, p_ref = reference_pose(model.scene, name)
        assert np.allclose(r, np.array(r_ref.tolist(), dtype=float), atol=1e-12), name
        assert np.allclose(p, np.array(p_ref.tolist(), dtype=float).ravel(), atol=1e-12), name


def test_frame_poses_at_random_states_equal_pinocchios_placements():
    pin = pytest.importorskip("pinocchio")
    from symgen.oracle.pinocchio_check import constrained_states
    from symgen.oracle.pinocchio_tree import frame_placement, tree_robot

    model = symgen.derive(symgen.load("arm_on_plane"))
    robot = tree_robot(model)
    data = robot.model.createData()
    for state in constrained_states(model, 3, seed=5):
        pin.forwardKinematics(robot.model, data, robot.q_vector(state["config"]))
        for name in model.scene.frames:
            joint, placement = frame_placement(robot, name)
            world = data.oMi[joint] * placement
            r, p = model.frame_pose(state["config"], name)
            assert np.allclose(r, world.rotation, atol=1e-12) and np.allclose(p, world.translation, atol=1e-12), name


def test_wrenches_in_a_axes_hold_the_loop_forces_and_zeros_elsewhere():
    model = symgen.derive(symgen.load("four_bar"))
    q, v, tau = model.reference, [0.4], [1.0]
    lam = model.loop_forces(q, v, tau)
    wrenches = model.constraint_wrenches(q, v, tau)
    k = 0
    for con in model.scene.constraints.values():
        for i, comp in enumerate(COMPONENTS):
            if comp in con.components:
                assert wrenches[con.name][i] == pytest.approx(lam[k])
                k += 1
            else:
                assert wrenches[con.name][i] == 0
    assert k == len(lam)


def test_bad_axes_and_unknown_frames_are_typed_errors():
    model = symgen.derive(symgen.load("four_bar"))
    with pytest.raises(StateError, match="axes"):
        model.constraint_wrenches(model.reference, [0.0], [0.0], axes="C")
    with pytest.raises(StateError, match="no frame 'nowhere'"):
        model.frame_pose(model.reference, "nowhere")


def test_world_wrenches_equal_pinocchio_lambda_c_in_world_aligned_axes():
    """The MJCF four-bar closed by a CONTACT_3D expressed LOCAL_WORLD_ALIGNED: lambda_c is the force
    on A's body in world axes (Pinocchio's multipliers sit on the right, like symgen's)."""
    pin = pytest.importorskip("pinocchio")
    from symgen.oracle.pinocchio_check import constrained_states

    from .pinocchio_contact import four_bar_contact

    model, robot, (data, models, datas) = four_bar_contact(pin, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
    for state in constrained_states(model, 4, seed=3):
        d = model.evaluate(state["config"], V_m=state["V_m"])
        tau = np.zeros(robot.model.nv)
        tau[robot.v_index(model.coordinate_names())] = state["tau"]
        pin.constraintDynamics(robot.model, data, robot.q_vector(state["config"]),
                               robot.v_vector(np.asarray(d.maps.P.v @ d.qd, float)), tau, models, datas,
                               pin.ProximalSettings(1e-14, 1e-9, 100))
        world = model.constraint_wrenches(state["config"], state["V_m"], state["tau"], axes="world")["closure"]
        scale = np.max(np.abs(world))
        assert scale > 0.1
        assert np.allclose(np.array(data.lambda_c), world[:3], rtol=TOL, atol=TOL * scale)


@pytest.mark.parametrize("spec", ["four_bar", "arm_on_plane", "five_bar"])
def test_b_axes_wrenches_are_the_world_wrenches_turned_into_frame_b(spec):
    """axes="B": the same wrench on A's body (moment about A's origin) in frame B's axes, i.e.
    R_W_B^T times the world-axes wrench, with R_W_B from Model.frame_pose (checked against Pinocchio
    above); its norm is the world wrench's (a rotation)."""
    from symgen.closure import random_consistent_states

    model = symgen.derive(symgen.load(spec))
    rng = np.random.default_rng(5)
    for config, v_m in random_consistent_states(model, 3, seed=6):
        tau = rng.uniform(-1, 1, model.counts.n)
        world = model.constraint_wrenches(config, v_m, tau, axes="world")
        in_b = model.constraint_wrenches(config, v_m, tau, axes="B")
        for con in model.scene.constraints.values():
            r_wb, _ = model.frame_pose(config, con.frame_b)
            want = np.concatenate([r_wb.T @ world[con.name][:3], r_wb.T @ world[con.name][3:]])
            scale = max(1.0, np.max(np.abs(want)))
            assert np.allclose(in_b[con.name], want, rtol=0, atol=TOL * scale), con.name
            assert np.isclose(np.linalg.norm(in_b[con.name]), np.linalg.norm(world[con.name]), rtol=1e-12)


def test_b_axes_equal_a_axes_where_a_weld_holds_the_frames_together():
    """Two arms welded at the grasp (O1 = O2 on closed states): B's axes are A's, so the wrenches
    agree to rounding, while the world axes differ from both."""
    from symgen.closure import random_consistent_states

    model = symgen.derive(symgen.load("multi_arm:h=2"))
    config, v_m = random_consistent_states(model, 1, seed=8)[0]
    tau = np.linspace(-1, 1, model.counts.n)
    in_a = model.constraint_wrenches(config, v_m, tau, axes="A")["grasp12"]
    in_b = model.constraint_wrenches(config, v_m, tau, axes="B")["grasp12"]
    world = model.constraint_wrenches(config, v_m, tau, axes="world")["grasp12"]
    scale = np.max(np.abs(in_a))
    assert np.allclose(in_b, in_a, rtol=0, atol=1e-10 * scale)
    assert not np.allclose(world, in_a, rtol=0, atol=1e-3 * scale)


@pytest.mark.parametrize("spec", ["four_bar", "arm_on_plane", "multi_arm:h=2", "chain:n=3"])
def test_task_rates_invert_the_joint_rates_and_accelerations(spec):
    """Joint, frame-twist and gamma-weighted tasks: V_m and dV_m back from every joint's rates and
    accelerations (computed through model (32) by joint_rates / joint_accelerations / forward_dynamics)."""
    from symgen.closure import random_consistent_states

    model = symgen.derive(symgen.load(spec))
    rng = np.random.default_rng(2)
    for config, v_m in random_consistent_states(model, 2, seed=4):
        tau = rng.uniform(-1, 1, model.counts.n)
        qd_all = model.joint_rates(config, v_m)
        qdd_all = model.joint_accelerations(config, v_m, tau)
        dv_m, _ = model.forward_dynamics(config, v_m, tau)
        got_v, got_dv = model.task_rates(config, qd_all, qdd_all)
        assert np.allclose(got_v, v_m, rtol=1e-10, atol=1e-10)
        assert np.allclose(got_dv, dv_m, rtol=1e-9, atol=1e-9 * max(1.0, np.max(np.abs(dv_m))))


def test_task_rates_of_a_joint_task_are_the_motion_joints_rates():
    """A hand check: chain:n=3 with V_m = the three joint rates."""
    model = symgen.derive(symgen.load("chain:n=3"))
    qd_all, qdd_all = np.array([0.1, -0.2, 0.3]), np.array([1.0, 2.0, -3.0])
    v_m, dv_m = model.task_rates(model.reference, qd_all, qdd_all)
    assert np.array_equal(v_m, qd_all) and np.array_equal(dv_m, qdd_all)


def test_task_rates_refuse_a_wrong_length_naming_the_argument():
    model = symgen.derive(symgen.load("four_bar"))
    with pytest.raises(StateError, match=r"qd_all must have shape \(4,\)"):
        model.task_rates(model.reference, [0.1, 0.2])
    with pytest.raises(StateError, match=r"qdd_all must have shape \(4,\)"):
        model.task_rates(model.reference, [0.1] * 4, [0.0])
