"""A motion space that mixes a frame's twist components with joint rates (Step 10, eq. 17):
``V_m = [gamma-weighted frame components; joint rates]``. Checked against independent references:
central differences of the frame's pose, the joints-only model of the same mechanism (simulated),
exact proofs, and for two 7-joint Pandas holding a box a KKT solve with Pinocchio's ``crba``,
``nonLinearEffects`` and frame Jacobians (qdd of every joint, the loop forces, dV_m)."""
from pathlib import Path

import numpy as np
import pytest

import symgen
import symgen.steps.task_space as task_space
from symgen.control.tasks import MixedTask
from symgen.errors import ConstraintError, SceneError, SingularConfigurationError
from symgen.io.scene_yaml import dump_scene, load_scene, save_scene
from symgen.oracle.pinocchio_check import constrained_states
from symgen.simulation.closed_loop import run_closed_loop
from symgen.simulation.control_demo import Demo, setup

from .urdf_util import needs_examples

EXAMPLE = Path(__file__).resolve().parents[1] / "docs" / "examples" / "dual_panda_box.yaml"
#: the KKT comparison's tolerance (relative to the largest entry of the reference)
TOL_KKT = 1e-9
#: central differences of the frame pose with step H: truncation ~H^2, rounding ~1e-16 / H
H, TOL_FD = 1e-5, 1e-8
STATES = 10


def _gap(a, b) -> float:
    return float(np.max(np.abs(np.asarray(a, float) - np.asarray(b, float))))


def _mixed_five_bar():
    """The five-bar (m = 2) with ``V_m = [tip2's vy (own axes); j1]``."""
    scene = symgen.load("five_bar")
    scene.motion = None
    scene.set_motion(frame="tip2", components=["vy"], joints=["j1"])
    return scene


@pytest.fixture(scope="module")
def five_bar():
    return symgen.derive(_mixed_five_bar())


# ------------------------------------------------------------------ the declaration
def test_mixed_motion_lists_the_frame_components_then_the_joint_rates():
    motion = _mixed_five_bar().motion
    assert (motion.dim, motion.frame_dim, motion.mixed, motion.on_joints) == (2, 1, True, False)
    assert motion.labels() == ["tip2.vy", "j1"]


def test_mixed_v_m_is_the_frame_twist_and_the_joint_rate_by_central_differences(five_bar):
    # V_m -> qd_all by the model, then the frame's twist from central differences of its pose
    v_m = np.array([0.7, -0.4])
    config = five_bar.reference
    qd_all = five_bar.joint_rates(config, v_m)
    names = five_bar.all_coordinate_names()

    def pose(sign):
        moved = {name: float(config.positions[name]) + sign * H * qd_all[k] for k, name in enumerate(names)}
        return five_bar.frame_pose(moved, "tip2")

    (r_plus, p_plus), (r_minus, p_minus) = pose(1), pose(-1)
    r0, _ = five_bar.frame_pose(config, "tip2")
    vy = (r0.T @ (p_plus - p_minus) / (2 * H))[1]
    assert abs(vy - v_m[0]) < TOL_FD
    assert abs(qd_all[names.index("j1")] - v_m[1]) < 1e-14


def test_components_without_a_frame_are_refused():
    scene = symgen.load("five_bar")
    with pytest.raises(SceneError, match="components go with frame"):
        scene.set_motion(joints=["j1", "j2"], components=["vx"])


def test_frame_and_frames_together_are_refused():
    scene = symgen.load("five_bar")
    with pytest.raises(SceneError, match="not both"):
        scene.set_motion(frame="tip2", frames={"tip2": 1}, joints=["j1"])


def test_the_count_of_eq_5_is_on_the_total_and_names_both_parts():
    scene = symgen.load("five_bar")
    scene.motion = None
    scene.set_motion(frame="tip2", components=["vx", "vy"], joints=["j1"])
    with pytest.raises(ConstraintError, match=r"V_m has 3 coordinates \(2 frame components \+ 1 joint rates\) "
                                              r"but the scene has m = .* = 2"):
        scene.validate()


