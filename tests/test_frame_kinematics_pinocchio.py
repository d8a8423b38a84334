"""The Model's frame kinematics, centre of mass and centroidal momentum (symgen.frame_kinematics)
equal Pinocchio's own algorithms -- framesForwardKinematics, computeFrameJacobian (LOCAL and
LOCAL_WORLD_ALIGNED), getFrameClassicalAcceleration at ddq = 0, centerOfMass,
jacobianCenterOfMass, computeCentroidalMomentum -- at random states mapped through
symgen.io.coordinates.CoordinateMap, on the UR5 and the Panda (example-robot-data URDFs read by
Pinocchio's own parser) and on the benchmark chain with a frame added (Pinocchio's twin of its tree)."""
from __future__ import annotations

import warnings

import numpy as np
import pytest

import symgen
from symgen.io.coordinates import CoordinateMap

pin = pytest.importorskip("pinocchio", reason="pinocchio is not installed (extra 'oracle')")
pytest.importorskip("yourdfpy", reason="yourdfpy is not installed (extra 'urdf')")

from .urdf_util import needs_examples  # noqa: E402

#: agreement with Pinocchio, absolute (every quantity is O(1) on these robots)
TOL = 1e-10
STATES = 3
AXES = {"local": pin.LOCAL, "world_aligned": pin.LOCAL_WORLD_ALIGNED}


def _urdf(name: str):
    from symgen.io.urdf.examples import example_path

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        scene = symgen.load(name)
        pmodel = pin.buildModelFromUrdf(str(example_path(name)))
    return scene, pmodel


def _chain():
    from symgen.oracle.pinocchio_tree import tree_robot

    scene = symgen.load("chain:n=6")
    scene.add_frame("tip", "link5", xyz=(0.1, 0.02, -0.03), rpy=(0.3, -0.2, 0.5))
    return scene, tree_robot(symgen.derive(scene)).model


def _ball_chain():
    """The chain with a spherical wrist and a prismatic finger after it (quaternion positions,
    angular-velocity rates in the child frame, a sliding joint)."""
    from symgen.oracle.pinocchio_tree import tree_robot

    scene = symgen.load("chain:n=3")
    scene.add_body("wrist", 0.7, com=(0.01, 0.02, 0.03), inertia=[0.004, 0.005, 0.006])
    scene.add_joint("ball", "spherical", "link2", "wrist", xyz=(0.1, 0, 0), rpy=(0.1, 0.2, 0.3), actuated=True)
    scene.add_body("finger", 0.3, com=(0.0, 0.01, 0.02), inertia=[0.001, 0.002, 0.003])
    scene.add_joint("slide", "prismatic", "wrist", "finger", xyz=(0.05, 0, 0), axis="x", actuated=True)
    scene.add_frame("tip", "finger", xyz=(0.03, -0.01, 0.02), rpy=(-0.4, 0.1, 0.2))
    scene.set_motion(joints=list(scene.joints))
    return scene, tree_robot(symgen.derive(scene)).model


#: robot -> (scene and Pinocchio model, the scene's frame, Pinocchio's name of it)
ROBOTS = {"ur5": (lambda: _urdf("ur5"), "tool0", "tool0"),
          "panda": (lambda: _urdf("panda"), "panda_hand_tcp", "panda_hand_tcp"),
          "chain": (_chain, "tip", "symgen/tip"), "ball_chain": (_ball_chain, "tip", "symgen/tip")}


def _states(scene, pmodel, seed):
    """``(model, cmap, [(q, v, config, qd)])``: random Pinocchio states, locked joints at rest."""
    model = symgen.derive(scene)
    cmap = CoordinateMap.pinocchio(scene, pmodel)
    idx = cmap.velocity_indices(model.coordinate_names())
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(STATES):
        q = rng.uniform(-np.pi, np.pi, pmodel.nq)
        for joint in pmodel.joints[1:]:
            if joint.nq == 2:                           # a continuous joint: cos, sin
                q[joint.idx_q:joint.idx_q + 2] = [np.cos(q[joint.idx_q]), np.sin(q[joint.idx_q])]
            elif joint.nq == 4:                         # a ball joint: a unit quaternion
                q[joint.idx_q:joint.idx_q + 4] /= np.linalg.norm(q[joint.idx_q:joint.idx_q + 4])
        config, _ = cmap.to_symgen(q)
        q, _ = cmap.from_symgen(config)                 # locked joints at their locked value
        v = np.zeros(pmodel.nv)
        v[idx] = rng.uniform(-1, 1, idx.size)
        config, rates = cmap.to_symgen(q, v)
        out.append((q, v, config, np.array([rates[n] for n in model.coordinate_names()])))
    return model, idx, out


