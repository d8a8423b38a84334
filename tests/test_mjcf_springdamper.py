"""``springdamper="timeconst dampratio"`` (symgen.io.mjcf.springdamper): the stiffness and damping
MuJoCo sets from the inverse mass matrix at qpos0, against a hand derivation of a pendulum and
against MuJoCo's compiled ``jnt_stiffness``, ``dof_damping`` and ``dof_invweight0``."""
from __future__ import annotations

import numpy as np
import pytest

from symgen.io.mjcf import MjcfError, parse_mjcf_text

mujoco = pytest.importorskip("mujoco", minversion="3.3.6")

CHAIN = """<mujoco>
  {flags}
  <worldbody>
    <body name="a" pos="0 0 1" euler="10 20 30">
      <joint name="h1" axis="0 1 0" armature="0.05" springdamper="0.2 0.7"/>
      <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.05"/>
      <body name="b" pos="0.4 0 0">
        <joint name="s" type="slide" axis="1 0 1" damping="3" springdamper="0.5 1.5"/>
        <joint name="h2" axis="0 0 1" pos="0.1 0 0" stiffness="7"/>
        <geom type="box" size="0.1 0.05 0.02" pos="0.2 0 0"/>
      </body>
    </body>
  </worldbody>
</mujoco>"""


def joints(text: str) -> dict:
    return {j.name: j for b in parse_mjcf_text(text).bodies for j in b.joints}


def test_a_pendulums_springdamper_equals_the_hand_derivation():
    """One hinge about y, point-like mass m at distance l plus Iyy and armature: M = Iyy + m l^2 + a,
    so k = M / (tc^2 zeta^2) and b = 2 M / tc."""
    text = """<mujoco><worldbody><body name="p"><joint name="q" axis="0 1 0" armature="0.1"
      springdamper="0.25 2"/><inertial pos="0.5 0 0" mass="2" diaginertia="0.01 0.02 0.03"/>
      </body></worldbody></mujoco>"""
    q = joints(text)["q"]
    inertia = 0.02 + 2 * 0.5**2 + 0.1
    assert float(q.stiffness) == pytest.approx(inertia / (0.25**2 * 2**2), rel=1e-14)
    assert float(q.damping) == pytest.approx(2 * inertia / 0.25, rel=1e-14)


def test_a_chains_springdampers_equal_mujocos_compiled_values():
    text = CHAIN.format(flags="")
    m = mujoco.MjModel.from_xml_string(text)
    ours = joints(text)
    for name in ("h1", "s", "h2"):
        i = m.joint(name).id
        dof = m.jnt_dofadr[i]
        assert float(ours[name].stiffness) == pytest.approx(m.jnt_stiffness[i], rel=1e-12, abs=0), name
        assert float(ours[name].damping) == pytest.approx(m.dof_damping[dof], rel=1e-12, abs=0), name


def test_the_mass_matrix_at_qpos0_and_its_inverse_diagonal_are_mujocos():
    from symgen.io.mjcf.springdamper import mass_matrix_at_reference

    text = CHAIN.format(flags="")
    m = mujoco.MjModel.from_xml_string(text)
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    dense = np.zeros((m.nv, m.nv))
    mujoco.mj_fullM(m, dense, d.qM) if hasattr(d, "qM") else mujoco.mj_fullM(m, d, dense)
    _, ours = mass_matrix_at_reference(parse_mjcf_text(text).bodies)
    assert np.max(np.abs(ours - dense)) <= 1e-13 * np.max(np.abs(dense))
    assert np.allclose(np.diag(np.linalg.inv(ours)), m.dof_invweight0, rtol=1e-12, atol=0)


def test_disabled_springs_and_dampers_keep_their_zeros():
    text = CHAIN.format(flags='<option><flag spring="disable" damper="disable"/></option>')
    got = joints(text)
    assert got["h1"].stiffness == 0 and got["h1"].damping == 0 and got["s"].damping == 0


@pytest.mark.parametrize("attribute, words", [
    (' springdamper="0.2 0"', "both numbers must be positive"),
    (' springdamper="-1 1"', "both numbers must be positive"),
    (' type="ball" springdamper="0.2 1"', "springdamper on a ball joint"),
])
def test_a_springdamper_mujoco_refuses_or_symgen_does_not_read_is_a_typed_error(attribute, words):
    text = CHAIN.format(flags="").replace(' axis="0 1 0" armature="0.05" springdamper="0.2 0.7"', attribute)
    with pytest.raises(MjcfError, match=words) as info:
        parse_mjcf_text(text)
    assert info.value.line == 5
