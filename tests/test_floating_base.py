"""Floating bases (the free joint) and feet on the ground, against hand derivations and Pinocchio's
``JointModelFreeFlyer`` (its ``aba``, ``rnea`` and an independent KKT solve for the contacts)."""
from __future__ import annotations

import numpy as np
import pytest

from symgen import derive
from symgen.closure import random_consistent_states
from symgen.errors import SceneError
from symgen.math.configuration import as_configuration
from symgen.scene import Scene

pin = pytest.importorskip("pinocchio")
legged = pytest.importorskip("symgen.io.urdf.legged")

from .pinocchio_floating import FloatingTwin, quat_matrix  # noqa: E402


def brick():
    scene = Scene(name="brick")
    scene.add_body("b", 2, com=(0, 0, 0), inertia=(0.1, 0.2, 0.3))
    scene.add_joint("base", "free", "world", "b", q0=[0, 0, 1, 1, 0, 0, 0])
    scene.set_motion(joints=["base"])
    return scene


def test_free_body_falls_and_turns_by_euler_equations():
    """A free brick: pdd = g and I wd = -w x I w (Euler), whatever its pose."""
    model = derive(brick())
    q = np.array([0.9, 0.1, -0.3, 0.2])
    q /= np.linalg.norm(q)
    config = {"base_x": 0.3, "base_y": -0.2, "base_z": 1.0, "base_rot": q}
    v = np.array([0.5, -1.0, 0.2, 0.7, -0.4, 1.3])
    dv, _ = model.forward_dynamics(config, v, np.zeros(6))
    inertia, w = np.diag([0.1, 0.2, 0.3]), v[3:]
    np.testing.assert_allclose(dv[:3], [0, 0, -9.81], atol=1e-14)
    np.testing.assert_allclose(dv[3:], -np.linalg.solve(inertia, np.cross(w, inertia @ w)), rtol=1e-14)


def test_free_joint_declares_its_parts_and_coordinates():
    scene = brick()
    free = scene.free_joints["base"]
    assert free.joints == ("base_x", "base_y", "base_z", "base_rot")
    assert all(scene.bodies[b].is_massless for b in free.carriers)
    model = derive(scene)
    assert [c.label for c in model.tree.coordinates] == list(free.velocity_labels)
    assert model.counts.m == 6 and model.counts.n == 6


@pytest.mark.parametrize("kwargs, words", [
    (dict(actuated=True), "not actuated"),
    (dict(viscous=1), "no viscous"),
    (dict(q0=[0, 0, 1]), "7 numbers"),
    (dict(axis="x"), "no axis"),
])
def test_free_joint_refuses_what_it_cannot_be(kwargs, words):
    scene = Scene(name="s")
    scene.add_body("b", 1, inertia=(1, 1, 1))
    with pytest.raises(SceneError, match=words):
        scene.add_joint("base", "free", "world", "b", **kwargs)


def test_free_joint_refuses_a_name_clash():
    scene = Scene(name="s")
    scene.add_body("b", 1, inertia=(1, 1, 1))
    scene.add_body("base_x_link", 1, inertia=(1, 1, 1))
    with pytest.raises(SceneError, match="already exist"):
        scene.add_joint("base", "free", "world", "b")


def test_contact_frame_must_exist():
    from symgen.ground_contacts import add_ground_contact

    scene = brick()
    with pytest.raises(SceneError, match="'toe' is not declared"):
        add_ground_contact(scene, "toe")
    scene.add_frame("toe", "b", xyz=[0, 0, -1])
    with pytest.raises(SceneError, match="unknown contact kind"):
        add_ground_contact(scene, "toe", "sticky")


def _random_tree_state(model, rng):
    """A random configuration (base anywhere, joints within +-1) and rates of a contact-free scene."""
    positions = {}
    for j in model.scene.joints.values():
        if j.kind.position_is_rotation:
            q = rng.normal(size=4)
            positions[j.name] = q / np.linalg.norm(q)
        elif j.dof:
            positions[j.name] = rng.uniform(-1, 1)
    return positions, rng.normal(size=model.counts.m)


def _urdf(robot):
    """The URDF Pinocchio reads for ``robot``: the installed file, or for ANYmal the text symgen
    read (the file without its base's placeholder inertial; see test_anymal_leaves_out_...)."""
    from symgen.io.urdf.examples import example_path

    return legged.anymal_robot().text if robot == "anymal" else example_path(robot)


