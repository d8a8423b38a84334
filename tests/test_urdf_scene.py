"""URDF to scene (symgen.io.urdf.build) and the urdf: section of scene files (symgen.io.urdf.yaml_section):
what becomes a body, a frame, a joint, and what is carried along."""

import pytest
import sympy as sp

pytest.importorskip("yourdfpy", reason="yourdfpy is not installed (extra 'urdf')")

import symgen  # noqa: E402
from symgen.errors import SceneError  # noqa: E402
from symgen.io.scene_yaml import dump_scene, load_scene  # noqa: E402
from symgen.io.urdf import UrdfError, add_urdf, scene_from_urdf  # noqa: E402

from .urdf_util import DATA  # noqa: E402
TILTED = DATA / "fixed_and_tilted.urdf"
R = sp.Rational


from .urdf_util import needs_examples  # noqa: E402


@pytest.fixture(scope="module")
def tilted():
    return scene_from_urdf(TILTED)


def test_moving_joints_become_bodies_and_fixed_links_become_frames(tilted):
    assert list(tilted.bodies) == ["link1", "link2", "link3", "link4", "link5"]
    assert list(tilted.joints) == ["j1", "j2", "j3", "j4", "j5"]
    assert {f: tilted.frames[f].body for f in tilted.frames} == {
        "base": "world", "mount": "world", "link2b": "link2", "camera": "link3", "tool": "link5"}


def test_a_fixed_branch_is_merged_into_its_parent_body(tilted):
    # camera (0.2 kg, com (0, 0, 0.01) in its frame) at (0.05, 0.05, 0.02), rpy (-pi/2, 0, pi):
    # R = Rz(pi) Rx(-pi/2) = [[-1, 0, 0], [0, 0, -1], [0, -1, 0]], so its com is (0.05, 0.04, 0.02)
    # in link3; link3 itself: 1 kg at (0, 0.1, 0). Merged: 1.2 kg at (1/120, 0.09, 1/300).
    link3 = tilted.bodies["link3"]
    assert link3.mass == R(6, 5)
    assert list(link3.com) == [R(1, 120), R(9, 100), R(1, 300)]
    assert tilted.frames["camera"].pose.rotation == sp.Matrix([[-1, 0, 0], [0, 0, -1], [0, -1, 0]])


def test_the_root_and_links_fixed_to_it_carry_no_mass(tilted):
    assert sum(b.mass for b in tilted.bodies.values()) == R(2) + R(3, 2) + R(1, 2) + R(6, 5) + R(2, 5) + R(3, 10)


def test_a_joint_below_fixed_links_is_placed_in_the_merged_body(tilted):
    # j1 sits 0.2 above mount, which is 0.1 above the root turned by yaw 0.5 -> origin (0, 0, 0.3)
    assert list(tilted.joints["j1"].origin.translation) == [0, 0, R(3, 10)]


def test_damping_and_friction_become_the_joint_friction_of_eq_22(tilted):
    j2, j3, j4 = (tilted.joints[n] for n in ("j2", "j3", "j4"))
    assert (j2.viscous, j2.coulomb) == (R(1, 10), R(1, 20))
    assert (j3.viscous, j3.coulomb) == (0, R(1, 20))
    assert (j4.viscous, j4.coulomb) == (R(1, 5), 0)
    assert scene_from_urdf(TILTED, friction=False).joints["j2"].viscous == 0


def test_joint_friction_read_from_dynamics_is_announced_in_a_note(tilted):
    assert any("<dynamics damping friction>: read as the joint friction" in n and "j2" in n for n in tilted.notes)
    quiet = scene_from_urdf(TILTED, friction=False)
    assert any("<dynamics damping friction>: left out (friction=False)" in n for n in quiet.notes)


def test_limits_are_carried_and_continuous_joints_have_none(tilted):
    limits = tilted.joint_limits
    assert (limits["j2"].lower, limits["j2"].upper) == (-2, 2)
    assert (limits["j4"].upper, limits["j4"].effort) == (R(3, 10), 100)
    assert limits["j3"].lower is None and limits["j3"].upper is None
    assert tilted.joints["j3"].type == "revolute"


def test_axes_are_coordinate_names_or_exact_unit_vectors(tilted):
    assert list(tilted.joints["j3"].axis) == [0, -1, 0]
    assert list(tilted.joints["j4"].axis) == [R(3, 5), 0, R(4, 5)]
    assert list(tilted.joints["j5"].axis) == [sp.sqrt(2) / 2, sp.sqrt(2) / 2, 0]


def test_q0_defaults_to_zero_or_the_middle_of_limits_that_exclude_it():
    text = TILTED.read_text().replace('<limit lower="0" upper="0.3"', '<limit lower="0.1" upper="0.3"')
    scene = scene_from_urdf(text)
    assert scene.joints["j4"].q0 == R(1, 5) and scene.joints["j1"].q0 == 0


def test_a_q0_outside_the_limits_is_refused():
    with pytest.raises(UrdfError, match="outside its limits"):
        scene_from_urdf(TILTED, q0={"j2": 3})


