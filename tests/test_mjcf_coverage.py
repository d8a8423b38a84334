"""Every DeepMind Control Suite model the dm_control wheel ships, read in one process: the files
that load, each compared with MuJoCo on the same file, and a typed error naming the element for
each refused one (benchmarks/mjcf_coverage.py writes the table).

The expected sets come from reading the files, not from symgen: five models have a free joint
(a floating base, read); ball_in_cup, cheetah, fish, humanoid and humanoid_CMU have joint springs
(``stiffness``, read: checked against MuJoCo's ``qfrc_spring``); dog computes inertias from mesh
geoms (read) and sets its tail's springs by ``springdamper`` (read: stiffness and damping from
M(qpos0)); swimmer and fish have a fluid
(``<option density>``: read with ``fluid="ignore"``), fish also a tendon spring (refused);
manipulator, stacker and quadruped (whose sites placed by ``fromto`` are read) couple joints by
tendons; lqr.xml is a template with no body (dm_control adds them in Python).
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
          "manipulator.xml", "stacker.xml", "quadruped.xml",
          # a fluid medium, read with fluid="ignore"
          "swimmer.xml",
          # inertia from mesh geoms, springdamper
          "dog.xml"}
#: the files that load only with the reader option fluid="ignore"
WITH_FLUID_OPTION = {"swimmer.xml"}
#: file -> (element named, words of the reason)
REFUSED = {
    "fish.xml": ("<fixed name='fins_sym'>", "a tendon spring"),
    "lqr.xml": ("<worldbody>", "has no joint"),
}


@pytest.fixture(scope="module")
def loaded():
    return {name: coverage.load_with_option(name, path) for name, path in coverage.suite_files().items()}


def test_the_suite_files_that_load(loaded):
    assert set(loaded) == LOADED | set(REFUSED)
    assert {name for name, (outcome, _) in loaded.items() if outcome.loaded} == LOADED
    assert {name for name, (outcome, _) in loaded.items() if outcome.loaded and outcome.option} == WITH_FLUID_OPTION


def test_every_refusal_is_a_typed_error_naming_the_element_and_its_reason(loaded):
    for name, (element, words) in REFUSED.items():
        err = loaded[name][0].error
        assert isinstance(err, SymgenError), name
        assert err.element == element and words in str(err), (name, str(err))


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(LOADED))
def test_a_loaded_model_equals_mujoco(loaded, name):
    path = coverage.suite_files()[name]
    options = coverage.FLUID_OPTION if name in WITH_FLUID_OPTION else {}
    worst = {**coverage.mass_properties_check(path, **options), **coverage.dynamics_check(path, loaded[name][1])}
    assert all(v <= coverage.tolerance(name, k) for k, v in worst.items()), worst


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


def test_fluid_forces_are_refused_by_default_and_left_out_with_the_reader_option(loaded):
    """swimmer.xml sets <option density="3000">: refused naming the option and the reader option;
    with fluid="ignore" its mass matrix and bias forces equal MuJoCo's (which leave fluid forces out
    of both), while MuJoCo's fluid force at the same state is not zero -- the part left out."""
    import warnings

    import mujoco
    import numpy as np

    from symgen.io.mjcf import FluidWarning, scene_from_mjcf

    path = coverage.suite_files()["swimmer.xml"]
    refused, _ = coverage.try_load("swimmer.xml", path)
    assert refused.error.element == "<option>" and "density='3000'" in str(refused.error)
    assert "fluid='ignore'" in str(refused.error)
    with pytest.warns(FluidWarning, match="fluid forces left out"):
        scene = scene_from_mjcf(path, fluid="ignore")
    assert any("fluid forces left out" in n and "density=3000" in n for n in scene.notes)
    worst = coverage.dynamics_check(path, scene, states=2)
    assert max(worst.values()) <= coverage.TOL, worst
    m = mujoco.MjModel.from_xml_path(path)
    d = mujoco.MjData(m)
    d.qvel[:] = np.random.default_rng(0).uniform(-1, 1, m.nv)
    mujoco.mj_forward(m, d)
    assert np.max(np.abs(d.qfrc_fluid)) > 1e-3
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(SymgenError, match="must be one of refuse, ignore"):
            scene_from_mjcf(path, fluid="keep")
