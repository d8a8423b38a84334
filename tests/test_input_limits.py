"""The bounded front door: pathological scene files and URDFs give typed errors naming the element
and the line, quickly (no parser, exact constructor or SymPy conversion sees the bad number)."""
import time

import pytest

import symgen
from symgen.scene import input_limits as limits
from symgen.errors import ConstraintError, SceneError, SymgenError
from symgen.scene import Scene
from symgen.io.scene_yaml import load_scene
from symgen.io.urdf import UrdfError, read_urdf, scene_from_urdf

#: every refusal below must come well within this many seconds (the unbounded readers took minutes)
FAST = 2.0

BASE = """\
name: pendulum
bodies:
  link: {mass: 1, com: [0.5, 0, 0], inertia: [0.01, 0.1, 0.1]}
joints:
  hinge: {type: revolute, parent: world, child: link, xyz: [0, 0, 1], axis: y, actuated: true}
motion: {joints: [hinge]}
"""

URDF = """<robot name="r">
  <link name="base"/>
  <link name="arm">
    <inertial><mass value="{mass}"/><inertia ixx="{ixx}" iyy="0.1" izz="0.1"/></inertial>{extra}
  </link>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="arm"/><origin xyz="0 0 {z}"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
</robot>
"""


def urdf(mass="1", ixx="0.1", z="0.5", extra=""):
    return URDF.format(mass=mass, ixx=ixx, z=z, extra=extra)


def refused(text: str, error=SceneError) -> SceneError:
    start = time.perf_counter()
    with pytest.raises(error) as info:
        load_scene(text)
    assert time.perf_counter() - start < FAST
    return info.value


def edited(old: str, new: str) -> str:
    assert old in BASE, old
    return BASE.replace(old, new, 1)


def test_the_base_scene_and_urdf_load():
    assert symgen.derive(load_scene(BASE)).counts.m == 1
    assert scene_from_urdf(urdf()).name == "r"


# ---------------------------------------------------------------------------- structure of the text
def test_nesting_a_thousand_levels_deep_is_refused_with_its_line():
    err = refused(BASE + "gravity: " + "[" * 1000 + "]" * 1000 + "\n")
    assert f"nested more than {limits.MAX_DEPTH} levels" in str(err) and "line 7" in str(err)
    assert err.line == 7


def test_a_nul_byte_is_refused_with_its_line():
    err = refused(edited("motion:", "\0motion:"))
    assert "NUL" in str(err) and err.line == 6


def test_a_lone_surrogate_in_a_description_is_refused():
    err = refused(BASE + 'description: "broken \\ud800 text"\n')
    assert "surrogate" in str(err) and "description" in str(err) and err.line == 7


def test_an_alias_bomb_is_refused_while_it_is_parsed():
    levels = ["a0: &a0 [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]"]
    levels += [f"a{i}: &a{i} [" + ", ".join([f"*a{i - 1}"] * 10) + "]" for i in range(1, 9)]
    text = BASE.replace("name: pendulum\n", "name: pendulum\nx-anchors:\n  " + "\n  ".join(levels) + "\n")
    err = refused(text + "gravity: *a8\n")
    assert "alias" in str(err) and err.line is not None


def test_an_alias_to_its_own_container_is_refused():
    err = refused(BASE + "gravity: &g [0, 0, *g]\n")
    assert "contains it" in str(err)


# ---------------------------------------------------------------------------- numbers in YAML
def test_an_integer_of_thousands_of_digits_is_refused_before_it_is_converted():
    err = refused(edited("mass: 1,", "mass: " + "7" * 5000 + ","))
    assert "5000 digits" in str(err) and "bodies.link.mass" in str(err) and err.line == 3


@pytest.mark.parametrize("text", ["1e99999999", "'1e99999999'", "1e-999999", "'-3e-999999*pi'"])
def test_huge_exponents_are_refused_from_the_text(text):
    err = refused(edited("xyz: [0, 0, 1]", f"xyz: [0, 0, {text}]"))
    assert "exponent" in str(err) and "joints.hinge.xyz[2]" in str(err) and err.line == 5


@pytest.mark.parametrize("old, new, element", [
    ("mass: 1,", "mass: 1e200,", "body 'link'"),
    ("inertia: [0.01, 0.1, 0.1]", "inertia: [1e160, 1e160, 1e160]", "body 'link'"),
    ("com: [0.5, 0, 0]", "com: [1e300, 0, 0]", "body 'link'"),
    ("xyz: [0, 0, 1]", "xyz: [0, 0, 1e-200]", "joint 'hinge'"),
])
def test_numbers_out_of_the_magnitude_range_name_the_element_and_line(old, new, element):
    err = refused(edited(old, new))
    assert err.element == element and "outside the range" in str(err)
    assert "line 3" in str(err) or "line 5" in str(err)


def test_extreme_gravity_is_refused():
    err = refused(BASE + "gravity: [0, 0, -1e300]\n")
    assert "gravity" in str(err) and "outside the range" in str(err)


