"""Identification on simulated data: the scene's own parameters are the truth, the joint forces
come from symgen's inverse dynamics (model (32), not the regressor), Gaussian noise of standard
deviation NOISE is added to tau. Zero noise: the base parameters come back to 1e-8 (relative to
the largest); with noise: every one within Z_MAX reported standard deviations."""
import functools

import numpy as np
import pytest

import symgen
from symgen.cli import main
from symgen.control.contact import ContactLaw
from symgen.identification.base import base_parameters
from symgen.identification.data import Samples, read_csv, simulated_samples, write_csv
from symgen.identification.estimate import identify, observations, weighted_least_squares
from symgen.identification.regressor import evaluate_state, make_problem, sample_rows, true_forces
from symgen.identification.states import random_states
from symgen.identification.trajectory import random_trajectory, trajectory_states

NOISE = 0.01          # N m on every tau
EXACT = 1e-8          # relative, zero noise
Z_MAX = 3.5           # |estimate - truth| / std, worst over ~20-60 base parameters
#: viscous and Coulomb coefficients of arm_on_plane's contact law (the truth)
CONTACT = (0.8, 0.4)


def _setup(spec, eta_f_measured=False):
    model = symgen.derive(symgen.load(spec))
    law = ContactLaw.for_scene(model.scene, *CONTACT) if model.scene.contact_forces else None
    problem = make_problem(model, eta_f_measured=eta_f_measured, contact=law)
    return model, law, problem


def _states(model, spec):
    """Along a random Fourier trajectory for chain:n=6 and five_bar; random states otherwise."""
    if spec in ("chain:n=6", "five_bar"):
        traj = random_trajectory(model, seed=2, frequency=0.2)
        return [s for s, _ in trajectory_states(model, traj, 40)]
    return random_states(model, 30, seed=4)


def _eta_f(model):
    """A pushing force that changes from sample to sample (measured or not, it must not matter)."""
    k = model.counts.n - model.counts.m
    return (lambda i: 5.0 + np.sin(i + np.arange(k))) if k else None


def test_regressor_times_true_parameters_is_the_inverse_dynamics():
    """Y P = tau - J_f^T eta_f with tau from model.inverse_dynamics, contact forces from the law."""
    for spec in ("ur5", "five_bar", "arm_on_plane"):
        model, law, problem = _setup(spec, eta_f_measured=True)
        for i, state in enumerate(random_states(model, 4, seed=1)):
            eta_f = _eta_f(model)(i) if _eta_f(model) else None
            tau, _ = true_forces(problem, state, eta_f=eta_f, law=law)
            data, dv = evaluate_state(model, state)
            w, _ = sample_rows(problem, state, data, dv)
            rhs = tau - (data.maps.J_f.v.T @ eta_f if eta_f is not None else 0)
            assert np.max(np.abs(w @ problem.params.values - rhs)) <= 1e-10 * max(1.0, np.max(np.abs(tau)))


CASES = [("chain:n=6", False), ("five_bar", False), ("arm_on_plane", False), ("arm_on_plane", True)]


@functools.lru_cache(maxsize=None)
def _clean(spec):
    """Noise-free samples (with eta_f columns where the scene has eta_f), computed once per scene."""
    model, law, problem = _setup(spec, eta_f_measured=True)
    return simulated_samples(problem, _states(model, spec), law=law, eta_f=_eta_f(model))


@functools.lru_cache(maxsize=None)
def _base(spec, eta_f_measured):
    """From 35 random states: at least as many rows as parameters (arm_on_plane projected: 3 a state)."""
    _, _, problem = _setup(spec, eta_f_measured)
    return base_parameters(problem, count=35)


def _errors(spec, eta_f_measured, noise):
    """Estimate and truth; without eta_f measured its columns are dropped from the same samples."""
    model, _, problem = _setup(spec, eta_f_measured)
    clean = _clean(spec)
    rng = np.random.default_rng(9)
    cols = {k: (v + noise * rng.normal(size=v.shape) if k.startswith("tau_") else v)
            for k, v in clean.columns.items() if eta_f_measured or not k.startswith("eta_f_")}
    base = _base(spec, eta_f_measured)
    est = identify(problem, Samples(cols), base=base)
    return est, base.values(problem.params.values)


@pytest.mark.parametrize("spec,eta_f_measured", CASES)
def test_zero_noise_recovers_the_base_parameters(spec, eta_f_measured):
    est, truth = _errors(spec, eta_f_measured, 0.0)
    assert np.max(np.abs(est.values - truth)) <= EXACT * np.max(np.abs(truth))


