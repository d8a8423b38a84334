"""YAML scene files: exact reading, exact round trip, deterministic writing."""
from dataclasses import fields

import pytest
import sympy as sp
import yaml

from symgen.errors import SceneError
from symgen.scene import Scene
from symgen.io.scene_yaml import dump_scene, load_scene, save_scene, scene_from_dict

# A valid scene using every feature of the format: parameters, 3- and 6-entry inertia, all four
# joint types, rpy / quat / rotation placements, a non-coordinate axis, friction, rotor inertia,
# q0 of each kind, frames on bodies and on the world, a planar weld with a non-z normal, a custom
# constraint against the world, weighted motion frames, contact forces and joint-space forces.
# Coordinates: 1 + 1 + 1 + 3 + 0 + 1 = 7; constraints 3 + 1 = 4; so m = 3.
EVERY_FEATURE = """\
name: every_feature
description: a scene that uses every part of the YAML format
gravity: [0.0, 0, -9.81]
parameters: {m_arm: 1.5, len_arm: 0.25}
bodies:
  base_link: {mass: 2, com: [0, 0, 0.1], inertia: [0.02, 0.03, 0.04, 0.001, 0, -0.002]}
  arm: {mass: m_arm, com: [0.125, 0, 0], inertia: [0.001, 0.01, 0.01]}
  slider: {mass: 1/3, inertia: [0.001, 0.001, 0.001]}
  ball_link: {mass: 0.5, com: [0, 0, 0.05], inertia: [0.002, 0.002, 0.001]}
  tool: {mass: 0}
  rocker: {mass: 1.0, com: [0, 0, 0.1], inertia: [0.004, 0.004, 0.0001]}
joints:
  j_base: {type: revolute, parent: world, child: base_link, xyz: [0, 0, 0.05], rpy: [0, 0, pi/4], axis: z,
           actuated: true, rotor_inertia: 0.002, friction: {viscous: 0.1, coulomb: 0.05}, q0: pi/6}
  j_arm: {type: revolute, parent: base_link, child: arm, xyz: [0.1, 0, 0.2], rpy: [0.1, 0.2, 0.3], axis: [1, 1, 0],
          actuated: true}
  j_slide: {type: prismatic, parent: arm, child: slider, xyz: [len_arm, 0, 0], quat: [1, 1, 0, 0], axis: -x,
            actuated: true, q0: 0.05}
  j_ball: {type: spherical, parent: slider, child: ball_link, q0: [1, 0, 0, 1]}
  j_tool: {type: fixed, parent: ball_link, child: tool, xyz: [0, 0, 0.1], rotation: [[0, 0, 1], [1, 0, 0], [0, 1, 0]]}
  j_rock: {type: revolute, parent: world, child: rocker, xyz: [0.5, 0, 0], axis: y}
frames:
  tip: {body: tool, xyz: [0, 0, 0.1], rpy: [pi/2, 0, 0]}
  anchor: {body: world, xyz: [0.4, 0, 0.3]}
  O1: {body: rocker, xyz: [0, 0, 0.2]}
  O2: {body: arm, xyz: [len_arm, 0, 0]}
constraints:
  c_plane: {type: planar_weld, frames: [tip, anchor], normal: x}
  c_height: {type: custom, frames: [O1], components: [vz]}
motion: {frames: {O1: 1/3, O2: 2/3}, components: [vx, vy, wz]}
contact_forces: {frame: tip, components: [vx, vy, wz]}
constraint_forces: joint
"""

R = sp.Rational
SQ2 = sp.sqrt(2) / 2


def assert_same_scene(a: Scene, b: Scene) -> None:
    """Field by field first (readable failures), then the whole dataclass."""
    for f in fields(Scene):
        assert getattr(a, f.name) == getattr(b, f.name), f.name
    assert a == b


def round_trip(scene: Scene, validate: bool = True) -> Scene:
    return scene_from_dict(yaml.safe_load(dump_scene(scene)), validate=validate)


@pytest.fixture(scope="module")
def every() -> Scene:
    return load_scene(EVERY_FEATURE)


