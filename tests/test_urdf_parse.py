"""Reading URDF files: exact numbers, and a typed error naming the link or joint and the line for
every bad file (tests/data/urdf/*.urdf)."""
from fractions import Fraction
from pathlib import Path

import pytest

pytest.importorskip("yourdfpy", reason="yourdfpy is not installed (extra 'urdf')")
pytest.importorskip("lxml", reason="lxml is not installed (extra 'urdf')")

from symgen.errors import SceneError, SymgenError  # noqa: E402
from symgen.io.urdf import UrdfError, read_urdf, scene_from_urdf  # noqa: E402
from symgen.io.urdf._deps import MissingExtraError  # noqa: E402

DATA = Path(__file__).parent / "data" / "urdf"

#: file -> (element named, line, words in the message)
BAD_FILES = {
    "missing_inertial": ("link 'arm'", 8, "has no <inertial>"),
    "zero_mass": ("link 'arm'", 8, "zero mass"),
    "negative_mass": ("link 'arm'", 10, "mass -1.5 is negative"),
    "triangle_inertia": ("link 'arm'", 11, "triangle inequality"),
    "indefinite_inertia": ("link 'arm'", 11, "not positive semi-definite"),
    "missing_parent": ("joint 'j1'", 4, "parent link 'shoulder' does not exist"),
    "cycle": ("joint 'j3'", 24, "form a cycle"),
    "malformed": ("URDF file 'malformed.urdf'", 7, "malformed XML"),
    "mimic_unknown": ("joint 'finger_joint'", 17, "mimics joint 'nowhere', which is not a joint of this robot"),
    "floating": ("joint 'free'", 17, "floating is not supported"),
}


@pytest.mark.parametrize("name", sorted(BAD_FILES))
def test_a_bad_file_names_the_element_and_its_line(name):
    element, line, words = BAD_FILES[name]
    path = DATA / f"{name}.urdf"
    with pytest.raises(UrdfError) as info:
        scene_from_urdf(path)
    err = info.value
    assert isinstance(err, SceneError)
    assert err.element == element and err.line == line and err.source == str(path)
    assert words in str(err) and f"line {line}" in str(err)


def test_a_cycle_names_every_joint_in_it():
    with pytest.raises(UrdfError, match="'j3', 'j2' form a cycle"):
        read_urdf(DATA / "cycle.urdf")


def _robot(joint: str, links: str = '<link name="a"/>' + '<link name="b"><inertial><mass value="1"/>'
           '<inertia ixx="1" iyy="1" izz="1"/></inertial></link>') -> str:
    return f'<robot name="r">\n{links}\n{joint}\n</robot>'


INLINE = {
    "a link with two parent joints": (
        _robot('<joint name="j1" type="fixed"><parent link="a"/><child link="b"/></joint>\n'
               '<joint name="j2" type="fixed"><parent link="a"/><child link="b"/></joint>'),
        "link 'b'", "is the child of two joints"),
    "two roots": ('<robot name="r"><link name="a"/>\n<link name="c"/></robot>', "link 'c'", "not connected"),
    "a link declared twice": ('<robot name="r"><link name="a"/>\n<link name="a"/></robot>', "link 'a'",
                              "declared twice (lines 1 and 2)"),
    "an unknown joint type": (_robot('<joint name="j" type="ball"><parent link="a"/><child link="b"/></joint>'),
                              "joint 'j'", "not a URDF joint type"),
    "a revolute joint without limit": (
        _robot('<joint name="j" type="revolute"><parent link="a"/><child link="b"/></joint>'),
        "joint 'j'", "needs a <limit>"),
    "lower above upper": (_robot('<joint name="j" type="prismatic"><parent link="a"/><child link="b"/>'
                                 '<limit lower="1" upper="-1" effort="1" velocity="1"/></joint>'),
                          "joint 'j'", "lower 1 > upper -1"),
    "a zero axis": (_robot('<joint name="j" type="continuous"><parent link="a"/><child link="b"/>'
                           '<axis xyz="0 0 0"/></joint>'), "joint 'j'", "zero vector"),
    "a mass that is not a number": (
        _robot('<joint name="j" type="continuous"><parent link="a"/><child link="b"/></joint>',
               '<link name="a"/><link name="b"><inertial><mass value="heavy"/><inertia ixx="1" iyy="1" izz="1"/>'
               '</inertial></link>'), "link 'b'", "'heavy' is not a finite number"),
    "negative damping": (_robot('<joint name="j" type="continuous"><parent link="a"/><child link="b"/>'
                                '<dynamics damping="-0.1"/></joint>'), "joint 'j'", "damping -0.1 is negative"),
    "a root element other than robot": ('<model name="r"/>', "URDF file '<string>'", "expected <robot>"),
    "a robot without name": ('<robot><link name="a"/></robot>', "<robot>", "no name attribute"),
    "a missing effort (found by yourdfpy)": (
        _robot('<joint name="j" type="revolute"><parent link="a"/><child link="b"/>'
               '<limit lower="-1" upper="1" velocity="1"/></joint>'), "robot 'r'", "missing attribute 'effort'"),
}


@pytest.mark.parametrize("case", sorted(INLINE))
def test_inline_bad_urdf_is_a_typed_error_naming_the_element(case):
    text, element, words = INLINE[case]
    with pytest.raises(UrdfError) as info:
        scene_from_urdf(text)
    assert info.value.element == element and words in str(info.value)


def test_a_missing_file_is_named():
    with pytest.raises(UrdfError, match="'/no/such/robot.urdf': not found"):
        read_urdf("/no/such/robot.urdf")


def test_numbers_are_the_exact_decimals_of_the_file():
    robot = read_urdf(DATA / "fixed_and_tilted.urdf")
    j2, j4 = robot.joints["j2"], robot.joints["j4"]
    assert j2.origin.rpy[0] == Fraction("1.5707963267948966")
    assert j2.origin.xyz == (Fraction(1, 10), 0, Fraction(3, 10))
    assert (j2.damping, j2.friction) == (Fraction(1, 10), Fraction(1, 20))
    assert j4.axis == (Fraction(3, 5), 0, Fraction(4, 5))
    assert (j4.limits.lower, j4.limits.upper, j4.limits.velocity) == (0, Fraction(3, 10), Fraction(1, 2))
    link1 = robot.links["link1"]
    assert link1.inertial.mass == 2 and link1.inertial_origin.rpy == (Fraction(1, 10), Fraction(1, 5), Fraction(3, 10))
    assert link1.inertial.inertia[0, 2] == Fraction(-2, 1000)


def test_the_tree_is_read_in_file_order_from_its_root():
    robot = read_urdf(DATA / "fixed_and_tilted.urdf")
    assert robot.root == "base"
    assert robot.children["link3"] == ["camera_mount", "j4"]
    assert robot.links["tool"].inertial is None


def test_a_missing_parser_names_the_extra_to_install(monkeypatch):
    import symgen.io.urdf._deps as deps

    real = deps.importlib.import_module

    def fake(name, *args):
        if name == "yourdfpy":
            raise ImportError(name)
        return real(name, *args)

    monkeypatch.setattr(deps.importlib, "import_module", fake)
    with pytest.raises(MissingExtraError) as info:
        read_urdf(DATA / "fixed_and_tilted.urdf")
    assert isinstance(info.value, SymgenError) and "pip install 'symgen[urdf]'" in str(info.value)
