"""The stacked regressor Y = T_S^T Y_r at X_r = X against Pinocchio's joint-torque regressor on
real open chains (UR5, Panda), after the documented change of parameters:

* Pinocchio's per-joint dynamic parameters are ``[m, m c_x, m c_y, m c_z, Ixx, Ixy, Iyy, Ixz,
  Iyz, Izz]`` about the joint frame's origin, in the joint frame (the URDF child link's frame);
* symgen's are ``[m, h, Ixx, Iyy, Izz, Ixy, Ixz, Iyz]`` about the body frame's origin in the
  body's internal frame ``user frame * A`` (``A`` turns the joint axis onto z, symgen.tree), so
  ``h = A^T h_pin`` and ``I_o = A^T I_pin A``.

For random parameter vectors both regressors must give the same torques."""
import numpy as np
import pytest

import symgen
from symgen.control.law import default_parameters, regressor
from symgen.control.parameters import BODY_QUANTITIES

pytest.importorskip("pinocchio", reason="pin (Pinocchio) is not installed (extra 'oracle')")
pytest.importorskip("yourdfpy", reason="yourdfpy is not installed (extra 'urdf')")

from symgen.oracle.pinocchio_check import open_chain_states  # noqa: E402
from symgen.oracle.pinocchio_model import pinocchio_robot  # noqa: E402

TOL = 1e-10
VECTORS = 10


def _symgen_parameters(tree, joint, p_pin) -> np.ndarray:
    """symgen's ten parameters of ``joint``'s child body from Pinocchio's ten (module docstring)."""
    a = np.array(tree.bodies[joint.child].align.tolist(), dtype=float)
    m, h = p_pin[0], p_pin[1:4]
    ixx, ixy, iyy, ixz, iyz, izz = p_pin[4:]
    inertia = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
    h_int, i_int = a.T @ h, a.T @ inertia @ a
    return np.array([m, *h_int, i_int[0, 0], i_int[1, 1], i_int[2, 2], i_int[0, 1], i_int[0, 2], i_int[1, 2]])


@pytest.mark.parametrize("spec", ["ur5", "panda"])
def test_regressor_gives_pinocchios_torques_for_random_parameters(spec):
    model = symgen.derive(symgen.load(spec))
    robot = pinocchio_robot(model.scene)
    pin, pmodel = robot.pin, robot.model
    params = default_parameters(model)
    rng = np.random.default_rng(7)
    joints = [j for j in model.tree.joints if j.kind.dof]
    for state in open_chain_states(model, 3, seed=11):
        data = model.evaluate(state["config"], qd=state["qd"])
        y, _, _ = regressor(model, data, params, data.V_m, np.asarray(state["qdd"]) if model.scene.motion.joints
                            else None)
        names = [model.tree.coordinates[c].label for c in model.partition.independent]
        idx = robot.v_index(names)
        v, a = np.zeros(pmodel.nv), np.zeros(pmodel.nv)
        v[idx], a[idx] = state["qd"], state["qdd"]
        y_pin = pin.computeJointTorqueRegressor(pmodel, pmodel.createData(), robot.q_vector(state["config"]), v, a)
        for _ in range(VECTORS):
            p_pin = rng.normal(size=y_pin.shape[1])
            p_ours = np.zeros(len(params))
            for joint in joints:
                jid = robot.joints[joint.name]
                cols = [params.index(f"{q}_{model.tree.bodies[joint.child].name}") for q in BODY_QUANTITIES]
                p_ours[cols] = _symgen_parameters(model.tree, joint, p_pin[10 * (jid - 1):10 * jid])
            want = (y_pin @ p_pin)[idx]
            got = y @ p_ours
            assert np.max(np.abs(got - want)) <= TOL * max(1.0, np.max(np.abs(want)))
