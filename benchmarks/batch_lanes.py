"""Lanes across states: the generated C ``_batch`` entry points with and without vector lanes.

For each scene and function, the generated source is compiled twice with the ctypes binding's
flags (``cc -std=c99 -O2 -fPIC -shared -march=native``), once as it is (the lanes: 4 states per
vector with AVX2, 8 with AVX-512F under ``-DSYMGEN_VECTOR_512``) and once with ``-DSYMGEN_NO_LANES`` (the scalar loop over the
single-state function). Both libraries' ``_batch`` run the same ``BATCH`` random states (uniform
in [-1, 1], seed ``SEED``) through ctypes, one call per measurement, in interleaved rounds (the
order of the two alternates from round to round) timed by the thread's CPU clock, so other
processes on the machine do not count. A row gives the fastest round of each (ns per state and
states per second on one core) and the median of the per-round ratios scalar / lanes.

    python benchmarks/batch_lanes.py            # writes batch_lanes.md and batch_lanes.csv
"""
from __future__ import annotations

import argparse
import csv
import ctypes
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE))
from codegen_speed import vector_width  # noqa: E402

CC = os.environ.get("CC", "cc")
FLAGS = ["-std=c99", "-O2", "-fPIC", "-shared", "-march=native"]
SEED = 0
BATCH = 4096
ROUNDS = 15
CALLS = 3
#: (scene, function, states/s target or None, ratio target) of the task
CASES = [("chain:n=6", "inverse_dynamics", 3e7, 3.5), ("chain:n=6", "forward_dynamics", None, 3.5),
         ("chain:n=64", "inverse_dynamics", None, 3.0), ("chain:n=64", "forward_dynamics", None, 3.0)]


def processor() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown"


def source_only():
    """The C target rendering only ``<scene>.h`` and ``<scene>.c``: the standalone test program's
    50-digit reference values take minutes at ``chain:n=64`` and are not timed here."""
    from symgen.codegen.targets.c import CTarget

    class SourceOnly(CTarget):
        def files(self, module, python_extension=False):
            return super().files(module)[:2]

    return SourceOnly()


def build(spec: str, functions: list[str], work: Path):
    """``(module, {"lanes": CDLL, "scalar": CDLL}, {function: (input sizes, output size)}, compile s,
    lanes per vector)``."""
    from symgen.codegen.generate import generate, trace_all
    from symgen.io.builtin import get_scene
    from symgen.model import derive

    model = derive(get_scene(spec))
    lowered = trace_all(model, functions)
    gen = generate(model, source_only(), lowered=lowered)
    for name, text in gen.files.items():
        (work / name).write_text(text)
    libs, seconds = {}, {}
    for tag, extra in (("lanes", []), ("scalar", ["-DSYMGEN_NO_LANES"])):
        path = work / f"{gen.module}_{tag}.so"
        start = time.perf_counter()
        subprocess.run([CC, *FLAGS, *extra, "-o", str(path), str(work / f"{gen.module}.c"), "-lm"], check=True)
        seconds[tag] = time.perf_counter() - start
        libs[tag] = ctypes.CDLL(str(path))
    sizes = {}
    for low in lowered:
        out = 1
        for s in low.outputs[0][0].shape:
            out *= s
        sizes[low.function.name] = ([a.size for a in low.function.inputs], out, len(low.outputs))
    return gen.module, libs, sizes, seconds, vector_width(CC, FLAGS, work / f"{gen.module}.c")


def measure(module, libs, name, sizes):
    ins, out_size, n_out = sizes
    assert n_out == 1
    rng = np.random.default_rng(SEED)
    arrays = [rng.uniform(-1, 1, (BATCH, n)) for n in ins]
    outs = {tag: np.empty((BATCH, out_size)) for tag in libs}
    cond = np.empty(1)
    calls = {}
    for tag, lib in libs.items():
        fn = getattr(lib, f"symgen_{module}_{name}_batch")
        args = [ctypes.c_int(BATCH)] + [a.ctypes.data_as(ctypes.c_void_p) for a in arrays + [outs[tag], cond]]
        calls[tag] = (fn, args)
        status = fn(*args)
        assert status == 0, f"{module} {name} {tag}: state {status - 1} failed"
    scale = np.maximum(np.max(np.abs(outs["scalar"]), axis=1), 1e-2)
    diff = float(np.max(np.max(np.abs(outs["lanes"] - outs["scalar"]), axis=1) / scale))
    times = {tag: [] for tag in libs}
    for r in range(ROUNDS):
        order = ("lanes", "scalar") if r % 2 == 0 else ("scalar", "lanes")
        for tag in order:
            fn, args = calls[tag]
            start = time.thread_time_ns()
            for _ in range(CALLS):
                fn(*args)
            times[tag].append((time.thread_time_ns() - start) / (CALLS * BATCH))
    ratios = [s / v for s, v in zip(times["scalar"], times["lanes"])]
    return dict(scalar=min(times["scalar"]), lanes=min(times["lanes"]), ratio=statistics.median(ratios),
                spread=(min(ratios), max(ratios)), diff=diff)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(HERE / "batch_lanes"), help="output stem (.md and .csv)")
    args = parser.parse_args(argv)
    rows, width = [], 1
    scenes = {}
    for spec, name, _, _ in CASES:
        scenes.setdefault(spec, []).append(name)
    with tempfile.TemporaryDirectory() as tmp:
        for spec, functions in scenes.items():
            work = Path(tmp) / spec.replace(":", "_").replace("=", "")
            work.mkdir()
            module, libs, sizes, seconds, width = build(spec, functions, work)
            for case in CASES:
                if case[0] != spec:
                    continue
                got = measure(module, libs, case[1], sizes[case[1]])
                rows.append(dict(scene=spec, function=case[1], width=width, got=got, rate_target=case[2],
                                 ratio_target=case[3], compile=seconds))
                print(f"{spec} {case[1]}: scalar {got['scalar']:.1f} ns, lanes {got['lanes']:.1f} ns, "
                      f"ratio {got['ratio']:.2f}", flush=True)
    write(rows, Path(args.out), width)
    return 0


