"""Joint couplings (``Scene.add_coupling``): a linear relation of joint coordinates as one row of
eq. (6), checked on two pendulums geared together against the closed form written out by hand."""
from __future__ import annotations

import dataclasses

import numpy as np
import sympy as sp
import pytest

from symgen.closure import random_consistent_states
from symgen.errors import SceneError
from symgen.model import derive
from symgen.scene import Scene

G, L_A, L_B, M_A, M_B, I_A, I_B = 9.81, 0.5, 0.3, 1.2, 0.7, 0.02, 0.05
RATIO, OFFSET = -2.0, 0.1
RTOL = 1e-12


def geared_pendulums(actuated_b: bool = False) -> Scene:
    """Pendulums ``a`` (actuated) and ``b`` about parallel y axes, ``q_b = RATIO q_a + OFFSET``."""
    s = Scene("geared")
    for name, length, mass, inertia, y in (("a", L_A, M_A, I_A, 0), ("b", L_B, M_B, I_B, 1)):
        s.add_body(name, mass, com=(length, 0, 0), inertia=(inertia, inertia, inertia))
        s.add_joint(f"j{name}", "revolute", "world", name, xyz=(0, y, 0), axis="y",
                    actuated=name == "a" or actuated_b, q0=OFFSET if name == "b" else 0)
    s.add_coupling("gear", "jb", "ja", multiplier=RATIO, offset=OFFSET)
    s.set_motion(joints=["ja"])
    return s


def closed_form(q_a: float, q_b: float, tau: float) -> tuple[float, float]:
    """By hand: with the axis y and com at (L, 0, 0), the com height is ``-L sin q`` and gravity's
    joint torque ``m g L cos q``; the inertia about the pivot is ``J = I + m L^2``. Lagrange on
    ``q_a`` with ``q_b = RATIO q_a + OFFSET``: ``(J_a + RATIO^2 J_b) qdd_a = tau + m_a g L_a cos q_a
    + RATIO m_b g L_b cos q_b``; joint b alone: ``J_b qdd_b = m_b g L_b cos q_b + lam`` (T = [-RATIO,
    1]). Returns ``(qdd_a, lam)``."""
    j_a, j_b = I_A + M_A * L_A ** 2, I_B + M_B * L_B ** 2
    g_a, g_b = M_A * G * L_A * np.cos(q_a), M_B * G * L_B * np.cos(q_b)
    qdd_a = (tau + g_a + RATIO * g_b) / (j_a + RATIO ** 2 * j_b)
    return qdd_a, j_b * RATIO * qdd_a - g_b


def test_coupling_counts_make_the_mimicking_joint_dependent():
    counts = derive(geared_pendulums()).counts
    assert (counts.nc, counts.np, counts.m, counts.n) == (1, 1, 1, 1)


def test_coupling_forward_dynamics_and_force_match_the_hand_derivation():
    model = derive(geared_pendulums())
    states = random_consistent_states(model, 5, seed=3, spread=1.0)
    for (config, v_m), tau in zip(states, (0.3, -1.0, 0.0, 2.5, -0.4)):
        q_a, q_b = float(config.positions["ja"]), float(config.positions["jb"])
        assert q_b == pytest.approx(RATIO * q_a + OFFSET, abs=1e-13)
        out = model.motion(config, v_m, tau=[tau])
        qdd_a, lam = closed_form(q_a, q_b, tau)
        assert out.qdd_all == pytest.approx([qdd_a, RATIO * qdd_a], rel=RTOL)
        assert out.qd_all[1] == pytest.approx(RATIO * out.qd_all[0], rel=RTOL)
        assert out.lam == pytest.approx([lam], rel=RTOL)
    assert model.constraint_force_names() == ["gear.tau"]


def test_the_hand_check_catches_a_wrong_ratio():
    """The planted error: the model read with the ratio's sign flipped misses the closed form."""
    scene = geared_pendulums()
    scene.constraints.clear()
    scene.joints["jb"] = dataclasses.replace(scene.joints["jb"], q0=-OFFSET)
    scene.add_coupling("gear", "jb", "ja", multiplier=-RATIO, offset=-OFFSET)
    model = derive(scene)
    config, v_m = random_consistent_states(model, 1, seed=3, spread=1.0)[0]
    out = model.motion(config, v_m, tau=[0.3])
    qdd_a, _ = closed_form(float(config.positions["ja"]), float(config.positions["jb"]), 0.3)
    assert abs(out.qdd_all[0] - qdd_a) > 1e-3 * abs(qdd_a)


def test_two_actuated_coupled_joints_carry_the_coupling_in_eta_f():
    """Both joints actuated: n_p = 0, the coupling's force is eta_f; same motion as the closed form."""
    scene = geared_pendulums(actuated_b=True)
    scene.constraint_forces = "joint"
    model = derive(scene)
    assert (model.counts.np, model.counts.n) == (0, 2)
    config, v_m = random_consistent_states(model, 1, seed=5, spread=1.0)[0]
    out = model.motion(config, v_m, tau=[0.3, 0.0])
    qdd_a, lam = closed_form(float(config.positions["ja"]), float(config.positions["jb"]), 0.3)
    assert out.qdd_all == pytest.approx([qdd_a, RATIO * qdd_a], rel=RTOL)
    assert out.lam == pytest.approx([lam], rel=RTOL)


