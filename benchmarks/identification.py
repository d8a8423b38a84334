"""Identification on simulated data: base-parameter counts, exciting trajectories, estimate error
against noise, measured in one run.

For each scene: the standard and base parameter counts (and, for the URDF robots, the rank of
Pinocchio's joint-torque regressor stacked over the same number of random states, with the
rotor-inertia and friction columns qdd_j, qd_j, sign(qd_j) appended); the condition number of the
stacked base regressor along a random Fourier trajectory and along the optimised one
(``OPT`` settings); then ``SAMPLES`` samples along each trajectory with the scene's own inverse
dynamics (its parameters are the truth) and Gaussian noise on each tau column, of standard
deviation ``NOISE`` times that column's rms, and
the two-step weighted least squares: the worst relative error ``max |P_b - P_b,true| / max |P_b,true|``
and the worst ``|P_b - P_b,true| / std``.

    nice python benchmarks/identification.py          # writes benchmarks/identification.md
"""
import platform
import time
from pathlib import Path

import numpy as np

import symgen
from symgen.control.contact import ContactLaw
from symgen.control.parameters import BODY_QUANTITIES
from symgen.identification.base import base_from_regressor, base_parameters
from symgen.identification.data import Samples, simulated_samples
from symgen.identification.estimate import identify
from symgen.identification.regressor import make_problem, stacked_regressor
from symgen.identification.states import random_states
from symgen.identification.trajectory import optimise_trajectory, trajectory_states

HERE = Path(__file__).parent
#: (scene, eta_f measured): arm_on_plane both ways (projected rows, or the pushing force measured)
SCENES = [("chain:n=6", False), ("ur5", False), ("panda", False), ("five_bar", False), ("arm_on_plane", False),
          ("arm_on_plane", True)]
OPT = dict(harmonics=5, frequency=0.3, samples=30, max_evals=150, budget=90.0, seed=0)
SAMPLES = 200
#: noise std on each tau column, as a fraction of that column's rms (the scenes' torques differ by
#: orders of magnitude: five_bar moves in a horizontal plane, tau ~ 0.01 N m; the UR5 holds its arm)
NOISE = (0.0, 1e-3, 1e-2, 1e-1)
CONTACT = (0.8, 0.4)
PIN_STATES = 60


def pinocchio_ranks(model):
    """``(rank of Pinocchio's regressor, rank with the joint columns)`` over random states."""
    from symgen.oracle.pinocchio_check import open_chain_states
    from symgen.oracle.pinocchio_model import pinocchio_robot

    robot = pinocchio_robot(model.scene)
    pin, pmodel = robot.pin, robot.model
    idx = robot.v_index(model.coordinate_names())
    blocks = []
    for s in open_chain_states(model, PIN_STATES, seed=5):
        v, a = np.zeros(pmodel.nv), np.zeros(pmodel.nv)
        v[idx], a[idx] = s["qd"], s["qdd"]
        y = pin.computeJointTorqueRegressor(pmodel, pmodel.createData(), robot.q_vector(s["config"]), v, a)[idx]
        blocks.append(np.hstack([y, np.diag(s["qdd"]), np.diag(s["qd"]), np.diag(np.sign(s["qd"]))]))
    w = np.vstack(blocks)
    n = len(idx)
    return int(np.linalg.matrix_rank(w[:, :-3 * n])), int(np.linalg.matrix_rank(w))


def errors(problem, base, traj, law, eta_f_measured, seed=0):
    """``{noise: (relative error, max |z|)}`` along ``traj``."""
    model = problem.model
    states = [s for s, _ in trajectory_states(model, traj, SAMPLES)]
    k = model.counts.n - model.counts.m
    eta_f = (lambda i: 5.0 + np.sin(0.1 * i + np.arange(k))) if k and eta_f_measured else None
    clean = simulated_samples(problem, states, law=law, eta_f=eta_f)
    truth = base.values(problem.params.values)
    out = {}
    rng = np.random.default_rng(seed)
    for noise in NOISE:
        cols = {c: (v + noise * np.sqrt(np.mean(v ** 2)) * rng.normal(size=v.shape) if c.startswith("tau_") else v)
                for c, v in clean.columns.items()}
        est = identify(problem, Samples(cols), base=base)
        rel = float(np.max(np.abs(est.values - truth)) / np.max(np.abs(truth)))
        z = float(np.max(np.abs(est.values - truth) / est.std)) if noise else float("nan")
        out[noise] = (rel, z)
    return out


