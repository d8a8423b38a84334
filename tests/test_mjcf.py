"""The MJCF reader: exact numbers, located typed errors, dropped constraint rows, and the two loop
models of ``tests/data/mjcf`` against Pinocchio's own MJCF reader (same files) and the KKT
reference of the test suite."""
from __future__ import annotations

import pathlib

import numpy as np
import pytest
import sympy as sp

from symgen.closure import random_consistent_states
from symgen.io.loading import load
from symgen.io.mjcf import MjcfError, parse_mjcf_text, scene_from_mjcf_model
from symgen.model import derive
from tests.reference import tree_dynamics as ref

DATA = pathlib.Path(__file__).parent / "data" / "mjcf"
MODELS = ["four_bar.xml", "five_bar.xml"]
#: agreement with Pinocchio on the same file
TOL_PINOCCHIO = 1e-10


@pytest.mark.parametrize("name", MODELS)
def test_mjcf_loop_models_agree_with_pinocchio(name):
    pytest.importorskip("pinocchio")
    from symgen.oracle.pinocchio_check import check_against_pinocchio

    model = derive(load(str(DATA / name)))
    diffs = check_against_pinocchio(model, states=10, seed=2)
    assert {d.quantity.split(" (")[0] for d in diffs} >= {"motion rates dV_m", "loop-closure forces lam"}
    for d in diffs:
        assert d.worst <= TOL_PINOCCHIO, (d.quantity, d.worst)


def test_a_keyframe_pinocchio_refuses_is_dropped_for_the_check(tmp_path):
    """A <key qpos> of the wrong size makes Pinocchio's reader raise ValueError; keyframes do not
    change the dynamics, so the check reads the file again without them and still agrees."""
    pytest.importorskip("pinocchio")
    from symgen.oracle.pinocchio_check import check_against_pinocchio

    text = (DATA / "four_bar.xml").read_text(encoding="utf-8")
    path = tmp_path / "four_bar_key.xml"
    path.write_text(text.replace("</mujoco>", '<keyframe><key name="home" qpos="0 0"/></keyframe>\n</mujoco>'),
                    encoding="utf-8")
    diffs = check_against_pinocchio(derive(load(str(path))), states=3, seed=2)
    assert diffs and all(d.worst <= TOL_PINOCCHIO for d in diffs)


