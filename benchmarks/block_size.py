"""How the C target's block size moves the machine code and the time of long generated functions.

A generated C function beyond ``SPLIT_STATEMENTS`` statements is cut into static blocks of at most
``BLOCK_STATEMENTS`` statements (:mod:`symgen.codegen.targets.c_blocks`). For each scene of
``SCENES`` and function of ``FUNCTIONS`` (traced once), the C file is rendered whole and cut at
each block size of ``BLOCKS`` (every function cut, whatever its length), compiled by each of
``cc`` and ``clang`` (``-O3 -march=native -std=c99 -DSYMGEN_NO_LANES``), and

* **code KB**: the machine code of the function, its public symbol and its blocks (``nm -S``);
* **ns**: one call per state over 200 states (``codegen_timing.c -DDERIVATIVES``, thread CPU
  clock, the median of its repeats), the median over interleaved rounds (every variant once per
  round), and **/ whole**: that time over the whole function's of the same build and round
  (median over rounds);
* **max rel diff**: the outputs of every variant against the whole function's of the same compiler
  (the same statements in the same order: 0 unless a compiler contracts across statements).

Writes ``block_size.md`` and ``block_size.csv`` beside this file.

    python benchmarks/block_size.py [--rounds R] [--scenes SPEC ...]
"""
from __future__ import annotations

import argparse
import csv
import json
import re
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from codegen_speed import C_COMPILERS, compiler_name, fmt, machine, write_generated  # noqa: E402
from derivative_speed import GENERATED_CFLAGS, N_STATES, compile_timers, run  # noqa: E402

SCENES = ["general_chain:n=7", "panda", "chain:n=6"]
FUNCTIONS = ["inverse_dynamics_derivatives", "forward_dynamics_derivatives"]
#: block sizes tried (``None``: the function whole)
BLOCKS = [None, 500, 1000, 2000, 5000]
REPEATS = 9


def variant_name(block) -> str:
    return "whole" if block is None else f"blocks of {block}"


def code_bytes(obj: Path, symbol: str) -> int:
    """Bytes of machine code of ``symbol`` and of its ``_block<k>`` functions in ``obj``, with the
    parts a compiler splits off them (GCC's ``.cold``, ``.constprop.0``, ...)."""
    out = subprocess.run(["nm", "-S", str(obj)], capture_output=True, text=True, check=True).stdout
    mine = re.compile(rf"{re.escape(symbol)}(_block\d+)?(\..*)?")
    return sum(int(parts[1], 16) for parts in map(str.split, out.splitlines())
               if len(parts) == 4 and mine.fullmatch(parts[3]))


def build(spec: str, work: Path) -> tuple[list[dict], int]:
    """Every variant's timers: one dict per (variant, function, compiler)."""
    from symgen.codegen.generate import generate, trace_all
    from symgen.codegen.targets import target
    from symgen.io.builtin import get_scene
    from symgen.model import derive

    model = derive(get_scene(spec))
    n = model.counts.n
    lowered = trace_all(model, FUNCTIONS)
    c = target("c")
    saved = c.split_statements, c.block_statements
    builds = []
    try:
        for block in BLOCKS:
            c.split_statements, c.block_statements = (10**12, saved[1]) if block is None else (0, block)
            gen = generate(model, "c", lowered=lowered)
            variant = variant_name(block)
            src = write_generated(gen, work / f"{gen.module}_{variant.replace(' ', '_')}")
            ops = {f: v["total"] for f, v in json.loads(gen.files["ops.json"])["functions"].items()}
            for cc in C_COMPILERS:
                obj = src / f"{gen.module}_{compiler_name(cc)}.o"
                timers = {f"symgen_{gen.module}_{f}": src / f"timer_{f}_{compiler_name(cc)}" for f in FUNCTIONS}
                compile_timers(cc, [], src / f"{gen.module}.c", obj, timers, n)
                for function, (symbol, timer) in zip(FUNCTIONS, timers.items()):
                    builds.append(dict(scene=spec, function=function, ops=ops[function], variant=variant,
                                       compiler=compiler_name(cc), code_kb=code_bytes(obj, symbol) / 1024,
                                       timer=timer))
    finally:
        c.split_statements, c.block_statements = saved
    return builds, n


