"""The sign of the loop forces against Pinocchio's ``constraintDynamics`` (the docs' "Coming from
Pinocchio" table): Pinocchio solves ``M a = tau - h + J_c^T lambda_c`` (multipliers on the right),
symgen's loop forces solve ``M qdd + h = tau + T^T lam`` (eq. 6 rows, on the right too), so
``data.lambda_c`` must equal ``Model.loop_forces`` with the same sign.

The four-bar is the MJCF one (``tests/data/mjcf/four_bar.xml``), closed by a ``connect`` at the
rocker's ground pivot; symgen drops the row normal to the plane (it vanishes), Pinocchio keeps a
``CONTACT_3D`` whose third multiplier must then be zero. The vanishing row makes the exact KKT
(``mu = 0``) singular, so the proximal solver runs with a small ``mu``: it converges to the exact
multipliers on the rows that constrain anything.
"""
import numpy as np
import pytest

pin = pytest.importorskip("pinocchio", reason="pin (Pinocchio) is not installed (extra 'oracle')")

from symgen.oracle.pinocchio_check import constrained_states  # noqa: E402
from .pinocchio_contact import four_bar_contact  # noqa: E402

PROXIMAL_MU = 1e-9          # regularisation of the proximal solver (the vanishing row needs one)
TOL = 1e-9                  # relative, as the other Pinocchio comparisons (TOL_CONSTRAINED)


@pytest.fixture(scope="module")
def four_bar():
    model, robot, solver = four_bar_contact(pin, pin.ReferenceFrame.LOCAL)
    con = model.scene.constraints["closure"]
    assert con.components == ("vx", "vy") and model.constraint_force_names() == ["closure.fx", "closure.fy"]
    return model, robot, solver


def _solve(model, robot, solver, state):
    data, models, datas = solver
    d = model.evaluate(state["config"], V_m=state["V_m"])
    q = robot.q_vector(state["config"])
    v = robot.v_vector(np.asarray(d.maps.P.v @ d.qd, float))
    tau = np.zeros(robot.model.nv)
    tau[robot.v_index(model.coordinate_names())] = state["tau"]
    ddq = pin.constraintDynamics(robot.model, data, q, v, tau, models, datas,
                                 pin.ProximalSettings(1e-14, PROXIMAL_MU, 100))
    return np.array(ddq), np.array(data.lambda_c)


def test_lambda_c_equals_loop_forces_with_the_same_sign(four_bar):
    model, robot, solver = four_bar
    for state in constrained_states(model, 5, seed=11):
        ddq, lambda_c = _solve(model, robot, solver, state)
        lam = np.asarray(model.loop_forces(state["config"], state["V_m"], state["tau"]), float)
        assert np.max(np.abs(lam)) > 0.1                        # a state that loads the loop
        assert np.allclose(lambda_c[:2], lam, rtol=TOL, atol=TOL * np.max(np.abs(lam)))
        assert not np.allclose(lambda_c[:2], -lam, rtol=0.1)    # the opposite sign is not it
        assert abs(lambda_c[2]) <= TOL * np.max(np.abs(lam))   # the row normal to the plane carries nothing
        qdd_all = np.asarray(model.joint_accelerations(state["config"], state["V_m"], state["tau"]), float)
        assert np.allclose(ddq[robot.v_of_coord], qdd_all, rtol=TOL, atol=TOL * np.max(np.abs(qdd_all)))
