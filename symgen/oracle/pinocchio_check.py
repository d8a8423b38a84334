"""symgen's model of a URDF scene against Pinocchio, run on the same files.

**Open chains** (no constraint). At random states ``(q, qd, qdd)``, revolute angles uniform in
``[-pi, pi]``:

* ``M_q qdd + C_q qd + G_q`` equals ``rnea(q, qd, qdd)`` plus the joint friction
  ``b qd + c sign(qd)`` (eq. 22), with ``b, c`` taken from Pinocchio's own parse of
  ``<dynamics damping friction>``. Pinocchio's ``rnea`` leaves friction out.
* ``M_q`` equals ``crba(q)``, whose upper triangle is copied to the lower one.
* ``G_q`` equals ``computeGeneralizedGravity(q)``.

**Closed loops and contact** (constraints from :mod:`symgen.io.urdf.overlay`), at random
loop-closed states with random ``V_m``, ``tau`` and ``eta_m``. The oracle is a Lagrange-multiplier
(KKT) solve built from Pinocchio alone:

    [ M    J_c^T ] [ qdd ]   [ tau - D_m^T eta_m - h(q, qd) ]
    [ J_c  0     ] [ mu  ] = [ -gamma                       ]

Here ``M`` is from ``crba`` and ``h`` from ``nonLinearEffects`` plus friction. Each constraint
between frames A and B contributes the rows ``S (J_A - Ad(A^-1) J_B^world)`` (its components
``S`` of the relative twist, in A's axes, as in :mod:`symgen.closure`), built from
``getFrameJacobian``. The drift is ``gamma = S (a_A - Ad(A^-1) a_B^world + ad(V_A) Ad(A^-1) V_B^world)``,
from ``getFrameAcceleration`` with ``qdd = 0``. ``D_m^T eta_m = (S_m J_F)^T eta_m``
(eq. 16). Then symgen's ``dV_m`` (the joint accelerations or the frame twist rates of eq. 17,
``S_m a_F`` from ``getFrameAcceleration``) and ``eta_f`` of model (32) must equal the KKT's.
For ``constraint_forces: operational`` ``J_f = T``, so ``eta_f = mu``; and the loop-closure forces of
:meth:`symgen.model.Model.loop_forces` (the passive loops' forces too) are ``lam = -mu``.

The differences are reported as the worst relative error over the states: ``max |a - b| / max |b|``.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..closure import random_consistent_states, random_positions
from ..math.spatial import COMPONENTS
from ..io.mjcf.build import mjcf_source
from ..io.sdf.build import sdf_source
from .pinocchio_model import OracleError, PinocchioRobot, pinocchio_robot

#: named tolerances (relative): joint-space quantities, and the constrained KKT solve
TOL_JOINT_SPACE = 1e-10
TOL_CONSTRAINED = 1e-9


@dataclass
class Difference:
    """Worst relative difference of one quantity over the states."""

    quantity: str
    worst: float
    tolerance: float
    states: int
    against: str

    @property
    def passed(self) -> bool:
        return bool(self.worst <= self.tolerance)

    def as_dict(self) -> dict:
        return dict(quantity=self.quantity, worst=self.worst, tolerance=self.tolerance, states=self.states,
                    against=self.against, passed=self.passed)


def relative(a, b) -> float:
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.max(np.abs(a - b)) / max(float(np.max(np.abs(b))), 1e-300)) if b.size else 0.0


# ----------------------------------------------------------------------------- states
def open_chain_states(model, count: int, seed: int = 0) -> list[dict]:
    """Random ``config, qd, qdd`` (angles in [-pi, pi], prismatic within limits or +-0.5 m)."""
    rng = np.random.default_rng(seed)
    n = model.counts.n
    return [dict(config=random_positions(model, rng), qd=rng.uniform(-1, 1, n), qdd=rng.uniform(-1, 1, n))
            for _ in range(count)]


def constrained_states(model, count: int, seed: int = 0) -> list[dict]:
    """Loop-closed states near ``q0`` with random ``V_m``, ``tau`` and ``eta_m``."""
    rng = np.random.default_rng(seed + 1)
    cf = model.scene.contact_forces
    return [dict(config=cfg, V_m=np.asarray(v_m, float), tau=rng.uniform(-1, 1, model.counts.n),
                 eta_m=rng.uniform(-1, 1, len(cf.components)) if cf else np.zeros(0))
            for cfg, v_m in random_consistent_states(model, count, seed=seed)]


# ----------------------------------------------------------------------------- Pinocchio side
def _friction(robot: PinocchioRobot, v) -> np.ndarray:
    return robot.friction(v)


def joint_space_reference(robot: PinocchioRobot, q, v, a) -> dict:
    """``tau`` (rnea + friction + joint springs), ``M`` (crba, symmetrised) and ``G``
    (computeGeneralizedGravity + joint springs) from Pinocchio."""
    pin, model = robot.pin, robot.model
    data = model.createData()
    springs = robot.spring_forces(q)
    tau = pin.rnea(model, data, q, v, a) + _friction(robot, v) + springs
    upper = np.triu(pin.crba(model, data, q))
    return dict(tau=tau, M=upper + np.triu(upper, 1).T,
                G=pin.computeGeneralizedGravity(model, data, q).copy() + springs)


def _constraint_rows(robot: PinocchioRobot, data, con, q, v):
    """``(J_c, gamma, residual)`` of one constraint, from Pinocchio's frames (see module docstring);
    a joint coupling's row is its coefficients at Pinocchio's velocity indices (constant: ``gamma =
    0``) and its residual ``sum_i c_i q_i - offset`` from Pinocchio's ``q``."""
    if con.is_coupling:
        return _coupling_rows(robot, con, q)
    pin, model = robot.pin, robot.model
    sel = [COMPONENTS.index(c) for c in con.components]
    fa = robot.frames[con.frame_a]
    o_m_a = data.oMf[fa]
    a_inv = o_m_a.inverse().toActionMatrix()
    j_a = pin.getFrameJacobian(model, data, fa, pin.ReferenceFrame.LOCAL)
    v_a = pin.getFrameVelocity(model, data, fa, pin.ReferenceFrame.LOCAL)
    acc_a = pin.getFrameAcceleration(model, data, fa, pin.ReferenceFrame.LOCAL).vector
    if con.frame_b == "world":
        j_b, vel_b, acc_b, o_m_b = np.zeros((6, model.nv)), np.zeros(6), np.zeros(6), pin.SE3.Identity()
    else:
        fb = robot.frames[con.frame_b]
        j_b = a_inv @ pin.getFrameJacobian(model, data, fb, pin.ReferenceFrame.WORLD)
        vel_b = a_inv @ pin.getFrameVelocity(model, data, fb, pin.ReferenceFrame.WORLD).vector
        acc_b = a_inv @ pin.getFrameAcceleration(model, data, fb, pin.ReferenceFrame.WORLD).vector
        o_m_b = data.oMf[fb]
    gamma = acc_a - acc_b + v_a.action @ vel_b
    rel = o_m_a.inverse() * o_m_b
    residual = np.concatenate([rel.translation, pin.log3(rel.rotation)])
    return (j_a - j_b)[sel], gamma[sel], residual[sel]