def test_a_long_but_moderate_exact_number_is_accepted():
    """Exact rationals of a few hundred digits (what symgen writes for merged links) are data."""
    third = "3" * 300 + "/" + "1" + "0" * 300
    assert load_scene(edited("xyz: [0, 0, 1]", f"xyz: [0, 0, '{third}']")).joints["hinge"].origin.translation[2] > 0


def test_an_axis_of_two_hundred_digits_is_a_direction():
    scene = load_scene(edited("axis: y", "axis: [0, " + "9" * 200 + ", 0]"))
    assert list(scene.joints["hinge"].axis) == [0, 1, 0]


def test_the_scene_api_applies_the_same_bounds():
    scene = Scene("api")
    with pytest.raises(SceneError, match="outside the range"):
        scene.add_body("b", 10 ** 40)
    start = time.perf_counter()
    with pytest.raises(SceneError, match="exponent"):
        scene.add_body("c", "1e99999999")
    with pytest.raises(SceneError, match="outside the range"):
        scene.add_parameter("m", "1e-300")
    assert time.perf_counter() - start < FAST


# ---------------------------------------------------------------------------- URDF
@pytest.mark.parametrize("kwargs, what", [
    (dict(mass="1e99999999"), "mass"), (dict(ixx="1e-999999"), "inertia ixx"), (dict(z="1" * 5000), "origin xyz"),
])
def test_urdf_number_text_is_bounded(kwargs, what):
    start = time.perf_counter()
    with pytest.raises(UrdfError) as info:
        read_urdf(urdf(**kwargs))
    assert time.perf_counter() - start < FAST
    assert info.value.element in ("link 'arm'", "joint 'j1'") and what in str(info.value) and info.value.line


@pytest.mark.parametrize("kwargs", [dict(mass="1e300"), dict(ixx="1e160")])
def test_urdf_magnitudes_out_of_range_are_typed(kwargs):
    with pytest.raises(UrdfError, match="outside the range") as info:
        read_urdf(urdf(**kwargs))
    assert info.value.line


def test_a_urdf_origin_below_the_range_is_read_as_zero_with_a_note():
    """CAD exports write 7.9e-31 for a zero angle: below 1e-30 an origin value is 0, and a note says so."""
    robot = read_urdf(urdf(z="1e-250"))
    assert robot.notes == ["joint 'j1': origin xyz 1e-250 is below 1e-30: read as 0 (line 7)"]
    assert robot.joints["j1"].origin.xyz[2] == 0


def test_a_urdf_element_yourdfpy_cannot_index_names_the_link_and_line():
    with pytest.raises(UrdfError) as info:
        read_urdf(urdf(extra="<visual><geometry/></visual>"))
    assert info.value.element == "link 'arm'" and info.value.line == 3 and "IndexError" in str(info.value)


def test_a_nul_byte_in_a_urdf_is_refused_with_its_line():
    with pytest.raises(UrdfError, match="NUL") as info:
        read_urdf(urdf().replace("<link name=\"base\"/>", "<link name=\"base\"/>\0"))
    assert info.value.line == 2


# ---------------------------------------------------------------------------- derive
ARM = symgen.__path__[0] + "/io/scenes/arm_on_plane.yaml"


def arm_without_actuation(joint: str, forces: str = "operational") -> str:
    lines = open(ARM, encoding="utf-8").read().splitlines()
    text = "\n".join(line.replace(" actuated: true,", "") if line.strip().startswith(f"{joint}:") else line
                     for line in lines)
    return text.replace("constraint_forces: operational", f"constraint_forces: {forces}")


def test_arm_on_plane_with_a_passive_wrist_joint_says_why_in_the_papers_terms():
    """Joint j2 passive: one of the n_c = 3 contact constraints falls on it (n_p = 1), so the
    operational choice T_c = T_a1 of eq. (12) is not square."""
    with pytest.raises(ConstraintError) as info:
        symgen.derive(load_scene(arm_without_actuation("j2")))
    assert info.value.element == "constraint_forces"
    assert "n_p = 1" in str(info.value) and "constraint_forces: joint" in str(info.value)


def test_arm_on_plane_with_a_passive_joint_and_joint_forces_derives():
    """The fix the error names works: with T_c = 1 the model has n = m + n_c - n_p = 5 (eq. 13)."""
    model = symgen.derive(load_scene(arm_without_actuation("j2", "joint")))
    assert model.counts.as_dict()["np"] == 1 and model.counts.n == 5


@pytest.mark.parametrize("joint", ["j1", "j2", "j3", "j4", "j5", "j6"])
def test_arm_on_plane_with_any_joint_made_passive_gives_a_model_or_a_typed_error(joint):
    try:
        model = symgen.derive(load_scene(arm_without_actuation(joint)))
    except SymgenError:
        return
    assert model.counts.m == 3
