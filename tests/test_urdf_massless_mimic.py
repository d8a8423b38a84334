"""URDF joints that move no mass are locked, ``mimic=False`` reads mimicking joints as independent
ones (Pinocchio's default parse), and a file without a robot name is named after itself; each
checked against Pinocchio's own reading of the same file where it applies."""
import warnings
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

pytest.importorskip("yourdfpy", reason="yourdfpy is not installed (extra 'urdf')")

import symgen  # noqa: E402
from symgen.io.urdf import UrdfError, scene_from_urdf  # noqa: E402
from symgen.io.urdf.physics import MasslessJointWarning, UrdfWarning  # noqa: E402

DATA = Path(__file__).parent / "data" / "urdf"


def loaded(name: str, **options):
    """The scene of ``DATA/name``, and the URDF warnings it raised."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        scene = scene_from_urdf(DATA / name, **options)
    return scene, [w for w in caught if issubclass(w.category, UrdfWarning)]


def test_a_hand_that_moves_no_mass_is_locked_with_its_mimicking_finger():
    scene, caught = loaded("massless_hand.urdf")
    assert list(scene.joints) == ["shoulder", "elbow"]
    assert [w.category for w in caught] == [MasslessJointWarning]
    text = str(caught[0].message)
    assert "joint 'hand' and 1 joint(s) that mimic it (finger) move no mass" in text and "link 'palm'" in text
    # the finger follows the hand's q0 (0): 0.5 * 0 + 0.1
    assert scene.sources[0].lock == {"hand": 0, "finger": sp.Rational(1, 10)}


def test_the_locked_hand_equals_pinocchio_reduced_at_the_same_positions():
    pytest.importorskip("pinocchio", reason="pinocchio is not installed (extra 'oracle')")
    import pinocchio as pin

    scene, _ = loaded("massless_hand.urdf")
    model = symgen.derive(scene)
    full = pin.buildModelFromUrdf(str(DATA / "massless_hand.urdf"))
    # what the lock avoids (docs/guide/coming_from.md): Pinocchio keeps the joints, and its aba is NaN
    full_data = full.createData()
    assert np.isnan(pin.aba(full, full_data, np.full(full.nq, 0.1), np.zeros(full.nv), np.zeros(full.nv))).all()
    q_ref = pin.neutral(full)
    q_ref[full.joints[full.getJointId("finger")].idx_q] = 0.1
    reduced = pin.buildReducedModel(full, [full.getJointId("hand"), full.getJointId("finger")], q_ref)
    data = reduced.createData()
    rng = np.random.default_rng(3)
    for _ in range(5):
        q, v, a = rng.uniform(-1, 1, (3, 2))
        tau = model.inverse_dynamics(q, v, a)
        expected = pin.rnea(reduced, data, q, v, a)
        assert np.allclose(np.asarray(tau, dtype=float), expected, rtol=1e-12, atol=1e-12)


def test_strict_refuses_the_massless_hand_and_a_lone_massless_joint_is_refused():
    with pytest.raises(UrdfError, match="inertia='strict' refuses it") as info:
        scene_from_urdf(DATA / "massless_hand.urdf", inertia="strict")
    assert info.value.element == "link 'palm'"
    with pytest.raises(UrdfError, match="no other joint moves, so it cannot be locked") as info:
        scene_from_urdf(DATA / "zero_mass.urdf")
    assert info.value.element == "link 'arm'"


def test_a_massless_joint_mimicked_by_a_massive_one_keeps_its_coordinate():
    """Joint ``a`` moves a massless link, but ``b`` mimics it and moves 1 kg: the coupled row of the
    mass matrix is regular, so nothing is locked; the forward dynamics equals a Pinocchio KKT solve."""
    pytest.importorskip("pinocchio", reason="pinocchio is not installed (extra 'oracle')")
    from symgen.oracle.pinocchio_check import check_against_pinocchio

    scene, caught = loaded("massless_leader.urdf")
    assert list(scene.joints) == ["a", "b", "c"] and not caught
    diffs = check_against_pinocchio(symgen.derive(scene), states=5)
    assert any("dV_m" in d.quantity for d in diffs) and all(d.passed for d in diffs)


def test_mimic_false_reads_a_mimic_of_an_unknown_joint_as_an_independent_joint():
    with pytest.raises(UrdfError, match="mimic=False, or --no-mimic"):
        scene_from_urdf(DATA / "mimic_unknown.urdf")
    scene, _ = loaded("mimic_unknown.urdf", mimic=False)
    assert scene.joints["finger_joint"].actuated and not scene.constraints
    assert scene.motion.joints == ("j1", "finger_joint")
    assert any("<mimic> element(s) not read (mimic=False): joints finger_joint" in n for n in scene.notes)


def test_mimic_false_is_read_from_yaml_and_the_command_line(tmp_path, capsys):
    from symgen.cli import main
    from symgen.io.loading import load

    path = tmp_path / "scene.yaml"
    path.write_text(f"name: s\nurdf:\n  file: {DATA / 'mimic_unknown.urdf'}\n  mimic: false\n")
    assert "finger_joint" in load(str(path)).motion.joints
    path.write_text(f"name: s\nurdf:\n  file: {DATA / 'mimic_unknown.urdf'}\n  mimic: 0\n")
    with pytest.raises(symgen.errors.SymgenError, match="mimic must be true or false"):
        load(str(path))
    assert main(["info", str(DATA / "mimic_unknown.urdf"), "--no-mimic"]) == 0
    assert "qd (eq. 14)   : j1, finger_joint" in capsys.readouterr().out


def test_a_file_without_a_robot_name_is_named_after_itself_and_an_empty_one_is_refused():
    scene, _ = loaded("unnamed.urdf")
    assert scene.name == "unnamed" and any("has no name attribute" in n for n in scene.notes)
    with pytest.raises(UrdfError, match="has no <link>: the description is empty") as info:
        scene_from_urdf(DATA / "empty.urdf")
    assert info.value.element == "robot 'empty'"


def test_symgen_info_prints_what_the_reader_changed(capsys):
    from symgen.cli import main

    assert main(["info", str(DATA / "massless_hand.urdf")]) == 0
    out = capsys.readouterr().out
    assert "  note: URDF robot 'massless_hand': joint 'hand' and 1 joint(s) that mimic it" in out
