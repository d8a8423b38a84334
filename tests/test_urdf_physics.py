"""What the URDF reader accepts of imperfect files, and how it says so (symgen.io.urdf.physics):
each rule on a small handwritten file of tests/data/urdf/."""
import warnings
from fractions import Fraction
from itertools import combinations

import numpy as np
import pytest
import sympy as sp

pytest.importorskip("yourdfpy", reason="yourdfpy is not installed (extra 'urdf')")
pytest.importorskip("lxml", reason="lxml is not installed (extra 'urdf')")

from symgen.errors import SceneError, SymgenError  # noqa: E402
from symgen.io.loading import load  # noqa: E402
from symgen.io.scene_yaml import load_scene  # noqa: E402
from symgen.io.urdf import UrdfError, read_urdf, scene_from_urdf  # noqa: E402
from symgen.io.urdf.build import NoMovingJointError  # noqa: E402
from symgen.io.urdf.inertia import repaired_inertia  # noqa: E402
from symgen import errors as symgen_errors  # noqa: E402
from symgen.io.urdf.physics import FixedBaseWarning, InertiaWarning, UrdfWarning  # noqa: E402

from .urdf_util import DATA  # noqa: E402


def quietly(path, **options):
    """The scene, and the URDF warnings it raised."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        scene = scene_from_urdf(DATA / path, **options)
    return scene, [w for w in caught if issubclass(w.category, UrdfWarning)]


def exact_psd(matrix) -> bool:
    """Every principal minor of the symmetric rational ``matrix`` is >= 0 (exact, no eigenvalues)."""
    m = sp.Matrix(matrix)
    return all(m.extract(list(rows), list(rows)).det() >= 0 for k in (1, 2, 3) for rows in combinations(range(3), k))


def exact_rigid_body_inertia(matrix) -> bool:
    """PSD, and the triangle inequality: the moments a, b, c obey a + b >= c for every order exactly
    when tr(I)/2 - I (eigenvalues (a + b - c)/2 ...) is PSD."""
    m = sp.Matrix(matrix)
    return exact_psd(m) and exact_psd(m.trace() / 2 * sp.eye(3) - m)


def arm_inertia(scene):
    return sp.Matrix(scene.bodies["arm"].inertia)


# ----------------------------------------------------------------------------- inertia violations
@pytest.mark.parametrize("name, words", [("small_triangle_violation", "triangle inequality by 2e-08"),
                                         ("small_indefinite", "not positive semi-definite")])
def test_a_violation_within_rounding_is_kept_with_a_warning_and_a_note(name, words):
    scene, caught = quietly(f"{name}.urdf")
    assert [w.category for w in caught] == [InertiaWarning]
    message = str(caught[0].message)
    assert "link 'arm'" in message and words in message and "kept as written" in message
    assert message in scene.notes
    assert not exact_rigid_body_inertia(arm_inertia(scene))   # as written, not repaired


def test_the_kept_inertia_is_the_file_value_exactly():
    scene, _ = quietly("small_triangle_violation.urdf")
    assert arm_inertia(scene)[2, 2] == sp.Rational("0.0200000004") and arm_inertia(scene)[0, 1] == sp.Rational("0.001")


@pytest.mark.parametrize("name", ["small_triangle_violation", "small_indefinite", "large_violation_rotated",
                                  "triangle_inertia", "indefinite_inertia"])
def test_repair_gives_an_exactly_physical_inertia_near_the_file(name):
    scene, caught = quietly(f"{name}.urdf", inertia="repair")
    written = np.array(read_urdf(DATA / f"{name}.urdf").links["arm"].inertial.inertia, dtype=float)
    repaired = arm_inertia(scene)
    assert exact_rigid_body_inertia(repaired)
    assert [w.category for w in caught] == [InertiaWarning] and "repaired" in str(caught[0].message)
    moments = np.linalg.eigvalsh(written)
    # never further than the violation: moving each moment by at most the excess (a third of it)
    excess = max(-moments[0], moments[2] - moments[1] - moments[0], 0)
    assert np.max(np.abs(np.array(repaired, dtype=float) - written)) <= excess + 1e-15


def test_repair_of_a_diagonal_inertia_is_the_projection_onto_a_plus_b_equals_c():
    # moments (1, 1, 3)/100 break a + b >= c by 1/100; the nearest point of the plane a + b = c along
    # its normal (1, 1, -1) moves each by a third of that: (4, 4, 8)/300
    repaired = repaired_inertia(sp.diag(sp.Rational(1, 100), sp.Rational(1, 100), sp.Rational(3, 100)))
    assert np.allclose(np.array(repaired, dtype=float), np.diag([4, 4, 8]) / 300, rtol=0, atol=1e-18)
    assert exact_rigid_body_inertia(repaired)


def test_a_consistent_inertia_is_not_touched_by_repair():
    scene, caught = quietly("fixed_and_tilted.urdf", inertia="repair")
    plain, _ = quietly("fixed_and_tilted.urdf")
    assert not caught and {b: plain.bodies[b].inertia for b in plain.bodies} == \
        {b: scene.bodies[b].inertia for b in scene.bodies}


@pytest.mark.parametrize("name", ["small_triangle_violation", "small_indefinite", "zero_mass_rotor",
                                  "welded_dummies"])
def test_strict_refuses_every_violation_naming_the_link(name):
    with pytest.raises(UrdfError) as info:
        scene_from_urdf(DATA / f"{name}.urdf", inertia="strict")
    assert info.value.element in ("link 'arm'", "link 'foot'", "link 'base'") and info.value.line


def test_a_large_violation_is_refused_naming_the_link_its_size_and_the_repair():
    with pytest.raises(UrdfError) as info:
        scene_from_urdf(DATA / "large_violation_rotated.urdf")
    err = info.value
    assert err.element == "link 'arm'" and err.line == 11
    assert "triangle inequality by 0.335" in str(err) and "inertia='repair'" in str(err)


def test_an_unknown_inertia_option_is_refused():
    with pytest.raises(UrdfError, match="'warn', 'repair', 'strict'"):
        scene_from_urdf(DATA / "triangle_inertia.urdf", inertia="fix")


# ----------------------------------------------------------------------------- tiny numbers
def test_tiny_inertia_entries_and_origin_values_are_read_as_zero_with_a_note():
    robot = read_urdf(DATA / "tiny_entries.urdf")
    assert robot.links["arm"].inertial.inertia[0, 2] == 0            # 2.4e-35 next to 0.02
    assert robot.links["tip"].inertial.inertia == sp.zeros(3)        # 2.4e-35 alone: below 1e-30 kg m^2
    assert robot.joints["tip_joint"].origin.rpy[1] == 0 and robot.joints["tip_joint"].origin.xyz[2] == 0
    assert len(robot.notes) == 4 and any("link 'arm': inertia ixz 2.41e-35" in n for n in robot.notes)
    scene, caught = quietly("tiny_entries.urdf")
    assert not caught and all(any(n in s for s in scene.notes) for n in robot.notes)


# ----------------------------------------------------------------------------- dummy and massless links
def test_links_welded_to_the_world_carry_no_dynamics_and_are_only_noted():
    scene, caught = quietly("welded_dummies.urdf")
    assert not caught
    assert [b for b in scene.bodies] == ["arm"] and scene.bodies["arm"].mass == 2
    assert any("link 'base' is welded to the world" in n and "triangle inequality" in n for n in scene.notes)
    assert "tool0" in scene.frames and "pedestal" in scene.frames


def test_a_zero_mass_link_keeps_its_inertia_as_pinocchio_does():
    scene, caught = quietly("zero_mass_rotor.urdf")
    assert [w.category for w in caught] == [InertiaWarning] and "link 'foot'" in str(caught[0].message)
    body = scene.bodies["arm"]
    # arm: 2 kg at x = 0.2, I = diag(1, 20, 20)/1000 about its centre; foot: no mass, I = diag(3, 4, 5)/1000
    assert body.mass == 2 and list(body.com) == [sp.Rational(1, 5), 0, 0]
    assert sp.Matrix(body.inertia) == sp.diag(4, 24, 25) / 1000


# ----------------------------------------------------------------------------- structure
def test_a_robot_with_no_moving_joint_is_a_typed_error_saying_so():
    with pytest.raises(NoMovingJointError) as info:
        scene_from_urdf(DATA / "no_moving_joint.urdf")
    assert isinstance(info.value, SymgenError) and info.value.element == "robot 'statue'"
    assert "has no moving joint" in str(info.value) and "joint types in the file: fixed" in str(info.value)


def test_a_limit_without_lower_and_upper_is_read_as_no_position_limit():
    scene, caught = quietly("limit_without_bounds.urdf")
    assert not caught and list(scene.joints) == ["wheel", "spin"]
    limits = scene.joint_limits["wheel"]
    assert limits.lower is None and limits.upper is None and limits.velocity == Fraction(20)
    assert any("joint 'wheel': <limit> gives neither lower nor upper" in n for n in scene.notes)


def test_a_root_that_looks_like_a_free_body_is_welded_with_a_warning():
    scene, caught = quietly("free_base.urdf")
    assert [w.category for w in caught] == [FixedBaseWarning]
    message = str(caught[0].message)
    assert "root link 'trunk'" in message and "loaded welded to the world" in message
    assert "floating=True" in message and issubclass(FixedBaseWarning, symgen_errors.FixedBaseWarning)
    assert message in scene.notes and list(scene.joints) == ["left_hip", "right_hip"]


def test_a_single_arm_on_a_massive_base_gets_no_free_base_warning():
    _, caught = quietly("fixed_and_tilted.urdf")
    assert not caught


def test_a_mimic_joint_is_read_as_a_passive_joint_and_a_coupling():
    """The file's prismatic finger follows revolute j1: ``q_finger = 0.02 q_j1`` (m per rad)."""
    scene = scene_from_urdf(DATA / "mimic.urdf")
    con = scene.constraints["finger_joint_mimic"]
    assert con.is_coupling and con.terms == (("finger_joint", 1), ("j1", -sp.Rational(1, 50))) and con.offset == 0
    assert not scene.joints["finger_joint"].actuated and scene.motion.joints == ("j1",)


