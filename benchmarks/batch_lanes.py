"""Lanes across states: the generated C ``_batch`` entry points with and without vector lanes.

For each scene and function, the generated source is compiled twice with the ctypes binding's
flags (``cc -std=c99 -O2 -fPIC -shared -march=native -ffp-contract=fast``), once as it is (the
lanes: 8 states per vector with AVX-512F, 4 with AVX2) and once with ``-DSYMGEN_NO_LANES`` (the
scalar loop over the single-state function). Both libraries' ``_batch`` run the same random states
(uniform in [-1, 1], seed ``SEED``) through ctypes, one call per measurement, in interleaved rounds
(the order of the two alternates from round to round) timed by the thread's CPU clock, so other
processes on the machine do not count. A row gives the fastest round of each (ns per state and
states per second on one core) and the median of the per-round ratios scalar / lanes.

``chain:n=64`` is timed at two batch sizes, one within the core's second-level cache and one
beyond it: its functions read and write 2 KB per state, so 512 states fit in 1 MB and 4096 states
take 8 MB.
Each row also times ``memmove`` of the batch's input bytes in the same rounds, for scale: the rate
at which this core moves data that size, beside the rate the lanes read and write theirs.

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
from symgen.codegen.targets.c import BINDING_FLAGS, X86_64_FLAGS  # noqa: E402

CC = os.environ.get("CC", "cc")
#: the ctypes binding's flags on x86-64
FLAGS = [*BINDING_FLAGS, *X86_64_FLAGS]
SEED = 0
ROUNDS = 15
#: states timed per round (the calls of a round add up to about this many)
PER_ROUND = 12288
#: (scene, function, states/s target or None, ratio target, states per call)
CASES = [("chain:n=6", "inverse_dynamics", 3e7, 3.5, 4096), ("chain:n=6", "forward_dynamics", None, 3.5, 4096),
         ("chain:n=64", "inverse_dynamics", None, 3.0, 512), ("chain:n=64", "inverse_dynamics", None, 3.0, 4096),
         ("chain:n=64", "forward_dynamics", None, 3.0, 512), ("chain:n=64", "forward_dynamics", None, 3.0, 4096)]


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
    """``(module, {"lanes": CDLL, "scalar": CDLL[, "lanes4": CDLL]}, {function: (input sizes, output
    size)}, compile s, (lanes per kernel, scalar trig vector width))``; ``lanes4``, the 4 lanes
    ``-DSYMGEN_LANES_256`` asks for, only where the default is 8."""
    from symgen.codegen.generate import generate, trace_all
    from symgen.io.builtin import get_scene
    from symgen.model import derive

    model = derive(get_scene(spec))
    lowered = trace_all(model, functions)
    gen = generate(model, source_only(), lowered=lowered)
    for name, text in gen.files.items():
        (work / name).write_text(text)
    source = work / f"{gen.module}.c"
    widths = (vector_width(CC, FLAGS, source, "SYMGEN_LANES"), vector_width(CC, FLAGS, source, "SYMGEN_VECTOR"))
    builds = [("lanes", []), ("scalar", ["-DSYMGEN_NO_LANES"])]
    if widths[0] == 8:
        builds.append(("lanes4", ["-DSYMGEN_LANES_256"]))
    libs, seconds = {}, {}
    for tag, extra in builds:
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
    return gen.module, libs, sizes, seconds, widths


def measure(module, libs, name, sizes, batch):
    ins, out_size, n_out = sizes
    assert n_out == 1
    rng = np.random.default_rng(SEED)
    arrays = [rng.uniform(-1, 1, (batch, n)) for n in ins]
    outs = {tag: np.empty((batch, out_size)) for tag in libs}
    cond = np.empty(1)
    calls = {}
    for tag, lib in libs.items():
        fn = getattr(lib, f"symgen_{module}_{name}_batch")
        args = [ctypes.c_int(batch)] + [a.ctypes.data_as(ctypes.c_void_p) for a in arrays + [outs[tag], cond]]
        calls[tag] = (fn, args)
        status = fn(*args)
        assert status == 0, f"{module} {name} {tag}: state {status - 1} failed"
    scale = np.maximum(np.max(np.abs(outs["scalar"]), axis=1), 1e-2)
    diff = float(np.max(np.max(np.abs(outs["lanes"] - outs["scalar"]), axis=1) / scale))
    # the batch's input bytes moved by memmove, from one buffer into another of the same size
    source = np.concatenate([a.ravel() for a in arrays])
    target = np.empty_like(source)
    calls["memmove"] = (ctypes.memmove, [target.ctypes.data, source.ctypes.data, source.nbytes])
    repeat = max(1, PER_ROUND // batch)
    times = {tag: [] for tag in calls}
    for r in range(ROUNDS):
        order = list(calls) if r % 2 == 0 else list(calls)[::-1]
        for tag in order:
            fn, args = calls[tag]
            start = time.thread_time_ns()
            for _ in range(repeat):
                fn(*args)
            times[tag].append((time.thread_time_ns() - start) / (repeat * batch))
    ratios = [s / v for s, v in zip(times["scalar"], times["lanes"])]
    four = {}
    if "lanes4" in times:
        four = dict(lanes4=min(times["lanes4"]),
                    ratio4=statistics.median(f / v for f, v in zip(times["lanes4"], times["lanes"])))
    state_bytes = 8 * (sum(ins) + out_size)
    return dict(**four, scalar=min(times["scalar"]), lanes=min(times["lanes"]), ratio=statistics.median(ratios),
                spread=(min(ratios), max(ratios)), diff=diff, batch=batch, kib=batch * state_bytes / 1024,
                lanes_rate=state_bytes / min(times["lanes"]), copy_rate=2 * source.nbytes / batch / min(times["memmove"]))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(HERE / "batch_lanes"), help="output stem (.md and .csv)")
    args = parser.parse_args(argv)
    rows, width = [], (1, 1)
    scenes = {}
    for spec, name, *_ in CASES:
        if name not in scenes.setdefault(spec, []):
            scenes[spec].append(name)
    with tempfile.TemporaryDirectory() as tmp:
        for spec, functions in scenes.items():
            work = Path(tmp) / spec.replace(":", "_").replace("=", "")
            work.mkdir()
            module, libs, sizes, seconds, width = build(spec, functions, work)
            for case in CASES:
                if case[0] != spec:
                    continue
                got = measure(module, libs, case[1], sizes[case[1]], case[4])
                rows.append(dict(scene=spec, function=case[1], width=width[0], got=got, rate_target=case[2],
                                 ratio_target=case[3], compile=seconds))
                print(f"{spec} {case[1]} ({case[4]} states): scalar {got['scalar']:.1f} ns, lanes {got['lanes']:.1f} ns, "
                      f"ratio {got['ratio']:.2f}", flush=True)
    write(rows, Path(args.out), width)
    return 0


def _met(value, target) -> str:
    return "" if target is None else ("yes" if value >= target else "no")


def write(rows, stem: Path, widths: tuple[int, int]) -> None:
    width, trig_width = widths
    header = ["scene", "function", "states per call", "data (KiB)", "scalar batch (ns/state)", "lanes (ns/state)",
              "lanes (states/s)", "scalar / lanes", "ratio range", "target ratio", "ratio met", "target states/s",
              "rate met", "4 lanes (ns/state)", "4 lanes / lanes", "lanes data rate (GB/s)", "memmove (GB/s)",
              "max rel. diff", "compile lanes / scalar (s)"]
    lines = []
    with open(stem.with_suffix(".csv"), "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["scene", "function", "lanes", "states_per_call", "data_kib", "scalar_ns", "lanes_ns",
                    "lanes_states_per_s", "ratio", "ratio_min", "ratio_max", "lanes4_ns", "lanes4_ratio",
                    "lanes_gb_per_s", "memmove_gb_per_s",
                    "max_rel_diff", "compile_lanes_s", "compile_scalar_s"])
        for r in rows:
            g = r["got"]
            rate = 1e9 / g["lanes"]
            four = (f"{g['lanes4']:.2f}", f"{g['ratio4']:.3f}") if "lanes4" in g else ("", "")
            w.writerow([r["scene"], r["function"], r["width"], g["batch"], f"{g['kib']:.0f}", f"{g['scalar']:.2f}",
                        f"{g['lanes']:.2f}", f"{rate:.4g}", f"{g['ratio']:.3f}", f"{g['spread'][0]:.3f}",
                        f"{g['spread'][1]:.3f}", *four, f"{g['lanes_rate']:.2f}", f"{g['copy_rate']:.2f}",
                        f"{g['diff']:.2e}", f"{r['compile']['lanes']:.2f}", f"{r['compile']['scalar']:.2f}"])
            target = "" if r["rate_target"] is None else f"{r['rate_target']:.0e}".replace("e+0", "e")
            lines.append(f"| `{r['scene']}` | {r['function']} | {g['batch']} | {g['kib']:.0f} | {g['scalar']:.1f} | "
                         f"{g['lanes']:.1f} | {rate:.3g} | {g['ratio']:.2f}× | {g['spread'][0]:.2f}–{g['spread'][1]:.2f} | "
                         f"≥ {r['ratio_target']}× | {_met(g['ratio'], r['ratio_target'])} | {target} | "
                         f"{_met(rate, r['rate_target'])} | "
                         + (f"{g['lanes4']:.1f} | {g['ratio4']:.2f}× | " if "lanes4" in g else "| | ")
                         + f"{g['lanes_rate']:.1f} | {g['copy_rate']:.1f} | "
                         f"{g['diff']:.1e} | {r['compile']['lanes']:.1f} / {r['compile']['scalar']:.1f} |")
    text = ["# Lanes across states: the `_batch` entry points with and without vector lanes", "",
            f"Processor: {processor()}; `{CC} {' '.join(FLAGS)}` (the ctypes binding's flags); lanes: "
            f"{width} states per vector (the compiler's choice for this processor). One core.", "",
            "| " + " | ".join(header) + " |", "|" + "---|" * len(header), *lines, "",
            f"- Random states (uniform in [-1, 1], seed {SEED}), *states per call* of them per `_batch` call "
            f"through ctypes; {ROUNDS} interleaved rounds of about {PER_ROUND} states each, the order "
            "alternating, timed by the thread's CPU clock. ns/state and states/s: the fastest round; "
            "*scalar / lanes*: the median of the per-round ratios, *ratio range* their minimum and maximum.",
            "- *data*: the inputs and outputs of one call. *lanes data rate*: those bytes per state over the "
            "lanes' time per state; *memmove*: the call's input bytes copied into another buffer in the same "
            "rounds, bytes read plus bytes written per second, for scale: compare the two `chain:n=64` "
            "sizes of one function (within and beyond the core's second-level cache) for what streaming "
            "the data costs the lanes.",
            "- *scalar batch*: the same source with `-DSYMGEN_NO_LANES` (the loop over the single-state "
            "function); *max rel. diff*: the largest difference of the two over the states, relative to each "
            "state's largest output (floor 1e-2): fused multiply-adds (`-ffp-contract=fast`) round the lanes "
            "and the scalar code apart where the compiler fuses them differently.",
            "- *4 lanes*: where the lanes are 8 wide (AVX-512F), the same source with `-DSYMGEN_LANES_256` "
            "timed in the same rounds; *4 lanes / lanes*: the median of the per-round ratios (above 1: the "
            "default 8 lanes are faster).",
            "- *compile*: seconds of `cc` for the source with both functions, with and without the lanes.",
            "- The scalar batch is not one angle at a time: the single-state function evaluates its joint "
            f"angles' sines and cosines {trig_width} per vector instruction (`symgen_sincos_n`). The lanes speed "
            f"up the rest of the function more than the sines and cosines ({width} per vector instruction here), "
            "so a function whose sines and cosines are a large share of its work (`chain:n=64` inverse "
            "dynamics: 63 angles beside 4622 operations) gains less than the vector width.",
            "- `python benchmarks/batch_lanes.py` rewrites this file and `batch_lanes.csv`.", ""]
    stem.with_suffix(".md").write_text("\n".join(text))


if __name__ == "__main__":
    sys.exit(main())
