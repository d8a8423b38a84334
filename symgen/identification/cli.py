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


def register(subparsers) -> None:
    p = subparsers.add_parser("params", help="base (identifiable) inertial parameters of a scene")
    p.add_argument("scene")
    p.add_argument("--states", type=int, help="random loop-closed states stacked (default 60, or more when a "
                                              "state gives few rows)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--eta-f-measured", action="store_true",
                   help="the constraint forces eta_f are measured (else the rows are projected with Omega^T)")
    p.add_argument("--eta-m-measured", action="store_true",
                   help="the contact forces eta_m are measured (else the contact law's P_m is identified)")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_params)
    p = subparsers.add_parser("excite", help="optimise a Fourier exciting trajectory (condition number of the "
                                             "base regressor); optionally write simulated samples")
    p.add_argument("scene")
    p.add_argument("--harmonics", type=int, default=5)
    p.add_argument("--frequency", type=float, default=0.3, help="base frequency (Hz), default 0.3")
    p.add_argument("--samples", type=int, default=30, help="samples per period in the optimisation")
    p.add_argument("--max-evals", type=int, default=200, help="condition-number evaluations at most")
    p.add_argument("--budget", type=float, default=30.0, help="seconds at most for the optimisation")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--data", metavar="CSV", help="write simulated samples along the optimised trajectory")
    p.add_argument("--data-samples", type=int, default=200, help="samples written with --data")
    p.add_argument("--noise", type=float, default=0.0, help="std of the Gaussian noise on tau (N, N m)")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_excite)
    p = subparsers.add_parser("identify", help="estimate the base parameters from samples q, qd, qdd, tau (CSV)")
    p.add_argument("scene")
    p.add_argument("data", help="CSV with q_<joint>, qd_<c>, qdd_<c>, tau_<c> [, eta_f_<k>] [, eta_m_<comp>]")
    p.add_argument("--weights", default="residual",
                   help="'residual' (two-step, default), 'none' (ordinary least squares), or one std per "
                        "channel, comma-separated")
    p.add_argument("--consistent", action="store_true",
                   help="fit every standard parameter under the pseudo-inertia LMIs (needs cvxpy)")
    p.add_argument("--out", metavar="SCENE.yaml", help="with --consistent: write the scene with the identified "
                                                       "parameters")
    p.add_argument("--states", type=int, help="random states for the base parameters (default as symgen params)")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_identify)


def _model(spec):
    from ..loading import load
    from ..model import derive

    return derive(load(spec))


def cmd_params(args) -> int:
    from .base import base_parameters, default_count
    from .regressor import make_problem

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


def cmd_excite(args) -> int:
    from .base import base_parameters
    from .data import simulated_samples, write_csv
    from .regressor import make_problem
    from .trajectory import optimise_trajectory, trajectory_states

    model = _model(args.scene)
    problem = make_problem(model)          # the samples --data writes carry no eta_f, eta_m columns
    base = base_parameters(problem, seed=args.seed)
    ex = optimise_trajectory(problem, base, harmonics=args.harmonics, frequency=args.frequency,
                             samples=args.samples, max_evals=args.max_evals, budget=args.budget, seed=args.seed)
    out = {"scene": model.scene.name, "free_coordinates": list(ex.optimised.names), "base": base.rank,
           "cond_random": ex.cond_random, "cond_optimised": ex.cond_optimised, "evaluations": ex.evaluations,
           "seconds": round(ex.seconds, 2), "period": ex.optimised.period, "scale": ex.optimised.scale,
           "a": ex.optimised.a.tolist(), "b": ex.optimised.b.tolist(), "center": ex.optimised.center.tolist()}
    if args.data:
        states = [s for s, _ in trajectory_states(model, ex.optimised, args.data_samples)]
        write_csv(args.data, simulated_samples(problem, states, noise=args.noise, seed=args.seed))
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
    if text in ("residual", "none"):
        return text
    from .errors import DataColumnError

    try:
        return [float(v) for v in text.split(",")]
    except ValueError:
        raise DataColumnError("--weights", f"{text!r}: give 'residual', 'none' or numbers") from None


def cmd_identify(args) -> int:
    from .base import base_parameters
    from .data import check_samples, read_csv
    from .errors import IdentificationError
    from .estimate import observations, weighted_least_squares
    from .regressor import make_problem

    if args.out and not args.consistent:
        raise IdentificationError("--out needs --consistent: least squares determines only the base parameters, "
                                  "not the standard ones a scene holds")
    model = _model(args.scene)
    samples = read_csv(args.data)
    present = check_samples(model, samples)
    problem = make_problem(model, eta_f_measured=present["eta_f"], eta_m_measured=present["eta_m"])
    base = base_parameters(problem, count=args.states)
    obs = observations(problem, samples)
    est = weighted_least_squares(obs, base, _weights(args.weights))
    out = {"scene": model.scene.name, "channels": problem.channels, **est.as_dict()}
    fit = None
    if args.consistent:
        from .consistent import consistent_fit

        fit = consistent_fit(problem, obs, est)
        out["consistent"] = {"status": fit.status, "min_pseudo_inertia_eigenvalue": fit.min_eigenvalue,
                             "standard": dict(zip(fit.names, map(float, fit.values))),
                             "base_values": fit.base_values.tolist()}
        if args.out:
            from .export import write_scene

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
