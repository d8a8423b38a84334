"""Fuzz the command line with many seeded mutations (``tests/fuzz_cli.py``), in-process.

Case ``k`` mutates one of the templates of ``tests/fuzz_cli.py`` with ``random.Random(k)`` and runs
it through ``symgen.cli.main`` in a scratch folder under the time bound ``CLI_CASE_BOUND``. Anything
but a parser refusal or a status 0/1/2 (status 2 with one error line) is a finding: an exception
escaping ``main``, a traceback, an untidy message, or a hang. Runs seeds ``start ..`` until
``--cases`` are done or ``--minutes`` have passed; writes ``fuzz_cli.md`` beside this file.

    python benchmarks/fuzz_cli.py [--cases 10000] [--minutes 10] [--start 0]
"""
from __future__ import annotations

import argparse
import collections
import pathlib
import random
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from tests.fuzz_cli import CLI_CASE_BOUND, make_files, mutate_argv, run_cli_case  # noqa: E402


def run(cases: int, minutes: float, start: int, folder: pathlib.Path) -> dict:
    files = make_files(folder)
    counts: collections.Counter = collections.Counter()
    findings, slowest = [], (0.0, None)
    begin = time.perf_counter()
    done = 0
    for seed in range(start, start + cases):
        if time.perf_counter() - begin > 60 * minutes:
            break
        argv = mutate_argv(random.Random(seed), files)
        scratch = folder / f"case{seed}"
        scratch.mkdir()
        t0 = time.perf_counter()
        outcome, finding = run_cli_case(argv, scratch)
        took = time.perf_counter() - t0
        if took > slowest[0]:
            slowest = (took, seed)
        counts[(argv[0] if argv else "-", outcome)] += 1
        if finding:
            findings.append((seed, argv, finding))
        done += 1
    return dict(counts=counts, findings=findings, slowest=slowest, seconds=time.perf_counter() - begin,
                cases=done, start=start)


def write(result: dict) -> pathlib.Path:
    lines = ["# Fuzzing the command line", "",
             f"{result['cases']} cases (seeds {result['start']}..{result['start'] + result['cases'] - 1}), mutated "
             "command lines of `tests/fuzz_cli.py` run in-process through `symgen.cli.main`, in "
             f"{result['seconds']:.0f} s. Time bound per case: {CLI_CASE_BOUND:g} s; slowest case "
             f"{result['slowest'][0]:.2f} s (seed {result['slowest'][1]}). Reproduce with "
             f"`python benchmarks/fuzz_cli.py --cases {result['cases']}`.", "",
             "| command | outcome | cases |", "|---|---|---|"]
    for (command, outcome), n in sorted(result["counts"].items()):
        lines.append(f"| {command} | {outcome} | {n} |")
    lines += ["", f"Findings (an exception escaping `main`, a traceback, a status-2 message that is not one line, "
                  f"or a hang): {len(result['findings'])}.", ""]
    for seed, argv, what in result["findings"][:20]:
        lines += [f"* seed {seed}: `{' '.join(argv)}`: {what}"]
    out = pathlib.Path(__file__).resolve().parent / "fuzz_cli.md"
    out.write_text("\n".join(lines).rstrip("\n") + "\n", encoding="utf-8")
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=10_000)
    parser.add_argument("--minutes", type=float, default=float("inf"))
    parser.add_argument("--start", type=int, default=0)
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        result = run(args.cases, args.minutes, args.start, pathlib.Path(tmp))
    print(write(result).read_text(encoding="utf-8"))
    return 1 if result["findings"] else 0


if __name__ == "__main__":
    raise SystemExit(main())
