"""symgen's dynamics of any scene against Pinocchio's, on the tree of :mod:`symgen.oracle.pinocchio_tree`.

**The spanning tree** (every joint coordinate free, constraints ignored). At random
configurations (angles uniform in ``[-pi, pi]``, rotations ``exp`` of a random vector), random
``qd_all`` and ``qdd_all``:

* symgen's tree forces ``tau_tree = T_S,all^T (M_S dX + C_S X + G_S)``
  (:func:`symgen.steps.loop_forces.tree_forces`, eqs. 24-25 and 30 with ``P = 1``) equal
  Pinocchio's ``rnea`` (rotor inertias as ``armature``) plus the friction ``xi`` of eqs. (22)-(23);
* symgen's tree mass matrix ``T_S,all^T M_S T_S,all`` equals ``crba``.

**Constrained forward dynamics.** At loop-closed states (:func:`symgen.closure.random_consistent_states`)
with random ``tau`` (and ``eta_m``), ``model.forward_dynamics`` -- ``dV_m`` and ``eta_f`` of model
(32) -- must equal

* the KKT solve of :func:`symgen.oracle.pinocchio_check.kkt_reference` (``crba``,
  ``nonLinearEffects``, ``getFrameJacobian`` with the constraint's components), for every scene;
* Pinocchio's ``constraintDynamics`` (after ``initConstraintDynamics``) when every constraint is a
  weld or a ball (:func:`~symgen.oracle.pinocchio_tree.maps_to_pinocchio`). Its multipliers
  ``lambda_c`` are the wrench on frame A's body, so ``eta_f = -lambda_c``; ``dV_m`` follows from
  ``ddq`` by ``forwardKinematics`` and ``getFrameAcceleration`` (LOCAL: the derivative of the
  body-frame twist, symgen's ``d/dt X``).
"""
from __future__ import annotations

import numpy as np

from ..closure import random_positions
from ..kinematics import tree_kinematics
from ..math.spatial import COMPONENTS
from ..steps.loop_forces import tree_forces, tree_velocity_map
from ..steps.subsystem_space import subsystem_terms
from .pinocchio_check import (TOL_CONSTRAINED, TOL_JOINT_SPACE, Difference, compare_constrained, constrained_states,
                              relative)
from .pinocchio_tree import TreeRobot, constraint_models, maps_to_pinocchio, tree_robot


# ----------------------------------------------------------------------------- the tree
def random_tree_states(model, count: int, seed: int = 0) -> list[dict]:
    """Random ``config, qd_all, qdd_all`` of the spanning tree (no loop closed)."""
    rng = np.random.default_rng(seed)
    n = model.tree.n_coords
    return [dict(config=random_positions(model, rng), qd=rng.uniform(-1, 1, n), qdd=rng.uniform(-1, 1, n))
            for _ in range(count)]


def symgen_tree_dynamics(model, config, qd_all, qdd_all) -> dict:
    """symgen's tree forces and tree mass matrix (eqs. 24-25, 30 with ``P = 1``), all coordinates."""
    fld = model.float_field
    tau = tree_forces(fld, tree_kinematics(model.tree, fld, config, qd_all), qd_all, qdd_all)
    kin = tree_kinematics(model.tree, fld, config)
    vmap = tree_velocity_map(fld, kin)
    terms = subsystem_terms(fld, kin, vmap.space, fld.zeros((vmap.T_S.v.shape[0],)), gravity=False)
    return dict(tau=np.asarray(tau, float), M=np.asarray(vmap.T_S.v.T @ terms.M_S @ vmap.T_S.v, float))


def pinocchio_tree_dynamics(robot: TreeRobot, config, qd_all, qdd_all) -> dict:
    """``rnea`` plus friction and joint springs, and ``crba``, mapped to symgen's coordinate order."""
    pin = robot.pin
    data = robot.model.createData()
    q, v, a = robot.q_vector(config), robot.v_vector(qd_all), robot.v_vector(qdd_all)
    tau = robot.to_coordinates(pin.rnea(robot.model, data, q, v, a) + robot.friction(v) + robot.spring_forces(q))
    mass = pin.crba(robot.model, data, q)
    mass = np.triu(mass) + np.triu(mass, 1).T
    return dict(tau=tau, M=mass[np.ix_(robot.v_of_coord, robot.v_of_coord)])


