"""MJCF ``<equality><joint joint1 joint2 polycoef>`` read as a joint coupling, against MuJoCo: the
coupling's row of ``T`` equals MuJoCo's equality row of ``efc_J`` (MuJoCo enforces equalities
softly, so the Jacobian and the residual ``efc_pos`` are compared, not accelerations), and
``efc_pos`` vanishes on symgen's closed states, ``ref`` included."""
from __future__ import annotations

import numpy as np
import pytest

from symgen.closure import random_consistent_states
from symgen.io.mjcf import MjcfError, parse_mjcf_text, scene_from_mjcf_model
from symgen.model import derive

mujoco = pytest.importorskip("mujoco", minversion="3.3.6")

TOL = 1e-12


def gear_mjcf(equality: str, ref: str = "0.3") -> str:
    """Two hinged links side by side; ``b`` follows ``a`` by ``equality``; ``a`` is driven."""
    return f"""<mujoco model="gear">
  <worldbody>
    <body name="a"><joint name="ja" type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02"/></body>
    <body name="b" pos="0 0.2 0"><joint name="jb" type="hinge" axis="0 1 0" ref="{ref}"/>
      <geom type="capsule" fromto="0 0 0 0.2 0 0.05" size="0.03"/></body>
  </worldbody>
  <equality>{equality}</equality>
  <actuator><motor joint="ja"/></actuator>
</mujoco>"""


def read(text: str):
    return scene_from_mjcf_model(parse_mjcf_text(text))


def _equality_rows(text: str, model, spread: float):
    """At 5 of symgen's loop-closed states: MuJoCo's equality rows of ``efc_J`` (columns in symgen's
    coordinate order), symgen's rows of ``T`` (eq. 6), and MuJoCo's first equality residual."""
    m = mujoco.MjModel.from_xml_string(text)
    names = model.all_coordinate_names()
    idx = [int(m.jnt_dofadr[m.joint(n).id]) for n in names]
    for config, _ in random_consistent_states(model, 5, seed=2, spread=spread):
        d = mujoco.MjData(m)
        for n in names:
            d.qpos[m.jnt_qposadr[m.joint(n).id]] = float(config.positions[n])
        mujoco.mj_forward(m, d)
        rows = d.efc_type[:d.nefc] == mujoco.mjtConstraint.mjCNSTR_EQUALITY
        jac = np.asarray(d.efc_J).reshape(-1)[:d.nefc * m.nv].reshape(d.nefc, m.nv)[rows][:, idx]
        yield jac, np.asarray(model.evaluate(config).maps.T.v, float), d.efc_pos[:d.nefc][rows][0]


@pytest.mark.parametrize("polycoef", ["0.1 -2 0 0 0", "0 0.5 0 0 0", "-0.25 1 0 0 0"])
def test_the_coupling_row_and_residual_equal_mujocos(polycoef):
    text = gear_mjcf(f'<joint name="gear" joint1="jb" joint2="ja" polycoef="{polycoef}"/>')
    scene = read(text)
    assert scene.constraints["gear"].is_coupling and scene.motion.joints == ("ja",)
    model = derive(scene)
    for jac, ours, residual in _equality_rows(text, model, spread=0.8):
        assert jac.shape == (1, 2) and np.max(np.abs(jac - ours)) <= TOL
        assert abs(residual) <= TOL, "MuJoCo's equality is open on symgen's closed state"


def test_the_mujoco_check_catches_a_wrong_multiplier():
    """The planted error: symgen reading the file with c1 of the opposite sign misses MuJoCo's row."""
    text = gear_mjcf('<joint name="gear" joint1="jb" joint2="ja" polycoef="0.1 -2 0 0 0"/>')
    wrong = derive(read(gear_mjcf('<joint name="gear" joint1="jb" joint2="ja" polycoef="0.1 2 0 0 0"/>')))
    m = mujoco.MjModel.from_xml_string(text)
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    rows = d.efc_type[:d.nefc] == mujoco.mjtConstraint.mjCNSTR_EQUALITY
    jac = np.asarray(d.efc_J).reshape(-1)[:d.nefc * m.nv].reshape(d.nefc, m.nv)[rows]
    assert np.max(np.abs(jac - np.asarray(wrong.evaluate(wrong.reference).maps.T.v, float))) > 1


