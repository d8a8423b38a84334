"""symgen: symbolic models, proofs, generated code and numerics of general constrained robots.

Commands: ``scenes | info | steps | export | prove | generate | ops`` here, and ``simulate``,
``accuracy``, ``stability``, ``complexity``, ``check``, ``control``, ``params``, ``excite``,
``identify`` from the other modules of :mod:`symgen.cli` (:data:`COMMAND_MODULES`).
A SCENE is a built-in name with parameters (``chain:n=8``, ``multi_arm:h=3``, ``ur5``), a path to
a YAML scene file, or a URDF file. Errors print one line naming the offending element and exit with status 2; a failed
proof exits with status 1. A bad option value is refused by the parser, naming the option (status 2); a file that
cannot be read or written is one line naming it (status 2).
"""
from __future__ import annotations

import argparse
import json
import sys
import time

import numpy as np
import sympy as sp

from ..codegen.functions import library_flops
from ..codegen.targets import TARGETS
from ..errors import SymgenError
from .args import add_scene, bounded, load_scene
from . import accuracy, complexity, control, identification, simulation, stability, urdf


def _derive(args):
    from ..model import derive

    return derive(load_scene(args))


def cmd_scenes(args) -> int:
    from ..io.builtin import list_builtins, list_examples

    rows, examples = list_builtins(), list_examples()
    if args.json:
        print(json.dumps([{"name": n, "params": p, "description": d, "needs": None} for n, p, d in rows]
                         + [{"name": n, "params": p, "description": d, "needs": "example-robot-data"}
                            for n, p, d in examples], indent=1))
        return 0
    for title, table in (("", rows), ("real robots (URDF from example-robot-data, pip install 'symgen[examples]'):",
                                      examples)):
        if title:
            print(title)
        for name, params, desc in table:
            spec = name + (":" + ",".join(f"{k}={v}" for k, v in params.items()) if params else "")
            print(f"{'  ' if title else ''}{spec:<18} {desc}")
    return 0


def cmd_info(args) -> int:
    model = _derive(args)
    counts = model.counts.as_dict()
    if args.json:
        print(json.dumps(counts))
        return 0
    print(f"scene {model.scene.name}: {model.scene.description}")
    print("  " + "  ".join(f"{k}={v}" for k, v in counts.items()))
    part, coords = model.partition, model.tree.coordinates
    label = lambda idx: ", ".join(coords[i].label for i in idx) or "-"  # noqa: E731
    print(f"  qd (eq. 14)   : {', '.join(model.coordinate_names())}")
    print(f"  dependent u1  : {label(part.u1)}")
    print(f"  constrained a1: {label(part.a1)}")
    for note in model.scene.notes:      # what a reader changed or left out (friction read, joints locked ...)
        print(f"  note: {note}")
    return 0


def cmd_steps(args) -> int:

    model = _derive(args)
    if args.field == "symbolic":
        data = model.evaluate(model.symbolic_configuration(), qd=model.symbolic_velocity(), field="symbolic")
    else:
        data = model.evaluate(model.reference, qd=np.zeros(model.counts.n))
    quantities = data.quantities()
    names = args.quantity or list(quantities)
    for name in names:
        if name not in quantities:
            raise SymgenError(f"unknown quantity {name!r}; choose from {', '.join(quantities)}")
        value = quantities[name]
        print(f"{name} {tuple(np.shape(value))}:")
        if args.field == "symbolic":
            print(sp.pretty(sp.Matrix(value).applyfunc(sp.simplify) if np.size(value) < 400 else sp.Matrix(value),
                            wrap_line=False))
        else:
            with np.printoptions(precision=4, suppress=True, linewidth=160):
                print(np.asarray(value, dtype=float))
    return 0


def cmd_prove(args) -> int:
    from ..control.parameters import sprung_joints
    from ..control.proofs import prove_regressor
    from ..proofs import prove

    model = _derive(args)
    start = time.perf_counter()
    results = prove(model, points=args.points, seed=args.seed, method=args.method, progress=not args.json)
    sprung = sprung_joints(model.tree)
    skipped = ([f"the Section 4 regressor (35)-(37) is not checked: joint {sprung[0]!r} has a spring, for which "
                "the regressor has no term (the controller and identification refuse the scene)"] if sprung else [])
    if not sprung:
        results += prove_regressor(model, points=args.points, seed=args.seed)
    elapsed = time.perf_counter() - start
    ok = all(r.passed for r in results)
    if args.json:
        print(json.dumps({"scene": model.scene.name, "passed": ok, "seconds": round(elapsed, 3),
                          "results": [r.as_dict() for r in results], "skipped": skipped}, indent=1))
    else:
        print(f"scene {model.scene.name}  ({', '.join(f'{k}={v}' for k, v in model.counts.as_dict().items())})")
        for r in results:
            status = "PASS" if r.passed else "FAIL"
            print(f"  {status}  {r.name:<52} {r.equation:<16} {r.method}, {r.points} point(s)"
                  + (f"  -- {r.detail}" if r.detail else ""))
        for text in skipped:
            print(f"  SKIP  {text}")
        print(f"{'all properties hold' if ok else 'SOME PROPERTIES FAIL'}{' (one skipped)' if skipped else ''} "
              f"({elapsed:.1f} s)")
    return 0 if ok else 1