def test_a_singular_mixed_task_at_q0_names_the_dependent_motion_entry():
    # chain:n=2: a frame on link0 turns with j0 only, so its wz is j0's rate: [J_m; J_f] is singular
    scene = symgen.load("chain:n=2")
    scene.add_frame("F", "link0")
    scene.set_motion(frame="F", components=["wz"], joints=["j0"])
    with pytest.raises(SingularConfigurationError, match=r"motion entry 'j0' \(row 2 of V_m\) depends on J_f"):
        symgen.derive(scene)
    scene.set_motion(frame="F", components=["wz"], joints=["j1"])    # the other joint: regular
    assert symgen.derive(scene).counts.m == 2


def test_mixed_task_matrix_is_the_hand_derived_one_in_the_exact_and_symbolic_fields():
    # chain:n=2, F on link0 half a metre along its x axis: j0 turns link0 about its z axis, so F's
    # vy (own axes) is qd0 / 2 at every angle, and j1's rate is j1's: A = [[1/2, 0], [0, 1]]
    import sympy as sp

    from symgen.math.configuration import Configuration, CosSin

    scene = symgen.load("chain:n=2")
    scene.add_frame("F", "link0", xyz=(sp.Rational(1, 2), 0, 0))
    scene.set_motion(frame="F", components=["vy"], joints=["j1"])
    model = symgen.derive(scene)
    q0, q1 = sp.symbols("q0 q1", real=True)
    configs = {"exact": Configuration({"j0": CosSin(sp.Rational(3, 5), sp.Rational(4, 5)),
                                       "j1": CosSin(sp.Rational(5, 13), sp.Rational(-12, 13))}),
               "symbolic": Configuration({"j0": CosSin(sp.cos(q0), sp.sin(q0)), "j1": CosSin(sp.cos(q1), sp.sin(q1))})}
    for field, config in configs.items():
        a = model.evaluate(config, field=field).maps.A.v
        assert sp.simplify(sp.Matrix(a) - sp.Matrix([[sp.Rational(1, 2), 0], [0, 1]])) == sp.zeros(2, 2), field


# ------------------------------------------------------------------ YAML
def test_yaml_reads_a_mixed_motion_and_dumps_it_back(tmp_path):
    scene = _mixed_five_bar()
    text = dump_scene(scene)
    assert "motion: {frame: tip2, components: [vy], joints: [j1]}" in text
    path = tmp_path / "mixed.yaml"
    save_scene(scene, path)
    assert load_scene(path).motion == scene.motion


def test_yaml_refuses_frame_and_frames_together():
    text = dump_scene(_mixed_five_bar()).replace("motion: {frame: tip2,", "motion: {frames: {tip2: 1}, frame: tip2,")
    with pytest.raises(SceneError, match="give joints, or one of frame, frames"):
        load_scene(text)


# ------------------------------------------------------------------ fields, proofs, simulation
def test_the_mixed_five_bar_forward_dynamics_agree_in_the_float_and_50_digit_fields(five_bar):
    config, v_m, tau = five_bar.reference, [0.3, -0.2], [0.5, -1.0]
    dv_f, eta_f = five_bar.forward_dynamics(config, v_m, tau)
    dv_mp, eta_mp = five_bar.forward_dynamics(config, v_m, tau, field="mp")
    assert five_bar.counts.n == 2 and eta_f.size == np.asarray(eta_mp).size == 0   # n = m: no eta_f
    assert _gap(dv_f, np.asarray(dv_mp, float)) < 1e-12


def test_symgen_prove_passes_on_a_mixed_scene_from_yaml(tmp_path, capsys):
    from symgen.cli.commands import main

    path = tmp_path / "mixed.yaml"
    save_scene(_mixed_five_bar(), path)
    assert main(["prove", str(path), "--points", "1"]) == 0
    assert "FAIL" not in capsys.readouterr().out


def test_the_mixed_five_bar_moves_as_the_joints_only_five_bar(five_bar):
    # the same mechanism, unforced, from the same state: only the coordinates of V_m differ
    from symgen.simulation import StateLayout, simulate

    joints = symgen.derive(symgen.load("five_bar"))
    qd_all = joints.joint_rates(joints.reference, [0.5, -0.5])
    v_mixed, _ = five_bar.task_rates(five_bar.reference, qd_all)
    runs = [simulate(model, 0.2, "DOP853", rtol=1e-11, atol=1e-11, x0=StateLayout(model).initial_state(V_m=v))
            for model, v in ((joints, [0.5, -0.5]), (five_bar, v_mixed))]
    assert runs[1].max_drift < 1e-8
    assert np.max(np.abs(runs[0].q() - runs[1].q())) < 1e-8


