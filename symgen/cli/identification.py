"""``symgen params | excite | identify``: base parameters, exciting trajectories, estimation.

* ``symgen params SCENE`` -- the base parameters (vanishing, identifiable alone, regrouped);
* ``symgen excite SCENE`` -- an optimised Fourier trajectory, its condition number against the
  random start; ``--data FILE`` writes simulated samples along it (the scene's parameters are
  the truth, Gaussian noise ``--noise`` on tau);
* ``symgen identify SCENE DATA.csv`` -- weighted least squares (and ``--consistent``: the LMI fit
  of every standard parameter; ``--out`` writes the scene with them).
"""
from __future__ import annotations

import json
import pathlib

from .args import bounded
from ..identification.base import MAX_STATES
from ..identification.data import SAMPLE_LIMIT
from ..identification.errors import OptionError
from ..identification.estimate import WEIGHT_LIMIT
from ..identification.trajectory import (MAX_BUDGET, MAX_CLOSED_DATA_SAMPLES, MAX_DATA_SAMPLES, MAX_EVALS, MAX_FREQUENCY,
                         MAX_HARMONICS, MAX_PERIOD_SAMPLES)

_SEED = bounded(int, low=0, high=2 ** 63 - 1)
_STATES = bounded(int, low=1, high=MAX_STATES)


def _register_params(subparsers) -> None:
    p = subparsers.add_parser("params", help="base (identifiable) inertial parameters of a scene")
    p.add_argument("scene")
    p.add_argument("--states", type=_STATES, help=f"random loop-closed states stacked (default 60, or more when "
                                                  f"a state gives few rows; at most {MAX_STATES})")
    p.add_argument("--seed", type=_SEED, default=0)
    p.add_argument("--eta-f-measured", action="store_true",
                   help="the constraint forces eta_f are measured (else the rows are projected with Omega^T)")
    p.add_argument("--eta-m-measured", action="store_true",
                   help="the contact forces eta_m are measured (else the contact law's P_m is identified)")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_params)


def _register_excite(subparsers) -> None:
    p = subparsers.add_parser("excite", help="optimise a Fourier exciting trajectory (condition number of the "
                                             "base regressor); optionally write simulated samples")
    p.add_argument("scene")
    p.add_argument("--harmonics", type=bounded(int, low=1, high=MAX_HARMONICS), default=5)
    p.add_argument("--frequency", type=bounded(float, low=0, low_open=True, high=MAX_FREQUENCY), default=0.3,
                   help="base frequency (Hz), default 0.3")
    p.add_argument("--samples", type=bounded(int, low=1, high=MAX_PERIOD_SAMPLES), default=30,
                   help="samples per period in the optimisation")
    p.add_argument("--max-evals", type=bounded(int, low=1, high=MAX_EVALS), default=200,
                   help="condition-number evaluations at most (after the random start)")
    p.add_argument("--budget", type=bounded(float, low=0, low_open=True, high=MAX_BUDGET), default=30.0,
                   help="seconds at most for the optimisation (checked between evaluations)")
    p.add_argument("--seed", type=_SEED, default=0)
    p.add_argument("--data", metavar="CSV", help="write simulated samples along the optimised trajectory")
    p.add_argument("--data-samples", type=bounded(int, low=1, high=MAX_DATA_SAMPLES),
                   help=f"samples written with --data (default 200; at most {MAX_DATA_SAMPLES}, "
                        f"{MAX_CLOSED_DATA_SAMPLES} on a closed chain)")
    p.add_argument("--noise", type=bounded(float, low=0, high=SAMPLE_LIMIT),
                   help="with --data: std of the Gaussian noise on tau (N, N m), default 0")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_excite)


def _register_identify(subparsers) -> None:
    p = subparsers.add_parser("identify", help="estimate the base parameters from samples q, qd, qdd, tau (CSV)")
    p.add_argument("scene")
    p.add_argument("data", help="CSV with q_<joint>, qd_<c>, qdd_<c>, tau_<c> [, eta_f_<k>] [, eta_m_<comp>]")
    p.add_argument("--weights", type=_weights, default="residual",
                   help="'residual' (two-step, default), 'none' (ordinary least squares), or one std per "
                        "channel, comma-separated")
    p.add_argument("--consistent", action="store_true",
                   help="fit every standard parameter under the pseudo-inertia LMIs (needs cvxpy)")
    p.add_argument("--out", metavar="SCENE.yaml", help="with --consistent: write the scene with the identified "
                                                       "parameters")
    p.add_argument("--states", type=_STATES, help="random states for the base parameters (default as symgen "
                                                  "params)")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_identify)


