"""Every URDF file of example-robot-data, read in one process: the files that load, and a typed
error naming the element for each refused one (benchmarks/urdf_coverage.py writes the table).

The expected sets come from reading the files, not from symgen: 9 files have a moving mimic joint
(four Talos files have ``<mimic>`` only on fixed joints, which couple no coordinate), read as joint
couplings; of those, Alex's hands mimic a joint the file does not have (``index_q1``; its joints are
``Left_index_q1`` ...), Romeo's ``LHand`` moves a massless link and only mimicking fingers below it,
and PR2 has an inertia no rigid body has (``sensor_mount_link``, 0.001 0.001 0.01). 2 have no
moving joint (free bodies: they load with ``floating=True``), ur3.urdf has no robot name
(Pinocchio refuses it too), and 6 have an inertia on a moving link that breaks positive
semi-definiteness or the triangle inequality by 0.18 % (Romeo LAAS small) to 100 % (HyQ) of its
largest principal moment, far beyond rounding. iCub's ``l_ankle_2`` inertia is CAD noise (entries
of 1e-20 kg m^2), rounded to zero (entries below 1e-15 kg m^2) with a note.
"""
import importlib.util
import sys
from pathlib import Path

import pytest

pytest.importorskip("yourdfpy", reason="yourdfpy is not installed (extra 'urdf')")

from symgen.errors import SymgenError  # noqa: E402
from symgen.io.urdf.build import NoMovingJointError  # noqa: E402

from .urdf_util import needs_examples  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
_spec = importlib.util.spec_from_file_location("urdf_coverage", ROOT / "benchmarks" / "urdf_coverage.py")
coverage = sys.modules.setdefault("urdf_coverage", importlib.util.module_from_spec(_spec))
_spec.loader.exec_module(coverage)

#: files with a moving mimic joint that load (the mimicking joints become couplings)
MIMIC_LOADS = {"baxter_description/urdf/baxter.urdf", "panda_description/urdf/panda.urdf",
               "panda_description/urdf/panda_collision.urdf", "tiago_pro_description/robots/tiago_pro.urdf"} | {
    f"talos_data/robots/talos_{v}.urdf" for v in ("full_v2", "full_v2_box")}
#: the mimic of a joint the file does not have
MIMIC_UNKNOWN = {"alex_description/urdf/alex_psyonic_hands.urdf": "joint 'Left_index_q2'"}
#: a moving joint whose child link and fixed descendants have no mass (the rest of the hand mimics it)
MASSLESS = {"romeo_description/urdf/romeo.urdf": "link 'LFinger11Link'"}
NO_MOVING_JOINT = {"hector_description/robots/quadrotor_base.urdf", "iris_description/robots/iris_simple.urdf"}
NO_ROBOT_NAME = {"ur_description/urdf/ur3.urdf"}
#: file -> the link whose inertia is refused first (file order)
BAD_INERTIA = {"allegro_hand_description/urdf/allegro_left_hand.urdf": "link_11.0",
               "allegro_hand_description/urdf/allegro_right_hand.urdf": "link_3.0",
               "hyq_description/robots/hyq_no_sensors.urdf": "lf_foot",
               "pr2_description/urdf/pr2.urdf": "sensor_mount_link",
               "romeo_description/urdf/romeo_laas_small.urdf": "LShoulderYaw_link",
               "romeo_description/urdf/romeo_small.urdf": "RShoulderYawLink"}
#: with inertia="repair" these load, except Romeo LAAS small, whose gripper link has no <inertial>
REPAIR_STILL_REFUSED = {"romeo_description/urdf/romeo_laas_small.urdf"}
#: entries of 1e-20 kg m^2 rounded to zero: they load by default
TINY_INERTIA = {"icub_description/robots/icub.urdf", "icub_description/robots/icub_reduced.urdf"}


def _file_names(path: str) -> set:
    from lxml import etree

    root = etree.parse(path).getroot()
    return {f"{el.tag} {el.get('name')!r}" for el in root.iter("link", "joint")} | {f"robot {root.get('name')!r}"}


@pytest.fixture(scope="module")
def warn():
    return {o.file: o for o in coverage.coverage("warn")}


@needs_examples
def test_the_files_that_load_by_default(warn):
    refused = set(MIMIC_UNKNOWN) | set(MASSLESS) | NO_MOVING_JOINT | NO_ROBOT_NAME | set(BAD_INERTIA)
    assert len(warn) == 69 and refused <= set(warn) and MIMIC_LOADS <= set(warn)
    assert {f for f, o in warn.items() if o.loaded} == set(warn) - refused
    assert sum(o.loaded for o in warn.values()) == 58
    for name in TINY_INERTIA:
        assert any("l_ankle_2" in n and "rounded to zero" in n for n in warn[name].notes), name


@needs_examples
def test_a_free_body_without_joints_loads_with_a_floating_base(warn):
    """A drone's URDF has no moving joint: refused as a fixed robot, with a hint; with floating=True
    its root is a free body with six rates."""
    paths = coverage.example_urdfs()
    for name in NO_MOVING_JOINT:
        assert "floating=True" in str(warn[name].error)
        outcome = coverage.try_load(name, paths[name], "repair", floating=True)
        assert outcome.loaded, outcome.error


@needs_examples
def test_every_refusal_is_a_typed_error_naming_an_element_of_the_file(warn):
    paths = coverage.example_urdfs()
    for name, outcome in warn.items():
        if outcome.loaded:
            continue
        err = outcome.error
        assert isinstance(err, SymgenError), name
        assert err.element in _file_names(paths[name]) or err.element == "<robot>", (name, err.element)
        if name in MIMIC_UNKNOWN:
            assert err.element == MIMIC_UNKNOWN[name] and "which is not a joint of this robot" in str(err)
        elif name in MASSLESS:
            assert err.element == MASSLESS[name] and "has zero mass" in str(err)
        elif name in NO_MOVING_JOINT:
            assert isinstance(err, NoMovingJointError)
        elif name in BAD_INERTIA:
            assert err.element == f"link {BAD_INERTIA[name]!r}" and "inertia='repair'" in str(err)


@needs_examples
def test_repair_loads_the_files_refused_over_inertias():
    paths = coverage.example_urdfs()
    for name in BAD_INERTIA:
        outcome = coverage.try_load(name, paths[name], "repair")
        assert outcome.loaded == (name not in REPAIR_STILL_REFUSED), (name, outcome.error)
        assert outcome.loaded or "has no <inertial>" in str(outcome.error)
        assert not outcome.loaded or "InertiaWarning" in outcome.warned


@needs_examples
@pytest.mark.parametrize("name", coverage.PINOCCHIO_CHECKED[:4] + coverage.PINOCCHIO_CHECKED[-1:])
def test_newly_loaded_robots_equal_pinocchio(name):
    pytest.importorskip("pinocchio", reason="pinocchio is not installed (extra 'oracle')")
    differences = coverage.pinocchio_check(name)
    assert differences and all(d.passed for d in differences), [d.as_dict() for d in differences]


@needs_examples
@pytest.mark.parametrize("name", ["solo_description/robots/solo12.urdf", "go2_description/urdf/go2.urdf",
                                  "a1_description/urdf/a1.urdf", "laikago_description/urdf/laikago.urdf",
                                  "talos_data/robots/talos_reduced.urdf"])
def test_a_legged_robot_is_loaded_welded_to_the_world_with_a_warning_saying_so(warn, name):
    outcome = warn[name]
    assert outcome.loaded and "FixedBaseWarning" in outcome.warned
    assert any("loaded welded to the world" in n and "floating=True" in n for n in outcome.notes)
