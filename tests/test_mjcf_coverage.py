"""Every DeepMind Control Suite model the dm_control wheel ships, read in one process: the files
that load, each compared with MuJoCo on the same file, and a typed error naming the element for
each refused one (benchmarks/mjcf_coverage.py writes the table).

The expected sets come from reading the files, not from symgen: five models have a free joint
(a floating base, read), but dog computes inertias from mesh geoms, fish, humanoid and
humanoid_CMU have joint springs, and quadruped places sites by ``fromto``; ball_in_cup and cheetah
have joint springs (``stiffness``); swimmer has a fluid (``<option density>``); manipulator and stacker couple
joints by ``<equality><tendon>``; lqr.xml is a template with no body (dm_control adds them in
Python).
"""
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

LOADED = {"acrobot.xml", "cartpole.xml", "finger.xml", "hopper.xml", "pendulum.xml", "point_mass.xml",
          "reacher.xml", "walker.xml"}
#: file -> (element named, words of the reason)
REFUSED = {
    "dog.xml": ("<geom>", "a mesh geom"),
    "fish.xml": ("<joint name='tail2'>", "a joint spring"),
    "humanoid.xml": ("<joint>", "a joint spring"),
    "humanoid_CMU.xml": ("<joint>", "a joint spring"),
    "ball_in_cup.xml": ("<joint>", "a joint spring"),
    "cheetah.xml": ("<joint name='bthigh'>", "a joint spring"),
    "swimmer.xml": ("<option>", "fluid forces"),
    # their fixed-tendon coupling is read (tests/test_couplings_mujoco.py); their springs are not
    "manipulator.xml": ("<joint>", "a joint spring"),
    "stacker.xml": ("<joint>", "a joint spring"),
    "quadruped.xml": ("<site name='rf_00'>", "'fromto' is not read"),
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
