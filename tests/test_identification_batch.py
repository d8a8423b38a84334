"""The batched identification rows (one generated NumPy function over every sample) equal the dense
per-sample rows, and are fast enough for an ordinary log."""
from __future__ import annotations

import time

import numpy as np
import pytest

import symgen
from symgen.control.contact import ContactLaw
from symgen.identification import batch
from symgen.identification.batch import batch_rows, position_matrix, sample_rows_batch
from symgen.identification.data import column_names, simulated_samples
from symgen.identification.errors import IdentificationError
from symgen.identification.estimate import observations
from symgen.identification.regressor import evaluate_state, make_problem, measured_side, sample_rows
from symgen.identification.states import random_states
from symgen.identification.trajectory import random_trajectory, trajectory_samples, trajectory_states

#: the batched rows equal the dense ones to this, relative to the largest entry
ROUNDING = 1e-12
#: rows per second the batched path must reach at least (the dense path reached 130 to 160)
MIN_ROWS_PER_SECOND = 2000


def _dense(problem, states, samples):
    names = column_names(problem.model)
    ws, ys = [], []
    for k, state in enumerate(states):
        data, dv = evaluate_state(problem.model, state)
        w, t_map = sample_rows(problem, state, data, dv)
        eta_f = samples.block(names["eta_f"])[k] if all(c in samples.columns for c in names["eta_f"]) else None
        eta_m = samples.block(names["eta_m"])[k] if problem.eta_m_measured else None
        ws.append(w)
        ys.append(measured_side(problem, data, t_map, samples.block(names["tau"])[k], eta_f, eta_m))
    return np.array(ws), np.array(ys)


CASES = [("chain:n=2", False, False), ("four_bar", False, False), ("five_bar", False, False),
         ("arm_on_plane", False, False), ("arm_on_plane", True, False), ("arm_on_plane", True, True)]


@pytest.mark.parametrize("spec, eta_f, eta_m", CASES)
def test_batched_rows_equal_the_dense_rows(spec, eta_f, eta_m):
    model = symgen.derive(symgen.load(spec))
    law = ContactLaw.for_scene(model.scene, viscous=2.0, coulomb=0.5) if model.scene.contact_forces else None
    problem = make_problem(model, eta_f_measured=eta_f, eta_m_measured=eta_m, contact=None if eta_m else law)
    states = random_states(model, 5, seed=3)
    n, m = model.counts.n, model.counts.m
    force = (lambda k: np.linspace(-1.0, 1.0, n - m) * (k + 1)) if eta_f else None
    samples = simulated_samples(problem, states, eta_f=force, law=law, eta_m_columns=eta_m, noise=0.1, seed=2)
    w, y = sample_rows_batch(problem, samples)
    w_ref, y_ref = _dense(problem, states, samples)
    assert w.shape == w_ref.shape == (5, len(problem.channels), len(problem.params))
    assert np.max(np.abs(w - w_ref)) <= ROUNDING * max(1.0, np.max(np.abs(w_ref)))
    assert np.max(np.abs(y - y_ref)) <= ROUNDING * max(1.0, np.max(np.abs(y_ref)))


def test_missing_dependent_positions_are_closed_row_by_row_to_the_same_rows():
    model = symgen.derive(symgen.load("five_bar"))
    problem = make_problem(model)
    states = [s for s, _ in trajectory_states(model, random_trajectory(model, seed=1), 5)]
    full = simulated_samples(problem, states)
    free = simulated_samples(problem, states, dependent=False)
    assert "q_j3" in full.columns and "q_j3" not in free.columns
    np.testing.assert_allclose(position_matrix(model, free), position_matrix(model, full), atol=1e-10)


def test_a_long_log_without_dependent_positions_is_refused_by_name(monkeypatch):
    model = symgen.derive(symgen.load("four_bar"))
    problem = make_problem(model)
    states = [s for s, _ in trajectory_states(model, random_trajectory(model, seed=1), 6)]
    monkeypatch.setattr(batch, "MAX_CLOSED_ROWS", 5)
    with pytest.raises(IdentificationError, match=r"6 rows without the columns q_j2, q_j3, q_j4: .* at most 5 rows"):
        sample_rows_batch(problem, simulated_samples(problem, states, dependent=False))


def test_a_regressor_too_large_for_memory_is_refused(monkeypatch):
    model = symgen.derive(symgen.load("chain:n=2"))
    problem = make_problem(model)
    samples = simulated_samples(problem, random_states(model, 4, seed=1))
    monkeypatch.setattr(batch, "MAX_ENTRIES", 100)
    with pytest.raises(IdentificationError, match=r"4 samples x 2 channels x 26 parameters = 208 regressor entries"):
        sample_rows_batch(problem, samples)


def test_an_overflowing_sample_is_named_by_its_number():
    model = symgen.derive(symgen.load("chain:n=2"))
    problem = make_problem(model)
    q, qd = np.zeros((4, 2)), np.full((4, 2), 0.1)
    qd[2] = 1e200                                     # squared in the Coriolis terms: beyond double precision
    with pytest.raises(IdentificationError, match=r"^sample 3: identification_rows: output W contains NaN or inf"):
        batch_rows(problem, q, qd, np.zeros((4, 2)), np.zeros((4, 2)))


def test_fast_trajectory_samples_equal_the_dense_simulation():
    for spec, count in (("chain:n=3", 15), ("four_bar", 4)):
        model = symgen.derive(symgen.load(spec))
        problem = make_problem(model)
        traj = random_trajectory(model, seed=4)
        fast = trajectory_samples(problem, traj, count)
        dense = simulated_samples(problem, [s for s, _ in trajectory_states(model, traj, count)])
        assert set(fast.columns) == set(dense.columns)
        for name, values in dense.columns.items():
            np.testing.assert_allclose(fast.columns[name], values, rtol=0, atol=1e-12, err_msg=name)


def test_an_ordinary_log_is_read_at_thousands_of_rows_per_second():
    model = symgen.derive(symgen.load("chain:n=6"))
    problem = make_problem(model)
    samples = trajectory_samples(problem, random_trajectory(model, seed=1), 20_000, noise=0.01)
    observations(problem, samples.__class__({k: v[:10] for k, v in samples.columns.items()}))   # trace once
    start = time.perf_counter()
    obs = observations(problem, samples)
    rate = len(samples) / (time.perf_counter() - start)
    assert obs.W.shape == (20_000 * 6, 78)
    assert rate > MIN_ROWS_PER_SECOND, f"{rate:.0f} rows/s"
