"""Joint springs ``k (q - q_spring)`` (a potential term of G, eq. 22): checked against hand
derivations (a spring pendulum's G and equilibrium, a mass on a spring's period), MuJoCo's
``qfrc_spring`` on a file with ``ref`` and ``springref`` in degrees, the generated code, energy
conservation of a simulated run, and the typed refusals (ball and free joints, exact angles)."""
import math

import mujoco
import numpy as np
import pytest

from symgen.errors import SceneError, StateError, SymgenError
from symgen.io.coordinates import CoordinateMap
from symgen.io.mjcf import scene_from_mjcf
from symgen.io.scene_yaml import dump_scene, load_scene, scene_from_dict
from symgen.model import derive

M, L, G0, K, Q_S, I_C = 2.0, 0.5, 9.81, 3.0, 0.4, 0.01


def _pendulum(gravity=G0, stiffness=K, springref=Q_S, kind="revolute"):
    """A bob of mass ``M`` (inertia ``I_C`` about its centre) ``L`` below a joint about y."""
    return {
        "name": "spring_pendulum", "gravity": [0, 0, -gravity],
        "bodies": {"bob": {"mass": M, "com": [0, 0, -L], "inertia": [I_C, I_C, I_C]}},
        "joints": {"j": {"type": kind, "parent": "world", "child": "bob", "axis": "y" if kind == "revolute" else "z",
                         "actuated": True, "stiffness": stiffness, "springref": springref}},
        "motion": {"joints": ["j"]},
    }


def _hand_g(q):
    """``dU/dq`` of ``U = -M g L cos q + K (q - Q_S)^2 / 2`` (the bob at ``(-L sin q, 0, -L cos q)``)."""
    return M * G0 * L * math.sin(q) + K * (q - Q_S)


@pytest.fixture(scope="module")
def pendulum():
    return derive(scene_from_dict(_pendulum()))


@pytest.mark.parametrize("q", [-1.2, 0.3, 4.0])
def test_g_of_a_spring_pendulum_is_the_hand_derivation_in_float_and_50_digits(pendulum, q):
    """``q = 4`` rad is past pi: the spring acts on the angle itself, not on its cosine and sine."""
    assert float(pendulum.evaluate({"j": q}, qd=[0.0]).G_q[0]) == pytest.approx(_hand_g(q), rel=1e-13)
    mp = pendulum.evaluate({"j": q}, qd=[0.0], field="mp").G_q[0]
    assert abs(float(mp) - _hand_g(q)) <= 1e-13 * abs(_hand_g(q))


def test_the_equilibrium_of_a_spring_pendulum_is_where_g_vanishes(pendulum):
    """Equilibrium ``M g L sin q + K (q - Q_S) = 0`` found by bisection on the hand formula: the
    model's forward dynamics there is at rest, and a step off it accelerates back."""
    lo, hi = 0.0, Q_S
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if _hand_g(mid) < 0 else (lo, mid)
    q_eq = 0.5 * (lo + hi)
    dv, _ = pendulum.forward_dynamics({"j": q_eq}, [0.0], [0.0])
    assert abs(float(dv[0])) < 1e-12
    assert float(pendulum.forward_dynamics({"j": q_eq + 0.1}, [0.0], [0.0])[0][0]) < 0


def test_a_mass_on_a_vertical_spring_oscillates_at_sqrt_k_over_m_in_exact_arithmetic():
    """Prismatic along z (gravity -z): ``M qdd = -K (q - Q_S) - M g``, exact (a displacement has no
    cosine-sine form, so the exact field takes the spring too)."""
    from fractions import Fraction

    model = derive(scene_from_dict(_pendulum(gravity=10, stiffness=8, springref=Fraction(1, 4), kind="prismatic")))
    for q in (Fraction(0), Fraction(3, 7)):
        dv, _ = model.forward_dynamics({"j": q}, [0], [0], field="exact")
        assert dv[0] == (-8 * (q - Fraction(1, 4)) - 2 * 10) / 2


def test_the_generated_code_has_the_spring_and_matches_the_evaluator(pendulum):
    from symgen.codegen.runtime import load_generated

    module = load_generated(pendulum, "numpy", ["gravity", "inverse_dynamics"])
    for q in (-1.2, 4.0):
        assert float(np.ravel(module.gravity(np.array([q])))[0]) == pytest.approx(_hand_g(q), rel=1e-13)
        tau = np.ravel(module.inverse_dynamics(np.array([q]), np.array([0.7]), np.array([-0.3])))[0]
        expected = pendulum.evaluate({"j": q}, qd=[0.7])
        assert tau == pytest.approx(float(expected.M_q[0, 0] * -0.3 + (expected.C_q @ expected.qd)[0]
                                          + expected.G_q[0]), rel=1e-13)