def compare_tree(model, robot: TreeRobot, states) -> list[Difference]:
    """Worst differences of the tree's inverse dynamics and mass matrix over ``states``."""
    worst = {"tau": 0.0, "M": 0.0}
    for s in states:
        got = symgen_tree_dynamics(model, s["config"], s["qd"], s["qdd"])
        ref = pinocchio_tree_dynamics(robot, s["config"], s["qd"], s["qdd"])
        for key in worst:
            worst[key] = max(worst[key], relative(got[key], ref[key]))
    return [Difference("tree inverse dynamics tau_tree", worst["tau"], TOL_JOINT_SPACE, len(states),
                       "rnea + friction + springs"),
            Difference("tree mass matrix", worst["M"], TOL_JOINT_SPACE, len(states), "crba")]


# ----------------------------------------------------------------------------- constraintDynamics
class ConstraintDynamics:
    """Pinocchio's ``constraintDynamics`` on a robot's weld/ball constraints, initialised once."""

    def __init__(self, robot: TreeRobot):
        pin = robot.pin
        self.robot, self.pin = robot, pin
        self.models = pin.StdVec_RigidConstraintModel()
        self.datas = pin.StdVec_RigidConstraintData()
        for cm in constraint_models(robot):
            self.models.append(cm)
            self.datas.append(cm.createData())
        self.data = robot.model.createData()
        pin.initConstraintDynamics(robot.model, self.data, self.models, self.datas)
        self.settings = pin.ProximalSettings(1e-14, 0.0, 1)     # mu = 0: the exact KKT solve

    def __call__(self, q, v, tau) -> tuple[np.ndarray, np.ndarray]:
        """``(ddq, lambda_c)`` in Pinocchio's coordinates."""
        ddq = self.pin.constraintDynamics(self.robot.model, self.data, q, v, tau, self.models, self.datas,
                                          self.settings)
        return np.array(ddq), np.array(self.data.lambda_c)


def motion_rates(robot: TreeRobot, q, v, ddq) -> np.ndarray:
    """``dV_m`` of the scene's motion coordinates from Pinocchio's ``ddq``: joint accelerations, or
    the weighted LOCAL frame accelerations' components (eq. 17), or both (frames first)."""
    pin, model, scene = robot.pin, robot.model, robot.scene
    motion = scene.motion
    joint_part = ddq[robot.v_index(motion.joints)] if motion.joints else np.zeros(0)
    if not motion.frames:
        return joint_part
    data = model.createData()
    pin.forwardKinematics(model, data, q, v, ddq)
    sel = [COMPONENTS.index(c) for c in motion.components]
    frame_part = sum(scene.value_of(g) * pin.getFrameAcceleration(model, data, robot.frames[f],
                                                                  pin.ReferenceFrame.LOCAL).vector[sel]
                     for f, g in motion.frames)
    return np.concatenate([frame_part, joint_part])


def compare_constraint_dynamics(model, robot: TreeRobot, states) -> list[Difference]:
    """Worst differences of ``dV_m`` and ``eta_f`` against ``constraintDynamics`` (see module docstring)."""
    solve = ConstraintDynamics(robot)
    tau_idx = robot.v_index(model.coordinate_names())
    worst = {"dV_m": 0.0, "eta_f": 0.0}
    for s in states:
        d = model.evaluate(s["config"], V_m=s["V_m"])
        q, v = robot.q_vector(s["config"]), robot.v_vector(np.asarray(d.maps.P.v @ d.qd, float))
        u = np.zeros(robot.model.nv)
        u[tau_idx] = s["tau"]
        ddq, lam = solve(q, v, u)
        dv, eta_f = model.forward_dynamics(s["config"], s["V_m"], s["tau"])
        worst["dV_m"] = max(worst["dV_m"], relative(dv, motion_rates(robot, q, v, ddq)))
        if model.counts.np == 0:
            worst["eta_f"] = max(worst["eta_f"], relative(eta_f, -lam))
    against = "constraintDynamics (" + ", ".join(str(m.type).split(".")[-1] for m in solve.models) + ")"
    out = [Difference("motion rates dV_m (32)", worst["dV_m"], TOL_CONSTRAINED, len(states), against)]
    if model.counts.np == 0:
        out.append(Difference("constraint forces eta_f (32)", worst["eta_f"], TOL_CONSTRAINED, len(states), against))
    return out


def check_scene(model, states: int = 10, seed: int = 0) -> list[Difference]:
    """Every comparison of this module that applies to ``model`` (any derived scene)."""
    robot = tree_robot(model)
    out = compare_tree(model, robot, random_tree_states(model, states, seed))
    if model.scene.constraints:
        sample = constrained_states(model, states, seed)
        out += compare_constrained(model, robot, sample)
        if maps_to_pinocchio(model.scene):
            native = tree_robot(model, drop_massless_spherical_leaves=True)
            out += compare_constraint_dynamics(model, native, sample)
    return out
