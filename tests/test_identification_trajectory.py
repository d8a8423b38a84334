"""Exciting trajectories: the optimised condition number is below the random start's, the ranges
hold, and on a closed chain the states are loop-closed with consistent rates."""
import numpy as np
import pytest

import symgen
from symgen.closure import closure_residual
from symgen.identification.base import base_parameters
from symgen.identification.regressor import make_problem
from symgen.identification.states import close_configuration
from symgen.identification.trajectory import (coordinate_ranges, optimise_trajectory, random_trajectory,
                                              trajectory_states)


@pytest.mark.parametrize("spec", ["chain:n=2", "five_bar"])
def test_optimised_condition_number_is_below_the_random_trajectorys(spec):
    model = symgen.derive(symgen.load(spec))
    problem = make_problem(model)
    base = base_parameters(problem, count=30)
    # an evaluation budget, not a time budget: the result must not depend on the machine's load
    ex = optimise_trajectory(problem, base, harmonics=3, samples=12, max_evals=15, budget=float("inf"), seed=1)
    assert ex.cond_optimised < ex.cond_random
    assert ex.evaluations <= 15


def test_ranges_and_velocity_limits_hold_between_the_samples():
    """UR5: URDF position and velocity limits; checked on a grid 5x finer than the one fitted."""
    model = symgen.derive(symgen.load("ur5"))
    traj = random_trajectory(model, seed=3, frequency=0.3)
    lo, hi, vel = coordinate_ranges(model)
    q, qd, _ = traj.evaluate(traj.times(2000))
    assert np.all(q >= lo) and np.all(q <= hi)
    assert np.all(np.abs(qd) <= vel)
    assert np.isclose(np.max(np.abs(qd) / vel), 0.98, atol=0.01) or np.isclose(
        np.max(np.abs(q - traj.center) / ((hi - lo) / 2)), 0.98, atol=0.01)   # the scale is active


def test_closed_chain_states_close_the_loops_and_move_consistently():
    """five_bar: each state closes the loop; the dependent joints' rates from the model
    (``joint_rates``) match a central difference of their closed positions."""
    model = symgen.derive(symgen.load("five_bar"))
    traj = random_trajectory(model, seed=2, frequency=0.2)
    n, dt = 30, 1e-5
    states = [s for s, _ in trajectory_states(model, traj, n)]
    for s in states:
        assert np.max(np.abs(closure_residual(model, s.config))) < 1e-11
    t = traj.times(n)
    joints = [c.joint for c in model.tree.coordinates]
    for k in (3, 17):
        pos = []
        for dt_k in (-dt, dt):
            q, _, _ = traj.evaluate([t[k] + dt_k])
            config = close_configuration(model, dict(zip(("j1", "j2"), q[0])), states[k].config)
            pos.append(np.array([config.positions[j] for j in joints]))
        fd = (pos[1] - pos[0]) / (2 * dt)
        data = model.evaluate(states[k].config, qd=states[k].qd)
        rates = model.joint_rates(states[k].config, data.V_m)
        assert np.allclose(rates, fd, atol=1e-6 * max(1.0, np.max(np.abs(fd))))