def test_locking_a_joint_merges_its_child_at_that_position():
    scene = scene_from_urdf(TILTED, lock={"j4": "0.1"})
    assert "j4" not in scene.joints and "link4" not in scene.bodies
    # link4 (0.4 kg at its origin) slides 0.1 along (0.6, 0, 0.8) from (0, 0.2, 0) in link3
    assert scene.frames["link4"].pose.translation == sp.Matrix([R(6, 100), R(2, 10), R(8, 100)])
    assert scene.bodies["link3"].mass == R(6, 5) + R(2, 5)
    assert scene.joints["j5"].parent == "link3"


def test_one_file_twice_with_prefixes_and_a_base_placement():
    scene = symgen.Scene("pair")
    add_urdf(scene, TILTED, prefix="a1_")
    add_urdf(scene, TILTED, prefix="a2_", base_xyz=[1, 0, 0], base_rpy=[0, 0, "pi"])
    assert "a1_j1" in scene.joints and "a2_link5" in scene.bodies and "a2_tool" in scene.frames
    assert list(scene.joints["a2_j1"].origin.translation) == [1, 0, R(3, 10)]
    # the root turns by pi, then mount by 0.5 about z: the first joint's frame turns by pi + 0.5
    rot = scene.joints["a2_j1"].origin.rotation
    assert abs(float(rot[0, 0]) - float(sp.cos(sp.pi + R(1, 2)))) < 1e-18


def test_names_that_are_not_identifiers_are_rewritten():
    text = TILTED.read_text().replace('"link5"', '"link-5"')
    scene = scene_from_urdf(text)
    assert "link_5" in scene.bodies and scene.frames["tool"].body == "link_5"


def test_a_locked_unknown_joint_is_named():
    with pytest.raises(UrdfError, match="lock 'elbow': no joint of this name"):
        scene_from_urdf(TILTED, lock={"elbow": 0})


def test_the_scene_writes_to_yaml_and_reads_back_equal(tilted):
    again = load_scene(dump_scene(tilted))
    for part in ("bodies", "joints", "frames", "motion", "gravity"):
        assert getattr(again, part) == getattr(tilted, part), part


# ------------------------------------------------------------------ the urdf: section of scene files
def test_a_scene_file_adds_a_contact_to_a_urdf_robot():
    scene = load_scene(DATA / "tilted_on_plane.yaml")
    model = symgen.derive(scene)
    assert model.counts.as_dict() == {"n1a": 5, "n1u": 0, "n3a": 0, "n3u": 0, "m": 2, "nc": 3, "np": 0, "n": 5}
    assert scene.constraints["contact"].components == ("vz", "wx", "wy")
    assert scene.frames["plane"].body == "world"


def test_a_scene_file_holds_one_object_with_two_copies_of_a_urdf():
    scene = load_scene(DATA / "tilted_pair.yaml")
    model = symgen.derive(scene)
    assert model.counts.as_dict() == {"n1a": 10, "n1u": 0, "n3a": 0, "n3u": 0, "m": 4, "nc": 6, "np": 0, "n": 10}
    assert scene.joints["box_grip"].parent == "a1_link5" and scene.motion.joints[-1] == "a2_j4"


def test_a_closure_without_motion_gets_joints_chosen_at_q0():
    text = (f"name: loop\nurdf:\n  file: {TILTED}\n  q0: {{j2: 0.5, j3: 0.3, j4: 0.1, j5: 0.4}}\n"
            "  close: {tip: {type: ball, frames: [tool, world]}}\n")
    model = symgen.derive(load_scene(text))
    assert model.counts.m == 2 and model.scene.frames["tip_b"].body == "world"


def test_a_scene_file_without_constraints_moves_every_joint():
    scene = load_scene(f"name: t\nurdf: {{file: {TILTED}}}\n")
    assert scene.motion.joints == ("j1", "j2", "j3", "j4", "j5")


def test_an_unknown_key_in_the_urdf_section_is_named_with_its_line():
    with pytest.raises(SceneError, match=r"unknown key 'lokc'; did you mean 'lock'\?.*line 4"):
        load_scene(f"name: t\nurdf:\n  file: {TILTED}\n  lokc: {{j1: 0}}\n")


def test_a_urdf_error_keeps_the_urdf_file_line(tmp_path):
    (tmp_path / "bad.urdf").write_text((DATA / "negative_mass.urdf").read_text())
    (tmp_path / "s.yaml").write_text("name: s\nurdf: {file: bad.urdf}\n")
    with pytest.raises(UrdfError) as info:
        load_scene(tmp_path / "s.yaml")
    assert info.value.line == 10 and "bad.urdf, line 10" in str(info.value)


@needs_examples
def test_a_scene_file_can_name_an_example_robot():
    scene = load_scene("name: arm\nurdf: {example: ur5, q0: {elbow_joint: pi/2}}\n")
    assert scene.joints["elbow_joint"].q0 == sp.pi / 2 and len(scene.joints) == 6