# ----------------------------------------------------------------------------- where the option is given
def test_load_passes_the_inertia_option_to_urdf_files_only():
    with pytest.warns(InertiaWarning, match="repaired"):
        scene = load(str(DATA / "triangle_inertia.urdf"), inertia="repair")
    assert exact_rigid_body_inertia(arm_inertia(scene))
    with pytest.raises(SceneError, match="apply to URDF files only"):
        load("chain:n=2", inertia="repair")


def test_the_scene_file_urdf_section_takes_the_inertia_option(tmp_path):
    path = tmp_path / "s.yaml"
    path.write_text(f"name: s\nurdf:\n  file: {DATA / 'triangle_inertia.urdf'}\n  inertia: repair\n")
    with pytest.warns(InertiaWarning):
        scene = load_scene(str(path))
    assert exact_rigid_body_inertia(arm_inertia(scene))
    path.write_text(f"name: s\nurdf:\n  file: {DATA / 'triangle_inertia.urdf'}\n")
    with pytest.raises(UrdfError, match="triangle inequality"):
        load_scene(str(path))


def test_a_scene_file_of_a_robot_with_no_moving_joint_says_so(tmp_path):
    path = tmp_path / "s.yaml"
    path.write_text(f"name: s\nurdf:\n  file: {DATA / 'no_moving_joint.urdf'}\n")
    with pytest.raises(NoMovingJointError, match="has no moving joint"):
        load_scene(str(path))


