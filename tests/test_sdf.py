"""The SDF reader (symgen.io.sdf): a planar parallelogram four-bar closed by a ball joint against
its closed-form dynamics, typed errors for bad files, and Cassie's four leg loops against an
independent KKT solve from Pinocchio's crba and nonLinearEffects (symgen.oracle)."""
from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest

import symgen
from symgen.closure import random_consistent_states
from symgen.io.sdf import SdfError, read_sdf, scene_from_sdf, spanning_tree

L, D, M_ROD, M_COUPLER, G = 0.5, 0.8, 1.5, 2.0, 9.81


def four_bar(coupler_mass=M_COUPLER, closing="ball", extra_joint="", pose_text=None, damping=""):
    """Crank (world -> crank) and rocker (world -> rocker) along +z at the drawn pose, axes y,
    joined by a coupler; the loop is closed by a joint from the coupler to the rocker's tip."""
    rod = f"""<inertial><pose>0 0 {L / 2} 0 0 0</pose><mass>{M_ROD}</mass>
      <inertia><ixx>{M_ROD * L * L / 12}</ixx><iyy>{M_ROD * L * L / 12}</iyy><izz>0.001</izz></inertia></inertial>"""
    return f"""<?xml version="1.0"?>
<sdf version="1.6">
  <model name="four_bar_sdf">
    <link name="crank"><pose>{pose_text or "0 0 0 0 0 0"}</pose>{rod}</link>
    <link name="coupler"><pose>0 0 {L} 0 0 0</pose>
      <inertial><pose>{D / 2} 0 0 0 0 0</pose><mass>{coupler_mass}</mass>
        <inertia><ixx>0.001</ixx><iyy>0.07</iyy><izz>0.07</izz></inertia></inertial>
      <visual name="v"><geometry><box><size>1 1 1</size></box></geometry></visual>
    </link>
    <link name="rocker"><pose>{D} 0 0 0 0 0</pose>{rod}</link>
    <joint name="crank_joint" type="revolute"><parent>world</parent><child>crank</child>
      <axis><xyz>0 1 0</xyz><limit><lower>-1</lower><upper>1</upper></limit></axis></joint>
    <joint name="coupler_joint" type="revolute"><parent>crank</parent><child>coupler</child>
      <axis><xyz>0 1 0</xyz></axis></joint>
    <joint name="rocker_joint" type="revolute"><parent>world</parent><child>rocker</child>
      <axis><xyz>0 1 0</xyz></axis></joint>
    <joint name="tip" type="{closing}"><pose>0 0 {L} 0 0 0</pose><parent>coupler</parent><child>rocker</child>
      {damping}</joint>
    {extra_joint}
  </model>
</sdf>"""


def four_bar_model(text=None):
    scene = scene_from_sdf(text or four_bar(), actuated=["crank_joint"], validate=False)
    scene.set_motion(joints=["crank_joint"])
    scene.validate()
    return symgen.derive(scene)


def closed_form_acceleration(q, qd, tau, coupler_mass=M_COUPLER):
    """Parallelogram: the coupler translates at L qd, crank and rocker turn about their ends.
    M = 2 m L^2/3 + m_c L^2 (constant, so no velocity term); the rods' centres are at height
    (L/2) cos q and the coupler's at L cos q, so G = -(m + m_c) g L sin q."""
    mass = 2 * M_ROD * L * L / 3 + coupler_mass * L * L
    return (tau + (M_ROD + coupler_mass) * G * L * math.sin(q)) / mass


def test_four_bar_loop_and_counts():
    model = four_bar_model()
    root, tree, closing = spanning_tree(read_sdf(four_bar()))
    assert root == "world" and [j.name for j in closing] == ["tip"]
    c = model.counts.as_dict()
    # 3 joints, the ball's 3 rows minus the row normal to the plane (dropped with a note): n_c = 2
    assert (c["nc"], c["np"], c["m"]) == (2, 2, 1)
    assert any("tip" in note and "dropped" in note for note in model.scene.notes)


def test_four_bar_forward_dynamics_closed_form():
    model = four_bar_model()
    rng = np.random.default_rng(3)
    for config, v_m in random_consistent_states(model, 6, seed=1):
        q = float(config.as_float().positions["crank_joint"])
        tau = rng.uniform(-5, 5)
        dv, _ = model.forward_dynamics(config, v_m, [tau])
        assert abs(float(dv[0]) - closed_form_acceleration(q, float(v_m[0]), tau)) <= 1e-9 * max(1.0, abs(float(dv[0])))


def test_four_bar_planted_mass_error_is_caught():
    """The same check on a coupler 1% heavier than the closed form assumes fails."""
    model = four_bar_model(four_bar(coupler_mass=M_COUPLER * 1.01))
    config, v_m = random_consistent_states(model, 1, seed=2)[0]
    q = float(config.as_float().positions["crank_joint"])
    dv, _ = model.forward_dynamics(config, v_m, [1.0])
    assert abs(float(dv[0]) - closed_form_acceleration(q, float(v_m[0]), 1.0)) > 1e-4


def test_load_sdf_path(tmp_path):
    path = tmp_path / "four_bar.sdf"
    path.write_text(four_bar())
    scene = symgen.load(str(path))
    assert set(scene.constraints) == {"tip"} and scene.frames["tip_child"].body == "rocker"
    assert scene.joint_limits["crank_joint"].upper == 1


