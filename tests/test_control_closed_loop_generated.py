"""The closed loop on generated code against the closed loop on the dense model (model (32)
evaluated per right-hand side, :func:`symgen.model.solve_forward`, the dense law of
:mod:`symgen.control.law`): the same right-hand side at states off the path, on a closed chain and
on a contact scene with friction forces; the frame twist of the NumPy kinematics against the dense
frame Jacobian; the defaults of a scene outside the demonstrations; typed errors."""
from pathlib import Path

import numpy as np
import pytest

import symgen

ROOT = Path(__file__).resolve().parent.parent

from symgen.control.errors import ControlInputError
from symgen.simulation.closed_loop_generated import GeneratedClosedLoop
from symgen.simulation.control_demo import DEMOS, DEFAULT_PRESS, Demo, default_demo, setup
from symgen.simulation.poses import Poses

#: generated against dense right-hand side, relative to its largest entry
RHS_TOL = 1e-10
SEED = 11


def _off_path_state(loop, x0, rng):
    """The start state with random task velocities, estimates inside their bounds and a force integral."""
    y = loop.initial_state(x0)
    nq, m, k = loop.layout.nq, loop.model.counts.m, len(loop.unc)
    y[nq:nq + m] = rng.uniform(-0.3, 0.3, m)
    y[nq + m:nq + m + k] = loop.lower + rng.uniform(0.1, 0.9, k) * (loop.upper - loop.lower)
    y[nq + m + k:] = rng.uniform(-0.1, 0.1, len(y) - nq - m - k)
    return y


@pytest.mark.parametrize("name", ["five_bar", "arm_on_plane"])
def test_generated_closed_loop_has_the_dense_right_hand_side(name):
    rng = np.random.default_rng(SEED)
    dense, x0 = setup(DEMOS[name])
    generated, _ = setup(DEMOS[name], backend="numpy", model=dense.model)
    assert isinstance(generated, GeneratedClosedLoop)
    for t in (0.3, 1.7):
        y = _off_path_state(dense, x0, rng)
        want, got = dense(t, y), generated(t, y)
        assert np.abs(got - want).max() <= RHS_TOL * np.abs(want).max()
        ev_d, ev_g = dense.evaluate(t, y), generated.evaluate(t, y)
        assert abs(generated.lyapunov(ev_g) - dense.lyapunov(ev_d)) <= RHS_TOL * dense.lyapunov(ev_d)


def test_frame_twist_is_the_dense_frame_jacobian_times_the_rates():
    loop, x0 = setup(DEMOS["arm_on_plane"])
    model, rng = loop.model, np.random.default_rng(SEED + 1)
    v_m = rng.uniform(-1, 1, model.counts.m)
    config = loop.layout.configuration(x0[:loop.layout.nq])
    data = model.evaluate(config, V_m=v_m)
    frame = model.scene.motion.frames[0][0]
    want = data.maps.kin.frame_jacobian(frame).v @ (data.maps.P.v @ data.qd)
    qd_all = data.maps.P.v @ data.qd
    r, p, twist = Poses(model).frame_twist(x0[:loop.layout.nq], qd_all, frame)
    np.testing.assert_allclose(twist, want, atol=1e-12)
    np.testing.assert_allclose(r, data.maps.kin.frame_pose(frame)[0].v, atol=1e-12)


def test_scene_outside_the_demonstrations_gets_a_pressing_default():
    """The §3.2 arm under another name: its plane contact presses, friction and force feedback on."""
    model = symgen.derive(symgen.load("arm_on_plane"))
    demo = default_demo("my_arm_on_plane", model)
    assert demo.eta_fd[0] == DEFAULT_PRESS and not any(demo.eta_fd[1:])
    assert len(demo.eta_fd) == model.counts.n - model.counts.m
    assert demo.force_gain > 0 and demo.contact
    assert set(demo.factors) == {b.name for b in model.tree.bodies if not b.massless}


def test_unknown_backend_is_refused():
    with pytest.raises(ControlInputError, match="backend 'fortran'"):
        setup(Demo("chain:n=2", {"link0": 1.3}), backend="fortran")


def test_control_command_runs_a_scene_outside_the_demonstrations(capsys):
    """``symgen control`` on a chain it has no demonstration for: the default run, shortened."""
    import json

    from symgen.cli import main

    assert main(["control", "chain:n=3", "--t-end", "0.2", "--backend", "numpy", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["scene"] == "chain:n=3" and out["estimates_inside_bounds"] and out["rhs_calls"] > 0
    assert out["lyapunov_largest_increase"] <= 1e-6 * out["lyapunov_start"]


def test_backend_with_the_regressor_is_refused(capsys):
    from symgen.cli import main

    assert main(["control", "chain:n=2", "--regressor", "--backend", "c"]) != 0
    assert "--backend" in capsys.readouterr().err


@pytest.mark.parametrize("file_name, tool", [("ur10_on_plane.yaml", "tool0"),
                                             ("kinova_on_plane.yaml", "j2s6s200_end_effector")])
def test_arm_scene_files_press_down_on_a_plane(file_name, tool):
    """The documented scene files: a plane contact on the tool, ``m = 3`` of ``n = 6``, and the
    tool's z axis pointing down at ``q0`` -- by Pinocchio's forward kinematics of the same URDF."""
    import yaml

    pin = pytest.importorskip("pinocchio")
    from symgen.io.urdf.examples import example_path

    scene_file = ROOT / "docs" / "examples" / file_name
    model = symgen.derive(symgen.load(str(scene_file)))
    assert (model.counts.n, model.counts.m) == (6, 3)
    assert [c.kind for c in model.scene.constraints.values()] == ["plane_contact"]
    spec = yaml.safe_load(scene_file.read_text())["urdf"]
    robot = pin.buildModelFromUrdf(str(example_path(spec["example"])))
    q = pin.neutral(robot)
    for name, value in spec["q0"].items():
        joint = robot.joints[robot.getJointId(name)]
        angle = float(eval(str(value), {"pi": np.pi}))
        q[joint.idx_q:joint.idx_q + joint.nq] = [angle] if joint.nq == 1 else [np.cos(angle), np.sin(angle)]
    data = robot.createData()
    pin.framesForwardKinematics(robot, data, q)
    z_axis = data.oMf[robot.getFrameId(tool)].rotation[:, 2]
    assert z_axis[2] < -np.cos(np.radians(5)), z_axis
