"""Every DeepMind Control Suite model the dm_control wheel ships, read in one process: the files
that load, each compared with MuJoCo on the same file, and a typed error naming the element for
each refused one (benchmarks/mjcf_coverage.py writes the table).

The expected sets come from reading the files, not from symgen: five models have a free joint
(a floating base, read); ball_in_cup, cheetah, fish, humanoid and humanoid_CMU have joint springs
(``stiffness``, read: checked against MuJoCo's ``qfrc_spring``), but dog computes inertias from mesh
geoms; swimmer and fish have a fluid (``<option density>``); manipulator, stacker and quadruped
(whose sites placed by ``fromto`` are read) couple joints by tendons; lqr.xml is a template with no
body (dm_control adds them in Python).
"""
import dataclasses
import importlib.util
import sys
from pathlib import Path

import pytest

from symgen.errors import SymgenError

pytest.importorskip("mujoco", minversion="3.3.6")
if importlib.util.find_spec("dm_control") is None:
    pytest.skip("dm-control is not installed (it is in the 'test' extra)", allow_module_level=True)

ROOT = Path(__file__).resolve().parent.parent
_spec = importlib.util.spec_from_file_location("mjcf_coverage", ROOT / "benchmarks" / "mjcf_coverage.py")
coverage = sys.modules.setdefault("mjcf_coverage", importlib.util.module_from_spec(_spec))
_spec.loader.exec_module(coverage)

LOADED = {"acrobot.xml", "ball_in_cup.xml", "cartpole.xml", "cheetah.xml", "finger.xml", "hopper.xml",
          "humanoid.xml", "humanoid_CMU.xml", "pendulum.xml", "point_mass.xml", "reacher.xml", "walker.xml",
          # fixed-tendon couplings (rows of T), compared with MuJoCo through the coupling map P
          "manipulator.xml", "stacker.xml", "quadruped.xml"}
#: file -> (element named, words of the reason)
REFUSED = {
    "dog.xml": ("<geom>", "a mesh geom"),
    "fish.xml": ("<option>", "fluid forces"),
    "swimmer.xml": ("<option>", "fluid forces"),
    "lqr.xml": ("<worldbody>", "has no joint"),
}


@pytest.fixture(scope="module")
def loaded():
    return {name: coverage.try_load(name, path) for name, path in coverage.suite_files().items()}


def test_the_suite_files_that_load(loaded):
    assert set(loaded) == LOADED | set(REFUSED)
    assert {name for name, (outcome, _) in loaded.items() if outcome.loaded} == LOADED


def test_every_refusal_is_a_typed_error_naming_the_element_and_its_reason(loaded):
    for name, (element, words) in REFUSED.items():
        err = loaded[name][0].error
        assert isinstance(err, SymgenError), name
        assert err.element == element and words in str(err), (name, str(err))


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(LOADED))
def test_a_loaded_model_equals_mujoco(loaded, name):
    path = coverage.suite_files()[name]
    worst = {**coverage.mass_properties_check(path), **coverage.dynamics_check(path, loaded[name][1])}
    assert max(worst.values()) <= coverage.TOL, worst


@pytest.mark.parametrize("name", ["acrobot.xml", "walker.xml"])
def test_an_underactuated_model_and_one_with_several_joints_per_body_equal_mujoco(loaded, name):
    path = coverage.suite_files()[name]
    worst = coverage.dynamics_check(path, loaded[name][1], states=2)
    assert max(worst.values()) <= coverage.TOL, worst


@pytest.mark.parametrize("name", ["ball_in_cup.xml", "cheetah.xml"])
def test_the_joint_springs_of_a_model_equal_mujocos_qfrc_spring(loaded, name):
    path = coverage.suite_files()[name]
    worst = coverage.dynamics_check(path, loaded[name][1], states=2)
    assert max(worst.values()) <= coverage.TOL, worst


def test_the_spring_check_catches_a_wrong_spring_rest_position(loaded):
    """A planted error: cheetah's ``bthigh`` spring at rest 0.1 rad off MuJoCo's ``springref``."""
    scene = loaded["cheetah.xml"][1]
    joint = scene.joints["bthigh"]
    planted = dataclasses.replace(scene, joints={**scene.joints,
                                                 "bthigh": dataclasses.replace(joint, springref=joint.springref + 0.1)})
    worst = coverage.dynamics_check(coverage.suite_files()["cheetah.xml"], planted, states=1)
    assert worst["joint springs"] > 1e-3 and worst["mass matrix"] <= coverage.TOL, worst