def test_generated_numpy_forward_dynamics_of_the_mixed_five_bar_equal_the_dense_model(five_bar):
    from symgen.codegen.runtime import load_generated
    from symgen.oracle.pinocchio_check import _symgen_constrained, generated_evaluator

    module = load_generated(five_bar, "numpy", ["forward_dynamics"])
    evaluate = generated_evaluator(module, five_bar)
    for state in constrained_states(five_bar, 3):
        got, ref = evaluate(five_bar, state), _symgen_constrained(five_bar, state)
        assert _gap(got["dV_m"], ref["dV_m"]) < 1e-10


# ------------------------------------------------------------------ two Pandas holding a box, m = 8
@pytest.fixture(scope="module")
def dual_panda():
    pytest.importorskip("pinocchio", reason="pin (Pinocchio) is not installed (extra 'oracle')")
    pytest.importorskip("yourdfpy", reason="yourdfpy is not installed (extra 'urdf')")
    return symgen.derive(load_scene(EXAMPLE))


def _kkt_worst(model, states) -> dict:
    """Worst relative differences to a KKT solve with Pinocchio's ``crba``, ``nonLinearEffects``
    and the weld's frame Jacobians, and of ``V_m`` and ``dV_m`` read from Pinocchio: the box
    frame's LOCAL twist and acceleration, and the two joint rates."""
    import pinocchio as pin

    from symgen.oracle import pinocchio_robot
    from symgen.oracle.pinocchio_check import kkt_reference, relative

    robot = pinocchio_robot(model.scene)
    all_idx = robot.v_index(model.all_coordinate_names())
    joint_idx = robot.v_index(list(model.scene.motion.joints))
    box = robot.frames["box_O1"]
    worst = dict(qdd=0.0, lam=0.0, V_m=0.0, dV_m=0.0)
    for s in states:
        got = model.motion(s["config"], s["V_m"], s["tau"])
        v, u = np.zeros(robot.model.nv), np.zeros(robot.model.nv)
        v[all_idx] = got.qd_all
        u[robot.v_index(model.coordinate_names())] = s["tau"]
        q = robot.q_vector(s["config"])
        ref = kkt_reference(robot, model.scene, q, v, u, s["eta_m"])
        data = robot.model.createData()
        pin.forwardKinematics(robot.model, data, q, v, ref["qdd"])
        twist = pin.getFrameVelocity(robot.model, data, box, pin.ReferenceFrame.LOCAL).vector
        accel = pin.getFrameAcceleration(robot.model, data, box, pin.ReferenceFrame.LOCAL).vector
        worst["qdd"] = max(worst["qdd"], relative(got.qdd_all, ref["qdd"][all_idx]))
        worst["lam"] = max(worst["lam"], relative(got.lam, -ref["mu"]))
        worst["V_m"] = max(worst["V_m"], relative(np.concatenate([twist, v[joint_idx]]), s["V_m"]))
        worst["dV_m"] = max(worst["dV_m"], relative(got.dV_m, np.concatenate([accel, ref["qdd"][joint_idx]])))
    return worst


@needs_examples
def test_two_pandas_holding_a_box_have_m_8_box_twist_and_one_rate_per_arm(dual_panda):
    assert dual_panda.counts.as_dict() == dict(n1a=14, n1u=0, n3a=0, n3u=0, m=8, nc=6, np=0, n=14)
    assert dual_panda.scene.motion.labels() == ["task.vx", "task.vy", "task.vz", "task.wx", "task.wy", "task.wz",
                                                "a1_panda_joint3", "a2_panda_joint3"]


@needs_examples
def test_two_pandas_holding_a_box_equal_a_kkt_solve_joint_by_joint(dual_panda):
    worst = _kkt_worst(dual_panda, constrained_states(dual_panda, STATES))
    assert all(w <= TOL_KKT for w in worst.values()), worst


