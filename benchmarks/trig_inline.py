"""sin and cos inline against the C library's: the generated inverse dynamics built both ways.

The generated C computes sin and cos with the lanes' reduction and polynomials
(``templates/trig.c.jinja``); ``-DSYMGEN_LIBM_TRIG`` makes the same file call the C library's
``sin`` and ``cos`` instead. Both builds of one scene are timed by ``codegen_timing.c`` (thread CPU
clock, median of the repeats) in interleaved rounds; the table gives the median over rounds of each
build, their ratio, and the largest difference of their outputs relative to the largest output.

    python benchmarks/trig_inline.py [--quick]

Writes ``benchmarks/trig_inline.md`` and ``benchmarks/trig_inline.csv``.
"""
from __future__ import annotations

import argparse
import csv
import platform
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from codegen_speed import CC, CFLAGS, N_SINGLE, draw_states, rel_err, run_timer, signature_sizes, write_generated  # noqa: E402

SCENES = ("chain:n=6", "ur5", "panda", "chain:n=64", "talos")
BUILDS = {"inline": [], "libm": ["-DSYMGEN_LIBM_TRIG"]}


def build(spec: str, work: Path) -> dict:
    """Generate ``spec``'s inverse dynamics, write its states, compile both timers."""
    from symgen.codegen.generate import generate
    from symgen.io.builtin import get_scene
    from symgen.model import derive

    gen = generate(derive(get_scene(spec)), "c", ["inverse_dynamics"])
    src = write_generated(gen, work / gen.module)
    nq, nv = signature_sizes(gen.files[f"{gen.module}.h"])
    q, qd, qdd = draw_states(nq, nv, N_SINGLE)
    states = work / f"{gen.module}.bin"
    np.concatenate([a.ravel() for a in (q, qd, qdd)]).tofile(states)
    binaries = {}
    for name, flags in BUILDS.items():
        binaries[name] = work / f"timer_{gen.module}_{name}"
        cmd = [CC, *CFLAGS, *flags, f"-DFUNC=symgen_{gen.module}_inverse_dynamics", f"-DNQ={nq}", f"-DNV={nv}",
               HERE / "codegen_timing.c", src / f"{gen.module}.c", "-lm", "-o", binaries[name]]
        subprocess.run([str(c) for c in cmd], check=True, capture_output=True, text=True)
    trig = gen.ops["inverse_dynamics"]["trig"]
    return dict(scene=spec, nv=nv, ops=gen.ops["inverse_dynamics"]["total"], trig=trig, states=states,
                binaries=binaries)


def time_scene(entry: dict, rounds: int, repeats: int, work: Path) -> dict:
    samples = {name: [] for name in BUILDS}
    outputs = {}
    for _ in range(rounds):
        for name, binary in entry["binaries"].items():
            out = work / f"out_{name}.bin"
            ns, tau = run_timer([binary, entry["states"], N_SINGLE, repeats, out], out, entry["nv"])
            samples[name].append(ns)
            outputs[name] = tau
    row = {k: v for k, v in entry.items() if k not in ("states", "binaries")}
    row.update({f"{name}_ns": statistics.median(v) for name, v in samples.items()})
    row["ratio"] = statistics.median(a / b for a, b in zip(samples["inline"], samples["libm"]))
    row["diff"] = rel_err(outputs["inline"], outputs["libm"])
    return row


def markdown(rows: list[dict], meta: str) -> str:
    lines = ["# sin and cos inline against the C library's", "",
             "`python benchmarks/trig_inline.py`. The generated `inverse_dynamics` of each scene compiled twice from "
             f"the same file (`{CC} {' '.join(CFLAGS)}`): as generated (sin and cos inline, `templates/trig.c.jinja`) "
             "and with `-DSYMGEN_LIBM_TRIG` (the C library's `sin` and `cos`), timed by `codegen_timing.c` on "
             f"{N_SINGLE} states in interleaved rounds (ns per call, median over rounds). **ratio**: inline / C "
             "library, the median of the per-round ratios; **diff**: max |inline - C library| / max |tau| over the "
             f"states. {meta}", "",
             "| scene | dof | ops | sin/cos | inline (ns) | C library (ns) | ratio | diff |",
             "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| `{r['scene']}` | {r['nv']} | {r['ops']} | {r['trig']} | {r['inline_ns']:.1f} | "
                     f"{r['libm_ns']:.1f} | {r['ratio']:.3f} | {r['diff']:.1e} |")
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="chain:n=6 only, 2 rounds of 5 repeats")
    args = parser.parse_args()
    scenes, rounds, repeats = (("chain:n=6",), 2, 5) if args.quick else (SCENES, 7, 31)
    compiler = subprocess.run([CC, "--version"], capture_output=True, text=True).stdout.splitlines()[0]
    meta = (f"{rounds} rounds of {repeats} repeats; {compiler}; {platform.machine()}, "
            f"Python {platform.python_version()}.")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        for spec in scenes:
            row = time_scene(build(spec, work), rounds, repeats, work)
            rows.append(row)
            print(f"{spec:<12} inline {row['inline_ns']:8.1f} ns  C library {row['libm_ns']:8.1f} ns  "
                  f"ratio {row['ratio']:.3f}  diff {row['diff']:.1e}", flush=True)
    if args.quick:
        return
    (HERE / "trig_inline.md").write_text(markdown(rows, meta))
    with open(HERE / "trig_inline.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print("wrote benchmarks/trig_inline.md and benchmarks/trig_inline.csv")


if __name__ == "__main__":
    main()