def cmd_export(args) -> int:
    from ..io.scene_yaml import dump_scene

    print(dump_scene(load_scene(args)), end="")
    return 0


def _frame_options(args) -> dict:
    """``--frame`` and ``--axes``: the options of the frame functions (``frame_pose``,
    ``frame_jacobian``, ``frame_drift``; :mod:`symgen.frame_kinematics`)."""
    return {"frame": args.frame, "axes": args.axes} if args.frame else {}


def _add_frame_options(p) -> None:
    p.add_argument("--frame", help="frame_pose, frame_jacobian, frame_drift: the scene's frame they are of")
    p.add_argument("--axes", choices=("local", "world_aligned"), default="local",
                   help="frame_jacobian, frame_drift: the frame's own axes (Pinocchio's LOCAL) or the world's "
                        "(LOCAL_WORLD_ALIGNED), at the frame's origin either way")


def cmd_generate(args) -> int:
    from ..codegen.generate import generate
    from ..io.writer import write_tree

    model = _derive(args)
    functions = [f.strip() for f in args.functions.split(",") if f.strip()] if args.functions else None
    options = {"uncertain": args.uncertain} if args.uncertain else {}
    options.update(_frame_options(args))
    if functions and "control" in functions:
        if args.gain is None:
            raise SymgenError("generate: the controller needs its feedback gain: --gain K (K_A = K 1, K > 0) or "
                              "--gain input (K_A an n x n input of the generated function)")
        options["gain"] = args.gain
    elif args.gain is not None:
        raise SymgenError("generate: --gain is the feedback gain of the control function; add control to --functions")
    start = time.perf_counter()
    gen = generate(model, args.target, functions, options=options or None, show_progress=True,
                   python_extension=args.python_extension, parameters=_parameters(args))
    out = write_tree(args.out, gen.files, force=args.force)
    print(f"wrote {len(gen.files)} files to {out} ({time.perf_counter() - start:.2f} s)")
    for name, ops in gen.ops.items():
        print(f"  {name:<22} {ops['mul']:>7} mul {ops['add']:>7} add {ops['trig']:>5} trig"
              + (f"  + LU {ops['factorizations']}" if ops["factorizations"] else ""))
    return 0


def _parameters(args) -> list[str] | None:
    """The run-time parameters of ``--parameters`` and ``--payload`` (a body's ten), in that order."""
    names = [n.strip() for n in (args.parameters or "").split(",") if n.strip()]
    names += [b.strip() for b in (args.payload or "").split(",") if b.strip()]
    return names or None


def _add_parameter_options(p) -> None:
    p.add_argument("--parameters", help="comma-separated inertial parameters read at run time from an extra "
                                        "last input p instead of folded: BODY (its ten), BODY.mass, BODY.com, "
                                        "BODY.inertia, or a parameter the scene declares")
    p.add_argument("--payload", help="comma-separated bodies whose ten inertial parameters (mass, com, inertia "
                                     "about the com) are read from p; the same as naming them in --parameters")


def cmd_ops(args) -> int:
    from ..codegen.generate import operation_counts
    from ..codegen.linearity import family_counts, fit_line

    if args.fit and _parameters(args):
        raise SymgenError("ops: --fit counts the family with every constant folded; drop --parameters/--payload")
    if args.fit:
        rows = family_counts(args.fit, function=args.function)
        sizes, totals = [s for s, _ in rows], [o["total"] for _, o in rows]
        fit = fit_line(sizes, totals)
        if args.json:
            print(json.dumps({"family": args.fit, "function": args.function,
                              "counts": {str(s): o for s, o in rows},
                              "fit": {"slope": fit.slope, "intercept": fit.intercept, "r2": fit.r2}}, indent=1))
            return 0
        key = "N" if args.fit == "chain" else "H"
        print(f"{args.function} on {args.fit}: total = mul + add")
        print(f"{key:>4} {'mul':>8} {'add':>8} {'total':>8} {'per ' + key:>8}")
        for s, o in rows:
            print(f"{s:>4} {o['mul']:>8} {o['add']:>8} {o['total']:>8} {o['total'] / s:>8.1f}")
        print(f"fit: total = {fit}")
        return 0
    if not args.scene:
        raise SymgenError("give a SCENE, or --fit chain|multi_arm")
    model = _derive(args)
    functions = [f.strip() for f in args.functions.split(",") if f.strip()] if args.functions else None
    counts = operation_counts(model, functions, _frame_options(args) or None, parameters=_parameters(args))
    if args.json:
        print(json.dumps({"scene": model.scene.name, "functions": counts}, indent=1))
        return 0
    print(f"scene {model.scene.name}: mul (div included), add (sub included), total = mul + add")
    print(f"  {'function':<22} {'mul':>7} {'div':>5} {'add':>7} {'total':>7} {'trig':>5} {'sqrt':>5} "
          f"{'lib flops':>11} {'all':>7}  library calls; pivots checked")
    for name, o in counts.items():
        parts = [f"LU {o['factorizations']}, {len(o['solves'])} solves"] if o["factorizations"] else []
        parts += [f"{len(o['products'])} products"] if o.get("products") else []
        lib = ", ".join(parts) or "-"
        if o.get("pivot_checks"):
            lib += f"; {sum(o['pivot_checks'])}"
        print(f"  {name:<22} {o['mul']:>7} {o['div']:>5} {o['add']:>7} {o['total']:>7} {o['trig']:>5} "
              f"{o['sqrt']:>5} {library_flops(o):>11} {o['total'] + library_flops(o):>7}  {lib}")
        if "method_costs" in o:
            costs = ", ".join(f"{route} {cost}" for route, cost in sorted(o["method_costs"].items()))
            print(f"  {'':<22} route kept: {o['method']} (ops + library flops of each: {costs})")
    return 0


