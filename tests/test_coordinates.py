"""symgen.io.coordinates: a Pinocchio ``q``/``v`` mapped into symgen gives Pinocchio's own ``rnea``
(the independent reference) on the example-robot-data URDFs, continuous joints (``cos, sin``) and
branched robots (Talos, Solo12) included; the ball-joint quaternion orders of Pinocchio (x y z w)
and MuJoCo (w x y z) both map to the same rotation."""
from __future__ import annotations

import importlib.util
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

from symgen.io.coordinates import CoordinateError, CoordinateMap
from symgen.model import derive

pin = pytest.importorskip("pinocchio", reason="pinocchio is not installed (extra 'oracle')")
pytest.importorskip("yourdfpy", reason="yourdfpy is not installed (extra 'urdf')")

from .urdf_util import needs_examples  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
_spec = importlib.util.spec_from_file_location("urdf_coverage", ROOT / "benchmarks" / "urdf_coverage.py")
urdf_coverage = sys.modules.setdefault("urdf_coverage", importlib.util.module_from_spec(_spec))
_spec.loader.exec_module(urdf_coverage)

#: agreement with Pinocchio's rnea, relative to its largest entry (at least 1)
TOL = 1e-12
STATES = 3
TALOS = "talos_data/robots/talos_reduced.urdf"
#: Talos's two gripper joints (the moving joint the file's mimic joints follow), locked closed
TALOS_LOCK = ["gripper_left_joint", "gripper_right_joint"]
FAST = ["ur_description/urdf/ur5_robot.urdf", "double_pendulum_description/urdf/double_pendulum_continuous.urdf",
        "kinova_description/robots/kinova.urdf", "solo_description/robots/solo12.urdf"]


def _scene(path: str, **options):
    from symgen.io.urdf import scene_from_urdf

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return scene_from_urdf(path, friction=False, **options)   # Pinocchio's rnea has no friction


def rnea_agrees(path: str, seed: int, **options) -> float:
    """The worst relative difference between Pinocchio's rnea at random (q, v, a) and symgen's
    ``M_q qdd + C_q qd + G_q`` at the mapped state."""
    scene = _scene(path, **options)
    couplings = [name for name, c in scene.constraints.items() if c.is_coupling]
    if couplings:     # Pinocchio's parser reads a mimicking joint as a free one: compare the trees
        for name in couplings:            # (the couplings: tests/test_couplings_pinocchio.py)
            del scene.constraints[name]
        scene.set_motion(joints=[j for j in scene.joints if scene.joints[j].dof])
    model = derive(scene)
    pmodel = pin.buildModelFromUrdf(path)
    pmodel.lowerPositionLimit[:] = np.maximum(pmodel.lowerPositionLimit, -np.pi)
    pmodel.upperPositionLimit[:] = np.minimum(pmodel.upperPositionLimit, np.pi)
    data = pmodel.createData()
    cmap = CoordinateMap.pinocchio(scene, pmodel)
    rng = np.random.default_rng(seed)
    names = model.coordinate_names()
    idx = cmap.velocity_indices(names)
    worst = 0.0
    for _ in range(STATES):
        q = pin.randomConfiguration(pmodel)
        v, a = rng.uniform(-1, 1, pmodel.nv), rng.uniform(-1, 1, pmodel.nv)
        if cmap.locked:               # locked joints sit at their value, at rest
            config, _ = cmap.to_symgen(q)
            q, _ = cmap.from_symgen(config)
            keep = np.zeros(pmodel.nv, bool)
            keep[idx] = True
            v[~keep], a[~keep] = 0.0, 0.0
        tau = pin.rnea(pmodel, data, q, v, a)[idx]
        config, rates = cmap.to_symgen(q, v)
        _, accel = cmap.to_symgen(q, a)
        out = model.evaluate(config, qd=[rates[n] for n in names])
        ours = out.M_q @ np.array([accel[n] for n in names]) + out.C_q @ out.qd + out.G_q
        worst = max(worst, float(np.max(np.abs(np.asarray(ours, float).ravel() - tau))) / max(np.max(np.abs(tau)), 1))
    return worst


