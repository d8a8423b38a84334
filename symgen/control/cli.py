"""``symgen control SCENE [--report DIR]``: the adaptive controller of Section 4 in closed loop,
with adaptation and with frozen (wrong) estimates, on a demonstration of :mod:`symgen.control.demo`
or, for any other scene, with every massive body's parameters 30% too large at the start."""
from __future__ import annotations

import dataclasses
import json
import shlex
import sys


def register(subparsers) -> None:
    p = subparsers.add_parser("control", help="adaptive control (Section 4) in closed loop: tracking, force and "
                                              "estimates with adaptation against frozen wrong estimates")
    p.add_argument("scene", help="built-in scene or scene file (demonstrations: see symgen.control.demo.DEMOS)")
    p.add_argument("--t-end", type=float, help="simulated time (s); default: the demonstration's")
    p.add_argument("--report", metavar="DIR", help="write control.md, control.csv and control.png into DIR (atomic)")
    p.add_argument("--force", action="store_true", help="replace an existing report directory")
    p.add_argument("--json", action="store_true", help="print the summary as JSON")
    p.add_argument("--regressor", action="store_true",
                   help="print Y = [T_S^T Y_r, Y_m] (eqs. 35-37) column by column instead of simulating")
    p.add_argument("--field", choices=("float", "symbolic"), default="float",
                   help="with --regressor: at q0 with V_m = V_mr = 0.1, dV_mr = 0 (float), or in symbols "
                        "c_j, s_j, qd_j, V_r_k, dV_r_k (small scenes)")
    p.set_defaults(func=cmd_control)


def _demo(spec: str):
    from ..loading import load
    from ..model import derive
    from .demo import DEMOS, Demo

    if spec in DEMOS:
        return DEMOS[spec]
    model = derive(load(spec))
    bodies = {b.name: 1.3 for b in model.tree.bodies if not b.massless}
    return Demo(spec, bodies, description=f"{spec}: every massive body's parameters start 30% too large")


def print_regressor(spec: str, field: str) -> None:
    """Each parameter's column of ``Y`` (space A), skipping the columns that are zero."""
    import numpy as np
    import sympy as sp

    from ..loading import load
    from ..model import derive
    from .contact import ContactLaw
    from .law import default_parameters, regressor

    model = derive(load(spec))
    contact = ContactLaw.for_scene(model.scene) if model.scene.contact_forces is not None else None
    m = model.counts.m
    if field == "symbolic":
        data = model.evaluate(model.symbolic_configuration(), qd=model.symbolic_velocity(), field="symbolic")
        v_r, dv_r = sp.symbols(f"V_r0:{m}", real=True), sp.symbols(f"dV_r0:{m}", real=True)
    else:
        data = model.evaluate(model.reference, V_m=np.full(m, 0.1))
        v_r, dv_r = np.full(m, 0.1), np.zeros(m)
    params = default_parameters(model, contact, data.field)
    y, _, _ = regressor(model, data, params, v_r, dv_r, contact=contact)
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


def cmd_control(args) -> int:
    from .demo import run_demo

    if args.regressor:
        print_regressor(args.scene, args.field)
        return 0
    from .report import summary, write_report

    demo = _demo(args.scene)
    if args.t_end:
        demo = dataclasses.replace(demo, t_end=args.t_end)
    runs = run_demo(demo)
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
