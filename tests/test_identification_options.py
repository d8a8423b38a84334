"""Options of the exciting-trajectory optimiser and of the base parameters: out of range is a typed
error naming the option; the random start is always evaluated, so no budget leaks an internal
exception."""
from __future__ import annotations

import numpy as np
import pytest

import symgen
from symgen.identification.base import MAX_STATES, base_parameters
from symgen.identification.errors import IdentificationError, OptionError, TooFewSamplesError
from symgen.identification.regressor import make_problem
from symgen.identification.trajectory import optimise_trajectory, random_trajectory


@pytest.fixture(scope="module")
def chain():
    problem = make_problem(symgen.derive(symgen.load("chain:n=2")))
    return problem, base_parameters(problem, count=20)


@pytest.mark.parametrize("option, value, text", [
    ("budget", 0.0, r"^budget: 0.0 is out of range: give a finite number > 0"),
    ("budget", -np.inf, r"^budget: -inf is out of range"),
    ("budget", np.nan, r"^budget: nan is out of range"),
    ("max_evals", 0, r"^max_evals: 0 is out of range: give an integer >= 1"),
    ("frequency", 0.0, r"^frequency: 0.0 is out of range: give a finite number > 0"),
    ("frequency", np.nan, r"^frequency: nan is out of range"),
    ("harmonics", 0, r"^harmonics: 0 is out of range: give an integer >= 1 and <= 50"),
    ("harmonics", 2.5, r"^harmonics: 2.5 is out of range: give an integer"),
    ("samples", 5000, r"^samples: 5000 is out of range: give an integer >= 1 and <= 1000"),
    ("seed", -1, r"^seed: -1 is out of range: give an integer >= 0"),
])
def test_an_option_out_of_range_is_named(chain, option, value, text):
    with pytest.raises(OptionError, match=text) as info:
        optimise_trajectory(*chain, **{option: value})
    assert info.value.option == option


def test_too_few_samples_per_period_for_the_base_parameters_states_the_numbers(chain):
    with pytest.raises(TooFewSamplesError, match=r"\(5 samples x 2 channels\) for cond\(W_b\): 10 < 12 needed; "
                                                 r"use at least 6 samples"):
        optimise_trajectory(*chain, samples=5)


def test_one_evaluation_is_the_random_start_and_nothing_leaks(chain):
    ex = optimise_trajectory(*chain, max_evals=1, samples=10)
    assert ex.evaluations == 1 and ex.cond_optimised == ex.cond_random


def test_a_spent_budget_still_returns_the_random_start(chain):
    ex = optimise_trajectory(*chain, budget=1e-9, samples=10)
    assert ex.evaluations == 1 and np.isfinite(ex.cond_optimised)


def test_a_zero_frequency_trajectory_is_refused_before_dividing_by_it():
    model = symgen.derive(symgen.load("chain:n=2"))
    with pytest.raises(OptionError, match="^frequency: 0 is out of range"):
        random_trajectory(model, frequency=0)


@pytest.mark.parametrize("count", [0, -3, MAX_STATES + 1])
def test_random_state_counts_out_of_range_are_refused(chain, count):
    with pytest.raises(IdentificationError, match=f"count of random states {count} is out of range"):
        base_parameters(chain[0], count=count)


def test_a_negative_seed_is_refused(chain):
    with pytest.raises(IdentificationError, match="seed -1 must be an integer >= 0"):
        base_parameters(chain[0], count=20, seed=-1)
