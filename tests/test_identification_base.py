"""Base parameters: the count against Pinocchio's joint-torque regressor (UR5, Panda), and the
base sets of a one-link arm and a planar 2R arm derived by hand, independently of the code."""
import numpy as np
import pytest

import symgen
from symgen.control.parameters import BODY_QUANTITIES
from symgen.identification.base import base_from_regressor, base_parameters
from symgen.identification.regressor import make_problem, stacked_regressor
from symgen.identification.states import random_states
from symgen.io.scene_yaml import load_scene

STATES = 40


def _row_space_equal(k_a, k_b) -> bool:
    ra, rb = np.linalg.matrix_rank(k_a), np.linalg.matrix_rank(k_b)
    return ra == rb == np.linalg.matrix_rank(np.vstack([k_a, k_b]))


def _functional(names, terms) -> np.ndarray:
    row = np.zeros(len(names))
    for coeff, name in terms:
        row[names.index(name)] = coeff
    return row


def test_one_link_about_the_vertical_keeps_izz_plus_rotor_and_friction():
    """chain:n=1: one revolute joint about the vertical z axis. By hand, tau = (Izz + I*) qdd +
    b qd + c sign(qd) -- gravity acts along the axis, so m and h never enter; Ixx, Iyy and the
    products only load the bearing. Base set {Izz + I*, b, c}; the other nine vanish."""
    model = symgen.derive(symgen.load("chain:n=1"))
    problem = make_problem(model)
    base = base_parameters(problem, count=15)
    names = list(problem.params.names)
    hand = np.array([_functional(names, [(1, "Izz_link0"), (1, "Ir_j0")]), _functional(names, [(1, "b_j0")]),
                     _functional(names, [(1, "c_j0")])])
    assert base.rank == 3
    assert _row_space_equal(base.matrix(), hand)
    assert set(base.classification()["vanishing"]) == {f"{q}_link0" for q in BODY_QUANTITIES if q != "Izz"}


PLANAR_2R = """
name: planar_2r
gravity: [0, -9.81, 0]
bodies:
  link1: {mass: 2, com: [0.2, 0.01, 0], inertia: [0.01, 0.05, 0.05]}
  link2: {mass: 1, com: [0.15, -0.02, 0.01], inertia: [0.005, 0.02, 0.02]}
joints:
  j1: {type: revolute, parent: world, child: link1, xyz: [0, 0, 0], axis: z, actuated: true,
       rotor_inertia: 0.01, friction: {viscous: 0.1, coulomb: 0.2}}
  j2: {type: revolute, parent: link1, child: link2, xyz: [0.5, 0, 0], axis: z, actuated: true,
       rotor_inertia: 0.01, friction: {viscous: 0.1, coulomb: 0.2}}
motion: {joints: [j1, j2]}
"""


def test_planar_2r_base_set_is_the_classical_one():
    """A planar 2R arm in a vertical plane (L1 = 0.5). By hand (Lagrange), with h = m r and Izz about
    each joint axis: the kinetic energy holds (Izz1 + m2 L1^2 + I*1) qd1^2/2, Izz2 (qd1 + qd2)^2/2,
    I*2 qd2^2/2 and L1 qd1 (qd1 + qd2)(hx2 cos q2 - hy2 sin q2); the potential energy g (hx1 + m2 L1) sin q1
    + g hy1 cos q1 + g (hx2 sin(q1+q2) + hy2 cos(q1+q2)). So the 11 base parameters are
    Izz1 + L1^2 m2 + I*1, hx1 + L1 m2, hy1, Izz2, hx2, hy2, I*2, b1, c1, b2, c2; m1, hz, Ixx, Iyy and
    the products of both links vanish (they act out of the plane, on the bearings)."""
    model = symgen.derive(load_scene(PLANAR_2R))
    problem = make_problem(model)
    base = base_parameters(problem, count=20)
    names = list(problem.params.names)
    length = 0.5
    terms = [[(1, "Izz_link1"), (length ** 2, "m_link2"), (1, "Ir_j1")], [(1, "hx_link1"), (length, "m_link2")],
             [(1, "hy_link1")], [(1, "Izz_link2")], [(1, "hx_link2")], [(1, "hy_link2")], [(1, "Ir_j2")],
             [(1, "b_j1")], [(1, "c_j1")], [(1, "b_j2")], [(1, "c_j2")]]
    hand = np.array([_functional(names, t) for t in terms])
    assert base.rank == 11
    assert _row_space_equal(base.matrix(), hand)
    vanish = {f"{q}_link{i}" for i in (1, 2) for q in ("hz", "Ixx", "Iyy", "Ixy", "Ixz", "Iyz")} | {"m_link1"}
    assert set(base.classification()["vanishing"]) == vanish


def test_regrouping_reproduces_the_regressor_columns():
    """W P = W_b P_b for any P: the dropped columns are the stated combinations of the kept ones."""
    model = symgen.derive(symgen.load("chain:n=3"))
    problem = make_problem(model)
    w = stacked_regressor(problem, random_states(model, 15, seed=3))
    base = base_from_regressor(w, problem.params.names)
    p = np.random.default_rng(0).normal(size=w.shape[1])
    assert np.allclose(w @ p, w[:, list(base.independent)] @ base.values(p), rtol=0, atol=1e-10 * np.abs(w @ p).max())


# ------------------------------------------------------------------ Pinocchio
pin_available = True
try:
    import pinocchio  # noqa: F401
    import yourdfpy  # noqa: F401
except ImportError:  # pragma: no cover
    pin_available = False


@pytest.mark.skipif(not pin_available, reason="pin (Pinocchio) and yourdfpy are needed")
@pytest.mark.parametrize("spec", ["ur5", "panda"])
def test_base_count_equals_the_rank_of_pinocchios_regressor(spec):
    """Pinocchio's joint-torque regressor (10 body parameters per joint, no rotor inertia or
    friction), stacked over random states: its rank is the number of body base parameters; with
    the columns qdd_j, qd_j, sign(qd_j) of each joint appended (I*, b, c of eq. 22, built here by
    hand) its rank is symgen's full base count."""
    from symgen.oracle.pinocchio_check import open_chain_states
    from symgen.oracle.pinocchio_model import pinocchio_robot

    model = symgen.derive(symgen.load(spec))
    robot = pinocchio_robot(model.scene)
    pin, pmodel = robot.pin, robot.model
    names = model.coordinate_names()
    idx = robot.v_index(names)
    blocks = []
    for state in open_chain_states(model, STATES, seed=5):
        v, a = np.zeros(pmodel.nv), np.zeros(pmodel.nv)
        v[idx], a[idx] = state["qd"], state["qdd"]
        y = pin.computeJointTorqueRegressor(pmodel, pmodel.createData(), robot.q_vector(state["config"]), v, a)[idx]
        joint_cols = np.hstack([np.diag(state["qdd"]), np.diag(state["qd"]), np.diag(np.sign(state["qd"]))])
        blocks.append(np.hstack([y, joint_cols]))
    stacked = np.vstack(blocks)
    pin_bodies = np.linalg.matrix_rank(stacked[:, :-3 * len(names)])
    pin_all = np.linalg.matrix_rank(stacked)

    problem = make_problem(model)
    w = stacked_regressor(problem, random_states(model, STATES, seed=5))
    body_cols = [k for k, p in enumerate(problem.params.parameters) if p.quantity in BODY_QUANTITIES]
    base_all = base_from_regressor(w, problem.params.names)
    base_bodies = base_from_regressor(w[:, body_cols], [problem.params.names[k] for k in body_cols])
    assert (base_bodies.rank, base_all.rank) == (pin_bodies, pin_all)
