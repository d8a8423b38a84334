"""Inertia from geoms and several joints in one body, against MuJoCo's compiled model (the
independent reference: ``body_mass``, ``body_ipos``, ``body_inertia`` turned by ``body_iquat``,
``mj_fullM`` and ``qfrc_bias``) and against hand derivations of the exact values."""
from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from symgen.io.mjcf import MjcfError, parse_mjcf, parse_mjcf_text, scene_from_mjcf

mujoco = pytest.importorskip("mujoco", minversion="3.3.6")

ROOT = Path(__file__).resolve().parent.parent
_spec = importlib.util.spec_from_file_location("mjcf_coverage", ROOT / "benchmarks" / "mjcf_coverage.py")
coverage = sys.modules.setdefault("mjcf_coverage", importlib.util.module_from_spec(_spec))
_spec.loader.exec_module(coverage)

TOL = 1e-10

#: every shape, fromto, orientations, frames, classes, mass over density, the group range
SHAPES = """<mujoco model="shapes">
  <compiler inertiagrouprange="0 2"/>
  <default>
    <geom density="800"/>
    <default class="heavy"><geom density="2500"/></default>
  </default>
  <worldbody>
    <body name="a" pos="0 0 1">
      <joint name="ja" axis="0 1 0"/>
      <geom type="sphere" size="0.1" pos="0.2 0 0"/>
      <geom type="capsule" fromto="0 0 0 0.3 0.1 -0.2" size="0.04"/>
      <geom type="box" size="0.05 0.02 0.1" euler="10 20 30" pos="0 0.1 0" class="heavy"/>
      <geom type="sphere" size="5" group="3"/>
      <body name="b" pos="0.3 0.1 -0.2" euler="0 0 40">
        <joint name="jb" axis="1 0 1" pos="0.01 0 0" ref="15"/>
        <geom type="cylinder" fromto="0 0 0 0 0.4 0" size="0.03" mass="0.7"/>
        <geom type="ellipsoid" size="0.05 0.08 0.02" quat="0.9 0.1 0.3 -0.2"/>
        <frame pos="0 0.2 0" euler="30 0 0">
          <geom type="capsule" size="0.02 0.05" pos="0.05 0 0" zaxis="1 1 0"/>
        </frame>
        <body name="c" pos="0 0.4 0">
          <joint name="jc" type="slide" axis="0 0 1"/>
          <geom type="box" fromto="0 0 0 0.2 0 0.1" size="0.03"/>
          <geom type="ellipsoid" fromto="0 0 0 0 -0.1 0.1" size="0.02"/>
        </body>
      </body>
    </body>
  </worldbody>
  <actuator><motor joint="ja"/><motor joint="jb"/><motor joint="jc"/></actuator>
</mujoco>
"""

#: a body with three joints (slide, hinge, hinge at their own pos, a ref), MuJoCo's planar root
MULTI = """<mujoco model="multi">
  <worldbody>
    <body name="torso" pos="0 0 1" euler="0 0 20">
      <joint name="rootx" type="slide" axis="1 0 0" pos="0 0 -0.2"/>
      <joint name="rootz" type="slide" axis="0 0 1" ref="0.3"/>
      <joint name="rooty" axis="0 1 0" pos="0.05 0 0.1" ref="10"/>
      <geom type="capsule" fromto="0 0 -0.3 0 0 0.3" size="0.05"/>
      <body name="thigh" pos="0 0 -0.3">
        <joint name="hip" axis="0 1 0" damping="0.1"/>
        <joint name="hip_roll" axis="1 0 0" pos="0 0.02 0" armature="0.01"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.4" size="0.04"/>
      </body>
    </body>
  </worldbody>
  <actuator><motor joint="hip"/></actuator>
</mujoco>
"""


def _file(tmp_path: Path, text: str) -> str:
    path = tmp_path / "model.xml"
    path.write_text(text)
    return str(path)


@pytest.mark.parametrize("text", [SHAPES, MULTI], ids=["shapes", "several_joints"])
def test_body_mass_properties_equal_mujocos(tmp_path, text):
    worst = coverage.mass_properties_check(_file(tmp_path, text))
    assert max(worst.values()) <= TOL, worst


@pytest.mark.parametrize("text", [SHAPES, MULTI], ids=["shapes", "several_joints"])
def test_mass_matrix_and_bias_forces_equal_mujocos(tmp_path, text):
    path = _file(tmp_path, text)
    worst = coverage.dynamics_check(path, scene_from_mjcf(path), states=4, seed=5)
    assert max(worst.values()) <= TOL, worst


