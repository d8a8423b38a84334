"""``symgen simulate SCENE --t-end T [--report DIR] ...``: one simulation, or the work-precision
study written as a report directory (CSV, markdown, PNG)."""
from __future__ import annotations

import json
import shlex
import sys

from ..codegen.targets import TARGETS
from .args import add_scene, bounded, load_scene

METHOD_HELP = "rk4, semi_implicit_euler, RK45, DOP853, Radau, BDF"
#: longest simulated time of one command (s); the right-hand-side calls are capped as well
#: (``symgen.simulation.integrators.MAX_RHS_CALLS``)
MAX_T_END = 1e4


def _floats(text: str, what: str) -> list[float]:
    from ..simulation.errors import SimulationInputError

    try:
        return [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise SimulationInputError(f"{what} must be comma-separated numbers, got {text!r}") from None


def _initial_state(model, args):
    from ..simulation.state import StateLayout

    layout = StateLayout(model)
    if args.v0:
        v0 = _floats(args.v0, "--v0")
    else:
        v0 = [args.speed * (-1) ** i for i in range(layout.m)]
    return layout.initial_state(V_m=v0)


def _print_single(model, traj, as_json: bool, tau=None) -> None:
    from ..simulation.loop_report import format_loop_forces, loop_force_summary

    summary = traj.summary()
    forces = loop_force_summary(model, traj, tau)
    if as_json:
        print(json.dumps({"scene": model.scene.name, **summary}, indent=1))
        return
    print(f"scene {model.scene.name}: {traj.method} ({traj.backend}), stabilization {traj.stabilization}, "
          f"settings {traj.settings}")
    print(f"  t_end {traj.t_end:g} s   steps {traj.steps}   RHS calls {traj.rhs_calls}   "
          f"wall time {traj.wall_time:.3g} s")
    print(f"  constraint drift (max |residual|) {traj.max_drift:.3g}"
          + (f"   before projection {traj.step_drift:.3g}" if traj.stabilization == "projection" else ""))
    drift = traj.energy_drift
    print("  relative energy drift " + (f"{drift:.3g}" if drift is not None else "- (not a conservative run)"))
    print("  final state:")
    for label, value in summary["final_state"].items():
        print(f"    {label:<14} {value: .12g}")
    for line in format_loop_forces(forces):
        print(line)


def _command(args) -> str:
    """The command line that reproduces a report (defaults left out)."""
    parts = ["symgen", "simulate", args.scene, "--t-end", f"{args.t_end:g}", "--report", args.report]
    for flag, value, default in (("--backend", args.backend, "both"), ("--methods", args.methods, None),
                                 ("--steps", args.steps, None), ("--tolerances", args.tolerances, None),
                                 ("--torque", args.torque, "spring"), ("--speed", args.speed, 0.5),
                                 ("--v0", args.v0, None)):
        if value != default:
            parts += [flag, f"{value:g}" if isinstance(value, float) else str(value)]
    if args.no_stabilization:
        parts.append("--no-stabilization")
    if getattr(args, "lock", None):
        parts += ["--lock", ",".join(f"{k}={v}" for k, v in args.lock.items())]
    return " ".join(shlex.quote(p) for p in parts)


def cmd_simulate(args) -> int:
    from ..model import derive
    from ..simulation.errors import SimulationInputError
    from ..simulation.forcing import named_torque
    from ..simulation.integrators import FIXED_METHODS, METHODS, resolve_method, simulate

    model = derive(load_scene(args))
    backends = TARGETS if args.backend == "both" else (args.backend,)
    tau = named_torque(model, args.torque)
    x0 = _initial_state(model, args)
    stabilization = "none" if args.no_stabilization else "auto"
    if args.report:
        from ..simulation.workprecision import DEFAULT_STEPS, DEFAULT_TOLERANCES, work_precision, write_report

        methods = [m.strip() for m in args.methods.split(",")] if args.methods else list(METHODS)
        steps = _floats(args.steps, "--steps") if args.steps else DEFAULT_STEPS
        tols = _floats(args.tolerances, "--tolerances") if args.tolerances else DEFAULT_TOLERANCES
        progress = None if args.json else (lambda line: print("  " + line, file=sys.stderr))
        study = work_precision(model, args.t_end, methods=methods, backends=backends, steps=steps, tolerances=tols,
                               tau=tau, x0=x0, stabilization=stabilization, progress=progress)
        study.description.update({"torque": args.torque, "initial V_m": [round(float(v), 12) for v in x0[-model.counts.m:]],
                                  "initial configuration": "the scene's reference q0"})
        out = write_report(study, args.report, force=args.force, command=_command(args))
        if args.json:
            print(json.dumps(study.as_dict(), indent=1))
        else:
            print(f"wrote work_precision.csv, .md, .png, .json to {out} ({len(study.rows)} runs; reference difference "
                  f"{study.reference_difference:.2g})")
        return 0
    method = resolve_method(args.method)
    if method in FIXED_METHODS and args.step is None:
        raise SimulationInputError(f"fixed-step method {method} needs --step")
    settings = dict(step=args.step) if method in FIXED_METHODS else dict(rtol=args.rtol, atol=args.atol)
    results = []
    for backend in backends:
        traj = simulate(model, args.t_end, method, backend=backend, tau=tau, x0=x0, stabilization=stabilization,
                        **settings)
        results.append(traj)
        if not args.json:
            _print_single(model, traj, False, tau)
    if args.json:
        from ..simulation.loop_report import loop_force_summary

        print(json.dumps([{"scene": model.scene.name, **t.summary(), "loop_forces": loop_force_summary(model, t, tau)}
                          for t in results], indent=1))
    return 0


def register(subparsers) -> None:
    p = subparsers.add_parser("simulate", help="forward simulation; --report DIR writes the work-precision study")
    add_scene(p)
    p.add_argument("--t-end", type=bounded(float, low=0, low_open=True, high=MAX_T_END), required=True,
                   help=f"end time (s), at most {MAX_T_END:g}")
    p.add_argument("--report", metavar="DIR", help="write work_precision.csv/.md/.png/.json into DIR (atomically)")
    p.add_argument("--backend", choices=TARGETS + ("both",), default=None,
                   help="generated code to run (default: c for one run, both for --report)")
    p.add_argument("--methods", help=f"comma-separated methods for --report (default: all: {METHOD_HELP})")
    p.add_argument("--method", default="DOP853", help=f"method of a single run: {METHOD_HELP} (default DOP853)")
    p.add_argument("--step", type=bounded(float, low=0, low_open=True),
                   help="step size (s) of a fixed-step single run (at most 10^6 right-hand-side calls in all)")
    p.add_argument("--rtol", type=float, default=1e-10, help="relative tolerance of an adaptive single run")
    p.add_argument("--atol", type=float, default=None, help="absolute tolerance (default: rtol)")
    p.add_argument("--steps", help="comma-separated fixed steps for --report (default 0.04,...,0.00125)")
    p.add_argument("--tolerances", help="comma-separated tolerances for --report (default 1e-4,1e-6,1e-8,1e-10)")
    p.add_argument("--torque", choices=("none", "spring", "sine"), default="spring",
                   help="actuator torque: spring (conservative, period 1 s about q0; default), sine, or none")
    p.add_argument("--speed", type=float, default=0.5, help="initial V_m = speed * (1, -1, 1, ...) (default 0.5)")
    p.add_argument("--v0", help="initial V_m as comma-separated numbers (overrides --speed)")
    p.add_argument("--no-stabilization", action="store_true", help="integrate positions without constraint stabilization")
    p.add_argument("--force", action="store_true", help="replace a --report directory symgen did not create")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=_dispatch)


def _dispatch(args) -> int:
    if args.backend is None:
        args.backend = "both" if args.report else "c"
    return cmd_simulate(args)