def main() -> None:
    rows = []
    for spec, eta_f_measured in SCENES:
        start = time.perf_counter()
        model = symgen.derive(symgen.load(spec))
        law = ContactLaw.for_scene(model.scene, *CONTACT) if model.scene.contact_forces else None
        problem = make_problem(model, eta_f_measured=eta_f_measured, contact=law)
        base = base_parameters(problem)
        row = {"scene": spec + (" (eta_f measured)" if eta_f_measured else ""), "standard": len(problem.params),
               "base": base.rank, "gap": (base.diagonal[base.rank - 1], base.diagonal[base.rank])}
        if spec in ("ur5", "panda"):
            w = stacked_regressor(problem, random_states(model, PIN_STATES, seed=5))
            cols = [k for k, p in enumerate(problem.params.parameters) if p.quantity in BODY_QUANTITIES]
            row["base_bodies"] = base_from_regressor(w[:, cols], [problem.params.names[k] for k in cols]).rank
            row["pin"] = pinocchio_ranks(model)
        ex = optimise_trajectory(problem, base, **OPT)
        row.update(cond_random=ex.cond_random, cond_opt=ex.cond_optimised, evals=ex.evaluations,
                   opt_seconds=ex.seconds)
        row["err_random"] = errors(problem, base, ex.random, law, eta_f_measured)
        row["err_opt"] = errors(problem, base, ex.optimised, law, eta_f_measured)
        row["seconds"] = time.perf_counter() - start
        rows.append(row)
        print(f"{row['scene']:<32} {row['standard']:>4} {row['base']:>4} cond {ex.cond_random:.3g} -> "
              f"{ex.cond_optimised:.3g} ({ex.evaluations} evals, {ex.seconds:.0f} s)  {row['seconds']:.0f} s",
              flush=True)
    write(rows)


def write(rows) -> None:
    lines = ["# Identification on simulated data", "",
             f"Measured in one run by `nice python benchmarks/identification.py` on {platform.machine()}, "
             f"Python {platform.python_version()}. Truth: each scene's own parameters; arm_on_plane's contact "
             f"law b = {CONTACT[0]}, c = {CONTACT[1]} on every component. Trajectories: {OPT['harmonics']} "
             f"harmonics at {OPT['frequency']} Hz, condition number over {OPT['samples']} samples per period, "
             f"optimiser stopped after {OPT['max_evals']} evaluations or {OPT['budget']:.0f} s; the random "
             "trajectory is the optimiser's start. Estimation: "
             f"{SAMPLES} samples over one period, Gaussian noise on every tau column with std = level x that "
             "column's rms.", "",
             "## Parameter counts", "",
             "Base parameters from 60 (or more) random loop-closed states; the rank gap is the smallest kept and "
             "largest dropped |R_kk|/|R_00| of the pivoted QR on unit columns (tolerance 1e-9).", "",
             "| scene | standard | base | rank gap (kept / dropped) | base of the body parameters | "
             "Pinocchio rank (bodies / with joint columns) |", "|---|---|---|---|---|---|"]
    for r in rows:
        pin = f"{r['pin'][0]} / {r['pin'][1]}" if "pin" in r else "-"
        lines.append(f"| `{r['scene']}` | {r['standard']} | {r['base']} | {r['gap'][0]:.1e} / {r['gap'][1]:.1e} | "
                     f"{r.get('base_bodies', '-')} | {pin} |")
    lines += ["", "## Exciting trajectories", "",
              "| scene | cond(W_b) random | cond(W_b) optimised | evaluations | seconds |", "|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| `{r['scene']}` | {r['cond_random']:.4g} | {r['cond_opt']:.4g} | {r['evals']} | "
                     f"{r['opt_seconds']:.0f} |")
    lines += ["", "## Estimate error against noise", "",
              "Worst relative error max|P_b - P_b,true| / max|P_b,true| and, in brackets, the worst "
              "|P_b - P_b,true| / std (two-step weighted least squares).", "",
              "| scene | trajectory | " + " | ".join(f"noise {n:g} rms" for n in NOISE) + " |",
              "|---|---|" + "---|" * len(NOISE)]
    for r in rows:
        for name, key in (("random", "err_random"), ("optimised", "err_opt")):
            cells = [f"{rel:.2e}" + ("" if np.isnan(z) else f" ({z:.2f})") for rel, z in
                     (r[key][n] for n in NOISE)]
            lines.append(f"| `{r['scene']}` | {name} | " + " | ".join(cells) + " |")
    (HERE / "identification.md").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
