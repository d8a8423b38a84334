"""``symgen control SCENE [--report DIR]``: the adaptive controller of Section 4 in closed loop,
with adaptation and with frozen (wrong) estimates, on a demonstration of :mod:`symgen.simulation.control_demo`
or on any other scene with the defaults of :func:`~symgen.simulation.control_demo.default_demo`;
plant and controller from generated code (C when a compiler is there, NumPy otherwise), a progress
bar on a terminal."""
from __future__ import annotations

import dataclasses
import json
import shlex
import sys

from .args import bounded
from ..errors import SymbolicTooLargeError
from ..simulation.closed_loop import MAX_T_END
from ..control.errors import ControlInputError

#: operations of the symbolic regressor (before simplification) that ``--field symbolic`` accepts:
#: simplifying ``chain:n=3`` (1,683 operations) takes about 10 s, ``chain:n=4`` (8,001) about 45 s
MAX_SYMBOLIC_OPS = 2500


def register(subparsers) -> None:
    """Add ``control`` to symgen's command line."""
    p = subparsers.add_parser("control", help="adaptive control (Section 4) in closed loop: tracking, force and "
                                              "estimates with adaptation against frozen wrong estimates")
    p.add_argument("scene", help="any built-in scene or scene file (YAML, URDF, MJCF); the demonstrations of "
                                 "symgen.simulation.control_demo.DEMOS run with their own settings, any other "
                                 "scene with default_demo's")
    p.add_argument("--t-end", type=bounded(float, low=0, low_open=True, high=MAX_T_END),
                   help=f"simulated time (s), at most {MAX_T_END:g}; default: the demonstration's")
    p.add_argument("--backend", choices=("c", "numpy", "dense"),
                   help="generated C or NumPy code, or the dense model per right-hand side (slow); default: "
                        "C when a compiler is on the path, else NumPy")
    p.add_argument("--report", metavar="DIR", help="write control.md, control.csv and control.png into DIR (atomic)")
    p.add_argument("--force", action="store_true", help="replace an existing report directory")
    p.add_argument("--json", action="store_true", help="print the summary as JSON")
    p.add_argument("--regressor", action="store_true",
                   help="print Y = [T_S^T Y_r, Y_m] (eqs. 35-37) column by column instead of simulating")
    p.add_argument("--field", choices=("float", "symbolic"),
                   help="with --regressor: at q0 with V_m = V_mr = 0.1, dV_mr = 0 (float, the default), or in "
                        "symbols c_j, s_j, qd_j, V_r_k, dV_r_k (small trees only)")
    p.set_defaults(func=cmd_control)


def _check_symbolic_scene(model) -> None:
    """``--field symbolic`` only on a tree without constraints: closing loops or solving
    constraint rows in symbols takes minutes (five_bar, arm_on_plane: over 100 s before any output)."""
    if model.scene.constraints or model.partition.u1 or model.partition.a1:
        raise SymbolicTooLargeError(f"scene {model.scene.name!r} has loop closures or constraints: its symbolic "
                                    "regressor would take minutes; use --field float")


def _check_symbolic_size(model, y) -> None:
    """Refuse to simplify a regressor of more than :data:`MAX_SYMBOLIC_OPS` operations."""
    import sympy as sp

    ops = sum(sp.count_ops(v) for v in y.flat)
    if ops > MAX_SYMBOLIC_OPS:
        raise SymbolicTooLargeError(f"scene {model.scene.name!r}: the symbolic regressor has {ops} operations "
                                    f"before simplification (limit {MAX_SYMBOLIC_OPS}, about 10 s); use --field float")


def print_regressor(spec: str, field: str) -> None:
    """Each parameter's column of ``Y`` (space A), skipping the columns that are zero."""
    import numpy as np
    import sympy as sp

    from ..io.loading import load
    from ..model import derive
    from ..control.contact import ContactLaw
    from ..control.law import default_parameters, regressor

    model = derive(load(spec))
    contact = ContactLaw.for_scene(model.scene) if model.scene.contact_forces is not None else None
    m = model.counts.m
    if field == "symbolic":
        _check_symbolic_scene(model)
        data = model.evaluate(model.symbolic_configuration(), qd=model.symbolic_velocity(), field="symbolic")
        v_r, dv_r = sp.symbols(f"V_r0:{m}", real=True), sp.symbols(f"dV_r0:{m}", real=True)
    else:
        data = model.evaluate(model.reference, V_m=np.full(m, 0.1))
        v_r, dv_r = np.full(m, 0.1), np.zeros(m)
    params = default_parameters(model, contact, data.field)
    y, _, _ = regressor(model, data, params, v_r, dv_r, contact=contact)
    if field == "symbolic":
        _check_symbolic_size(model, y)
    print(f"scene {model.scene.name}: Y = [T_S^T Y_r, Y_m] ({y.shape[0]} x {y.shape[1]}), rows in the order "
          f"of qd: {', '.join(model.coordinate_names())}")
    for k, name in enumerate(params.names):
        column = y[:, k]
        if field == "symbolic":
            column = [sp.simplify(v) for v in column]
            if all(v == 0 for v in column):
                continue
            print(f"{name}:")
            for row, v in zip(model.coordinate_names(), column):
                print(f"  {row}: {v}")
        elif np.any(np.asarray(column, float) != 0):
            print(f"{name:<16} {np.array2string(np.asarray(column, float), precision=4, suppress_small=True)}")


def _check_combination(args) -> None:
    """Options of the closed loop and of ``--regressor`` do not mix; the error names the option."""
    if args.regressor:
        for option, given in (("--t-end", args.t_end is not None), ("--report", args.report is not None),
                              ("--backend", args.backend is not None),
                              ("--force", args.force), ("--json", args.json)):
            if given:
                raise ControlInputError(f"{option} applies to the closed-loop run, not to --regressor")
    elif args.field is not None:
        raise ControlInputError("--field applies to --regressor only")
    elif args.force and args.report is None:
        raise ControlInputError("--force applies to --report DIR only")
    if args.report is not None:
        import importlib.util

        if importlib.util.find_spec("matplotlib") is None:
            raise ControlInputError("--report draws control.png with matplotlib, a dependency of symgen that is not "
                                    "installed: pip install matplotlib")


def cmd_control(args) -> int:
    from ..simulation.control_demo import run_demo

    _check_combination(args)
    if args.regressor:
        print_regressor(args.scene, args.field or "float")
        return 0
    from ..simulation.control_report import summary, write_report

    from ..io.loading import load
    from ..model import derive
    from ..simulation.control_demo import DEMOS, default_demo

    model = None if args.scene in DEMOS else derive(load(args.scene))
    demo = default_demo(args.scene, model)
    if args.t_end is not None:
        demo = dataclasses.replace(demo, t_end=args.t_end)
    runs = run_demo(demo, backend=args.backend, model=model)
    s = summary(runs)
    if args.json:
        print(json.dumps({"scene": demo.scene, **s}, indent=1))
    else:
        print(f"scene {demo.scene}: {demo.description}")
        for key, value in s.items():
            print(f"  {key:<30} {value:.4g}" if isinstance(value, float) else f"  {key:<30} {value}")
    if args.report:
        settings = {f.name: getattr(demo, f.name) for f in dataclasses.fields(demo) if f.name != "description"}
        command = "symgen control " + " ".join(shlex.quote(a) for a in sys.argv[2:]) if sys.argv[1:2] == ["control"] \
            else None
        path = write_report(args.report, demo.scene, demo.description, runs, settings, command=command,
                            force=args.force)
        print(f"wrote {path}")
    return 0
