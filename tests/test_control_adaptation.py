"""The projected adaptation law of eq. (38)."""
from fractions import Fraction

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from symgen.control.adaptation import (adaptation_step, clip_to_bounds, parameter_error_energy,
                                       parameter_rate, projection)
from symgen.control.errors import ControlInputError
from symgen.control.parameters import Parameter, ParameterSet

SEED = 380


@pytest.mark.parametrize("p_hat, s, expected", [
    (1.0, -2.0, 0),    # at the lower bound, pushed further down: blocked
    (0.5, -2.0, 0),    # below the lower bound (overshoot), pushed down: blocked
    (1.0, 0.0, 0),     # at the lower bound, s = 0: blocked (eq. 38 uses <=)
    (1.0, 2.0, 1),     # at the lower bound, pushed back inside: free
    (3.0, 2.0, 0),     # at the upper bound, pushed up: blocked
    (3.5, 0.0, 0),     # above the upper bound, s = 0: blocked
    (3.0, -2.0, 1),    # at the upper bound, pushed back inside: free
    (2.0, -2.0, 1),    # inside: free either way
    (2.0, 2.0, 1),
])
def test_projection_cases_of_eq38(p_hat, s, expected):
    assert projection(np.array([p_hat]), np.array([s]), np.array([1.0]), np.array([3.0]))[0] == expected


def test_rate_is_rho_kappa_s():
    rate = parameter_rate(np.array([2.0, 3.0]), np.array([4.0, 5.0]), np.array([1.0, 1.0]),
                          np.array([3.0, 3.0]), np.array([0.5, 0.5]))
    assert list(rate) == [2.0, 0.0]


def test_rate_is_exact_with_fractions():
    rate = parameter_rate(np.array([Fraction(1, 3)], dtype=object), np.array([Fraction(-3, 7)], dtype=object),
                          np.array([Fraction(0)], dtype=object), np.array([Fraction(1)], dtype=object),
                          np.array([Fraction(7, 2)], dtype=object))
    assert rate[0] == Fraction(-3, 2)


def test_known_parameters_never_move():
    pset = ParameterSet([Parameter("link", "m", 2.0, 1.0, 3.0, 1.0), Parameter("elbow", "b", 0.1)])
    rate = parameter_rate(pset.values, np.array([1.0, 1.0]), pset.lower, pset.upper, pset.rho)
    assert rate[1] == 0.0 and rate[0] == 1.0


def test_clipping_moves_overshoot_back_and_keeps_inside_values():
    lower, upper = np.array([0.0, 0.0, 0.0]), np.array([1.0, 1.0, 1.0])
    assert list(clip_to_bounds(np.array([-1e-9, 0.25, 1.0 + 1e-9]), lower, upper)) == [0.0, 0.25, 1.0]


def test_clipping_keeps_fractions_exact():
    out = clip_to_bounds(np.array([Fraction(5, 3), Fraction(1, 7)], dtype=object),
                         np.array([Fraction(0)] * 2, dtype=object), np.array([Fraction(1)] * 2, dtype=object))
    assert list(out) == [Fraction(1), Fraction(1, 7)]


def test_estimates_never_leave_their_bounds_with_stepping_and_clipping():
    """Euler steps under a persistent, sign-changing s_k that drives estimates hard into both
    bounds; after every clipped step each estimate is inside [P-, P+]."""
    rng = np.random.default_rng(SEED)
    n = 8
    lower, upper = -rng.random(n), rng.random(n)
    rho = 1.0 + 10 * rng.random(n)
    p_hat = (lower + upper) / 2
    for k in range(2000):
        s = 5 * np.sin(0.01 * k + np.arange(n)) + rng.normal(size=n)
        p_hat = adaptation_step(p_hat, s, lower, upper, rho, 0.01)
        assert np.all(lower <= p_hat) and np.all(p_hat <= upper)
    assert np.any(p_hat == lower) or np.any(p_hat == upper)   # the bounds were reached


def test_estimates_stay_in_bounds_with_an_adaptive_integrator_and_clipping():
    """solve_ivp (RK45) over short windows with clipping between them: every window starts and
    ends inside the bounds, and the estimate driven into its lower bound stays there."""
    lower, upper, rho = np.array([0.0, -1.0]), np.array([1.0, 1.0]), np.array([2.0, 3.0])
    p_hat = np.array([0.5, 0.0])
    for k in range(50):
        def rhs(t, p):
            return parameter_rate(p, np.array([np.cos(t), -1.0]), lower, upper, rho)
        sol = solve_ivp(rhs, (0.1 * k, 0.1 * (k + 1)), p_hat, rtol=1e-8, atol=1e-10)
        p_hat = clip_to_bounds(sol.y[:, -1], lower, upper)
        assert np.all(lower <= p_hat) and np.all(p_hat <= upper)
    assert p_hat[1] == -1.0


def test_lyapunov_term_by_hand():
    """1/2 ((3 - 1)^2 / 2 + (0 - 1)^2 / 4) = 1 + 1/8; the known parameter (rho = 0) is left out."""
    energy = parameter_error_energy(np.array([Fraction(3), Fraction(0), Fraction(9)], dtype=object),
                                    np.array([Fraction(1), Fraction(1), Fraction(1)], dtype=object),
                                    np.array([Fraction(2), Fraction(4), Fraction(0)], dtype=object))
    assert energy == Fraction(9, 8)


def test_projection_never_increases_the_lyapunov_term_when_the_truth_is_in_bounds():
    """d/dt sum (P_hat - P)^2 / (2 rho) = sum (P_hat - P) kappa s <= sum (P_hat - P) s: projection
    only removes steps that would move an estimate away from every in-bounds truth."""
    rng = np.random.default_rng(SEED + 1)
    lower, upper = np.zeros(6), np.ones(6)
    for _ in range(200):
        p_true = rng.random(6)
        p_hat = rng.choice([0.0, 1.0, 0.5], size=6)
        s = rng.normal(size=6)
        rho = 1 + rng.random(6)
        projected = np.sum((p_hat - p_true) * parameter_rate(p_hat, s, lower, upper, rho) / rho)
        free = np.sum((p_hat - p_true) * s)
        assert projected <= free + 1e-15


def test_mismatched_shapes_are_a_typed_error():
    with pytest.raises(ControlInputError):
        projection(np.zeros(2), np.zeros(3), np.zeros(2), np.zeros(2))