def _coupling_rows(robot: PinocchioRobot, con, q):
    row, value = np.zeros((1, robot.model.nv)), -float(con.offset)
    for joint, coefficient in con.terms:
        c = float(coefficient)
        pin_joint = robot.model.joints[robot.joints[joint]]
        row[0, robot.v_index([joint])[0]] = c
        position = q[pin_joint.idx_q:pin_joint.idx_q + pin_joint.nq]
        value += c * (float(np.arctan2(position[1], position[0])) if pin_joint.nq == 2 else float(position[0]))
    return row, np.zeros(1), np.array([value])


def _frame_rows(robot: PinocchioRobot, data, frame, components):
    pin = robot.pin
    sel = [COMPONENTS.index(c) for c in components]
    fid = robot.frames[frame]
    return (pin.getFrameJacobian(robot.model, data, fid, pin.ReferenceFrame.LOCAL)[sel],
            pin.getFrameAcceleration(robot.model, data, fid, pin.ReferenceFrame.LOCAL).vector[sel])


def kkt_reference(robot: PinocchioRobot, scene, q, v, u, eta_m) -> dict:
    """Constrained ``qdd``, multipliers ``mu``, and the motion rates ``dV_m`` from Pinocchio."""
    pin, model = robot.pin, robot.model
    data = model.createData()
    pin.forwardKinematics(model, data, q, v, np.zeros(model.nv))
    pin.updateFramePlacements(model, data)
    pin.computeJointJacobians(model, data, q)
    rows = [_constraint_rows(robot, data, con, q, v) for con in scene.constraints.values()]
    j_c = np.vstack([r[0] for r in rows])
    gamma = np.concatenate([r[1] for r in rows])
    mass = joint_space_reference(robot, q, v, np.zeros(model.nv))["M"]
    h = pin.nonLinearEffects(model, data, q, v) + _friction(robot, v) + robot.spring_forces(q)
    rhs_u = np.array(u, float)
    if scene.contact_forces is not None:
        j_m, _ = _frame_rows(robot, data, scene.contact_forces.frame, scene.contact_forces.components)
        rhs_u = rhs_u - j_m.T @ eta_m
    k = len(gamma)
    kkt = np.block([[mass, j_c.T], [j_c, np.zeros((k, k))]])
    sol = np.linalg.solve(kkt, np.concatenate([rhs_u - h, -gamma]))
    qdd, mu = sol[:model.nv], sol[model.nv:]
    pin.forwardKinematics(model, data, q, v, qdd)
    motion = scene.motion
    dv_m = qdd[robot.v_index(motion.joints)] if motion.joints else np.zeros(0)
    if motion.frames:          # a mixed V_m: the frames' components first (eq. 17)
        dv_m = np.concatenate([sum(scene.value_of(g) * _frame_rows(robot, data, f, motion.components)[1]
                                   for f, g in motion.frames), dv_m])
    return dict(qdd=qdd, mu=mu, dV_m=dv_m, closure=np.concatenate([r[2] for r in rows]), velocity=j_c @ v, J_c=j_c)