TREES = [("solo12", "solo12", ()), ("anymal", "anymal", ()), ("space_ur5", "ur5", ())]


@pytest.mark.parametrize("name, robot, lock", TREES + [pytest.param("talos", "talos", "talos", marks=pytest.mark.slow)])
def test_floating_tree_matches_pinocchio_free_flyer(name, robot, lock):
    """aba and rnea of Pinocchio's free-flyer model, through the coordinate maps, at 10 states."""
    model = derive(getattr(legged, name)())
    if lock == "talos":
        lock = list(legged._talos_lock())
    twin = FloatingTwin(pin, model, _urdf(robot), lock)
    if name == "space_ur5":
        twin.pmodel.gravity = pin.Motion.Zero()
    rng = np.random.default_rng(3)
    order = [c.label for c in model.tree.coordinates]
    independent = [order[i] for i in model.partition.independent]
    for _ in range(10):
        positions, v_m = _random_tree_state(model, rng)
        tau = rng.normal(size=model.counts.n) * np.array([0.0 if lab in twin.base.velocity_labels else 1.0
                                                           for lab in independent])
        motion = model.motion(positions, v_m, tau)
        config = as_configuration(positions, model.scene)
        q, v = twin.q(config), twin.v(config, motion.qd_all)
        tau_all = np.zeros(len(order))
        tau_all[list(model.partition.independent)] = tau
        a = pin.aba(twin.pmodel, twin.data, q, v, twin.generalized_force(config, tau_all))
        np.testing.assert_allclose(twin.v(config, motion.qd_all, motion.qdd_all), a,
                                   rtol=1e-9, atol=1e-9 * np.abs(a).max())
        tau_id = model.inverse_dynamics(positions, v_m, motion.dV_m)
        np.testing.assert_allclose(tau_id, tau, rtol=1e-9, atol=1e-9 * np.abs(tau).max())


STANDING = [("solo12_standing", "solo12", (), legged.SOLO_FEET, 3),
            ("anymal_standing", "anymal", (), legged.ANYMAL_FEET, 3)]


@pytest.mark.parametrize("name, robot, lock, feet, dim", STANDING + [
    pytest.param("talos_double_support", "talos", "talos", legged.TALOS_SOLES, 6, marks=pytest.mark.slow)])
def test_feet_on_the_ground_match_a_kkt_solve(name, robot, lock, feet, dim):
    """Joint accelerations (base included) and contact forces of model (32) equal an independent
    KKT solve on Pinocchio's free-flyer model, at 10 random states with the feet on the ground."""
    model = derive(getattr(legged, name)())
    if lock == "talos":
        lock = list(legged._talos_lock())
    twin = FloatingTwin(pin, model, _urdf(robot), lock)
    rng = np.random.default_rng(5)
    for config, v_m in random_consistent_states(model, 10, seed=7, spread=0.05):
        tau = rng.normal(size=model.counts.n) * 3
        motion = model.motion(config, v_m, tau)
        q, v = twin.q(config), twin.v(config, motion.qd_all)
        tau_all = np.zeros(model.tree.n_coords)
        tau_all[list(model.partition.independent)] = tau
        a, lam = twin.contact_kkt(q, v, twin.generalized_force(config, tau_all), feet, [dim] * len(feet))
        scale = max(np.abs(a).max(), 1.0)
        np.testing.assert_allclose(twin.v(config, motion.qd_all, motion.qdd_all), a, rtol=1e-9, atol=1e-9 * scale)
        np.testing.assert_allclose(motion.lam, lam, rtol=1e-9, atol=1e-9 * max(np.abs(lam).max(), 1.0))


@pytest.mark.parametrize("name", ["solo12_standing", "anymal_standing"])
def test_quadruped_holds_still_under_gravity_compensation(name):
    """Standing with zero base velocity, the inverse dynamics' torques for dV_m = 0 hold the
    robot still: every joint's acceleration is zero (to 1e-12)."""
    model = derive(getattr(legged, name)())
    config, v_m = model.reference, np.zeros(model.counts.m)
    tau = model.inverse_dynamics(config, v_m, np.zeros(model.counts.m), np.zeros(model.counts.n - model.counts.m))
    qdd = model.joint_accelerations(config, v_m, tau)
    assert np.abs(qdd).max() <= 1e-12