def test_a_simulated_spring_pendulum_conserves_kinetic_gravity_and_spring_energy(pendulum):
    """DOP853 over 2 s: kinetic + gravity + spring potential constant (the spring's share is large)."""
    from symgen.simulation import simulate

    traj = simulate(pendulum, 2.0, "DOP853", rtol=1e-11, atol=1e-11, x0={"j": 1.5})
    total = traj.kinetic + traj.potential
    assert np.ptp(total) < 1e-8 * np.ptp(traj.kinetic)
    spring = 0.5 * K * (traj.states[:, 0] - Q_S) ** 2
    assert np.ptp(spring) > 0.3 * np.ptp(traj.kinetic)        # the spring stores a real share
    assert np.ptp(total - spring) > 1e-2 * np.ptp(traj.kinetic)  # without it the sum is not kept


def test_a_rotor_on_a_spring_has_the_period_two_pi_sqrt_inertia_over_k():
    """No gravity: ``(I_C + M L^2) qdd = -K (q - Q_S)``, so ``q(T) = q(0)`` after ``T = 2 pi sqrt(J/K)``
    and ``q(T/2) = 2 Q_S - q(0)``."""
    from symgen.simulation import simulate

    model = derive(scene_from_dict(_pendulum(gravity=0)))
    period = 2 * math.pi * math.sqrt((I_C + M * L * L) / K)
    traj = simulate(model, period, "DOP853", rtol=1e-12, atol=1e-12, x0={"j": 1.0}, t_eval=[period / 2, period])
    assert traj.states[0, 0] == pytest.approx(2 * Q_S - 1.0, abs=1e-8)
    assert traj.states[1, 0] == pytest.approx(1.0, abs=1e-8)


MJCF = """<mujoco><compiler angle="degree"/>
<worldbody><body name="a" pos="0 0 1"><joint name="h" type="hinge" axis="0 1 1" stiffness="3" springref="30" ref="10"/>
<geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.05" mass="1"/>
<body name="b" pos="0.3 0 0"><joint name="s" type="slide" axis="1 0 0" stiffness="7" springref="0.1" ref="0.05"/>
<geom type="sphere" size="0.1" mass="2"/></body></body></worldbody></mujoco>"""


def test_mjcf_springs_equal_mujocos_qfrc_spring_with_ref_and_springref_in_degrees(tmp_path):
    """MuJoCo's rule: the spring pulls qpos toward ``qpos_spring`` = springref (not relative to
    ``ref``, which is qpos0); springref of a hinge is in the compiler's angle unit."""
    path = tmp_path / "springs.xml"
    path.write_text(MJCF)
    scene = scene_from_mjcf(str(path))
    model, m = derive(scene), mujoco.MjModel.from_xml_path(str(path))
    d, cmap = mujoco.MjData(m), CoordinateMap.mujoco(scene, m)
    names = model.coordinate_names()
    idx = cmap.velocity_indices(names)
    rng = np.random.default_rng(1)
    for _ in range(3):
        d.qpos[:] = m.qpos0 + rng.uniform(-2, 2, m.nq)
        mujoco.mj_forward(m, d)
        config, _ = cmap.to_symgen(d.qpos.copy(), d.qvel.copy())
        ours = np.asarray(model.evaluate(config, qd=[0.0, 0.0], gravity=False).G_q, float).ravel()
        theirs = -d.qfrc_spring[idx]
        assert np.max(np.abs(ours - theirs)) <= 1e-10 * np.max(np.abs(theirs))


def test_a_scene_file_keeps_its_springs_through_yaml():
    scene = scene_from_dict(_pendulum())
    again = load_scene(dump_scene(scene))
    assert (again.joints["j"].stiffness, again.joints["j"].springref) == (scene.joints["j"].stiffness,
                                                                         scene.joints["j"].springref)


def test_a_ball_joint_spring_is_refused_in_a_scene_and_in_mjcf(tmp_path):
    data = _pendulum()
    data["joints"]["j"] = {"type": "spherical", "parent": "world", "child": "bob", "stiffness": 1}
    with pytest.raises(SceneError, match="no spring"):
        scene_from_dict(data)
    xml = MJCF.replace('type="hinge" axis="0 1 1" stiffness="3" springref="30" ref="10"', 'type="ball" stiffness="2"')
    (tmp_path / "ball.xml").write_text(xml)
    with pytest.raises(SymgenError, match="ball joint's spring"):
        scene_from_mjcf(str(tmp_path / "ball.xml"))


def test_a_free_joint_spring_is_refused(tmp_path):
    xml = MJCF.replace('<joint name="h" type="hinge" axis="0 1 1" stiffness="3" springref="30" ref="10"/>',
                       '<joint name="h" type="free" stiffness="3"/>')
    (tmp_path / "free.xml").write_text(xml)
    with pytest.raises(SymgenError, match="stiffness on a free joint"):
        scene_from_mjcf(str(tmp_path / "free.xml"))