def test_the_pinocchio_check_refuses_a_robot_whose_inertias_were_repaired():
    pytest.importorskip("pinocchio", reason="pinocchio is not installed (extra 'oracle')")
    from symgen.oracle.pinocchio_model import OracleError, pinocchio_robot

    scene, _ = quietly("triangle_inertia.urdf", inertia="repair")
    with pytest.raises(OracleError, match="link 'arm'"):
        pinocchio_robot(scene)


@pytest.mark.parametrize("name", ["zero_mass_rotor", "welded_dummies", "small_triangle_violation",
                                  "limit_without_bounds", "tiny_entries"])
def test_what_the_reader_accepts_equals_pinocchio_on_the_same_file(name):
    pytest.importorskip("pinocchio", reason="pinocchio is not installed (extra 'oracle')")
    import symgen
    from symgen.oracle.pinocchio_check import check_against_pinocchio

    scene, _ = quietly(f"{name}.urdf")
    differences = check_against_pinocchio(symgen.derive(scene), states=5)
    assert differences and all(d.passed for d in differences), [d.as_dict() for d in differences]


def test_a_mimic_on_a_fixed_joint_couples_nothing_and_is_noted(tmp_path):
    inertial = ('<inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/>'
                '</inertial>')
    path = tmp_path / "fixed_mimic.urdf"
    path.write_text(f"""<robot name="r"><link name="base"/><link name="arm">{inertial}</link>
<link name="pad">{inertial}</link>
<joint name="j1" type="continuous"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/></joint>
<joint name="pad_joint" type="fixed"><parent link="arm"/><child link="pad"/><mimic joint="j1"/></joint>
</robot>""")
    scene = scene_from_urdf(path)
    assert list(scene.joints) == ["j1"]
    assert any("joint 'pad_joint' is fixed: its <mimic> of 'j1' couples no coordinate" in n for n in scene.notes)