def test_anymal_leaves_out_only_the_placeholder_inertial_of_its_base():
    """Pinocchio's parse of the installed file and of the text symgen reads differ by the
    placeholder alone: 1e-6 kg of mass on the root joint, every other body as in the file."""
    from symgen.io.urdf.examples import example_path

    as_file = pin.buildModelFromUrdf(str(example_path("anymal")), pin.JointModelFreeFlyer())
    as_read = pin.buildModelFromXML(legged.anymal_robot().text, pin.JointModelFreeFlyer())
    masses = [[inertia.mass for inertia in m.inertias] for m in (as_file, as_read)]
    assert masses[0][1] - masses[1][1] == pytest.approx(1e-6, rel=1e-9)
    assert masses[0][2:] == masses[1][2:] and as_file.nv == as_read.nv == 18


def test_the_free_flyer_comparison_sees_anymals_placeholder():
    """Planted difference: Pinocchio reading the installed file (with the 1e-6 kg placeholder) is
    ~8e-7 away from symgen's ANYmal in aba, far outside the 1e-9 of the comparison above; the
    text symgen read is within it."""
    from symgen.io.urdf.examples import example_path

    model = derive(legged.anymal())
    worst = []
    for source in (example_path("anymal"), legged.anymal_robot().text):
        twin, rng, errs = FloatingTwin(pin, model, source), np.random.default_rng(3), []
        for _ in range(3):
            positions, v_m = _random_tree_state(model, rng)
            motion = model.motion(positions, v_m, np.zeros(model.counts.n))
            config = as_configuration(positions, model.scene)
            a = pin.aba(twin.pmodel, twin.data, twin.q(config), twin.v(config, motion.qd_all), np.zeros(twin.pmodel.nv))
            errs.append(np.abs(twin.v(config, motion.qd_all, motion.qdd_all) - a).max() / np.abs(a).max())
        worst.append(max(errs))
    assert worst[0] > 1e-7 and worst[1] < 1e-12


def test_quaternion_helper_matches_pinocchio():
    q = np.array([0.3, -0.5, 0.1, 0.8])
    q /= np.linalg.norm(q)
    np.testing.assert_allclose(quat_matrix(*q), pin.Quaternion(q[0], q[1], q[2], q[3]).toRotationMatrix(), atol=1e-15)


@pytest.mark.parametrize("spec", ["solo12", "solo12_standing", "anymal", "anymal_standing",
                                  pytest.param("talos_double_support", marks=pytest.mark.slow)])
def test_symgen_check_covers_floating_bases_and_feet(spec):
    """``symgen check --against pinocchio`` rebuilds the robot on Pinocchio's translation+spherical
    root (symgen's free-joint coordinates) and passes for the dense model and both generated targets."""
    from symgen.io.builtin import get_scene
    from symgen.oracle.pinocchio_check import check_against_pinocchio

    diffs = check_against_pinocchio(derive(get_scene(spec)), states=5, targets=("numpy", "c"))
    assert len(diffs) >= 4 and all(d.passed for d in diffs), [d.as_dict() for d in diffs if not d.passed]


