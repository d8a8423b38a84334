"""Cost of the generated code's finiteness checks, side by side with the same code without them.

Every generated C function checks its outputs (``SYMGEN_NONFINITE``) and every NumPy function
its outputs (``NonFiniteOutputError``); the arguments are checked apart (NumPy module and ctypes
binding), not inside the C functions. This script renders the code of a few scenes,
makes a copy with the check lines removed, and times both per call:

* **C**: called once per state from a small C harness (written here), ``cc -O2 -std=c99``, over
  ``N_STATES`` loop-closed states (:func:`symgen.codegen.reference.reference_states`: random
  states would make closed chains' solves singular, and a singular solve returns early), median
  of ``REPEATS`` passes;
* **NumPy**: one state per call (the worst case: fixed overhead) and ``BATCH`` states per call.

Writes ``nonfinite_check.md`` beside this file; build products go to a temporary directory.

    python benchmarks/nonfinite_check.py [--quick]
"""
from __future__ import annotations

import argparse
import importlib.util
import os
import platform
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import symgen  # noqa: E402
from symgen.codegen.generate import generate, trace_all  # noqa: E402
from symgen.codegen.reference import reference_states  # noqa: E402

HERE = Path(__file__).resolve().parent
SCENES = ("chain:n=6", "four_bar", "stewart", "arm_on_plane")
FUNCTIONS = ("inverse_dynamics", "forward_dynamics")
N_STATES, REPEATS, BATCH, SEED, ROUNDS = 1000, 21, 1000, 7, 7
#: distinct loop-closed states (closing a loop is slow: they are repeated to fill the N_STATES)
N_DISTINCT = 50
CC = os.environ.get("CC", "cc")
CHECK_C = re.compile(r"^\s*if \(.*!symgen_finite\(.*\) return SYMGEN_NONFINITE;\n", re.M)
CHECK_PY = re.compile(r"^\s*_check_outputs\(.*\n", re.M)

HARNESS = """#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include "{module}.h"
static double now(void) {{ struct timespec t; clock_gettime(CLOCK_MONOTONIC, &t); return 1e9 * t.tv_sec + t.tv_nsec; }}
static int cmp(const void *a, const void *b) {{ double x = *(const double *)a, y = *(const double *)b; return (x > y) - (x < y); }}
int main(void)
{{
{decls}
    FILE *f = fopen("states.bin", "rb");
    if (!f || fread(in_all, sizeof(double), (size_t){n} * {insize}, f) != (size_t){n} * {insize}) return 2;
    fclose(f);
    double times[{repeats}], sink = 0.0;
    for (int r = 0; r < {repeats}; ++r) {{
        double start = now();
        for (int i = 0; i < {n}; ++i) {{
            const double *x = in_all + (size_t)i * {insize};
            sink += {func}({args}, NULL);
            sink += out0[0];
        }}
        times[r] = (now() - start) / {n};
    }}
    qsort(times, {repeats}, sizeof(double), cmp);
    printf("%.2f %g\\n", times[{repeats} / 2], sink);
    return 0;
}}
"""


def harness(module: str, low) -> str:
    fn = low.function
    insize = sum(a.size for a in fn.inputs)
    decls = [f"    static double in_all[{N_STATES} * {insize}];"]
    args, offset = [], 0
    for a in fn.inputs:
        args.append(f"x + {offset}")
        offset += a.size
    for k, (arg, _) in enumerate(fn.outputs):
        size = int(np.prod(arg.shape))
        decls.append(f"    static double out{k}[{size}];")
        args.append(f"out{k}")
    return HARNESS.format(module=module, decls="\n".join(decls), n=N_STATES, insize=insize,
                          repeats=REPEATS, func=f"symgen_{module}_{fn.name}", args=", ".join(args))


def build_c(folder: Path, gen, low, states: list[dict], strip: bool) -> Path:
    """The timing harness of ``low`` built against the generated (or check-stripped) source."""
    work = folder / ("plain" if strip else "checked") / low.function.name
    work.mkdir(parents=True)
    flat = [np.concatenate([np.asarray(s[a.name], dtype=float) for a in low.function.inputs]) for s in states]
    np.asarray(flat, dtype="<f8").tofile(work / "states.bin")
    for name, text in gen.files.items():
        (work / name).write_text(CHECK_C.sub("", text) if strip and name.endswith(".c") else text)
    (work / "harness.c").write_text(harness(gen.module, low))
    exe = work / "timer"
    subprocess.run([CC, "-O2", "-std=c99", "-o", str(exe), str(work / "harness.c"), str(work / f"{gen.module}.c"),
                    "-lm"], check=True, capture_output=True)
    return exe


def run_c(exe: Path) -> float:
    out = subprocess.run([str(exe)], check=True, capture_output=True, text=True, cwd=exe.parent).stdout
    return float(out.split()[0])


