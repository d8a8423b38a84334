"""Every URDF file of example-robot-data, read in one process: the files that load, and a typed
error naming the element for each refused one (benchmarks/urdf_coverage.py writes the table).

The expected sets come from reading the files, not from symgen: 9 files have a moving mimic joint
(four Talos files have ``<mimic>`` only on fixed joints, which couple no coordinate), read as joint
couplings; of those, Alex's hands mimic a joint the file does not have (``index_q1``; its joints are
``Left_index_q1`` ...: they load with ``mimic=False``), and Romeo's ``LHand`` moves a massless link
and only mimicking fingers below it, all massless (locked, with a warning), and PR2 has an inertia
no rigid body has (``sensor_mount_link``, 0.001 0.001 0.01). 2 have no moving joint (free bodies:
they load with ``floating=True``), ur3.urdf holds no link at all (an empty ``<robot>``; Pinocchio
refuses it too), and 6 have an inertia on a moving link that breaks positive semi-definiteness or
the triangle inequality by 0.18 % (Romeo LAAS small, whose grippers also move no mass) to 100 %
(HyQ) of its largest principal moment, far beyond rounding. iCub's ``l_ankle_2`` inertia is CAD
noise (entries of 1e-20 kg m^2), rounded to zero (entries below 1e-15 kg m^2) with a note.
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
#: hands whose joints move no mass (locked, with a warning): file -> the joints locked
MASSLESS = {"romeo_description/urdf/romeo.urdf": {"LHand", "RHand"}}
NO_MOVING_JOINT = {"hector_description/robots/quadrotor_base.urdf", "iris_description/robots/iris_simple.urdf"}
EMPTY = {"ur_description/urdf/ur3.urdf"}
#: file -> the link whose inertia is refused first (file order)
BAD_INERTIA = {"allegro_hand_description/urdf/allegro_left_hand.urdf": "link_11.0",
               "allegro_hand_description/urdf/allegro_right_hand.urdf": "link_3.0",
               "hyq_description/robots/hyq_no_sensors.urdf": "lf_foot",
               "pr2_description/urdf/pr2.urdf": "sensor_mount_link",
               "romeo_description/urdf/romeo_laas_small.urdf": "LShoulderYaw_link",
               "romeo_description/urdf/romeo_small.urdf": "RShoulderYawLink"}
#: with inertia="repair" these load; Romeo LAAS small's grippers (links without <inertial>) are locked
REPAIR_LOCKS = {"romeo_description/urdf/romeo_laas_small.urdf": {"l_gripper_joint", "r_gripper_joint"}}
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
    refused = set(MIMIC_UNKNOWN) | NO_MOVING_JOINT | EMPTY | set(BAD_INERTIA)
    assert len(warn) == 69 and refused <= set(warn) and MIMIC_LOADS <= set(warn)
    assert {f for f, o in warn.items() if o.loaded} == set(warn) - refused
    assert sum(o.loaded for o in warn.values()) == 59
    for name, joints in MASSLESS.items():
        assert "MasslessJointWarning" in warn[name].warned
        assert {j for j in joints if any(f"joint {j!r} and 11 joint(s) that mimic it" in n
                                         for n in warn[name].notes)} == joints


@needs_examples
def test_68_of_69_load_with_the_options_and_the_empty_file_is_refused(warn):
    """Each file refused by default loads with the option its refusal names, except the empty one
    (the benchmark loads every free body again floating as well)."""
    paths = coverage.example_urdfs()
    refused = [o for o in warn.values() if not o.loaded]
    retried = {o.file: coverage.try_load(o.file, paths[o.file], "repair", floating=o.file in NO_MOVING_JOINT,
                                         mimic=not coverage.unknown_mimic(o)) for o in refused}
    assert {f for f, o in warn.items() if coverage.unknown_mimic(o)} == set(MIMIC_UNKNOWN)
    assert {f for f, o in retried.items() if not o.loaded} == EMPTY
    assert sum(o.loaded for o in warn.values()) + sum(o.loaded for o in retried.values()) == 68
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
        elif name in EMPTY:
            assert "has no <link>: the description is empty" in str(err)
        elif name in NO_MOVING_JOINT:
            assert isinstance(err, NoMovingJointError)
        elif name in BAD_INERTIA:
            assert err.element == f"link {BAD_INERTIA[name]!r}" and "inertia='repair'" in str(err)


@needs_examples
def test_repair_loads_the_files_refused_over_inertias():
    paths = coverage.example_urdfs()
    for name in BAD_INERTIA:
        outcome = coverage.try_load(name, paths[name], "repair")
        assert outcome.loaded and "InertiaWarning" in outcome.warned, (name, outcome.error)
        locked = REPAIR_LOCKS.get(name, set())
        assert ("MasslessJointWarning" in outcome.warned) == bool(locked), name
        assert all(any(f"joint {j!r} moves no mass" in n for n in outcome.notes) for j in locked), name


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