def bench(builds: list[dict], n: int, rounds: int, work: Path, baseline=None, key: str = "vs_whole") -> list[dict]:
    """Time every build's timer in interleaved rounds (the generated functions read ``n`` of each
    input per state) and compare it with its ``baseline(build, builds)`` (default: the whole
    function of the same function and compiler): one row per build, without its ``timer``, with
    ``ns`` (median over rounds), ``key`` (median of the per-round ratios to the baseline) and
    ``max_rel_diff`` (outputs against the baseline's)."""
    baseline = baseline or (lambda b, every: next(w for w in every if w["variant"] == "whole"
                                                  and w["function"] == b["function"] and w["compiler"] == b["compiler"]))
    rng = np.random.default_rng(3)
    states = work / f"states_{n}.bin"
    np.concatenate([rng.uniform(-1, 1, N_STATES * n) for _ in range(3)]).tofile(states)
    out = work / "out.bin"
    times = {id(b): [] for b in builds}
    outputs = {}
    for _ in range(rounds):
        for b in builds:
            result = subprocess.run([str(c) for c in [b["timer"], states, N_STATES, REPEATS, out]],
                                    capture_output=True, text=True, check=True)
            times[id(b)].append(float(result.stdout.split()[0]))
            outputs[id(b)] = np.fromfile(out)
    rows = []
    for b in builds:
        base = baseline(b, builds)
        ref = outputs[id(base)]
        rel = float(np.abs(outputs[id(b)] - ref).max() / max(np.abs(ref).max(), 1e-300))
        rows.append({k: v for k, v in b.items() if k != "timer"} | {
            "ns": statistics.median(times[id(b)]),
            key: statistics.median(t / w for t, w in zip(times[id(b)], times[id(base)])),
            "max_rel_diff": rel})
    return rows


def write_tables(stem: str, text: str, rows: list[dict]) -> None:
    """``<stem>.md`` (``text``) and ``<stem>.csv`` (``rows``) beside this file."""
    (HERE / f"{stem}.md").write_text(text)
    with open(HERE / f"{stem}.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


def markdown(rows: list[dict], rounds: int) -> str:
    from symgen.codegen.targets.c_blocks import BLOCK_STATEMENTS, SPLIT_STATEMENTS

    head = ["scene", "function", "ops", "variant", "compiler", "code KB", "ns", "/ whole", "max rel diff"]
    lines = ["# Block size of long generated C functions: machine code and time", "",
             "`python benchmarks/block_size.py`. Each function traced once, its C rendered whole and cut into "
             "blocks of each size (every function cut, whatever its length), compiled by each compiler "
             f"(`{' '.join(GENERATED_CFLAGS)}`). **ops**: mul + add (`ops.json`); **code KB**: "
             "machine code of the function and its blocks (`nm -S`); **ns**: one call per state over "
             f"{N_STATES} states (`codegen_timing.c -DDERIVATIVES`, thread CPU clock), median over interleaved "
             "rounds; **/ whole**: over the whole function's time, same compiler and round (median); "
             "**max rel diff**: outputs against the whole function's, same compiler.", "",
             f"Defaults: functions beyond `SPLIT_STATEMENTS = {SPLIT_STATEMENTS}` statements are cut into blocks "
             f"of `BLOCK_STATEMENTS = {BLOCK_STATEMENTS}`; functions of at most {SPLIT_STATEMENTS} statements "
             f"(ops below) stay whole. {rounds} rounds of {REPEATS} repeats; {machine()}.", "",
             "| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        lines.append(f"| {r['scene']} | {r['function']} | {r['ops']} | {r['variant']} | {r['compiler']} | "
                     f"{r['code_kb']:.1f} | {fmt(r['ns'])} | {r['vs_whole']:.2f} | {r['max_rel_diff']:.1e} |")
    return "\n".join(lines) + "\n"


def run(argv, description: str, scenes: list[str], build, stem: str, markdown, baseline=None,
        key: str = "vs_whole") -> None:
    """The command line of a variants benchmark: ``--rounds``, ``--scenes`` (default ``scenes``);
    per scene ``build(spec, work) -> (builds, n)`` then :func:`bench` (``baseline``, ``key``), a
    line per row as it comes, and :func:`write_tables` of ``markdown(rows, rounds)``."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--scenes", nargs="*", default=scenes)
    args = parser.parse_args(argv)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for spec in args.scenes:
            builds, n = build(spec, Path(tmp))
            rows += bench(builds, n, args.rounds, Path(tmp), baseline, key)
            for r in rows[-len(builds):]:
                print(" ".join(str(r[k]) for k in ("scene", "function", "variant", "order", "compiler", "build")
                               if k in r), f"{r['code_kb']:.1f} KB {r['ns']:.0f} ns {r[key]:.2f}", flush=True)
    write_tables(stem, markdown(rows, args.rounds), rows)


def main(argv=None) -> None:
    run(argv, __doc__.split("\n")[0], SCENES, build, "block_size", markdown)


if __name__ == "__main__":
    main()