# ---------------------------------------------------------------------------- reading
def test_every_feature_reads_the_declared_values(every):
    m_arm = sp.Symbol("m_arm", real=True)
    assert every.parameters == {m_arm: R(3, 2), sp.Symbol("len_arm", real=True): R(1, 4)}
    assert every.gravity == sp.ImmutableMatrix([0, 0, R(-981, 100)])
    assert every.bodies["arm"].mass == m_arm
    assert every.bodies["slider"].mass == R(1, 3)
    assert every.bodies["base_link"].inertia == sp.ImmutableMatrix(
        [[R(2, 100), R(1, 1000), 0], [R(1, 1000), R(3, 100), R(-2, 1000)], [0, R(-2, 1000), R(4, 100)]])
    base = every.joints["j_base"]
    assert base.origin.rotation == sp.ImmutableMatrix([[SQ2, -SQ2, 0], [SQ2, SQ2, 0], [0, 0, 1]])
    assert (base.rotor_inertia, base.viscous, base.coulomb, base.q0) == (R(1, 500), R(1, 10), R(1, 20), sp.pi / 6)
    assert every.joints["j_arm"].axis == sp.ImmutableMatrix([SQ2, SQ2, 0])
    slide = every.joints["j_slide"]  # quat [1, 1, 0, 0]: a quarter turn about x
    assert slide.origin.rotation == sp.ImmutableMatrix([[1, 0, 0], [0, 0, -1], [0, 1, 0]])
    assert slide.origin.translation == sp.ImmutableMatrix([sp.Symbol("len_arm", real=True), 0, 0])
    assert slide.axis == sp.ImmutableMatrix([-1, 0, 0])
    assert every.joints["j_ball"].q0 == sp.ImmutableMatrix([[0, -1, 0], [1, 0, 0], [0, 0, 1]])
    assert every.joints["j_tool"].origin.rotation == sp.ImmutableMatrix([[0, 0, 1], [1, 0, 0], [0, 1, 0]])
    assert every.frames["tip"].pose.rotation == sp.ImmutableMatrix([[1, 0, 0], [0, 0, -1], [0, 1, 0]])
    assert every.constraints["c_plane"].components == ("vy", "vz", "wx")
    assert every.constraints["c_height"].frame_b == "world"
    assert every.motion.frames == (("O1", R(1, 3)), ("O2", R(2, 3)))
    assert every.contact_forces.components == ("vx", "vy", "wz")
    assert every.constraint_forces == "joint"


def test_declaration_order_is_kept(every):
    assert list(every.bodies) == ["base_link", "arm", "slider", "ball_link", "tool", "rocker"]
    assert list(every.joints) == ["j_base", "j_arm", "j_slide", "j_ball", "j_tool", "j_rock"]


def test_yaml_decimal_is_read_exactly():
    scene = load_scene("name: s\nbodies: {b: {mass: 0.1, com: [1.0e-3, 1e-3, -2.5]}}\n"
                       "joints: {j: {type: revolute, parent: world, child: b, q0: -pi/2}}\nmotion: {joints: [j]}")
    body = scene.bodies["b"]
    assert body.mass == R(1, 10) and isinstance(body.mass, sp.Rational)
    assert body.com == sp.ImmutableMatrix([R(1, 1000), R(1, 1000), R(-5, 2)])
    assert scene.joints["j"].q0 == -sp.pi / 2


def test_parameters_from_a_yaml_string():
    text = """\
name: pendulum
parameters: {m_link: 2.5, l_link: 1/2}
bodies:
  link: {mass: m_link, com: [l_link, 0, 0], inertia: [0.01, 0.02, 0.02]}
joints:
  pivot: {type: revolute, parent: world, child: link, axis: y}
motion: {joints: [pivot]}
"""
    scene = load_scene(text)
    m, l = sp.Symbol("m_link", real=True), sp.Symbol("l_link", real=True)
    assert scene.parameters == {m: R(5, 2), l: R(1, 2)}
    assert scene.bodies["link"].mass == m
    assert scene.bodies["link"].com == sp.ImmutableMatrix([l, 0, 0])
    assert scene.value_of(scene.bodies["link"].mass) == 2.5
    assert "m_link: 2.5" in dump_scene(scene)


def test_the_three_rotation_forms_agree():
    def pose(rotation: str):
        scene = load_scene(f"name: s\nframes: {{f: {{body: world, {rotation}}}}}", validate=False)
        return scene.frames["f"].pose

    expected = sp.ImmutableMatrix([[0, -1, 0], [1, 0, 0], [0, 0, 1]])
    assert pose("rpy: [0, 0, pi/2]").rotation == expected
    assert pose("quat: [1, 0, 0, 1]").rotation == expected
    assert pose("rotation: [[0, -1, 0], [1, 0, 0], [0, 0, 1]]").rotation == expected