@needs_examples
@pytest.mark.parametrize("name", FAST)
def test_a_pinocchio_state_mapped_into_symgen_gives_pinocchios_rnea(name):
    assert rnea_agrees(urdf_coverage.example_urdfs()[name], seed=1) <= TOL


@needs_examples
def test_talos_branched_with_its_grippers_locked_gives_pinocchios_rnea():
    assert rnea_agrees(urdf_coverage.example_urdfs()[TALOS], seed=2, lock={j: 0 for j in TALOS_LOCK}) <= TOL


@needs_examples
@pytest.mark.slow
def test_every_loaded_example_urdf_gives_pinocchios_rnea():
    worst = {}
    for name, path in urdf_coverage.example_urdfs().items():
        if urdf_coverage.try_load(name, path).loaded:
            worst[name] = rnea_agrees(path, seed=3)
    assert len(worst) == 59 and max(worst.values()) <= TOL, {k: v for k, v in worst.items() if v > TOL}


@needs_examples
def test_continuous_joints_map_to_cos_sin_and_back():
    path = urdf_coverage.example_urdfs()[FAST[1]]
    pmodel = pin.buildModelFromUrdf(path)
    cmap = CoordinateMap.pinocchio(_scene(path), pmodel)
    config, _ = cmap.to_symgen([np.cos(2.5), np.sin(2.5), np.cos(-0.5), np.sin(-0.5)])
    assert list(config.positions.values()) == pytest.approx([2.5, -0.5], abs=1e-15)
    q, v = cmap.from_symgen(config)
    assert q == pytest.approx([np.cos(2.5), np.sin(2.5), np.cos(-0.5), np.sin(-0.5)], abs=1e-15) and v.size == 2


def test_ball_joints_take_x_y_z_w_in_pinocchio_and_w_x_y_z_in_mujoco():
    mujoco = pytest.importorskip("mujoco")
    from symgen.io.mjcf import scene_from_mjcf

    path = str(ROOT / "tests" / "data" / "mjcf" / "ball_arm.xml")
    scene = scene_from_mjcf(path, motion=dict(frames={"grip": 1}, components=["vx", "vy", "wx", "wz"]))
    to_pin = CoordinateMap.pinocchio(scene, pin.buildModelFromMJCF(path))
    to_mj = CoordinateMap.mujoco(scene, mujoco.MjModel.from_xml_path(path))
    w, x, y, z = np.array([0.8, 0.2, -0.4, 0.4]) / np.linalg.norm([0.8, 0.2, -0.4, 0.4])
    qpos = np.array(to_mj.neutral)
    ball = next(s for s in to_mj.slots if s.form == "quat_wxyz")
    qpos[ball.q:ball.q + 4] = w, x, y, z
    config, _ = to_mj.to_symgen(qpos)
    expected = pin.Quaternion(w, x, y, z).toRotationMatrix()      # Pinocchio's constructor takes w first
    assert np.allclose(config.positions[ball.joint], expected, atol=1e-15)
    assert to_mj.rate_names() == to_pin.rate_names() == derive(scene).all_coordinate_names()
    q_pin, _ = to_pin.from_symgen(config)
    pin_ball = next(s for s in to_pin.slots if s.joint == ball.joint)
    assert q_pin[pin_ball.q:pin_ball.q + 4] == pytest.approx([x, y, z, w], abs=1e-15)


def test_a_free_flyer_is_refused_by_name():
    model = pin.Model()
    model.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), "base")
    from symgen.scene.declaration import Scene

    with pytest.raises(CoordinateError, match="Pinocchio joint 'base'"):
        CoordinateMap.pinocchio(Scene(name="s"), model)


@needs_examples
def test_a_scene_joint_missing_from_the_other_model_is_named():
    path = urdf_coverage.example_urdfs()[FAST[0]]
    pmodel = pin.buildModelFromUrdf(path)
    reduced = pin.buildReducedModel(pmodel, [pmodel.getJointId("wrist_3_joint")], pin.neutral(pmodel))
    with pytest.raises(CoordinateError, match="joint 'wrist_3_joint'.*not in Pinocchio's model"):
        CoordinateMap.pinocchio(_scene(path), reduced)