def load_numpy(folder: Path, gen, strip: bool):
    path = folder / ("plain" if strip else "checked") / f"{gen.module}.py"
    path.parent.mkdir(parents=True, exist_ok=True)
    text = gen.files[f"{gen.module}.py"]
    path.write_text(CHECK_PY.sub("", text) if strip else text)
    spec = importlib.util.spec_from_file_location(f"bench_{gen.module}_{int(strip)}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def time_numpy(fn, args, count: int) -> float:
    samples = []
    for _ in range(REPEATS):
        start = time.perf_counter()
        fn(*args)
        samples.append((time.perf_counter() - start) * 1e9 / count)
    return statistics.median(samples)


def numpy_arguments(low, states: list[dict], batch: tuple) -> list:
    count = int(np.prod(batch)) if batch else 1
    args = [np.array([s[a.name] for s in states[:count]], dtype=float) for a in low.function.inputs]
    return [a.reshape(batch + (a.shape[-1],)) for a in args]


def measure(spec: str, folder: Path) -> list[dict]:
    model = symgen.derive(symgen.load(spec))
    lowered = trace_all(model, list(FUNCTIONS))
    c_gen, np_gen = generate(model, "c", lowered=lowered), generate(model, "numpy", lowered=lowered)
    checked, plain = load_numpy(folder / spec / "np", np_gen, False), load_numpy(folder / spec / "np", np_gen, True)
    distinct = reference_states(model, N_DISTINCT, seed=SEED)
    states = [distinct[i % N_DISTINCT] for i in range(max(N_STATES, BATCH))]
    rows = []
    for low in lowered:
        row = dict(scene=spec, function=low.function.name)
        exes = {strip: build_c(folder / spec, c_gen, low, states[:N_STATES], strip) for strip in (True, False)}
        timers = {"c": {strip: (lambda exe=exe: run_c(exe)) for strip, exe in exes.items()}}
        for label, batch in (("np1", ()), ("npb", (BATCH,))):
            args = numpy_arguments(low, states, batch)
            count = int(np.prod(batch)) if batch else 1
            timers[label] = {strip: (lambda m=module, a=args, n=count: time_numpy(getattr(m, low.function.name), a, n))
                             for strip, module in ((True, plain), (False, checked))}
        for key, pair in timers.items():        # interleaved rounds: plain, checked, plain, ...
            samples = {True: [], False: []}
            for _ in range(ROUNDS):
                for strip in (True, False):
                    samples[strip].append(pair[strip]())
            row[f"{key}_plain"], row[f"{key}_checked"] = (statistics.median(samples[True]),
                                                          statistics.median(samples[False]))
        rows.append(row)
    return rows


def ratio(row, key) -> str:
    return f"{row[f'{key}_checked'] / row[f'{key}_plain'] - 1:+.1%}"


def write(rows: list[dict]) -> Path:
    lines = ["# Cost of the finiteness checks in generated code", "",
             f"Machine: {os.cpu_count()} cores, {platform.processor() or platform.machine()}, "
             f"{subprocess.run([CC, '--version'], capture_output=True, text=True).stdout.splitlines()[0]}, "
             f"Python {platform.python_version()}, NumPy {np.__version__}. Reproduce with "
             "`python benchmarks/nonfinite_check.py`.", "",
             "* **checked**: the code as generated -- C checks every output (`SYMGEN_NONFINITE`), NumPy every "
             "output (`NonFiniteOutputError`); **plain**: the same code with those check lines removed.",
             f"* **C**: one state per call from a C loop, `{CC} -O2 -std=c99`, {N_STATES} loop-closed states "
             f"(`reference_states`, seed {SEED}), median of {REPEATS} passes.",
             f"* Plain and checked run alternately, {ROUNDS} rounds each; the median round is shown.",
             f"* **NumPy 1**: one state per call; **NumPy {BATCH}**: {BATCH} states per call (time per state), "
             f"median of {REPEATS} calls. The machine is shared and noisy: differences of a few percent are noise.",
             "", "| scene | function | C plain (ns) | C checked (ns) | C cost | NumPy 1 plain (µs) | NumPy 1 checked (µs) "
             f"| NumPy 1 cost | NumPy {BATCH} plain (ns/state) | NumPy {BATCH} checked (ns/state) | NumPy {BATCH} cost |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| `{r['scene']}` | {r['function']} | {r['c_plain']:.1f} | {r['c_checked']:.1f} | {ratio(r, 'c')} "
                     f"| {r['np1_plain'] / 1e3:.1f} | {r['np1_checked'] / 1e3:.1f} | {ratio(r, 'np1')} "
                     f"| {r['npb_plain']:.1f} | {r['npb_checked']:.1f} | {ratio(r, 'npb')} |")
    out = HERE / "nonfinite_check.md"
    out.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return out


def main(argv=None) -> int:
    global REPEATS, N_STATES, ROUNDS
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="few repeats (a smoke run)")
    args = parser.parse_args(argv)
    if args.quick:
        REPEATS, N_STATES, ROUNDS = 5, 200, 2
    with tempfile.TemporaryDirectory() as tmp:
        rows = [row for spec in SCENES for row in measure(spec, Path(tmp))]
    print(write(rows).read_text())
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