# ----------------------------------------------------------------------------- comparisons
def _symgen_joint_space(model, state) -> dict:
    d = model.evaluate(state["config"], qd=state["qd"])
    g = model.evaluate(state["config"]).G_q
    return dict(tau=d.M_q @ state["qdd"] + d.C_q @ state["qd"] + d.G_q, M=d.M_q, G=g)


def compare_joint_space(model, robot: PinocchioRobot, states, evaluate=None, against="rnea, crba, "
                        "computeGeneralizedGravity") -> list[Difference]:
    """Worst differences of ``tau``, ``M`` and ``G`` (symgen's dense model, or ``evaluate``)."""
    evaluate = evaluate or _symgen_joint_space
    idx = robot.v_index(model.coordinate_names())
    worst = {"tau": 0.0, "M": 0.0, "G": 0.0}
    for s in states:
        q, v, a = robot.q_vector(s["config"]), np.zeros(robot.model.nv), np.zeros(robot.model.nv)
        v[idx], a[idx] = s["qd"], s["qdd"]
        ref = joint_space_reference(robot, q, v, a)
        ref["M"] = ref["M"][np.ix_(idx, idx)]
        ref["tau"], ref["G"] = ref["tau"][idx], ref["G"][idx]
        got = evaluate(model, s)
        for key in worst:
            if key in got:
                worst[key] = max(worst[key], relative(got[key], ref[key]))
    labels = {"tau": "inverse dynamics tau", "M": "mass matrix M_q", "G": "gravity G_q"}
    return [Difference(labels[k], w, TOL_JOINT_SPACE, len(states), against) for k, w in worst.items()]


def _symgen_constrained(model, state) -> dict:
    eta_m = state["eta_m"] if state["eta_m"].size else None
    dv, eta_f = model.forward_dynamics(state["config"], state["V_m"], state["tau"], eta_m)
    return dict(dV_m=dv, eta_f=eta_f, lam=model.loop_forces(state["config"], state["V_m"], state["tau"], eta_m))


def compare_constrained(model, robot: PinocchioRobot, states, evaluate=None,
                        against="KKT solve with Pinocchio's crba, nonLinearEffects and frame Jacobians"
                        ) -> list[Difference]:
    """Worst differences of ``dV_m`` and ``eta_f``; the states must close every loop in Pinocchio."""
    joint_forces = model.scene.constraint_forces != "operational"
    a1 = robot.v_index([model.tree.coordinates[c].label for c in model.partition.a1])
    evaluate = evaluate or _symgen_constrained
    coords = [c.label for c in model.tree.coordinates]
    all_idx, tau_idx = robot.v_index(coords), robot.v_index(model.coordinate_names())
    worst = {"dV_m": 0.0, "eta_f": 0.0, "lam": 0.0}
    closure, has_lam = 0.0, False
    for s in states:
        d = model.evaluate(s["config"], V_m=s["V_m"])
        v, u = np.zeros(robot.model.nv), np.zeros(robot.model.nv)
        v[all_idx] = np.asarray(d.maps.P.v @ d.qd, float)
        u[tau_idx] = s["tau"]
        ref = kkt_reference(robot, model.scene, robot.q_vector(s["config"]), v, u, s["eta_m"])
        closure = max(closure, float(np.max(np.abs(ref["closure"]))), float(np.max(np.abs(ref["velocity"]))))
        got = evaluate(model, s)
        worst["dV_m"] = max(worst["dV_m"], relative(got["dV_m"], ref["dV_m"]))
        # eta_f = -T_c^-T T_a1^T lam (eq. 12 with Pinocchio's mu = -lam): mu itself for T_c = T_a1
        # (operational), T_a1^T mu for T_c = 1 (joint)
        eta_f = ref["J_c"][:, a1].T @ ref["mu"] if joint_forces else ref["mu"]
        if eta_f.size and "eta_f" in got and got["eta_f"].size == eta_f.size:
            worst["eta_f"] = max(worst["eta_f"], relative(got["eta_f"], eta_f))
        has_lam = "lam" in got
        if has_lam:           # Pinocchio's KKT carries J_c^T mu on the left: the loop forces are -mu
            worst["lam"] = max(worst["lam"], relative(got["lam"], -ref["mu"]))
    out = [Difference("loop closure and J_c qd in Pinocchio (absolute)", closure, TOL_CONSTRAINED, len(states),
                      "oMf, getFrameJacobian")]
    labels = {"dV_m": "motion rates dV_m (32)", "eta_f": "constraint forces eta_f (32)",
              "lam": "loop-closure forces lam (Model.loop_forces)"}
    if not has_lam:
        worst.pop("lam")
    return out + [Difference(labels[k], w, TOL_CONSTRAINED, len(states), against) for k, w in worst.items()]