def test_a_sphere_of_default_density_has_its_exact_hand_derived_mass_and_inertia():
    # m = 1000 * 4/3 pi r^3 with r = 1/10: 4 pi / 3;  I = 2/5 m r^2 = 2 pi / 375
    text = ('<mujoco><worldbody><body name="s"><joint name="q"/><geom size="0.1" pos="0 0 0.5"/></body>'
            '</worldbody></mujoco>')
    inertial = parse_mjcf_text(text).bodies[0].inertial
    assert inertial.mass == sp.Rational(4, 3) * sp.pi
    assert inertial.pos == sp.Matrix([0, 0, sp.Rational(1, 2)])
    assert inertial.inertia == sp.eye(3) * 2 * sp.pi / 375


def test_a_capsule_along_z_has_its_hand_derived_inertia():
    # r = 1/10, cylinder length L = 2/5, mass 3: shares mc = 3 * pi r^2 L / V, ms = 3 * 4/3 pi r^3 / V
    text = ('<mujoco><worldbody><body name="s"><joint name="q"/><geom type="capsule" size="0.1 0.2" mass="3"/>'
            '</body></worldbody></mujoco>')
    inertia = parse_mjcf_text(text).bodies[0].inertial.inertia
    r, length = sp.Rational(1, 10), sp.Rational(2, 5)
    volume = sp.pi * r**2 * length + sp.Rational(4, 3) * sp.pi * r**3
    mc, ms = 3 * sp.pi * r**2 * length / volume, 3 * sp.Rational(4, 3) * sp.pi * r**3 / volume
    side = mc * (3 * r**2 + length**2) / 12 + ms * (2 * r**2 / 5 + length**2 / 4 + 3 * length * r / 8)
    assert sp.simplify(inertia[0, 0] - side) == 0 and sp.simplify(inertia[1, 1] - side) == 0
    assert sp.simplify(inertia[2, 2] - (mc * r**2 / 2 + 2 * ms * r**2 / 5)) == 0


@pytest.mark.parametrize("compiler, mass", [("auto", 2), ("true", 3), ("false", 2)])
def test_inertiafromgeom_chooses_the_inertial_or_the_geoms_as_mujoco(compiler, mass):
    text = (f'<mujoco><compiler inertiafromgeom="{compiler}"/><worldbody><body name="s"><joint name="q"/>'
            '<inertial pos="0 0 0" mass="2" diaginertia="1 1 1"/><geom size="0.1" mass="3"/></body>'
            '</worldbody></mujoco>')
    assert parse_mjcf_text(text).bodies[0].inertial.mass == mass
    assert mujoco.MjModel.from_xml_string(text).body_mass[1] == pytest.approx(mass)


def test_a_body_of_geoms_outside_the_group_range_is_massless_and_refused_as_mujoco_refuses_it():
    text = ('<mujoco><worldbody><body name="s"><joint name="q"/><geom size="0.1" group="4"/></body>'
            '</worldbody><compiler inertiagrouprange="0 3"/></mujoco>')
    with pytest.raises(MjcfError, match="mjMINVAL"):
        parse_mjcf_text(text)
    with pytest.raises(ValueError, match="mass and inertia"):
        mujoco.MjModel.from_xml_string(text)


def test_the_joints_of_one_body_become_a_chain_of_massless_bodies_in_file_order(tmp_path):
    scene = scene_from_mjcf(_file(tmp_path, MULTI))
    chain = [(j.name, j.parent, j.child) for j in scene.joints.values() if j.dof]
    assert chain == [("rootx", "world", "torso_rootx"), ("rootz", "torso_rootx", "torso_rootz"),
                     ("rooty", "torso_rootz", "torso"), ("hip", "torso", "thigh_hip"),
                     ("hip_roll", "thigh_hip", "thigh")]
    assert all(scene.bodies[b].mass == 0 for b in ("torso_rootx", "torso_rootz", "thigh_hip"))