@needs_examples
def test_the_kkt_check_catches_the_joint_rates_stacked_before_the_frame(dual_panda, monkeypatch):
    states = constrained_states(dual_panda, 2)
    original = task_space.motion_rows

    def swapped(field, kin, motion):
        rows = original(field, kin, motion)
        order = list(range(motion.frame_dim, motion.dim)) + list(range(motion.frame_dim))
        return rows[order, :]

    monkeypatch.setattr(task_space, "motion_rows", swapped)
    worst = _kkt_worst(dual_panda, states)
    assert worst["V_m"] > 1e-2 and worst["dV_m"] > 1e-2


@needs_examples
def test_generated_numpy_of_the_two_pandas_equals_the_kkt_solve(dual_panda):
    from symgen.oracle import TOL_CONSTRAINED, check_against_pinocchio

    diffs = check_against_pinocchio(dual_panda, 3, targets=("numpy",))
    assert any(d.quantity == "generated numpy: motion rates dV_m (32)" for d in diffs)
    assert all(d.passed and d.tolerance == TOL_CONSTRAINED for d in diffs), [(d.quantity, d.worst) for d in diffs]


@needs_examples
@pytest.mark.slow
def test_generated_c_of_the_two_pandas_equals_the_kkt_solve(dual_panda):
    from symgen.oracle import check_against_pinocchio

    diffs = check_against_pinocchio(dual_panda, 3, targets=("c",))
    assert any(d.quantity == "generated c: motion rates dV_m (32)" for d in diffs)
    assert all(d.passed for d in diffs), [(d.quantity, d.worst) for d in diffs]


@needs_examples
@pytest.mark.extended   # about 30 s on one core; the mixed five-bar's proofs run in the suite
def test_the_proofs_hold_for_the_two_pandas(dual_panda):
    results = symgen.prove(dual_panda, points=1)
    assert results and all(r.passed for r in results), [r.name for r in results if not r.passed]


# ------------------------------------------------------------------ the Section 4 controller
#: the five-bar's demonstration with V_m = [tip2's wz; j1]: a frame task and a joint task at once.
#: (A lone in-plane translation such as vy would not do: its pose error, in the turning frame's
#: axes, couples to the x error that no row of V_m drives, so even exact parameters leave the path.)
MIXED_DEMO = Demo("five_bar", {"distal1": 1.3, "proximal2": 0.7}, amplitude=(0.2, 0.05), t_end=2.0,
                  motion=dict(frame="tip2", components=["wz"], joints=["j1"]))
#: exact parameters, starting on the path: the tracking error stays below this (measured ~1e-15)
EXACT_TRACKING = 1e-8


def test_exact_parameters_track_a_mixed_task_to_integration_accuracy():
    loop, x0 = setup(MIXED_DEMO, exact=True)
    assert isinstance(loop.task, MixedTask)
    r = run_closed_loop(loop, x0, 0.2, samples=3, rtol=1e-10, atol=1e-12)
    assert r.task_error.max() < EXACT_TRACKING


def test_the_mixed_task_is_the_frame_task_then_the_joint_task():
    # the planted error: the same closed loop with the parts' order reversed leaves the path
    loop, x0 = setup(MIXED_DEMO, exact=True)
    stack = loop.task.stack
    loop.task.stack = lambda first, rest: stack(rest, first)
    r = run_closed_loop(loop, x0, 0.1, samples=3, rtol=1e-8, atol=1e-10)
    assert r.task_error.max() > 1e4 * EXACT_TRACKING


def test_generated_closed_loop_of_a_mixed_task_has_the_dense_right_hand_side():
    from symgen.simulation.closed_loop_generated import GeneratedClosedLoop

    rng = np.random.default_rng(5)
    dense, x0 = setup(MIXED_DEMO)
    generated, _ = setup(MIXED_DEMO, backend="numpy", model=dense.model)
    assert isinstance(generated, GeneratedClosedLoop)
    for t in (0.3, 1.7):
        y = dense.initial_state(x0)
        nq, m = dense.layout.nq, dense.model.counts.m
        y[nq:nq + m] = rng.uniform(-0.3, 0.3, m)
        want, got = dense(t, y), generated(t, y)
        assert np.abs(got - want).max() <= 1e-10 * np.abs(want).max()