def test_an_exact_revolute_spring_is_a_typed_error_naming_the_joint(pendulum):
    """The exact field holds an angle as a rational cosine-sine pair: no angle for the spring."""
    from symgen.math.configuration import CosSin

    with pytest.raises(StateError, match="joint 'j'.*spring"):
        pendulum.evaluate({"j": CosSin.from_half_tangent("1/3")}, qd=[0], field="exact")


@pytest.mark.parametrize("method", ["articulated-body", "dense"])
def test_generated_forward_dynamics_of_a_spring_pendulum_by_both_routes_is_the_hand_acceleration(pendulum, method):
    """At rest without torque ``qdd = -(M g L sin q + K (q - Q_S)) / (I_C + M L^2)``: the spring
    leaves the articulated-body recursion's input forces with the right sign."""
    from symgen.codegen.generate import trace_all
    from symgen.codegen.runtime import call_by_name, load_generated

    lowered = trace_all(pendulum, ["forward_dynamics"], {"method": method})
    assert all(low.function.metadata["method"] == method for low in lowered)
    module = load_generated(pendulum, "numpy", lowered=lowered)
    for q in (-1.2, 4.0):
        inputs = dict(q=np.array([q]), V_m=np.zeros(1), tau=np.zeros(1), eta_m=np.zeros(0))
        dv = float(np.ravel(call_by_name(module, "forward_dynamics", inputs)[0])[0])
        assert dv == pytest.approx(-_hand_g(q) / (I_C + M * L * L), rel=1e-13)


def test_a_negative_stiffness_is_a_typed_error_naming_the_joint():
    with pytest.raises(SceneError, match="joint 'j'.*stiffness must not be negative"):
        scene_from_dict(_pendulum(stiffness=-1))


def test_the_c_target_with_its_50_digit_test_values_carries_the_spring(pendulum):
    """Generating C evaluates the 50-digit reference of the test program (a revolute angle kept
    beside its cosine and sine); the compiled gravity equals the hand derivation."""
    from symgen.codegen.generate import generate
    from symgen.codegen.runtime import call_by_name, load_generated

    files = generate(pendulum, "c", ["gravity"])
    assert any("spring_j" in text for text in files.files.values())
    module = load_generated(pendulum, "c", ["gravity"])
    g = float(np.ravel(call_by_name(module, "gravity", dict(q=np.array([4.0]))))[0])
    assert g == pytest.approx(_hand_g(4.0), rel=1e-13)


def test_the_pinocchio_check_of_an_mjcf_scene_with_springs_agrees(tmp_path):
    """Pinocchio's model has no springs: the check keeps them beside it, like friction (MuJoCo's
    ``qfrc_spring`` above is the independent check of the springs themselves)."""
    pytest.importorskip("pinocchio")
    from symgen.oracle.pinocchio_check import check_against_pinocchio

    path = tmp_path / "springs.xml"
    path.write_text(MJCF)
    results = check_against_pinocchio(derive(scene_from_mjcf(str(path))), states=3)
    assert results and all(r.passed for r in results), results


def test_the_adaptive_controller_and_identification_refuse_a_sprung_joint_by_name(pendulum):
    """The regressor of eqs. (35)-(37) has no spring term: a sprung scene is refused, not
    controlled as if the spring were not there."""
    from symgen.control.parameters import tree_parameters
    from symgen.math.fields import make_field

    with pytest.raises(SceneError, match=r"joint 'j'.*spring"):
        tree_parameters(pendulum.tree, make_field("float", pendulum.tree.parameters))
    unsprung = derive(scene_from_dict(_pendulum(stiffness=0, springref=0)))
    assert len(tree_parameters(unsprung.tree, make_field("float", unsprung.tree.parameters))) > 0


def test_the_properties_of_model_32_are_proved_exactly_on_a_sprung_scene(pendulum):
    """The exact samples carry the angle (a rational within 1e-18 of 2 atan t) that the spring term
    needs, and the symbolic positions an angle symbol: every property holds."""
    import symgen

    results = symgen.prove(pendulum, points=1)
    assert results and all(r.passed for r in results), [r for r in results if not r.passed]


def test_the_prove_command_on_a_sprung_scene_checks_model_32_and_says_the_regressor_is_skipped(tmp_path, capsys):
    """``symgen prove`` runs every property of model (32) and reports, instead of raising, that the
    Section 4 regressor (which has no spring term) is not checked; the exit status is 0."""
    from symgen.cli import main

    path = tmp_path / "spring_pendulum.yaml"
    path.write_text(dump_scene(scene_from_dict(_pendulum())))
    assert main(["prove", str(path), "--points", "1"]) == 0
    out = capsys.readouterr().out
    assert "SKIP  the Section 4 regressor (35)-(37) is not checked: joint 'j' has a spring" in out
    assert "FAIL" not in out and "all properties hold (one skipped)" in out