@pytest.mark.parametrize("equality, words", [
    ('<joint name="gear" joint1="jb" joint2="ja" polycoef="0 1 0.5 0 0"/>', ["gear", "not linear"]),
    ('<joint name="gear" joint1="jb"/>', ["gear", "needs joint1 and joint2"]),
    ('<joint name="gear" joint1="jb" joint2="nope"/>', ["gear", "'nope'", "not declared"]),
    ('<joint name="gear" joint1="jb" joint2="jb"/>', ["gear", "itself"]),
    ('<joint name="gear" joint1="jb" joint2="ja" polycoef="0 x 0 0 0"/>', ["gear", "polycoef"]),
])
def test_bad_joint_equalities_are_typed_errors_naming_the_element(equality, words):
    with pytest.raises(MjcfError) as err:
        read(gear_mjcf(equality, ref="0"))
    for w in words:
        assert w in str(err.value)


def hand_mjcf(equality: str, ref: str = "0.2") -> str:
    """An arm hinge carrying a thumb and a finger (slides), tied by fixed tendons as the DeepMind
    Control Suite's manipulator ties them; a third joint enters one tendon of the two-tendon case."""
    return f"""<mujoco model="hand">
  <worldbody>
    <body name="palm"><joint name="arm" type="hinge" axis="0 1 0"/>
      <geom type="box" size="0.05 0.02 0.02" pos="0.1 0 0"/>
      <body name="thumb" pos="0.15 0 0.02"><joint name="thumb" type="hinge" axis="0 1 0" ref="{ref}"/>
        <geom type="capsule" fromto="0 0 0 0.05 0 0" size="0.01"/></body>
      <body name="finger" pos="0.15 0 -0.02"><joint name="finger" type="slide" axis="1 0 0"/>
        <geom type="capsule" fromto="0 0 0 0.05 0 0" size="0.01"/></body>
    </body>
  </worldbody>
  <tendon>
    <fixed name="grasp"><joint joint="thumb" coef=".5"/><joint joint="finger" coef=".5"/></fixed>
    <fixed name="coupling"><joint joint="thumb" coef="-.5"/><joint joint="finger" coef=".5"/></fixed>
    <fixed name="wrist"><joint joint="arm" coef="2"/></fixed>
  </tendon>
  <equality>{equality}</equality>
  <actuator><motor joint="arm"/><motor joint="finger"/></actuator>
</mujoco>"""


TENDON_EQUALITIES = {
    "manipulator_form": '<tendon name="tie" tendon1="coupling"/>',
    "two_tendons": '<tendon name="tie" tendon1="grasp" tendon2="wrist" polycoef="0 0.75 0 0 0"/>',
    "offset": '<tendon name="tie" tendon1="coupling" polycoef="0.01 1 0 0 0"/>',
}


@pytest.mark.parametrize("variant", sorted(TENDON_EQUALITIES))
def test_a_fixed_tendon_coupling_row_and_residual_equal_mujocos(variant):
    text = hand_mjcf(TENDON_EQUALITIES[variant])
    scene = read(text)
    assert scene.constraints["tie"].is_coupling
    model = derive(scene)
    for jac, ours, residual in _equality_rows(text, model, spread=0.5):
        # MuJoCo's row is dL1 - c1 dL2; symgen's is divided by its first joint's coefficient
        assert jac.shape == (1, 3) and np.linalg.matrix_rank(np.vstack([jac, ours]), tol=1e-9) == 1
        assert abs(residual) <= TOL, "MuJoCo's equality is open on symgen's closed state"


@pytest.mark.parametrize("equality, words", [
    ('<tendon name="tie" tendon1="nope"/>', ["tie", "'nope'", "not a declared"]),
    ('<tendon name="tie" tendon1="wrist"/>', ["tie", "holds a joint fixed"]),
    ('<tendon name="tie" tendon1="grasp" tendon2="coupling" polycoef="0 1 1 0 0"/>', ["tie", "not linear"]),
])
def test_bad_tendon_equalities_are_typed_errors_naming_the_element(equality, words):
    with pytest.raises(MjcfError) as err:
        read(hand_mjcf(equality))
    for w in words:
        assert w in str(err.value)