def register(subparsers) -> None:
    """Add ``params``, ``excite`` and ``identify`` to symgen's command line."""
    _register_params(subparsers)
    _register_excite(subparsers)
    _register_identify(subparsers)


def _writable(option: str, path: str) -> None:
    """Refuse an output path before any work: its folder must exist and it must not be a folder."""
    target = pathlib.Path(path)
    if target.is_dir():
        raise OptionError(option, f"{path!r} is a directory; give a file name")
    if not target.resolve().parent.is_dir():
        raise OptionError(option, f"the folder of {path!r} does not exist")


def _model(spec):
    from ..io.loading import load
    from ..model import derive

    return derive(load(spec))


def cmd_params(args) -> int:
    from ..identification.base import base_parameters, default_count
    from ..identification.regressor import make_problem

    model = _model(args.scene)
    problem = make_problem(model, eta_f_measured=args.eta_f_measured, eta_m_measured=args.eta_m_measured)
    base = base_parameters(problem, count=args.states, seed=args.seed)
    cls = base.classification()
    gap = (float(base.diagonal[base.rank - 1]), float(base.diagonal[base.rank]) if len(base.diagonal) > base.rank
           else 0.0)
    if args.json:
        print(json.dumps({"scene": model.scene.name, "standard": len(base.names), "base": base.rank,
                          "rank_tolerance": base.tolerance, "smallest_kept": gap[0], "largest_dropped": gap[1],
                          "channels": problem.channels, "base_parameters": base.labels(), **cls}, indent=1))
        return 0
    print(f"scene {model.scene.name}: {len(base.names)} standard parameters, {base.rank} base parameters "
          f"({args.states or default_count(problem)} random states; rows: {', '.join(problem.channels)})")
    print(f"  rank tolerance {base.tolerance:g} x |R_00| (unit columns): smallest kept {gap[0]:.2e}, "
          f"largest dropped {gap[1]:.2e}")
    print(f"  vanishing ({len(cls['vanishing'])}): {', '.join(cls['vanishing']) or '-'}")
    print(f"  identifiable alone ({len(cls['identifiable'])}): {', '.join(cls['identifiable']) or '-'}")
    print("  base parameters:")
    for k, label in enumerate(base.labels()):
        print(f"    P_b{k + 1:<3} = {label}")
    return 0


def _excite_data_options(args, model) -> None:
    """``--data-samples``/``--noise`` need ``--data``; defaults filled in; the output path and, on a
    closed chain, the sample count checked before the optimisation runs."""
    from ..identification.trajectory import _closed

    if not args.data:
        for option, value in (("--data-samples", args.data_samples), ("--noise", args.noise)):
            if value is not None:
                raise OptionError(option, "has no effect without --data CSV")
        return
    _writable("--data", args.data)
    args.data_samples = 200 if args.data_samples is None else args.data_samples
    args.noise = 0.0 if args.noise is None else args.noise
    if _closed(model) and args.data_samples > MAX_CLOSED_DATA_SAMPLES:
        raise OptionError("--data-samples", f"{args.data_samples} is more than the {MAX_CLOSED_DATA_SAMPLES} "
                                            f"allowed on scene {model.scene.name!r}: its loops are closed sample "
                                            "by sample (30 to 80 ms each)")


