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


@pytest.mark.parametrize("polycoef", ["0.1 -2 0 0 0", "0 0.5 0 0 0", "-0.25 1 0 0 0"])
def test_the_coupling_row_and_residual_equal_mujocos(polycoef):
    text = gear_mjcf(f'<joint name="gear" joint1="jb" joint2="ja" polycoef="{polycoef}"/>')
    scene = read(text)
    assert scene.constraints["gear"].is_coupling and scene.motion.joints == ("ja",)
    model = derive(scene)
    m = mujoco.MjModel.from_xml_string(text)
    names = model.all_coordinate_names()
    idx = [int(m.jnt_dofadr[m.joint(n).id]) for n in names]
    for config, _ in random_consistent_states(model, 5, seed=2, spread=0.8):
        d = mujoco.MjData(m)
        for n in names:
            d.qpos[m.jnt_qposadr[m.joint(n).id]] = float(config.positions[n])
        mujoco.mj_forward(m, d)
        rows = d.efc_type[:d.nefc] == mujoco.mjtConstraint.mjCNSTR_EQUALITY
        jac = np.asarray(d.efc_J).reshape(-1)[:d.nefc * m.nv].reshape(d.nefc, m.nv)[rows][:, idx]
        ours = np.asarray(model.evaluate(config).maps.T.v, float)
        assert jac.shape == (1, 2) and np.max(np.abs(jac - ours)) <= TOL
        assert abs(d.efc_pos[:d.nefc][rows][0]) <= TOL, "MuJoCo's equality is open on symgen's closed state"


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