@pytest.mark.parametrize("spec,eta_f_measured", CASES)
def test_noisy_estimates_are_within_their_standard_deviations(spec, eta_f_measured):
    est, truth = _errors(spec, eta_f_measured, NOISE)
    z = np.abs(est.values - truth) / est.std
    assert np.max(z) <= Z_MAX
    assert 0.7 < est.sigma_w < 1.3          # the weights of step 1 measured the noise
    if len(est.channel_std) == len(symgen.derive(symgen.load(spec)).coordinate_names()):
        assert np.allclose(est.channel_std, NOISE, rtol=0.3)    # rows are tau itself: sigma_j = NOISE


def test_ur5_estimates_zero_noise_exact_and_noisy_within_their_standard_deviations():
    est, truth = _errors("ur5", False, 0.0)
    assert np.max(np.abs(est.values - truth)) <= EXACT * np.max(np.abs(truth))
    est, truth = _errors("ur5", False, NOISE)
    assert np.max(np.abs(est.values - truth) / est.std) <= Z_MAX


def test_measured_contact_forces_are_moved_to_the_left_and_their_law_left_out():
    """arm_on_plane with eta_m and eta_f measured: P_m is not identified, the rest comes back exactly."""
    model = symgen.derive(symgen.load("arm_on_plane"))
    law = ContactLaw.for_scene(model.scene, *CONTACT)
    problem = make_problem(model, eta_f_measured=True, eta_m_measured=True)
    assert not any(n.endswith("_O") for n in problem.params.names)
    samples = simulated_samples(problem, random_states(model, 20, seed=6), law=law, eta_f=_eta_f(model),
                                eta_m_columns=True)
    base = base_parameters(problem, count=20)
    est = identify(problem, samples, base=base)
    truth = base.values(problem.params.values)
    assert np.max(np.abs(est.values - truth)) <= EXACT * np.max(np.abs(truth))


def test_identify_command_reads_the_csv_and_writes_a_consistent_scene(tmp_path, capsys):
    """CSV round trip through ``symgen identify --consistent --out``: the written scene derives, its
    pseudo-inertias are PSD and its base parameters are those of the fit."""
    pytest.importorskip("cvxpy")
    model, _, problem = _setup("five_bar")
    samples = simulated_samples(problem, _states(model, "five_bar")[:25], noise=1e-4, seed=1)
    path = tmp_path / "data.csv"
    write_csv(path, samples)
    assert set(read_csv(path).columns) == set(samples.columns)
    out = tmp_path / "identified.yaml"
    assert main(["identify", "five_bar", str(path), "--consistent", "--out", str(out), "--json",
                 "--states", "30"]) == 0
    import json

    report = json.loads(capsys.readouterr().out)
    assert report["consistent"]["status"] == "optimal"
    assert min(report["consistent"]["min_pseudo_inertia_eigenvalue"].values()) >= -1e-9
    written = symgen.derive(symgen.load(str(out)))
    base = _base("five_bar", False)
    fitted = np.array(report["consistent"]["base_values"])
    assert np.allclose(base.values(make_problem(written).params.values), fitted, rtol=1e-6, atol=1e-9)


def test_weights_given_per_channel_are_used():
    model, _, problem = _setup("chain:n=3")
    samples = simulated_samples(problem, random_states(model, 30, seed=2), noise=0.0, seed=1)
    obs = observations(problem, samples)
    base = base_parameters(problem, count=20)
    est = weighted_least_squares(obs, base, [0.1, 0.2, 0.3])
    assert list(est.channel_std) == [0.1, 0.2, 0.3]


@pytest.mark.parametrize("noise", [0.0, NOISE])
def test_consistent_fit_meets_the_lmis_and_keeps_the_base_parameters(noise):
    """chain:n=6, all 78 standard parameters under the LMIs: every pseudo-inertia PSD, and the base
    parameters they imply equal the truth (noise-free, 1e-6: the solver's accuracy) or lie within
    Z_MAX standard deviations of the least-squares estimate's (noisy)."""
    pytest.importorskip("cvxpy")
    from symgen.identification.consistent import consistent_fit, pseudo_inertia

    model, _, problem = _setup("chain:n=6")
    base = _base("chain:n=6", False)
    samples = simulated_samples(problem, random_states(model, 30, seed=2), noise=noise, seed=4)
    obs = observations(problem, samples)
    est = weighted_least_squares(obs, base)
    fit = consistent_fit(problem, obs, est)
    for owner in ("link0", "link3", "link5"):
        idx = [problem.params.index(f"{q}_{owner}") for q in ("m", "hx", "hy", "hz", "Ixx", "Iyy", "Izz", "Ixy",
                                                               "Ixz", "Iyz")]
        assert np.linalg.eigvalsh(pseudo_inertia(fit.values[idx])).min() >= 0
    truth = base.values(problem.params.values)
    if noise == 0:
        assert np.max(np.abs(fit.base_values - truth)) <= 1e-6 * np.max(np.abs(truth))
    else:
        assert np.max(np.abs(fit.base_values - truth) / est.std) <= Z_MAX
