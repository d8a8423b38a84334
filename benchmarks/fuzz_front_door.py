"""Fuzz the front door with many seeded mutations (the mutators of ``tests/fuzz_inputs.py``).

Case ``k`` mutates a scene file (``k`` even) or a URDF (``k`` odd) with ``random.Random(k)``, then
loads, derives and generates code under the time bound ``CASE_BOUND``; every accepted case's C is
compiled with ``cc -std=c99 -Wall -Wextra -Werror -pedantic`` (once per distinct source) and its
Python files are imported. Anything but a ``SymgenError`` refusal or clean generated code is a
finding. Writes ``fuzz_front_door.md`` beside this file (counts, slowest case, findings).

    python benchmarks/fuzz_front_door.py [--cases 12000] [--start 0]
"""
from __future__ import annotations

import argparse
import collections
import pathlib
import random
import sys
import tempfile
import time
import traceback

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from tests.fuzz_inputs import CASE_BOUND, check_generated, mutate_urdf, mutate_yaml, run_case  # noqa: E402


def run(cases: int, start: int, folder: pathlib.Path) -> dict:
    counts: collections.Counter = collections.Counter()
    findings, compiled, slowest = [], set(), (0.0, None)
    begin = time.perf_counter()
    for seed in range(start, start + cases):
        kind = "yaml" if seed % 2 == 0 else "urdf"
        rng = random.Random(seed)
        text = mutate_yaml(rng) if kind == "yaml" else mutate_urdf(rng)
        t0 = time.perf_counter()
        try:
            outcome, generated = run_case(kind, text)
            if generated is not None:
                check_generated(generated, folder, compiled)
                outcome = "accepted, compiled and imported"
        except BaseException as exc:  # noqa: BLE001 - every other exception is the finding
            if isinstance(exc, KeyboardInterrupt):
                raise
            outcome = f"FINDING {type(exc).__name__}"
            findings.append((seed, kind, f"{type(exc).__name__}: {str(exc)[:300]}",
                             traceback.format_exc(limit=-3)[-800:]))
        took = time.perf_counter() - t0
        if took > slowest[0]:
            slowest = (took, seed)
        counts[(kind, outcome)] += 1
    return dict(counts=counts, findings=findings, slowest=slowest, seconds=time.perf_counter() - begin,
                compiled=len(compiled), cases=cases, start=start)


def write(result: dict) -> pathlib.Path:
    lines = ["# Fuzzing the front door", "",
             f"{result['cases']} cases (seeds {result['start']}..{result['start'] + result['cases'] - 1}; even: "
             "scene YAML, odd: URDF), mutators of `tests/fuzz_inputs.py`, in "
             f"{result['seconds']:.0f} s; {result['compiled']} distinct C sources compiled with "
             "`-std=c99 -Wall -Wextra -Werror -pedantic`. Time bound per case: "
             f"{CASE_BOUND:g} s; slowest case {result['slowest'][0]:.2f} s (seed {result['slowest'][1]}). "
             "Reproduce with `python benchmarks/fuzz_front_door.py`.", "",
             "| input | outcome | cases |", "|---|---|---|"]
    for (kind, outcome), n in sorted(result["counts"].items()):
        lines.append(f"| {kind} | {outcome} | {n} |")
    lines += ["", f"Findings (an exception other than a `SymgenError`, a hang, or generated code that does not "
                  f"compile or import): {len(result['findings'])}.", ""]
    for seed, kind, what, trace in result["findings"][:20]:
        lines += [f"* seed {seed} ({kind}): `{what}`", "", "```", trace.strip(), "```", ""]
    out = pathlib.Path(__file__).resolve().parent / "fuzz_front_door.md"
    out.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=12_000)
    parser.add_argument("--start", type=int, default=0)
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        result = run(args.cases, args.start, pathlib.Path(tmp))
    print(write(result).read_text(encoding="utf-8"))
    return 1 if result["findings"] else 0


if __name__ == "__main__":
    raise SystemExit(main())