@pytest.mark.parametrize("text, element, words", [
    (four_bar(closing="screw"), "joint 'tip'", "type 'screw' is not supported"),
    (four_bar(closing="revolute"), "joint 'tip'", "closes loops with ball and fixed joints only"),
    (four_bar(extra_joint='<joint name="j9" type="revolute"><parent>crank</parent><child>nowhere</child></joint>'),
     "joint 'j9'", "names link 'nowhere'"),
    (four_bar(pose_text="0 0 0 0 0"), "<pose>", "needs 6 number(s), got 5"),
    (four_bar(pose_text="0 0 zero 0 0 0"), "<pose>", "is not a list of numbers"),
    (four_bar(extra_joint="<gripper name='g'/>"), "<gripper>", "is not supported"),
    (four_bar(damping="<axis><xyz>0 1 0</xyz><dynamics><damping>0.1</damping></dynamics></axis>"), "joint 'tip'",
     "closure_dynamics='note'"),
])
def test_bad_input_typed_errors(text, element, words):
    with pytest.raises(SdfError) as err:
        scene_from_sdf(text)
    assert err.value.element.startswith(element) and words in str(err.value) and "line" in str(err.value)


def test_closure_dynamics_note_and_springs_read():
    text = four_bar(damping="<axis><xyz>0 1 0</xyz><dynamics><damping>0.1</damping></dynamics></axis>")
    text = text.replace("<axis><xyz>0 1 0</xyz></axis></joint>\n    <joint name=\"rocker_joint\"",
                        "<axis><xyz>0 1 0</xyz><dynamics><spring_stiffness>30</spring_stiffness>"
                        "<spring_reference>0.25</spring_reference><damping>0.5</damping></dynamics></axis></joint>\n"
                        "    <joint name=\"rocker_joint\"", 1)
    scene = scene_from_sdf(text, closure_dynamics="note")
    joint = scene.joints["coupler_joint"]
    assert (joint.stiffness, joint.springref, joint.viscous) == (30, pytest.approx(0.25), pytest.approx(0.5))
    assert any("tip" in n and "left out" in n for n in scene.notes)


def test_axis_in_parent_model_frame():
    """A link turned by 90 degrees about x: its joint's z axis is the model's -y; written as
    use_parent_model_frame with xyz 0 -1 0 it must give the same scene axis as xyz 0 0 1."""
    def one(axis, flag):
        return f"""<sdf version="1.6"><model name="m">
          <link name="a"><pose>0 0 1 {math.pi / 2} 0 0</pose><inertial><mass>1</mass></inertial></link>
          <joint name="j" type="revolute"><parent>world</parent><child>a</child>
            <axis><xyz>{axis}</xyz><use_parent_model_frame>{flag}</use_parent_model_frame></axis></joint>
        </model></sdf>"""
    a = scene_from_sdf(one("0 0 1", "false")).joints["j"].axis
    b = scene_from_sdf(one("0 -1 0", "true")).joints["j"].axis
    assert max(abs(float(x - y)) for x, y in zip(a, b)) < 1e-15


# ------------------------------------------------------------------------------------ Cassie
@pytest.fixture(scope="module")
def cassie():
    pytest.importorskip("pinocchio")
    return symgen.derive(symgen.load("cassie"))


def test_cassie_counts_and_loops_closed_at_q0(cassie):
    from symgen.reference_kinematics import reference_pose, reference_poses

    scene = cassie.scene
    c = cassie.counts.as_dict()
    # 6 + 22 rates; 4 balls x 3 rows - the 2 rows normal to the foot four-bars' plane
    assert (c["nc"], c["np"], c["m"]) == (10, 10, 18)
    assert sum(j.actuated for j in scene.joints.values()) == 10
    poses = reference_poses(scene)
    for name in ("left_pitch_rod_joint", "right_pitch_rod_joint", "left_plantar_foot_joint",
                 "right_plantar_foot_joint"):
        with mpmath.workdps(50):
            pa = reference_pose(scene, f"{name}_child", poses)[1]
            pb = reference_pose(scene, f"{name}_parent", poses)[1]
            assert float(mpmath.norm(pa - pb)) < 1e-9
    # the drawn pelvis height of the file
    assert abs(float(poses["pelvis"][1][2]) - 1.01) < 1e-15


@pytest.mark.slow
def test_cassie_against_pinocchio_kkt(cassie):
    """Forward dynamics at 5 loop-closed states (Newton) against a KKT solve from Pinocchio's crba and
    nonLinearEffects of the spanning tree with the ball constraints' Jacobians; tree rnea and crba too."""
    from symgen.oracle.pinocchio_constrained import check_scene

    results = {d.quantity: d for d in check_scene(cassie, states=5)}
    for key in ("tree inverse dynamics tau_tree", "tree mass matrix", "motion rates dV_m (32)",
                "loop-closure forces lam (Model.loop_forces)"):
        assert results[key].worst <= 1e-9, results[key]
    assert results["loop closure and J_c qd in Pinocchio (absolute)"].worst <= 1e-9


def test_symgen_check_reads_an_sdf_scene_through_the_tree_twin():
    """check_against_pinocchio (``symgen check --against pinocchio``) on an SDF scene rebuilds its
    spanning tree in Pinocchio (no SDF parser in Pinocchio's wheel) and compares the KKT solve."""
    pytest.importorskip("pinocchio")
    from symgen.oracle.pinocchio_check import check_against_pinocchio

    diffs = check_against_pinocchio(four_bar_model(), states=3)
    assert diffs and all(d.worst <= d.tolerance for d in diffs)
    assert any("KKT" in d.against for d in diffs)
