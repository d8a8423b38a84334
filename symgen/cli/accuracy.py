"""``symgen accuracy SCENE``: relative error against a 50-digit mpmath reference and per-call time of
the generated NumPy and C functions, ``sympy.lambdify`` and the dense float model, as one table
(:mod:`symgen.accuracy.table`)."""
from __future__ import annotations

import json
import pathlib
import re

from .args import bounded

#: longest time limit of the lambdify column's subprocess (s)
MAX_LAMBDIFY_TIMEOUT = 3600.0


def register(subparsers) -> None:
    p = subparsers.add_parser("accuracy", help="error against an extended-precision (mpmath) reference and "
                                               "time per call of the generated functions")
    p.add_argument("scene")
    p.add_argument("--states", type=int, default=20, help="random loop-closed states (default 20)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--dps", type=int, default=50, help="decimal digits of the mpmath reference (>= 20, default 50)")
    p.add_argument("--functions", nargs="+", metavar="NAME",
                   help="only these generated functions (names, or one comma-separated list)")
    p.add_argument("--lambdify-timeout", type=bounded(float, low=0, high=MAX_LAMBDIFY_TIMEOUT), default=None,
                   metavar="SECONDS", help="time limit of the lambdify column's subprocess (default 60; 0 skips it; "
                                           f"at most {MAX_LAMBDIFY_TIMEOUT:g})")
    p.add_argument("--floor", type=float, default=None, metavar="F",
                   help="denominator floor of the relative error, in the outputs' units (default 1e-2)")
    p.add_argument("--json", action="store_true", help="print the report as JSON")
    p.add_argument("--out", metavar="DIR", help="also write accuracy_<scene>.md and .csv into DIR")
    p.set_defaults(func=cmd_accuracy)


def cmd_accuracy(args) -> int:
    from ..accuracy.lambdify import DEFAULT_TIMEOUT
    from ..accuracy.table import FLOOR, accuracy_report, check_request, format_text, markdown, write_csv

    functions = [f for item in args.functions or [] for f in item.split(",") if f.strip()] or None
    functions = [f.strip() for f in functions] if functions else None
    floor = FLOOR if args.floor is None else args.floor
    check_request(args.states, args.dps, functions, floor)      # typed errors before the slow part
    timeout = DEFAULT_TIMEOUT if args.lambdify_timeout is None else args.lambdify_timeout
    report = accuracy_report(args.scene, states=args.states, seed=args.seed, dps=args.dps, functions=functions,
                             lambdify_timeout=timeout, floor=floor)
    print(json.dumps(report.as_dict(), indent=1) if args.json else format_text(report), end="" if not args.json else "\n")
    if args.out:
        out = pathlib.Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        slug = re.sub(r"[^A-Za-z0-9]+", "_", pathlib.Path(args.scene).stem if args.scene.endswith((".yaml", ".yml"))
                      else args.scene).strip("_")
        (out / f"accuracy_{slug}.md").write_text(markdown(report))
        write_csv(report, out / f"accuracy_{slug}.csv")
        if not args.json:
            print(f"wrote {out / f'accuracy_{slug}.md'} and {out / f'accuracy_{slug}.csv'}")
    return 0