#: The modules that add the application packages' commands: each ``register(subparsers)`` adds them.
COMMAND_MODULES = (simulation, accuracy, stability, complexity, urdf, control, identification)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="symgen", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("scenes", help="list the built-in scenes")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_scenes)
    p = sub.add_parser("info", help="counts of Steps 1-8 (n1a n1u n3a n3u m nc np n)")
    add_scene(p)
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_info)
    p = sub.add_parser("steps", help="print the quantities of the twelve steps at the reference configuration")
    add_scene(p)
    p.add_argument("--quantity", "-q", action="append", help="only this quantity (repeatable), e.g. T_S, J_f, M")
    p.add_argument("--field", choices=("float", "symbolic"), default="float")
    p.set_defaults(func=cmd_steps)
    p = sub.add_parser("export", help="print a scene (built-in or file) as YAML")
    add_scene(p)
    p.set_defaults(func=cmd_export)
    p = sub.add_parser("prove", help="check the model's properties (exit status 1 if one fails)")
    add_scene(p)
    p.add_argument("--json", action="store_true")
    p.add_argument("--points", type=int, default=3, help="sampled configurations for the exact checks")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--method", choices=("auto", "exact", "symbolic"), default="auto")
    p.set_defaults(func=cmd_prove)
    p = sub.add_parser("generate", help="emit NumPy or C code for a scene (atomic write)")
    add_scene(p)
    p.add_argument("--target", choices=TARGETS, required=True)
    p.add_argument("--out", required=True, help="output directory (replaced as a whole)")
    p.add_argument("--functions", help="comma-separated subset, e.g. inverse_dynamics,mass_matrix")
    p.add_argument("--force", action="store_true", help="replace a directory symgen did not create")
    p.add_argument("--uncertain", help="control/adaptation: comma-separated parameters (names or patterns, "
                                       "e.g. m_link3,*_object) that are inputs P_hat; 'all' (default) or 'none'")
    p.add_argument("--gain", type=_gain, help="control: the feedback gain K_A of (34), a positive number K "
                                                "(K_A = K 1) or 'input' (an n x n input of the generated function)")
    p.add_argument("--python-extension", action="store_true",
                   help="C target: also a CPython extension module (<scene>_ext.c, imported by <scene>_ext.py), "
                        "one state per call at the cost of a built-in function call")
    _add_frame_options(p)
    _add_parameter_options(p)
    p.set_defaults(func=cmd_generate)
    p = sub.add_parser("ops", help="operation counts of the generated functions")
    add_scene(p, nargs="?")
    p.add_argument("--json", action="store_true")
    p.add_argument("--functions", help="comma-separated subset")
    p.add_argument("--fit", choices=("chain", "multi_arm"), help="counts over the family and the linear fit")
    p.add_argument("--function", default="inverse_dynamics", help="the function --fit counts")
    _add_frame_options(p)
    _add_parameter_options(p)
    p.set_defaults(func=cmd_ops)
    for module in COMMAND_MODULES:
        module.register(sub)
    return parser


def _gain(text: str):
    """``--gain``: ``input`` or a positive finite number."""
    if text == "input":
        return text
    return bounded(float, low=0, low_open=True, high=1e30)(text)


def _file_problem(exc: OSError) -> str:
    """One line for a file that cannot be read or written: the path and the system's reason."""
    where = f" {exc.filename!r}" if exc.filename is not None else ""
    return f"cannot use the file{where}: {exc.strerror or exc}"


def _silence_stdout() -> None:
    """Point stdout at the null device, so that the interpreter's final flush into a closed pipe
    does not print a second error (the recipe of Python's ``signal`` documentation)."""
    import os

    try:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):    # stdout is not a file (captured by a test)
        pass


def main(argv=None) -> int:
    """Run one command; the exit status (0 success, 1 a failed proof, 2 an error)."""
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except SymgenError as exc:
        print(f"symgen: error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:           # the reader went away (``symgen ... | head``): nothing left to say
        _silence_stdout()
        return 1
    except OSError as exc:            # a file named on the command line: missing, a directory, no permission
        print(f"symgen: error: {_file_problem(exc)}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
