"""Section 4's Lyapunov function along the five-bar closed loop, computed from its definition at the
integrated states -- not by the closed loop's or the report's own ``lyapunov``.

``V = 1/2 (V_mr - V_m)^T M (V_mr - V_m) + 1/2 sum_k (P_hat_k - P_k)^2 / rho_k`` with ``M`` the
task-space mass matrix of model (32) (``n = m`` on the five-bar: no constraint force), and
``dV/dt = -e^T K_A e <= 0`` when ``dV_mr`` is the exact derivative of ``V_mr``. The first-order
derivative the frame task used before (``dV_d + Lambda (V_d' - V)``) makes ``V`` rise: the planted
error below shows the check catches it.
"""
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from symgen.control import tasks
from symgen.control.pose_error import desired_twist_in_frame, required_twist
from symgen.simulation.control_demo import DEMOS, setup

#: simulated time (s): the first-order derivative makes V rise within the first second
T_END = 1.5
#: largest rise of V between samples, relative to V(0), that integration error may cause
RISE_TOL = 1e-4


def _lyapunov_along_the_loop(t_end=T_END):
    loop, x0 = setup(DEMOS["five_bar"])
    times = np.linspace(0.0, t_end, 31)
    sol = solve_ivp(loop, (0.0, t_end), loop.initial_state(x0), method="DOP853", t_eval=times, rtol=1e-9,
                    atol=1e-11)
    assert sol.status == 0, sol.message
    model, nq, m = loop.model, loop.layout.nq, model_m(loop)
    values = []
    for t, y in zip(sol.t, sol.y.T):
        q, v_m, p_unc = y[:nq], y[nq:nq + m], y[nq + m:nq + m + len(loop.unc)]
        config = loop.layout.configuration(loop.layout.normalized(q))
        data = model.evaluate(config, V_m=v_m)
        v_mr = loop.task.required(t, config, data)[0]
        err = v_mr - v_m
        kinetic = 0.5 * err @ np.asarray(data.M, float) @ err
        p_err = np.clip(p_unc, loop.lower, loop.upper) - loop.true[loop.unc]
        values.append(kinetic + 0.5 * np.sum(p_err * p_err / loop.rho))
    return np.array(values)


def model_m(loop):
    assert loop.model.counts.n == loop.model.counts.m
    return loop.model.counts.m


def _largest_relative_rise(v):
    return float(np.max(np.diff(v)) / v[0])


@pytest.mark.slow
def test_lyapunov_function_never_rises_on_the_five_bar():
    v = _lyapunov_along_the_loop()
    assert _largest_relative_rise(v) <= RISE_TOL, v
    assert v[-1] < v[0]


@pytest.mark.slow
def test_first_order_required_acceleration_makes_the_lyapunov_function_rise(monkeypatch):
    """The replaced derivative, planted back: V rises far beyond the tolerance."""
    def first_order(r, p, r_d, p_d, v, v_d, dv_d, gain):
        v_dp = desired_twist_in_frame(r, p, r_d, p_d, v_d)
        return required_twist(r, p, r_d, p_d, v_d, gain), dv_d + gain * (v_dp - v)
    monkeypatch.setattr(tasks, "required_twist_rate", first_order)
    v = _lyapunov_along_the_loop()
    assert _largest_relative_rise(v) > 10 * RISE_TOL, v
