"""symgen's models of URDF robots against Pinocchio on the same files (symgen.oracle): joint-space
inverse dynamics, mass matrix and gravity of the UR5, the Panda and a robot with fixed joints and
tilted axes, for the dense model and the generated NumPy and C; constrained accelerations and
constraint forces of contact, grasp and loop scenes against a KKT solve with Pinocchio's Jacobians."""
import argparse
import dataclasses
import json

import pytest
import sympy as sp

pytest.importorskip("pinocchio", reason="pin (Pinocchio) is not installed (extra 'oracle')")
pytest.importorskip("yourdfpy", reason="yourdfpy is not installed (extra 'urdf')")

import symgen  # noqa: E402
from symgen.oracle import (TOL_CONSTRAINED, TOL_JOINT_SPACE, OracleError, check_against_pinocchio,  # noqa: E402
                           compare_joint_space, pinocchio_robot)
from symgen.oracle.pinocchio_check import open_chain_states  # noqa: E402
from symgen.io.scene_yaml import load_scene  # noqa: E402
from symgen.io.urdf import scene_from_urdf  # noqa: E402

from .urdf_util import DATA  # noqa: E402
STATES = 20


from .urdf_util import needs_examples  # noqa: E402


def _worst(diffs) -> dict:
    return {d.quantity: d.worst for d in diffs}


def _assert_all_pass(diffs, tolerance):
    assert diffs and all(d.tolerance == tolerance for d in diffs if not d.quantity.startswith("loop"))
    failed = [(d.quantity, d.worst) for d in diffs if not d.passed]
    assert not failed, failed


@pytest.fixture(scope="module")
def ur5():
    return symgen.derive(symgen.load("ur5"))


@pytest.fixture(scope="module")
def panda():
    return symgen.derive(symgen.load("panda"))


@pytest.fixture(scope="module")
def tilted():
    return symgen.derive(scene_from_urdf(DATA / "fixed_and_tilted.urdf"))


# ------------------------------------------------------------------ open chains, joint space
@needs_examples
def test_ur5_dense_model_and_generated_numpy_and_c_equal_pinocchio(ur5):
    diffs = check_against_pinocchio(ur5, STATES, targets=("numpy", "c"))
    assert len(diffs) == 9   # tau, M, G for the dense model, numpy and C
    _assert_all_pass(diffs, TOL_JOINT_SPACE)


@needs_examples
def test_panda_with_locked_fingers_equals_pinocchio_reduced_model(panda):
    assert panda.counts.n == 7
    _assert_all_pass(check_against_pinocchio(panda, STATES), TOL_JOINT_SPACE)


@needs_examples
def test_panda_damping_enters_the_inverse_dynamics(panda):
    # the Panda file has damping 0.003 on every arm joint: without it the torques differ by ~b qd
    robot = pinocchio_robot(panda.scene)
    robot.damping[:] = 0
    worst = _worst(compare_joint_space(panda, robot, open_chain_states(panda, 3)))
    assert worst["inverse dynamics tau"] > 1e-5 and worst["mass matrix M_q"] < TOL_JOINT_SPACE


def test_fixed_joints_tilted_axes_continuous_and_prismatic_joints_equal_pinocchio(tilted):
    _assert_all_pass(check_against_pinocchio(tilted, STATES, targets=("numpy",)), TOL_JOINT_SPACE)


def test_the_check_fails_when_the_model_is_wrong(tilted):
    scene = scene_from_urdf(DATA / "fixed_and_tilted.urdf")
    body = scene.bodies["link4"]
    scene.bodies["link4"] = dataclasses.replace(body, mass=body.mass * sp.Rational(101, 100))
    worst = _worst(check_against_pinocchio(symgen.derive(scene), 3))
    assert worst["inverse dynamics tau"] > 1e-5 and worst["gravity G_q"] > 1e-5


# ------------------------------------------------------------------ constrained scenes (the overlay)
def _constrained(scene, states=5):
    diffs = check_against_pinocchio(symgen.derive(scene), states, targets=("numpy",))
    _assert_all_pass(diffs, TOL_CONSTRAINED)
    names = {d.quantity for d in diffs}
    assert {"motion rates dV_m (32)", "constraint forces eta_f (32)", "generated numpy: motion rates dV_m (32)"} <= names
    return diffs


@needs_examples
@pytest.mark.parametrize("spec", ["ur5_on_plane", "panda_on_plane", "multi_ur5:h=2"])
def test_contact_and_grasp_scenes_on_real_arms_equal_a_kkt_solve(spec):
    _constrained(symgen.load(spec))


def test_two_copies_of_a_urdf_holding_a_box_equal_a_kkt_solve():
    _constrained(load_scene(DATA / "tilted_pair.yaml"))


def test_a_ball_closure_to_the_world_equals_a_kkt_solve():
    text = (f"name: loop\nurdf:\n  file: {DATA / 'fixed_and_tilted.urdf'}\n  q0: {{j2: 0.5, j3: 0.3, j4: 0.1, "
            "j5: 0.4}\n  close: {tip: {type: ball, frames: [tool, world]}}\n")
    _constrained(load_scene(text))


def test_a_scene_not_built_from_urdf_is_refused():
    with pytest.raises(OracleError, match="was not built from a URDF file"):
        check_against_pinocchio(symgen.derive(symgen.load("four_bar")), 1)


# ------------------------------------------------------------------ symgen check
def _check(argv, capsys):
    from symgen.cli.urdf import register

    parser = argparse.ArgumentParser()
    register(parser.add_subparsers(dest="command", required=True))
    args = parser.parse_args(argv)
    status = args.func(args)
    return status, capsys.readouterr().out


def test_check_command_prints_the_worst_differences(capsys):
    status, out = _check(["check", str(DATA / "tilted_on_plane.yaml"), "--against", "pinocchio", "--states", "3"],
                         capsys)
    assert status == 0 and "PASS  motion rates dV_m (32)" in out and "all agree" in out


def test_check_command_json_reports_each_quantity(capsys):
    status, out = _check(["check", str(DATA / "tilted_on_plane.yaml"), "--against", "pinocchio", "--states", "2",
                          "--json"], capsys)
    report = json.loads(out)
    assert status == 0 and report["passed"] is True
    assert {d["quantity"] for d in report["differences"]} >= {"motion rates dV_m (32)", "constraint forces eta_f (32)"}