def test_closure_solve_restores_a_broken_coupling():
    from symgen.closure import closure_residual, solve_closure
    from symgen.math.configuration import Configuration

    model = derive(geared_pendulums())
    broken = Configuration({"ja": 0.4, "jb": 0.0})
    assert closure_residual(model, broken) == pytest.approx([OFFSET - (0.0 - RATIO * 0.4)])  # offset - (q_b - a q_a)
    fixed = solve_closure(model, broken)
    assert fixed.positions["ja"] == 0.4
    assert fixed.positions["jb"] == pytest.approx(RATIO * 0.4 + OFFSET, abs=1e-13)


@pytest.mark.parametrize("call, words", [
    (lambda s: s.add_coupling("c", "jb", "nope"), ["constraint 'c'", "'nope'", "not declared"]),
    (lambda s: s.add_coupling("c", "ghost", "ja"), ["constraint 'c'", "'ghost'", "not declared"]),
    (lambda s: s.add_coupling("c", "ja", "ja"), ["constraint 'c'", "'ja'", "itself"]),
    (lambda s: s.add_coupling("c", "jb", "ja", multiplier="two"), ["constraint 'c'", "multiplier"]),
    (lambda s: s.add_coupling("c", "jb", "ja", multiplier=0), ["constraint 'c'", "zero"]),
    (lambda s: s.add_coupling("c", "jb", "ja", terms={"ja": 1}), ["constraint 'c'", "not both"]),
    (lambda s: s.add_coupling("c", "jb", terms={}), ["constraint 'c'", "terms"]),
    (lambda s: s.add_coupling("c", "jf", "ja"), ["constraint 'c'", "'jf'", "fixed"]),
])
def test_bad_couplings_are_typed_errors_naming_the_element(call, words):
    s = geared_pendulums()
    s.add_body("f", 1, inertia=(0.1, 0.1, 0.1))
    s.add_joint("jf", "fixed", "a", "f")
    with pytest.raises(SceneError) as err:
        call(s)
    for w in words:
        assert w in str(err.value)


def two_finger_urdf(mimic: str) -> str:
    """Two prismatic fingers on a fixed base; the second carries ``mimic`` (a ``<mimic .../>`` tag)."""
    link = ('<link name="{0}"><inertial><mass value="0.1"/><inertia ixx="1e-4" iyy="1e-4" izz="1e-4" ixy="0" '
            'ixz="0" iyz="0"/></inertial></link>')
    joint = ('<joint name="{0}" type="prismatic"><parent link="base"/><child link="{1}"/><axis xyz="0 1 0"/>'
             '<limit lower="-0.1" upper="0.1" effort="10" velocity="1"/>{2}</joint>')
    return ('<robot name="hand"><link name="base"/>' + link.format("left") + link.format("right")
            + joint.format("left_joint", "left", "") + joint.format("right_joint", "right", mimic) + "</robot>")


def test_urdf_mimic_becomes_a_passive_joint_and_a_coupling(tmp_path):
    from symgen.io.urdf import scene_from_urdf

    path = tmp_path / "hand.urdf"
    path.write_text(two_finger_urdf('<mimic joint="left_joint" multiplier="-0.5" offset="0.01"/>'))
    scene = scene_from_urdf(str(path))
    con = scene.constraints["right_joint_mimic"]
    assert con.terms == (("right_joint", 1), ("left_joint", sp.Rational(1, 2))) and con.offset == sp.Rational(1, 100)
    assert not scene.joints["right_joint"].actuated and scene.joints["left_joint"].actuated
    assert scene.joints["right_joint"].q0 == sp.Rational(1, 100) and scene.motion.joints == ("left_joint",)
    assert derive(scene).counts.np == 1


@pytest.mark.parametrize("mimic, words", [
    ('<mimic joint="thumb_joint"/>', ["joint 'right_joint'", "'thumb_joint'", "not a joint"]),
    ('<mimic joint="right_joint"/>', ["joint 'right_joint'", "itself"]),
    ('<mimic joint="left_joint" multiplier="two"/>', ["joint 'right_joint'", "mimic multiplier", "'two'"]),
    ('<mimic multiplier="1"/>', ["joint 'right_joint'", "no joint attribute"]),
])
def test_bad_urdf_mimics_are_typed_errors_naming_the_joint(tmp_path, mimic, words):
    from symgen.io.urdf import scene_from_urdf
    from symgen.io.urdf.parse import UrdfError

    path = tmp_path / "hand.urdf"
    path.write_text(two_finger_urdf(mimic))
    with pytest.raises(UrdfError) as err:
        scene_from_urdf(str(path))
    for w in words:
        assert w in str(err.value)