def cmd_excite(args) -> int:
    from ..identification.base import base_parameters
    from ..identification.data import write_csv
    from ..identification.regressor import make_problem
    from ..identification.trajectory import optimise_trajectory, trajectory_samples

    model = _model(args.scene)
    _excite_data_options(args, model)
    problem = make_problem(model)          # the samples --data writes carry no eta_f, eta_m columns
    base = base_parameters(problem, seed=args.seed)
    ex = optimise_trajectory(problem, base, harmonics=args.harmonics, frequency=args.frequency,
                             samples=args.samples, max_evals=args.max_evals, budget=args.budget, seed=args.seed)
    out = {"scene": model.scene.name, "free_coordinates": list(ex.optimised.names), "base": base.rank,
           "cond_random": ex.cond_random, "cond_optimised": ex.cond_optimised, "evaluations": ex.evaluations,
           "seconds": round(ex.seconds, 2), "period": ex.optimised.period, "scale": ex.optimised.scale,
           "a": ex.optimised.a.tolist(), "b": ex.optimised.b.tolist(), "center": ex.optimised.center.tolist()}
    if args.data:
        write_csv(args.data, trajectory_samples(problem, ex.optimised, args.data_samples, noise=args.noise,
                                                seed=args.seed))
        out["data"] = args.data
    if args.json:
        print(json.dumps(out, indent=1))
        return 0
    print(f"scene {model.scene.name}: Fourier trajectory of {', '.join(ex.optimised.names)} "
          f"({args.harmonics} harmonics, {args.frequency:g} Hz, {ex.samples} samples per period)")
    print(f"  cond(W_b) random start {ex.cond_random:.4g} -> optimised {ex.cond_optimised:.4g} "
          f"({ex.evaluations} evaluations, {ex.seconds:.1f} s)")
    if args.data:
        print(f"  wrote {args.data_samples} samples (noise {args.noise:g} on tau) to {args.data}")
    return 0


def _weights(text: str):
    """``--weights``: ``residual``, ``none``, or one standard deviation per channel, each a finite
    number in ``[1/WEIGHT_LIMIT, WEIGHT_LIMIT]`` (the count is checked against the channels later)."""
    import argparse
    import math

    if text in ("residual", "none"):
        return text
    values = []
    for item in text.split(","):
        try:
            v = float(item)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{item.strip()!r} is not a number; give 'residual', 'none' or one "
                                             "standard deviation per channel, comma-separated") from None
        if not (math.isfinite(v) and 1 / WEIGHT_LIMIT <= v <= WEIGHT_LIMIT):
            raise argparse.ArgumentTypeError(f"standard deviation {item.strip()} is out of range: give finite "
                                             f"numbers >= {1 / WEIGHT_LIMIT:g} and <= {WEIGHT_LIMIT:g}")
        values.append(v)
    return values


def cmd_identify(args) -> int:
    from ..identification.base import base_parameters
    from ..identification.data import check_samples, read_csv
    from ..identification.errors import IdentificationError
    from ..identification.estimate import observations, weighted_least_squares
    from ..identification.regressor import make_problem

    if args.out and not args.consistent:
        raise IdentificationError("--out needs --consistent: least squares determines only the base parameters, "
                                  "not the standard ones a scene holds")
    if args.out:
        _writable("--out", args.out)
    model = _model(args.scene)
    samples = read_csv(args.data)
    present = check_samples(model, samples)
    problem = make_problem(model, eta_f_measured=present["eta_f"], eta_m_measured=present["eta_m"])
    base = base_parameters(problem, count=args.states)
    obs = observations(problem, samples)
    est = weighted_least_squares(obs, base, args.weights)
    out = {"scene": model.scene.name, "channels": problem.channels, **est.as_dict()}
    fit = None
    if args.consistent:
        from ..identification.consistent import consistent_fit

        fit = consistent_fit(problem, obs, est)
        out["consistent"] = {"status": fit.status, "min_pseudo_inertia_eigenvalue": fit.min_eigenvalue,
                             "standard": dict(zip(fit.names, map(float, fit.values))),
                             "base_values": fit.base_values.tolist()}
        if args.out:
            from ..identification.export import write_scene

            write_scene(model, problem.params, fit.values, args.out)
            out["out"] = args.out
    if args.json:
        print(json.dumps(out, indent=1))
        return 0
    print(f"scene {model.scene.name}: {est.samples} samples, {est.rows} rows ({', '.join(problem.channels)}), "
          f"{est.base.rank} base parameters; weighted residual std {est.sigma_w:.3g}")
    print(f"  channel std (weights): {', '.join(f'{s:.3g}' for s in est.channel_std)}")
    for k, label in enumerate(est.base.labels()):
        line = f"  {est.values[k]:>+14.6g} +- {est.std[k]:<10.3g} {label}"
        if fit is not None:
            line += f"   [consistent {fit.base_values[k]:+.6g}]"
        print(line)
    if fit is not None:
        print(f"  consistent fit: {fit.status}; smallest pseudo-inertia eigenvalue "
              f"{min(fit.min_eigenvalue.values(), default=0.0):.3g}")
    if args.out:
        print(f"wrote {args.out}")
    return 0
