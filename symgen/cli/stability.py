"""``symgen stability``: the stiff and extreme cases, as a table (or JSON)."""
from __future__ import annotations

import json

from ..codegen.targets import TARGETS


def register(subparsers) -> None:
    p = subparsers.add_parser("stability", help="stiff and extreme cases: conditioning, residual, error against "
                                                "50 digits, and which integrators succeed at what cost")
    p.add_argument("--cases", help="comma-separated case names (default: all; see --list)")
    p.add_argument("--list", action="store_true", help="list the cases and exit")
    p.add_argument("--backend", choices=TARGETS, default="c", help="generated code to test (default c)")
    p.add_argument("--no-integrators", action="store_true", help="evaluate the states only, no runs")
    p.add_argument("--json", action="store_true", help="print the results as JSON")
    p.add_argument("--out", metavar="DIR", help="also write stability.md and stability.csv into DIR (atomic)")
    p.set_defaults(func=cmd_stability)


def cmd_stability(args) -> int:
    import warnings

    from ..stability.cases import all_cases, get_case
    from ..stability.report import csv_text, markdown
    from ..stability.runner import IllConditionedWarning, run_case

    if args.list:
        for case in all_cases():
            print(f"{case.name:<24} {case.kind:<9} expects {case.expect:<9} {case.description}")
        return 0
    if args.cases is None:
        cases = all_cases()
    else:
        cases = [get_case(n.strip()) for n in args.cases.split(",") if n.strip()]
        if not cases:
            from ..errors import SymgenError

            raise SymgenError(f"--cases: no case named in {args.cases!r} (omit --cases for all; see --list)")
    results = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IllConditionedWarning)  # reported in the table's messages
        for case in cases:
            if not args.json:
                print(f"  running {case.name} ...", flush=True)
            results.append(run_case(case, args.backend, integrators=not args.no_integrators))
    if args.json:
        print(json.dumps([r.as_dict() for r in results], indent=1))
    else:
        print(markdown(results, args.backend), end="")
    if args.out:
        from ..io.writer import write_tree

        write_tree(args.out, {"stability.md": markdown(results, args.backend), "stability.csv": csv_text(results)},
                   force=False)
    unexpected = [r.name for r in results if not r.as_expected]
    if unexpected:
        print(f"symgen: cases not as expected: {', '.join(unexpected)}")
    return 1 if unexpected else 0
