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


def cmd_control(args) -> int:
    from .demo import run_demo
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