def _space_momentum():
    """The benchmark module that simulates the space robot and measures its momentum drift."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[1] / "benchmarks" / "space_momentum.py"
    spec = importlib.util.spec_from_file_location("space_momentum", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def space_robot():
    return _space_momentum().space_robot()


def test_space_robot_momentum_rate_is_zero(space_robot):
    """Zero gravity, internal joint torques only: the rate of change of the centroidal momentum
    (Pinocchio's computeCentroidalMomentumTimeVariation at symgen's accelerations) vanishes."""
    model, robot, v_idx, drive = space_robot
    data = robot.model.createData()
    rng = np.random.default_rng(11)
    for _ in range(10):
        positions, v_m = _random_tree_state(model, rng)
        motion = model.motion(positions, v_m, drive * rng.normal(size=len(drive)) * 10)
        q = robot.q_vector(as_configuration(positions, model.scene))
        v, a = np.zeros(robot.model.nv), np.zeros(robot.model.nv)
        v[v_idx], a[v_idx] = motion.qd_all, motion.qdd_all
        pin.computeCentroidalMomentumTimeVariation(robot.model, data, q, v, a)
        scale = np.abs(a).max() * 20               # ~ total mass times acceleration
        assert np.abs(data.dhg.vector).max() <= 1e-12 * scale


#: DOP853's tolerances for the momentum check: rtol just above SciPy's floor (100 eps), atol small
#: because the relative part is loose on a joint that spins to hundreds of radians. The drift is
#: at the integrator's floor, 0.7e-10 to 1.2e-10 over 10 s for atol in 1e-16..1e-14 depending on
#: the last bits of the dynamics (benchmarks/space_momentum.md); atol = 1e-14 takes the fewest steps
MOMENTUM_RTOL, MOMENTUM_ATOL = 2.3e-14, 1e-14
MOMENTUM_DRIFT = 1e-10


@pytest.mark.parametrize("t_end", [2.0, pytest.param(10.0, marks=pytest.mark.slow)])
def test_space_robot_conserves_momentum_in_simulation(t_end, space_robot):
    """Simulated with generated C (DOP853) under sinusoidal joint torques, the momentum
    (Pinocchio's centroidal momentum, about 2 N s, at every accepted step) drifts by at most 1e-10
    (8.6e-11 measured over 10 s, benchmarks/space_momentum.md, where glibc's sin and cos gave 6.5e-11
    and the inline ones without the reduction's tail 1.0e-10; 2.8e-10 at rtol = atol = 1e-13). The
    10 s case takes about 25 s on an idle core."""
    out = _space_momentum().momentum_drift(t_end, MOMENTUM_RTOL, MOMENTUM_ATOL, space_robot)
    assert out["momentum"] > 0.1            # it moves
    assert out["drift"] <= MOMENTUM_DRIFT


def test_the_momentum_check_sees_a_loose_tolerance(space_robot):
    """Planted error: at rtol = atol = 1e-11 a 1 s run drifts far beyond the bound."""
    assert _space_momentum().momentum_drift(1.0, 1e-11, 1e-11, space_robot)["drift"] > 10 * MOMENTUM_DRIFT


def test_free_joint_round_trips_through_yaml_as_one_entry():
    import yaml

    from symgen.io.scene_yaml import scene_from_dict
    from symgen.io.scene_yaml_dump import dump_scene

    scene = brick()
    scene.add_body("arm", 1, inertia=(1, 1, 1))
    scene.add_joint("j1", "revolute", "b", "arm", axis="y", actuated=True)
    scene.set_motion(joints=["j1", "base"])
    text = dump_scene(scene)
    data = yaml.safe_load(text)
    assert data["joints"]["base"]["type"] == "free" and "base_x_link" not in data["bodies"]
    assert data["motion"]["joints"] == ["j1", "base"]
    again = scene_from_dict(data)
    assert dump_scene(again) == text and list(again.joints) == list(scene.joints)
    assert derive(again).counts == derive(scene).counts


FREE_MJCF = """<mujoco><worldbody>
<body name="trunk" pos="0.1 -0.2 1.3" quat="0.8 0 0.6 0"><freejoint name="root"/>
<geom type="box" size="0.3 0.2 0.1"/>
<body name="arm" pos="0.3 0 0"><joint name="shoulder" axis="0 1 0"/><geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.05"/>
<body name="fore" pos="0.4 0 0"><joint name="elbow" axis="0 0 1"/><geom type="sphere" size="0.07" pos="0.2 0 0"/>
</body></body></body></worldbody><actuator><motor joint="shoulder"/><motor joint="elbow"/></actuator></mujoco>"""


def test_mjcf_free_joint_matches_mujoco():
    """An MJCF <freejoint> is symgen's free joint with MuJoCo's qpos/qvel: mass matrix (mj_fullM)
    and bias forces (qfrc_bias) agree through the coordinate map at random states."""
    mujoco = pytest.importorskip("mujoco")
    from symgen.io.coordinates import CoordinateMap
    from symgen.io.mjcf import parse_mjcf_text, scene_from_mjcf_model

    scene = scene_from_mjcf_model(parse_mjcf_text(FREE_MJCF))
    assert "root" in scene.free_joints and any("root" in note for note in scene.notes)
    model = derive(scene)
    mj = mujoco.MjModel.from_xml_string(FREE_MJCF)
    data = mujoco.MjData(mj)
    cmap = CoordinateMap.mujoco(scene, mj)
    idx = cmap.velocity_indices(model.coordinate_names())
    np.testing.assert_allclose(cmap.from_symgen(model.reference)[0], mj.qpos0, atol=1e-15)
    rng = np.random.default_rng(2)
    for _ in range(5):
        qpos = mj.qpos0 + np.r_[rng.normal(size=3), rng.normal(size=4), rng.normal(size=2)]
        qpos[3:7] /= np.linalg.norm(qpos[3:7])
        data.qpos[:], data.qvel[:] = qpos, rng.normal(size=mj.nv)
        mujoco.mj_forward(mj, data)
        mass = np.zeros((mj.nv, mj.nv))
        if hasattr(data, "qM"):
            mujoco.mj_fullM(mj, mass, data.qM)
        else:
            mujoco.mj_fullM(mj, data, mass)
        config, rates = cmap.to_symgen(data.qpos, data.qvel)
        qd = np.array([rates[n] for n in model.coordinate_names()])
        ev = model.evaluate(config, qd=qd)
        np.testing.assert_allclose(ev.M_q, mass[np.ix_(idx, idx)], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(ev.C_q @ qd + ev.G_q, data.qfrc_bias[idx], rtol=1e-12, atol=1e-11)


@pytest.mark.parametrize("text, words", [
    (FREE_MJCF.replace('<freejoint name="root"/>', "").replace('<joint name="shoulder" axis="0 1 0"/>',
                                                                '<freejoint name="s"/>'), "child of the world"),
    (FREE_MJCF.replace('<freejoint name="root"/>', '<joint name="root" type="free" damping="1"/>'),
     "damping on a free joint"),
    (FREE_MJCF.replace('<freejoint name="root"/>', '<freejoint name="root" align="true"/>'), "align"),
])
def test_mjcf_free_joint_refusals_name_the_element(text, words):
    from symgen.io.mjcf import MjcfError, parse_mjcf_text, scene_from_mjcf_model

    with pytest.raises(MjcfError, match=words):
        scene_from_mjcf_model(parse_mjcf_text(text))


def test_pinocchio_free_flyer_coordinate_map_keeps_kinetic_energy():
    """CoordinateMap.pinocchio on a JointModelFreeFlyer root: Pinocchio's (q, v) mapped to symgen
    give the same kinetic energy (an invariant of the velocity map) and gravity's power."""
    from symgen.io.coordinates import CoordinateMap
    from symgen.io.urdf.examples import example_path

    scene = legged.solo12()
    model = derive(scene)
    pmodel = pin.buildModelFromUrdf(str(example_path("solo12")), pin.JointModelFreeFlyer())
    pdata = pmodel.createData()
    cmap = CoordinateMap.pinocchio(scene, pmodel)
    rng = np.random.default_rng(4)
    for _ in range(5):
        q, v = pin.randomConfiguration(pmodel, -np.ones(pmodel.nq), np.ones(pmodel.nq)), rng.normal(size=pmodel.nv)
        config, rates = cmap.to_symgen(q, v)
        qd = np.array([rates[n] for n in model.coordinate_names()])
        ev = model.evaluate(config, qd=qd)
        energy = pin.computeKineticEnergy(pmodel, pdata, q, v)
        assert abs(0.5 * qd @ ev.M_q @ qd - energy) <= 1e-12 * max(energy, 1.0)
        gravity_power = pin.computeGeneralizedGravity(pmodel, pdata, q) @ v
        assert abs(ev.G_q @ qd - gravity_power) <= 1e-12 * max(abs(gravity_power), 1.0)
        q2, v2 = cmap.from_symgen(config, rates)
        np.testing.assert_allclose(v2, v, atol=1e-12)
        assert min(np.abs(q2 - q).max(), np.abs(np.r_[q2[:3], -q2[3:7], q2[7:]] - q).max()) <= 1e-12


def test_floating_from_the_command_line_and_yaml(tmp_path, capsys):
    from symgen import load
    from symgen.cli import main
    from symgen.io.urdf.examples import example_path

    path = str(example_path("solo12"))
    assert main(["info", path, "--floating"]) == 0
    assert "n1u=3  n3a=0  n3u=1  m=18" in capsys.readouterr().out
    assert main(["info", "four_bar", "--floating"]) != 0
    assert "apply to URDF files only" in capsys.readouterr().err
    (tmp_path / "solo.yaml").write_text(
        "name: solo_on_feet\nurdf:\n  example: solo12\n  floating: true\n  friction: false\n"
        "  base: {xyz: [0, 0, 0.235]}\n"
        "  q0: {FL_HFE: 0.8, FL_KFE: -1.6, FR_HFE: 0.8, FR_KFE: -1.6, HL_HFE: -0.8, HL_KFE: 1.6, HR_HFE: -0.8, "
        "HR_KFE: 1.6}\n  stand: {frames: [FL_FOOT, FR_FOOT, HL_FOOT, HR_FOOT], kind: point}\n")
    counts = derive(load(str(tmp_path / "solo.yaml"))).counts
    assert (counts.m, counts.nc, counts.np, counts.n) == (6, 12, 6, 12)
