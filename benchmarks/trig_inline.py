"""sin and cos in the generated C: together in vectors, one at a time, or the C library's.

The generated C computes sin and cos with the lanes' reduction and polynomials: a scalar function
takes its angles several per vector kernel (``symgen_sincos_n``, ``templates/trig.c.jinja``);
``-DSYMGEN_NO_VECTOR`` makes the same file take them one at a time (``symgen_sin``/``symgen_cos``,
the same bits), ``-DSYMGEN_LIBM_TRIG`` call the C library's ``sin`` and ``cos``. The three builds of
one scene, by each C compiler, are timed by ``codegen_timing.c`` (thread CPU clock, median of the
repeats) in interleaved rounds; the table gives the median over rounds of each build, the ratios,
and the largest difference of the outputs relative to the largest output.

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
from codegen_speed import (C_COMPILERS, CFLAGS, N_SINGLE, compiler_name, draw_states, rel_err,  # noqa: E402
                           run_timer, signature_sizes, vector_width, write_generated)

SCENES = ("chain:n=6", "ur5", "panda", "solo12", "chain:n=64", "talos")
BUILDS = {"vector": [], "scalar": ["-DSYMGEN_NO_VECTOR"], "libm": ["-DSYMGEN_LIBM_TRIG"]}
#: the 8-wide vectors an AVX-512F processor takes on request, timed where the compiler targets one
WIDE = {"vector512": ["-DSYMGEN_VECTOR_512"]}


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
    entries = []
    for cc in C_COMPILERS:
        binaries = {}
        wide = vector_width(cc, [*CFLAGS, *WIDE["vector512"]], src / f"{gen.module}.c") == 8
        for name, flags in {**BUILDS, **(WIDE if wide else {})}.items():
            binaries[name] = work / f"timer_{gen.module}_{compiler_name(cc)}_{name}"
            cmd = [cc, *CFLAGS, *flags, f"-DFUNC=symgen_{gen.module}_inverse_dynamics", f"-DNQ={nq}", f"-DNV={nv}",
                   HERE / "codegen_timing.c", src / f"{gen.module}.c", "-lm", "-o", binaries[name]]
            subprocess.run([str(c) for c in cmd], check=True, capture_output=True, text=True)
        trig = gen.ops["inverse_dynamics"]["trig"]
        entries.append(dict(scene=spec, build=compiler_name(cc), nv=nv, ops=gen.ops["inverse_dynamics"]["total"],
                            trig=trig, states=states, binaries=binaries))
    return entries


def time_scene(entries: list[dict], rounds: int, repeats: int, work: Path) -> list[dict]:
    """Every build of every compiler, interleaved round by round."""
    samples = [{name: [] for name in entry["binaries"]} for entry in entries]
    outputs = [{} for _ in entries]
    for _ in range(rounds):
        for entry, sample, output in zip(entries, samples, outputs):
            for name, binary in entry["binaries"].items():
                out = work / f"out_{name}.bin"
                ns, tau = run_timer([binary, entry["states"], N_SINGLE, repeats, out], out, entry["nv"])
                sample[name].append(ns)
                output[name] = tau
    rows = []
    for entry, sample, output in zip(entries, samples, outputs):
        row = {k: v for k, v in entry.items() if k not in ("states", "binaries")}
        row.update({f"{name}_ns": statistics.median(v) for name, v in sample.items()})
        row["vector_scalar"] = statistics.median(a / b for a, b in zip(sample["vector"], sample["scalar"]))
        row["ratio"] = statistics.median(a / b for a, b in zip(sample["vector"], sample["libm"]))
        wide = sample.get("vector512")
        row["vector512_ns"] = statistics.median(wide) if wide else ""
        row["wide_vector"] = statistics.median(a / b for a, b in zip(wide, sample["vector"])) if wide else ""
        if wide and output["vector512"].tobytes() != output["scalar"].tobytes():
            raise SystemExit(f"{row['scene']} ({row['build']}): the 512-bit sin/cos changed a bit of tau")
        if output["vector"].tobytes() != output["scalar"].tobytes():
            raise SystemExit(f"{row['scene']} ({row['build']}): the vector sin/cos changed a bit of tau")
        row["diff"] = rel_err(output["vector"], output["libm"])
        rows.append(row)
    return rows


def markdown(rows: list[dict], meta: str) -> str:
    lines = ["# sin and cos in the generated C: together in vectors, one at a time, the C library's", "",
             "`python benchmarks/trig_inline.py`. The generated `inverse_dynamics` of each scene compiled three "
             f"times from the same file by each C compiler (`{' '.join(CFLAGS)}`): as generated (**vector**: the "
             "angles' sin and cos several per vector kernel, `symgen_sincos_n`), with `-DSYMGEN_NO_VECTOR` "
             "(**one at a time**: `symgen_sin`/`symgen_cos`, the same kernel on one double) and with "
             "`-DSYMGEN_LIBM_TRIG` (the C library's `sin` and `cos`), timed by `codegen_timing.c` on "
             f"{N_SINGLE} states in interleaved rounds (ns per call, median over rounds). **vector / one**, "
             "**vector / libm**: medians of the per-round ratios; the vector and one-at-a-time builds give "
             "bit-identical outputs (checked); **diff**: max |vector - C library| / max |tau| over the states. "
             "Where the compiler targets AVX-512F, a fourth build with `-DSYMGEN_VECTOR_512` (**512-bit**: 8 "
             "angles per kernel instead of 4; its outputs checked bit-identical too) and **512 / vector**, the "
             f"median of its per-round ratio to the default build; `-` elsewhere. {meta}", "",
             "| scene | build | dof | ops | sin/cos | vector (ns) | one at a time (ns) | C library (ns) | "
             "vector / one | vector / libm | 512-bit (ns) | 512 / vector | diff |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        wide = (f"{r['vector512_ns']:.1f} | {r['wide_vector']:.3f}" if r["vector512_ns"] != "" else "- | -")
        lines.append(f"| `{r['scene']}` | {r['build']} | {r['nv']} | {r['ops']} | {r['trig']} | {r['vector_ns']:.1f} | "
                     f"{r['scalar_ns']:.1f} | {r['libm_ns']:.1f} | {r['vector_scalar']:.3f} | {r['ratio']:.3f} | "
                     f"{wide} | {r['diff']:.1e} |")
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="chain:n=6 only, 2 rounds of 5 repeats")
    args = parser.parse_args()
    scenes, rounds, repeats = (("chain:n=6",), 2, 5) if args.quick else (SCENES, 7, 31)
    compilers = "; ".join(subprocess.run([cc, "--version"], capture_output=True, text=True).stdout.splitlines()[0]
                          for cc in C_COMPILERS)
    meta = (f"{rounds} rounds of {repeats} repeats; {compilers}; {platform.machine()}, "
            f"Python {platform.python_version()}.")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        for spec in scenes:
            for row in time_scene(build(spec, work), rounds, repeats, work):
                rows.append(row)
                print(f"{spec:<12} {row['build']:<6} vector {row['vector_ns']:8.1f} ns  one at a time "
                      f"{row['scalar_ns']:8.1f} ns  C library {row['libm_ns']:8.1f} ns  vector/one "
                      f"{row['vector_scalar']:.3f}  vector/libm {row['ratio']:.3f}  512/vector {row['wide_vector'] or '-'}  "
                      f"diff {row['diff']:.1e}", flush=True)
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
