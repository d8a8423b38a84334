"""``symgen complexity``: op counts, derivation time and memory against DOF, as markdown, CSV, PNG.

    symgen complexity [--family chain|multi_arm] [--max-dof N] [--sizes 1,2,4] [--time-limit S]
                      [--methods symgen,kane,lagrange | --no-sympy] [--json] --out DIR

writes ``DIR/<family>.md``, ``DIR/<family>.csv`` and ``DIR/<family>_*.png``. Each (method, size)
runs in its own subprocess killed after ``--time-limit`` seconds (default 60); what did not finish
is shown as "> 60 s", never dropped, and is not attempted again at larger sizes.
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

from ..errors import SymgenError


def register(subparsers) -> None:
    p = subparsers.add_parser("complexity", help="operation counts, derivation time and memory against DOF "
                                                 "(markdown, CSV and PNG)")
    p.add_argument("--family", choices=("chain", "multi_arm"), default="chain",
                   help="chain:n=N (default) or multi_arm:h=H")
    p.add_argument("--max-dof", type=int, help="leave out sizes with more DOF (multi_arm:h=H has 6H)")
    p.add_argument("--sizes", help="comma-separated N (chain) or H (multi_arm); default "
                                   "1,2,3,4,6,8,12,16,24,32,48,64,100 or 1..8")
    p.add_argument("--time-limit", type=float, default=60.0, help="seconds per (method, size), default 60")
    p.add_argument("--methods", help="comma-separated subset of symgen,kane,lagrange (default: all that apply)")
    p.add_argument("--no-sympy", action="store_true", help="measure this formulation only")
    p.add_argument("--out", required=True, help="output directory (created; files of the family replaced)")
    p.add_argument("--json", action="store_true", help="print the measurements as JSON on stdout")
    p.set_defaults(func=cmd_complexity)


def parse_sizes(text: str | None, family: str, max_dof: int | None) -> list[int]:
    from ..complexity.sweep import DEFAULT_SIZES, dof

    if text:
        sizes = []
        for token in text.split(","):
            token = token.strip()
            if not token.isdigit() or int(token) < 1:
                raise SymgenError(f"--sizes: {token!r} is not a positive integer")
            sizes.append(int(token))
    else:
        sizes = list(DEFAULT_SIZES[family])
    if max_dof is not None:
        sizes = [s for s in sizes if dof(family, s) <= max_dof]
    if not sizes:
        raise SymgenError(f"no {family} size left with --max-dof {max_dof}")
    return sorted(set(sizes))


def chosen_methods(args) -> list[str]:
    from ..complexity.sweep import methods_for

    if args.methods and args.no_sympy:
        raise SymgenError("give --methods or --no-sympy, not both")
    if args.methods:
        names = [m.strip() for m in args.methods.split(",") if m.strip()]
    elif args.no_sympy or args.family != "chain":
        names = ["symgen"]
    else:
        names = ["symgen", "kane", "lagrange"]
    return methods_for(args.family, names)


def command_line(args) -> str:
    parts = ["symgen complexity", f"--family {args.family}"]
    if args.sizes:
        parts.append(f"--sizes {args.sizes}")
    if args.max_dof is not None:
        parts.append(f"--max-dof {args.max_dof}")
    parts.append(f"--time-limit {args.time_limit:g}")
    if args.methods:
        parts.append(f"--methods {args.methods}")
    if args.no_sympy:
        parts.append("--no-sympy")
    parts.append(f"--out {args.out}")
    return " ".join(parts)


def load_average() -> float | None:
    import os

    try:
        return os.getloadavg()[0]
    except (AttributeError, OSError):
        return None


def environment(loads=()) -> str:
    """Machine, versions and the 1-minute load average at the start and end of the run (other
    processes sharing the CPUs stretch the wall times, never the op counts)."""
    import os
    import platform

    import sympy

    text = (f"{platform.system()} {platform.machine()}, {os.cpu_count()} CPUs, Python {platform.python_version()}, "
            f"SymPy {sympy.__version__}")
    loads = [x for x in loads if x is not None]
    if loads:
        text += ", 1-minute load average " + " -> ".join(f"{x:.1f}" for x in loads) + " (start -> end of the run)"
    return text


def cmd_complexity(args) -> int:
    from ..complexity.sweep import run_sweep

    if not args.time_limit > 0:
        raise SymgenError(f"--time-limit must be positive, got {args.time_limit}")
    sizes = parse_sizes(args.sizes, args.family, args.max_dof)
    methods = chosen_methods(args)
    load_start = load_average()
    sweep = run_sweep(args.family, sizes, methods, args.time_limit, progress=_progress)
    env = environment((load_start, load_average()))
    files = write_outputs(sweep, Path(args.out), command_line(args), env)
    if args.json:
        print(json.dumps(as_json(sweep, files), indent=1))
    else:
        print(f"wrote {', '.join(str(f) for f in files)}")
    return 0


def write_outputs(sweep, out: Path, command: str, env: str) -> list[Path]:
    from ..complexity import plots
    from ..complexity.report import chain_markdown, multi_arm_markdown
    from ..complexity.tables import to_csv

    out.mkdir(parents=True, exist_ok=True)
    fam = sweep.family
    md = chain_markdown(sweep, command, env) if fam == "chain" else multi_arm_markdown(sweep, command, env)
    files = [out / f"{fam}.md", out / f"{fam}.csv"]
    files[0].write_text(md)
    files[1].write_text(to_csv(sweep))
    if fam == "chain":
        files.append(plots.chain_ops_plot(sweep, out / "chain_ops.png"))
        files.append(plots.chain_time_plot(sweep, out / "chain_time.png"))
    else:
        files.append(plots.multi_arm_ops_plot(sweep, out / "multi_arm_ops.png"))
    return files


def as_json(sweep, files) -> dict:
    from ..complexity.sweep import method_stages

    results = []
    for (method, size), outcome in sweep.cells.items():
        for stage in method_stages(method):
            status, rec = outcome.stages[stage]
            results.append({"method": method, "size": size, "stage": stage,
                            "status": sweep.display(method, size, stage),
                            **{k: v for k, v in rec.items() if k != "stage"}})
    return {"family": sweep.family, "time_limit": sweep.time_limit, "sizes": sweep.sizes, "methods": sweep.methods,
            "files": [str(f) for f in files], "results": results}


def _progress(method, size, outcome) -> None:
    parts = []
    for stage, (status, rec) in outcome.stages.items():
        parts.append(f"{stage} {rec['seconds']:.2f} s" if status == "ok" else f"{stage} {status}")
    print(f"  {method:<30} {size:>4}: {', '.join(parts)}", file=sys.stderr, flush=True)