def _met(value, target) -> str:
    return "" if target is None else ("yes" if value >= target else "no")


def write(rows, stem: Path, width: int) -> None:
    header = ["scene", "function", "lanes", "scalar batch (ns/state)", "lanes (ns/state)", "lanes (states/s)",
              "scalar / lanes", "ratio range", "target ratio", "ratio met", "target states/s", "rate met",
              "max rel. diff", "compile lanes / scalar (s)"]
    lines = []
    with open(stem.with_suffix(".csv"), "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["scene", "function", "lanes", "scalar_ns", "lanes_ns", "lanes_states_per_s", "ratio",
                    "ratio_min", "ratio_max", "max_rel_diff", "compile_lanes_s", "compile_scalar_s"])
        for r in rows:
            g = r["got"]
            rate = 1e9 / g["lanes"]
            w.writerow([r["scene"], r["function"], r["width"], f"{g['scalar']:.2f}", f"{g['lanes']:.2f}",
                        f"{rate:.4g}", f"{g['ratio']:.3f}", f"{g['spread'][0]:.3f}", f"{g['spread'][1]:.3f}",
                        f"{g['diff']:.2e}", f"{r['compile']['lanes']:.2f}", f"{r['compile']['scalar']:.2f}"])
            target = "" if r["rate_target"] is None else f"{r['rate_target']:.0e}".replace("e+0", "e")
            lines.append(f"| `{r['scene']}` | {r['function']} | {r['width']} | {g['scalar']:.1f} | {g['lanes']:.1f} | "
                         f"{rate:.3g} | {g['ratio']:.2f}× | {g['spread'][0]:.2f}–{g['spread'][1]:.2f} | "
                         f"≥ {r['ratio_target']}× | {_met(g['ratio'], r['ratio_target'])} | {target} | "
                         f"{_met(rate, r['rate_target'])} | {g['diff']:.1e} | "
                         f"{r['compile']['lanes']:.1f} / {r['compile']['scalar']:.1f} |")
    text = ["# Lanes across states: the `_batch` entry points with and without vector lanes", "",
            f"Processor: {processor()}; `{CC} {' '.join(FLAGS)}` (the ctypes binding's flags); lanes: "
            f"{width} states per vector (the compiler's choice for this processor). One core.", "",
            "| " + " | ".join(header) + " |", "|" + "---|" * len(header), *lines, "",
            f"- {BATCH} random states (uniform in [-1, 1], seed {SEED}) per `_batch` call through ctypes; "
            f"{ROUNDS} interleaved rounds of {CALLS} calls each, the order alternating, timed by the thread's "
            "CPU clock. ns/state and states/s: the fastest round; *scalar / lanes*: the median of the "
            "per-round ratios, *ratio range* their minimum and maximum.",
            "- *scalar batch*: the same source with `-DSYMGEN_NO_LANES` (the loop over the single-state "
            "function); *max rel. diff*: the largest difference of the two over the states, relative to each "
            "state's largest output (floor 1e-2).",
            "- *compile*: seconds of `cc` for the source with both functions, with and without the lanes.",
            "- The scalar batch is not one angle at a time: the single-state function evaluates its joint "
            "angles' sines and cosines several per vector instruction (`symgen_sincos_n`), as many as a lane "
            "kernel does per call. The lanes speed up the rest of the function, not the sines and cosines, "
            "so a function whose sines and cosines are a large share of its work (`chain:n=64` inverse "
            "dynamics: 63 angles, about 70 vector operations each, beside 4622 operations) gains less than "
            "the vector width.",
            "- `python benchmarks/batch_lanes.py` rewrites this file and `batch_lanes.csv`.", ""]
    stem.with_suffix(".md").write_text("\n".join(text))


if __name__ == "__main__":
    sys.exit(main())