@needs_examples
@pytest.mark.parametrize("robot", sorted(ROBOTS))
def test_frame_pose_jacobian_and_drift_equal_pinocchios(robot):
    make, frame, pin_frame = ROBOTS[robot]
    scene, pmodel = make()
    data = pmodel.createData()
    fid = pmodel.getFrameId(pin_frame)
    model, idx, states = _states(scene, pmodel, seed=3)
    for q, v, config, qd in states:
        pin.forwardKinematics(pmodel, data, q, v, np.zeros(pmodel.nv))
        pin.updateFramePlacements(pmodel, data)
        r, p = model.frame_pose(config, frame)
        assert np.max(np.abs(r - data.oMf[fid].rotation)) < TOL
        assert np.max(np.abs(p - data.oMf[fid].translation)) < TOL
        for axes, ref in AXES.items():
            jac = pin.computeFrameJacobian(pmodel, data, q, fid, ref)[:, idx]
            assert np.max(np.abs(model.frame_jacobian(config, frame, axes=axes) - jac)) < TOL
            pin.forwardKinematics(pmodel, data, q, v, np.zeros(pmodel.nv))
            drift = pin.getFrameClassicalAcceleration(pmodel, data, fid, ref).vector
            assert np.max(np.abs(model.frame_drift(config, qd, frame, axes=axes) - drift)) < TOL


@needs_examples
@pytest.mark.parametrize("robot", sorted(ROBOTS))
def test_center_of_mass_its_jacobian_and_the_centroidal_momentum_equal_pinocchios(robot):
    make, _, _ = ROBOTS[robot]
    scene, pmodel = make()
    data = pmodel.createData()
    model, idx, states = _states(scene, pmodel, seed=4)
    for q, v, config, qd in states:
        com = pin.centerOfMass(pmodel, data, q)
        assert np.max(np.abs(model.center_of_mass(config) - com)) < TOL
        jac = pin.jacobianCenterOfMass(pmodel, data, q)[:, idx]
        assert np.max(np.abs(model.com_jacobian(config) - jac)) < TOL
        h = pin.computeCentroidalMomentum(pmodel, data, q, v).vector
        assert np.max(np.abs(model.centroidal_momentum(config, qd) - h)) < TOL


@needs_examples
def test_a_drift_without_the_jacobians_rate_is_caught(monkeypatch):
    """Planted error: the drift without its ``dJ/dt qd_all`` term (only ``J dP/dt qd`` left) is far
    from Pinocchio's, so the comparison above can fail."""
    import symgen.frame_kinematics as fk

    make, frame, pin_frame = ROBOTS["ur5"]
    scene, pmodel = make()
    data = pmodel.createData()
    model, idx, states = _states(scene, pmodel, seed=3)
    q, v, config, qd = states[0]
    pin.forwardKinematics(pmodel, data, q, v, np.zeros(pmodel.nv))
    drift = pin.getFrameClassicalAcceleration(pmodel, data, pmodel.getFrameId(pin_frame), pin.LOCAL).vector
    assert np.max(np.abs(model.frame_drift(config, qd, frame) - drift)) < TOL
    monkeypatch.setattr(fk, "acceleration_bias", lambda rows, qd_all, bias: rows.v @ np.asarray(bias))
    assert np.max(np.abs(model.frame_drift(config, qd, frame) - drift)) > 1e-3


@needs_examples
@pytest.mark.parametrize("robot", ["ur5", "panda", "chain"])
def test_the_generated_momentum_derivatives_equal_pinocchios_centroidal_map_and_dh_dq(robot):
    """``A_G = dh/dqd`` against ``computeCentroidalMap``, ``dh_dq`` against the ``dh_dq`` of
    ``computeCentroidalDynamicsDerivatives`` (fixed bases: the tangent space is the joint space)."""
    from symgen.codegen.generate import trace_all
    from symgen.codegen.runtime import load_generated
    from symgen.codegen.trace import position_vector

    make, _, _ = ROBOTS[robot]
    scene, pmodel = make()
    data = pmodel.createData()
    model, idx, states = _states(scene, pmodel, seed=5)
    module = load_generated(model, "numpy", lowered=trace_all(model, ["centroidal_momentum_derivatives"]))
    for q, v, config, qd in states:
        dh_dq, a_g = module.centroidal_momentum_derivatives(position_vector(model, config), qd)
        assert np.max(np.abs(a_g - pin.computeCentroidalMap(pmodel, data, q)[:, idx])) < TOL
        want = pin.computeCentroidalDynamicsDerivatives(pmodel, data, q, v, np.zeros(pmodel.nv))[0]
        assert np.max(np.abs(dh_dq - want[:, idx])) < TOL