def test_couplings_round_trip_through_yaml_exactly():
    from symgen.io.scene_yaml import dump_scene, load_scene

    scene = geared_pendulums()
    scene.add_body("c", 1, com=(0.2, 0, 0), inertia=(0.01, 0.01, 0.01))
    scene.add_joint("jc", "revolute", "world", "c", xyz=(0, 2, 0), axis="y", actuated=True)
    scene.add_coupling("belt", "jc", terms={"ja": "1/3", "jb": -1}, offset="-0.1")
    scene.joints["jc"] = dataclasses.replace(scene.joints["jc"], q0=sp.Rational(-1, 10) + OFFSET)
    scene.set_motion(joints=["ja"])
    scene.constraint_forces = "joint"
    text = dump_scene(scene)
    assert "gear: {type: coupling, joint: jb, leader: ja, multiplier: -2, offset: 0.1}" in text
    assert "belt: {type: coupling, joint: jc, terms: {ja: 1/3, jb: -1}, offset: -0.1}" in text
    again = load_scene(text)
    assert again.constraints == scene.constraints
    assert dump_scene(again) == text
    assert derive(again).counts.nc == 2


@pytest.mark.parametrize("entry, words", [
    ("{type: coupling, joint: jb, leader: nope}", ["constraint 'gear'", "'nope'", "line 9"]),
    ("{type: coupling, joint: jb, leader: ja, multiplier: [1]}", ["constraint 'gear'", "multiplier"]),
    ("{type: coupling, joint: jb, terms: {ja: 1}, multiplier: 2}", ["constraint 'gear'", "with leader"]),
    ("{type: coupling, leader: ja}", ["constraint 'gear'", "missing required key 'joint'"]),
    ("{type: coupling, joint: jb, leader: ja, frames: [a, b]}", ["constraint 'gear'", "unknown key 'frames'"]),
])
def test_bad_yaml_couplings_name_the_constraint(entry, words):
    from symgen.io.scene_yaml import load_scene

    text = ("name: g\nbodies:\n  a: {mass: 1, com: [1, 0, 0]}\n  b: {mass: 1, com: [1, 0, 0]}\njoints:\n"
            "  ja: {type: revolute, parent: world, child: a, axis: y, actuated: true}\n"
            "  jb: {type: revolute, parent: world, child: b, axis: y}\nconstraints:\n"
            f"  gear: {entry}\nmotion: {{joints: [ja]}}\n")
    with pytest.raises(SceneError) as err:
        load_scene(text)
    for w in words:
        assert w in str(err.value)


def test_the_simulation_poses_see_the_coupling_residual_and_its_jacobian():
    """What the simulation's stabilization reads (:class:`symgen.simulation.poses.Poses`): residual
    ``offset - (q_b - RATIO q_a)`` and its derivative ``-[-RATIO, 1]``, by hand."""
    from symgen.codegen.reference import position_vector
    from symgen.math.configuration import Configuration
    from symgen.simulation.poses import Poses

    model = derive(geared_pendulums())
    poses = Poses(model)
    q = position_vector(model, Configuration({"ja": 0.3, "jb": -0.2}))
    r, jac = poses.residual_and_jacobian(q, [0, 1])
    assert r == pytest.approx([OFFSET - (-0.2 - RATIO * 0.3)], abs=1e-15)
    assert jac == pytest.approx(np.array([[RATIO, -1.0]]), abs=1e-15)
    assert poses.residual(q) == pytest.approx(r, abs=1e-15)


def test_the_property_proofs_pass_on_a_coupled_scene():
    from symgen.proofs import prove

    results = prove(derive(geared_pendulums()))
    assert results and all(r.passed for r in results), [r.name for r in results if not r.passed]


@pytest.mark.parametrize("method, stabilization, tol", [("rk4", "projection", 1e-7), ("DOP853", "baumgarte", 1e-8)])
def test_a_simulated_coupled_scene_follows_the_hand_derived_ode(method, stabilization, tol):
    """The simulation (generated NumPy code, stabilized on the coupling's residual) against SciPy
    integrating the closed form's one-DOF ODE ``qdd_a = f(q_a)`` with ``q_b = RATIO q_a + OFFSET``."""
    from scipy.integrate import solve_ivp

    from symgen.simulation.integrators import simulate

    model = derive(geared_pendulums())
    options = dict(step=1e-3) if method == "rk4" else dict(rtol=1e-11, atol=1e-11)
    run = simulate(model, 0.5, method, stabilization=stabilization, energy=False, **options)

    def ode(_, y):
        return [y[1], closed_form(y[0], RATIO * y[0] + OFFSET, 0.0)[0]]

    ref = solve_ivp(ode, (0, 0.5), [0.0, 0.0], method="DOP853", rtol=1e-12, atol=1e-12)
    q_a, q_b, v_a = run.final_state
    assert q_a == pytest.approx(ref.y[0, -1], abs=tol) and v_a == pytest.approx(ref.y[1, -1], abs=tol)
    assert q_b == pytest.approx(RATIO * q_a + OFFSET, abs=1e-9) and np.max(run.drift) < 1e-9