def test_yaml_merge_keys_share_a_definition():
    text = """\
name: s
bodies:
  a: &link {mass: 1.0, inertia: [0.01, 0.01, 0.01]}
  b: {<<: *link, mass: 2.0}
joints:
  ja: {type: revolute, parent: world, child: a}
  jb: {type: revolute, parent: a, child: b}
motion: {joints: [ja, jb]}
"""
    scene = load_scene(text)
    assert scene.bodies["b"].mass == 2 and scene.bodies["b"].inertia == scene.bodies["a"].inertia


# ---------------------------------------------------------------------------- writing
def test_round_trip_every_feature(every):
    assert_same_scene(round_trip(every), every)


def test_round_trip_through_the_exact_loader(every):
    assert_same_scene(load_scene(dump_scene(every)), every)


def test_dump_is_deterministic(every):
    text = dump_scene(every)
    assert dump_scene(load_scene(EVERY_FEATURE)) == text
    assert dump_scene(round_trip(every)) == text


def test_dump_writes_exact_forms(every):
    text = dump_scene(every)
    assert "mass: 1/3" in text  # not a decimal: written as a fraction
    assert "q0: pi/6" in text
    assert "rpy: [0, 0, pi/4]" in text  # irrational matrix: angles recovered from the matrix
    assert "rpy: [0.1, 0.2, 0.3]" in text
    assert "quat: [1, 1, 0, 0]" in text  # rational matrix: integer quaternion
    assert "axis: [1, 1, 0]" in text


@pytest.mark.parametrize("kind, normal", [("weld", "z"), ("ball", "z"), ("planar_weld", "x"), ("planar_weld", "y"),
                                          ("planar_weld", "z"), ("plane_contact", "x"), ("plane_contact", "y"),
                                          ("plane_contact", "z")])
def test_round_trip_constraint_kinds(kind, normal):
    scene = Scene("kinds")
    scene.add_body("b", 1, inertia=[1, 1, 1])
    scene.add_joint("j", "revolute", "world", "b")
    scene.add_frame("f", "b", xyz=[1, 0, 0])
    scene.add_constraint("c", kind, "f", "world", normal=normal)
    scene.add_constraint("c_custom", "custom", "f", components=["wy", "vx"])
    assert_same_scene(round_trip(scene, validate=False), scene)


@pytest.mark.parametrize("motion", [dict(joints=["j"]), dict(frame="f", components=["wz"]), dict(frame="f"),
                                    dict(frames={"f": "1/3", "g": "2/3"}, components=["vx", "vy"])])
def test_round_trip_motion_forms(motion):
    scene = Scene("motions")
    scene.add_body("b", 1, inertia=[1, 1, 1])
    scene.add_joint("j", "revolute", "world", "b")
    scene.add_frame("f", "b")
    scene.add_frame("g", "world")
    scene.set_motion(**motion)
    assert_same_scene(round_trip(scene, validate=False), scene)


def test_round_trip_of_a_python_built_scene():
    scene = Scene("api", description="built in Python")
    scene.gravity = sp.ImmutableMatrix([0, R(-981, 100), 0])
    scene.add_body("b", R(1, 7), com=[R(1, 3), 0, 0], inertia=[1, 1, 1])
    scene.add_joint("j", "revolute", "world", "b", rpy=[R(-1, 2), 2, sp.pi / 3], axis=[0, 3, 4], q0=R(22, 7))
    scene.add_frame("f", "b", rpy=[0, sp.pi / 2, 0])  # gimbal lock: roll and yaw are not unique
    scene.set_motion(joints=["j"])
    again = round_trip(scene)
    assert_same_scene(again, scene)
    assert again.joints["j"].axis == sp.ImmutableMatrix([0, R(3, 5), R(4, 5)])


def test_save_and_load_a_file(tmp_path, every):
    path = tmp_path / "every.yaml"
    save_scene(every, path)
    assert path.read_text(encoding="utf-8") == dump_scene(every)
    assert_same_scene(load_scene(path), every)
    assert_same_scene(load_scene(str(path)), every)
    assert [p.name for p in tmp_path.iterdir()] == ["every.yaml"]  # no temporary file left behind


def test_a_value_with_no_exact_form_is_refused():
    scene = Scene("s")
    scene.gravity = sp.ImmutableMatrix([0, 0, -sp.sqrt(2)])
    with pytest.raises(SceneError, match="gravity"):
        dump_scene(scene)


def test_every_builtin_scene_round_trips():
    from symgen.io.builtin import get_scene, list_builtins

    for name, _, _ in list_builtins():
        scene = get_scene(name)
        assert_same_scene(round_trip(scene), scene)