def test_a_tree_pinocchio_reads_otherwise_is_a_typed_error_naming_both_joint_lists(capsys):
    """defaults_tree.xml places bodies through <frame> and a second <worldbody>: Pinocchio's reader
    reads other joints than MuJoCo and symgen do, so the check refuses it, listing both."""
    pytest.importorskip("pinocchio")
    from symgen.cli import main
    from symgen.oracle.pinocchio_model import OracleError
    from symgen.oracle.pinocchio_check import check_against_pinocchio

    model = derive(load(str(DATA / "defaults_tree.xml")))
    with pytest.raises(OracleError, match=r"read the joints \[.*\].*symgen \[shoulder, extend, extend2, elbow, swing\]"):
        check_against_pinocchio(model, states=2)
    assert main(["check", str(DATA / "defaults_tree.xml"), "--against", "pinocchio"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("symgen: error: Pinocchio's MJCF reader") and err.count("\n") == 1


def test_planar_connect_drops_its_vanishing_row_with_a_note():
    scene = load(str(DATA / "four_bar.xml"))
    assert scene.constraints["closure"].components == ("vx", "vy")
    assert scene.notes == ["constraint 'closure': dropped component vz (its row of T, eq. 6, vanishes identically)"]
    assert derive(scene).counts.as_dict() == dict(n1a=1, n1u=2, n3a=0, n3u=0, m=1, nc=2, np=2, n=1)


def test_planar_weld_drops_three_rows():
    scene = load(str(DATA / "five_bar.xml"))
    assert scene.constraints["closure"].components == ("vx", "vy", "wz")
    assert [n.split("component ")[1].split(" ")[0] for n in scene.notes] == ["vz", "wx", "wy"]


def test_numbers_are_exact():
    """``euler="0 0 60"`` in degrees is the exact rotation by pi/3; ``"0.2"`` is 1/5."""
    scene = load(str(DATA / "four_bar.xml"))
    assert scene.joints["j1"].origin.rotation == sp.ImmutableMatrix([[sp.Rational(1, 2), -sp.sqrt(3) / 2, 0],
                                                                      [sp.sqrt(3) / 2, sp.Rational(1, 2), 0],
                                                                      [0, 0, 1]])
    assert scene.bodies["crank"].mass == sp.Rational(1, 5)
    assert scene.bodies["coupler"].inertia[0, 1] == sp.Rational(1, 100000)
    assert scene.gravity == sp.ImmutableMatrix([0, sp.Rational("-9.81"), 0])


@pytest.mark.parametrize("name", MODELS)
def test_loop_forces_of_mjcf_models_equal_the_kkt_multipliers(name):
    scene = load(str(DATA / name))
    model = derive(scene)
    rng = np.random.default_rng(1)
    for cfg, v_m in random_consistent_states(model, 10, seed=1, spread=0.2):
        tau = rng.uniform(-1, 1, model.counts.n)
        tau_all = np.zeros(model.tree.n_coords)
        tau_all[list(model.partition.independent)] = tau
        qdd, lam = ref.kkt(scene, cfg, model.joint_rates(cfg, v_m), tau_all)
        assert np.allclose(model.loop_forces(cfg, v_m, tau), lam, rtol=1e-9, atol=1e-11)
        assert np.allclose(model.joint_accelerations(cfg, v_m, tau), qdd, rtol=1e-9, atol=1e-11)


MINIMAL = """<mujoco model="m">
  <worldbody>
    <body name="link">
      {joint}
      <inertial pos="0 0 0" mass="1" diaginertia="1 1 1"/>
    </body>
  </worldbody>
</mujoco>"""


@pytest.mark.parametrize("joint, element, line, words", [
    ('<joint name="q" type="free" armature="1"/>', "<joint name='q'>", 4, "armature on a free joint"),
    ('<joint name="q" axis="0 0"/>', "<joint name='q'>", 4, "axis='0 0' must have 3 numbers"),
    ('<joint name="q" damping="x"/>', "<joint name='q'>", 4, "'x' is not a finite decimal number"),
    ('<joint type="hinge"/>', "<joint>", 4, "needs a name"),
    ('<joint name="q" springdamper="0.1 0"/>', "<joint name='q'>", 4, "both numbers must be positive"),
])
def test_malformed_mjcf_is_a_typed_error_with_element_and_line(joint, element, line, words):
    with pytest.raises(MjcfError) as info:
        scene_from_mjcf_model(parse_mjcf_text(MINIMAL.format(joint=joint), "robot.xml"))
    assert info.value.element == element and info.value.line == line and words in str(info.value)
    assert f"robot.xml, line {line}" in str(info.value)


def test_bad_inertia_and_broken_xml_are_located():
    text = MINIMAL.format(joint='<joint name="q"/>').replace('diaginertia="1 1 1"', 'diaginertia="1 1 5"')
    with pytest.raises(MjcfError, match=r"line 3"):
        scene_from_mjcf_model(parse_mjcf_text(text, "robot.xml"))
    with pytest.raises(MjcfError, match=r"not well-formed XML.*line 2"):
        parse_mjcf_text("<mujoco>\n<worldbody>\n</mujoco>", "robot.xml")
    with pytest.raises(MjcfError, match=r"line \d+"):
        parse_mjcf_text(MINIMAL.format(joint='<joint name="a"/><joint name="b" type="free"/>'), "robot.xml")


def test_too_few_motors_is_explained():
    text = (DATA / "four_bar.xml").read_text().replace('<motor joint="j1"/>', "")
    with pytest.raises(MjcfError, match="m = 1 motion DOF"):
        scene_from_mjcf_model(parse_mjcf_text(text, "four_bar.xml"))