def generated_evaluator(module, model):
    """``evaluate(model, state)`` from a generated module (:func:`symgen.codegen.runtime.load_generated`)."""
    from ..codegen.reference import position_vector
    from ..codegen.runtime import call_by_name

    # M and G of model (32) are over V_m: on an open chain a permutation of the independent
    # coordinates (a floating base's rates come first in V_m, last in qd)
    order = ([] if model.scene.constraints else
             [list(model.scene.motion.joints).index(name) for name in model.coordinate_names()])

    def joint_space(model, s):
        values = dict(s, q=position_vector(model, s["config"]), V_m=np.zeros(model.counts.m), eta_m=np.zeros(0))
        out = {}
        for function, output in (("inverse_dynamics", "tau"), ("mass_matrix", "M"), ("gravity", "G")):
            if hasattr(module, function):
                out[output] = np.asarray(call_by_name(module, function, values)[0])
        if "M" in out:
            out["M"] = out["M"][np.ix_(order, order)]
        if "G" in out:
            out["G"] = out["G"][order]
        return out

    def constrained(model, s):
        res = call_by_name(module, "forward_dynamics", dict(s, q=position_vector(model, s["config"])))
        return dict(dV_m=np.asarray(res[0]), eta_f=np.asarray(res[1]) if len(res) > 1 else np.zeros(0))

    return constrained if model.scene.constraints else joint_space


def check_against_pinocchio(model, states: int = 20, seed: int = 0, targets=()) -> list[Difference]:
    """Every comparison that applies to ``model`` (a derived URDF scene), for the dense model and
    for each generated target in ``targets`` (names from :data:`~symgen.codegen.targets.TARGETS`
    or :class:`~symgen.codegen.targets.Target` objects)."""
    if mjcf_source(model.scene) is not None:       # an MJCF scene: Pinocchio's own MJCF reader
        from .pinocchio_mjcf import pinocchio_robot_mjcf

        robot = pinocchio_robot_mjcf(model.scene)
    elif sdf_source(model.scene) is not None:      # an SDF scene: Pinocchio's pip wheel reads no SDF,
        from .pinocchio_tree import tree_robot     # so its spanning tree is rebuilt joint by joint

        robot = tree_robot(model)
    else:
        robot = pinocchio_robot(model.scene)
    if robot.model.nv != model.tree.n_coords:
        raise OracleError(f"Pinocchio's model has {robot.model.nv} velocity coordinates, the scene "
                          f"{model.tree.n_coords}")
    constrained = bool(model.scene.constraints)
    sample = constrained_states(model, states, seed) if constrained else open_chain_states(model, states, seed)
    compare = compare_constrained if constrained else compare_joint_space
    out = compare(model, robot, sample)
    for name in targets:
        from ..codegen.runtime import load_generated
        from ..codegen.targets import target

        tgt = target(name)
        functions = ["forward_dynamics"] if constrained else ["inverse_dynamics", "mass_matrix", "gravity"]
        module = load_generated(model, tgt, functions)
        for diff in compare(model, robot, sample, evaluate=generated_evaluator(module, model)):
            if not diff.quantity.startswith("loop closure"):
                diff.quantity = f"generated {tgt.name}: {diff.quantity}"
                out.append(diff)
    return out