def test_includes_are_expanded_relative_to_the_main_file_and_errors_name_the_included_file(tmp_path):
    (tmp_path / "parts").mkdir()
    (tmp_path / "parts" / "arm.xml").write_text(
        '<mujoco>\n<body name="s"><joint name="q"/><geom size="0.1"/></body>\n</mujoco>')
    (tmp_path / "parts" / "bad.xml").write_text('<mujoco>\n\n<body name="t"><joint name="k" springdamper="0.1 0"/>'
                                                '<geom size="0.1"/></body></mujoco>')
    main = tmp_path / "robot.xml"
    main.write_text('<mujoco><worldbody><include file="parts/arm.xml"/></worldbody></mujoco>')
    assert [b.name for b in parse_mjcf(main).bodies] == ["s"]
    main.write_text('<mujoco><worldbody><include file="parts/bad.xml"/></worldbody></mujoco>')
    with pytest.raises(MjcfError) as info:
        parse_mjcf(main)
    assert info.value.source.endswith("bad.xml") and info.value.line == 3
    main.write_text('<mujoco><worldbody><include file="parts/arm.xml"/><include file="parts/arm.xml"/>'
                    '</worldbody></mujoco>')
    with pytest.raises(MjcfError, match="included twice"):
        parse_mjcf(main)
    main.write_text('<mujoco><worldbody><include file="parts/none.xml"/></worldbody></mujoco>')
    with pytest.raises(MjcfError, match="not found"):
        parse_mjcf(main)


def test_an_underactuated_tree_takes_every_joint_as_motion_coordinate_with_a_note(tmp_path):
    scene = scene_from_mjcf(_file(tmp_path, MULTI))
    assert [n for n, j in scene.joints.items() if j.actuated] == ["hip"]
    assert any("4 of 5 joints have no actuator" in n for n in scene.notes)
    assert sorted(scene.motion.joints) == sorted(n for n, j in scene.joints.items() if j.dof)


def test_rates_and_positions_map_through_mujocos_qpos_and_back(tmp_path):
    from symgen.io.coordinates import CoordinateMap

    path = _file(tmp_path, SHAPES)
    m = mujoco.MjModel.from_xml_path(path)
    cmap = CoordinateMap.mujoco(scene_from_mjcf(path), m)
    qpos, qvel = np.array([0.1, -0.4, 0.25]), np.array([1.0, 2.0, 3.0])
    config, rates = cmap.to_symgen(qpos, qvel)
    assert config.positions == {"ja": 0.1, "jb": -0.4, "jc": 0.25} and rates == {"ja": 1.0, "jb": 2.0, "jc": 3.0}
    back = cmap.from_symgen(config, rates)
    assert np.array_equal(back[0], qpos) and np.array_equal(back[1], qvel)


def _random_geom(rng) -> str:
    """One geom of a random shape, size and placement (pos and an orientation, or fromto), by
    mass or by density."""
    kind = rng.choice(["sphere", "capsule", "cylinder", "box", "ellipsoid"])
    size = " ".join(f"{v:.3f}" for v in rng.uniform(0.01, 0.2, 3))
    weight = f'mass="{rng.uniform(0.1, 3):.3f}"' if rng.random() < 0.5 else f'density="{rng.uniform(100, 5000):.1f}"'
    if kind != "sphere" and rng.random() < 0.4:
        ends = " ".join(f"{v:.3f}" for v in rng.uniform(-0.3, 0.3, 6))
        return f'<geom type="{kind}" fromto="{ends}" size="{size}" {weight}/>'
    pos = " ".join(f"{v:.3f}" for v in rng.uniform(-0.3, 0.3, 3))
    orientation = rng.choice([f'euler="{" ".join(f"{v:.1f}" for v in rng.uniform(-180, 180, 3))}"',
                              f'quat="{" ".join(f"{v:.3f}" for v in rng.uniform(-1, 1, 4))}"',
                              f'axisangle="{" ".join(f"{v:.3f}" for v in rng.uniform(-1, 1, 3))} 37"', ""])
    return f'<geom type="{kind}" size="{size}" pos="{pos}" {orientation} {weight}/>'


def test_random_geoms_give_mujocos_body_mass_properties(tmp_path):
    rng = np.random.default_rng(11)
    bodies = "".join(f'<body name="b{i}" pos="0 0 {i}"><joint name="j{i}"/>'
                     + "".join(_random_geom(rng) for _ in range(int(rng.integers(1, 4)))) + "</body>"
                     for i in range(12))
    worst = coverage.mass_properties_check(_file(tmp_path, f"<mujoco><worldbody>{bodies}</worldbody></mujoco>"))
    assert max(worst.values()) <= TOL, worst
