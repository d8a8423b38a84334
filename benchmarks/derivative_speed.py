"""Per-call cost of symgen's generated C derivatives against Pinocchio's C++ analytic derivatives.

For each scene of ``SCENES``, timed round by round (interleaved, the median of the rounds kept):

* the generated C ``inverse_dynamics_derivatives`` (``dtau/dq``, ``dtau/dqd``, ``M``) against
  Pinocchio's ``computeRNEADerivatives``, and the generated ``forward_dynamics_derivatives``
  (``d qdd/dq``, ``d qdd/dqd``, ``d qdd/dtau``) against ``computeABADerivatives``, each called once
  per state from C (``codegen_timing.c`` built with ``-DDERIVATIVES``, the generated file compiled
  once with ``-DSYMGEN_NO_LANES``) and from C++ (``rnea_timing.cpp`` built with
  ``-DTIME_DERIVATIVES``, header-only, ``-O3 -march=native -DNDEBUG``, by clang++ and by g++; the
  ratio is taken against the fastest build of each round);
* each side built twice by each compiler: as above, and with ``-ffp-contract=fast`` (a multiply and
  the add that uses it fused into one instruction across statements, as the generated bindings
  build: with ``-std=c99`` GCC fuses nothing and Clang only within one expression, clang++ only
  within one expression; g++ already fuses across statements, so its two builds are alike), the
  fastest build of each side kept round by round;
* the same states for both (uniform in ``[-1, 1]``; motion on joints, so Pinocchio's ``q, v`` are
  symgen's coordinate for coordinate: :func:`codegen_speed.urdf_robot` checks the order), and the
  outputs compared: the largest relative difference over the states. Pinocchio leaves the URDF's
  joint friction out: it gets ``u = tau - b v - c sign(v)`` and its ``dtau/dv`` gains ``diag(b)``,
  its ``d qdd/dv`` loses ``Minv diag(b)``.

Writes ``derivative_speed.md`` and ``derivative_speed.csv`` beside this file.

    python benchmarks/derivative_speed.py [--quick] [--work DIR] [--scenes SPEC ...]

``--work DIR`` keeps the build (the Pinocchio binaries take minutes each to compile): the code is
generated on every run, and a scene's timers are rebuilt unless the source they were built from is
byte for byte the one symgen generates now. Needs Pinocchio's and
Eigen's headers: ``pip install pin cmeel-eigen``.
"""
from __future__ import annotations

import argparse
import csv
import json
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from codegen_speed import (C_COMPILERS, CFLAGS, CXXFLAGS, FUSED, PIN_DEFINES, SEED, VARIANTS, compiler_name,  # noqa: E402
                           fmt, general_robot, machine, urdf_robot, write_generated, write_model_file)

SCENES = ["chain:n=6", "chain:n=32", "ur5", "panda", "general_chain:n=7"]
FUNCTIONS = {"inverse_dynamics_derivatives": "rnea", "forward_dynamics_derivatives": "aba"}
PINOCCHIO = {"rnea": "computeRNEADerivatives", "aba": "computeABADerivatives"}
COMPILERS = ("clang++", "g++")
#: the issue's target: generated C at most this fraction of Pinocchio's time
TARGET = 0.5
N_STATES = 200
#: the generated file's build: the timers call the one-state functions only, so the lanes of the
#: ``_batch`` entries are preprocessed away (they add to the minutes the large derivatives take to compile)
GENERATED_CFLAGS = [*CFLAGS, "-DSYMGEN_NO_LANES"]


def compile_pinocchio(pin, work: Path) -> tuple[dict, list[str]]:
    """rnea_timing.cpp with ``-DTIME_DERIVATIVES``, header-only, by each compiler of
    :data:`COMPILERS` in each of :data:`VARIANTS` (a binary already in ``work`` is reused);
    ``({build name: binary}, notes)``."""
    prefix = next(p for p in Path(pin.__file__).resolve().parents if p.name == "cmeel.prefix")
    eigen = prefix / "include" / "eigen3"
    binaries, notes = {}, []
    for cxx in COMPILERS:
        for suffix, extra in VARIANTS.items():
            build = cxx + suffix
            binary = work / f"pin_derivatives_{build.replace(' ', '_')}"
            cmd = [cxx, *CXXFLAGS, *extra, *PIN_DEFINES, "-DTIME_DERIVATIVES", "-I", prefix / "include", "-I", eigen,
                   HERE / "rnea_timing.cpp", "-o", binary]
            if not binary.exists():
                result = subprocess.run([str(c) for c in cmd], capture_output=True, text=True)
                if result.returncode != 0:
                    notes.append(f"`{build}` failed: {(result.stderr.strip().splitlines() or ['?'])[-1]}")
                    continue
            binaries[build] = binary
            shown = " ".join(map(str, cmd)).replace(str(prefix), "$PREFIX").replace(str(work), "$TMP")
            notes.append(f"`{shown.replace(str(HERE), 'benchmarks')}`")
    return binaries, notes


def _digest(text: str) -> str:
    import hashlib

    return hashlib.sha256(text.encode()).hexdigest()


def run(cmd: list, out: Path, n: int) -> tuple[float, np.ndarray]:
    """(median ns per call, the three n x n matrices of every state)."""
    result = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, check=True)
    return float(result.stdout.split()[0]), np.fromfile(out).reshape(-1, 3, n, n)


def generated_builds() -> dict:
    """``{build name: (compiler, extra flags)}`` of the generated C: each of ``C_COMPILERS`` in each
    of :data:`VARIANTS`."""
    return {compiler_name(cc) + suffix: (cc, extra) for cc in C_COMPILERS for suffix, extra in VARIANTS.items()}


def compile_timers(cc: str, extra: list, source: Path, obj: Path, timers: dict, n: int) -> None:
    """``source`` (a generated C file) compiled by ``cc`` with ``extra`` flags into ``obj`` once, then
    linked into ``codegen_timing.c -DDERIVATIVES`` for each ``{symbol: timer path}`` of ``timers``."""
    subprocess.run([str(c) for c in [cc, *GENERATED_CFLAGS, *extra, "-c", source, "-o", obj]],
                   capture_output=True, text=True, check=True)
    for symbol, timer in timers.items():
        cmd = [cc, *CFLAGS, "-Wall", "-DDERIVATIVES", f"-DFUNC={symbol}", f"-DNQ={n}", f"-DNV={n}",
               HERE / "codegen_timing.c", obj, "-lm", "-o", timer]
        subprocess.run([str(c) for c in cmd], capture_output=True, text=True, check=True)


def prepare(spec: str, pin, work: Path) -> dict:
    """Generate and compile the C timers of one scene; its states, Pinocchio's model argument and
    the friction Pinocchio leaves out."""
    from symgen.codegen.functions import library_flops
    from symgen.codegen.generate import generate, module_name
    from symgen.io.builtin import get_scene
    from symgen.model import derive

    model = derive(get_scene(spec))
    n = model.counts.n
    module = module_name(model.scene.name)
    src = work / module
    builds = generated_builds()
    timers = {f: {b: work / f"timer_{module}_{f}_{b.replace(' ', '_')}" for b in builds} for f in FUNCTIONS}
    stamp = work / f"{module}.c.sha"           # the source the timers were built from
    gen = generate(model, "c", list(FUNCTIONS))
    digest = _digest(gen.files[f"{module}.c"])
    if not (stamp.exists() and (src / "ops.json").exists()
            and all(t.exists() for by_build in timers.values() for t in by_build.values())
            and stamp.read_text() == digest):
        src = write_generated(gen, work / gen.module)
        for build, (cc, extra) in builds.items():
            obj = work / f"{module}_{build.replace(' ', '_')}.o"   # compiled once per build, linked into both timers
            compile_timers(cc, extra, src / f"{module}.c", obj, {f"symgen_{module}_{f}": by_build[build]
                                                                 for f, by_build in timers.items()}, n)
        stamp.write_text(digest)
    ops = json.loads((src / "ops.json").read_text())["functions"]
    rng = np.random.default_rng(SEED)
    q, v, a = (rng.uniform(-1, 1, (N_STATES, n)) for _ in range(3))
    if spec.startswith(("chain:", "general_chain:")):   # no friction; the general one from symgen's tree
        damping, coulomb = np.zeros(n), np.zeros(n)
        pin_arg = n if spec.startswith("chain:") else write_model_file(general_robot(spec),
                                                                        work / f"{module}_pinocchio.txt")
    else:
        robot = urdf_robot(spec)
        pin_arg = write_model_file(robot.model, work / f"{module}_pinocchio.txt")
        damping, coulomb = np.asarray(robot.damping, float), np.asarray(robot.coulomb, float)
    files = {}
    for kind, third in (("symgen", a), ("rnea", a), ("aba", a - damping * v - coulomb * np.sign(v))):
        files[kind] = work / f"{module}_{kind}.bin"
        np.concatenate([x.ravel() for x in (q, v, third)]).tofile(files[kind])
    flops = {f: library_flops(ops[f]) for f in FUNCTIONS}
    ops = {f: ops[f]["total"] for f in FUNCTIONS}
    return dict(spec=spec, n=n, timers=timers, files=files, pin_arg=pin_arg, damping=damping, ops=ops, flops=flops)


def pinocchio_in_symgen_terms(kind: str, out: np.ndarray, damping: np.ndarray) -> np.ndarray:
    """Pinocchio's matrices with the friction it leaves out put back (module docstring)."""
    out = out.copy()
    if kind == "rnea":
        out[:, 1] += np.diag(damping)[None]
    else:
        out[:, 1] -= out[:, 2] * damping[None, None, :]
    return out


def bench(sc: dict, pin_bins: dict, rounds: int, repeats: int, work: Path) -> list[dict]:
    rows = []
    out = work / "out.bin"
    for function, kind in FUNCTIONS.items():
        samples = {"c": [], **{cxx: [] for cxx in pin_bins}}
        err = 0.0
        builds = sc["timers"][function]
        samples |= {f"c_{b}": [] for b in builds}
        for _ in range(rounds):
            outputs = []
            for build, timer in builds.items():          # per round, the faster build; every build compared
                ns, got = run([timer, sc["files"]["symgen"], N_STATES, repeats, out], out, sc["n"])
                samples[f"c_{build}"].append(ns)
                outputs.append(got)
            samples["c"].append(min(samples[f"c_{b}"][-1] for b in builds))
            for cxx, binary in pin_bins.items():
                ns, want = run([binary, sc["pin_arg"], sc["files"][kind], N_STATES, repeats, out, kind], out, sc["n"])
                samples[cxx].append(ns)
                want = pinocchio_in_symgen_terms(kind, want, sc["damping"])
                for got in outputs:
                    for k in range(3):
                        scale = max(float(np.abs(want[:, k]).max()), 1e-300)
                        err = max(err, float(np.abs(got[:, k] - want[:, k]).max()) / scale)
        best = [min(samples[cxx][r] for cxx in pin_bins) for r in range(rounds)]
        row = {"scene": sc["spec"], "dof": sc["n"], "function": function, "pinocchio": PINOCCHIO[kind],
               "ops": sc["ops"][function], "library_flops": sc["flops"][function], "c_ns": statistics.median(samples["c"]),
               **{f"c_{b}_ns": statistics.median(samples[f"c_{b}"]) for b in builds},
               **{f"pin_{cxx}_ns": statistics.median(samples[cxx]) for cxx in pin_bins},
               "pin_ns": statistics.median(best),
               "ratio": statistics.median(c / p for c, p in zip(samples["c"], best)), "max_rel_diff": err}
        print(f"{sc['spec']:<11} {function:<30} C {row['c_ns']:10.1f} ns  ratio {row['ratio']:.3f}  "
              f"diff {err:.1e}", flush=True)
        rows.append(row)
    return rows


def markdown(rows: list[dict], notes: list[str], meta: str) -> str:
    cxx = [k[4:-3] for k in rows[0] if k.startswith("pin_") and k.endswith("_ns") and k != "pin_ns"]
    builds = [k[2:-3] for k in rows[0] if k.startswith("c_") and k.endswith("_ns") and k != "c_ns"]
    lines = ["# Generated C derivatives against Pinocchio's analytic derivatives", "",
             "`python benchmarks/derivative_speed.py`. Per call (ns, median of the interleaved rounds); "
             "ratio = the fastest generated C build / the fastest Pinocchio build of the same round (median over rounds); "
             f"target: ratio <= {TARGET}. max rel diff: the outputs compared over the {N_STATES} states. "
             f"{meta}", "",
             "| scene | dof | function | Pinocchio | ops | library flops | generated C ns | "
             + " | ".join(f"Pinocchio {c} ns" for c in cxx) + f" | Pinocchio fastest ns | ratio | <= {TARGET} | max rel diff |",
             "|---|---|---|---|---|---|---|" + "---|" * len(cxx) + "---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['scene']} | {r['dof']} | {r['function']} | {r['pinocchio']} | {r['ops']} | {r['library_flops']} | "
                     f"{fmt(r['c_ns'], 4)} ("
                     + " / ".join(f"{b} {fmt(r[f'c_{b}_ns'], 4)}" for b in builds)
                     + ") | " + " | ".join(fmt(r[f'pin_{c}_ns'], 4) for c in cxx)
                     + f" | {fmt(r['pin_ns'], 4)} | {fmt(r['ratio'])} | {'yes' if r['ratio'] <= TARGET else 'no'} | {r['max_rel_diff']:.1e} |")
    lines += ["", f"Generated C: `{' '.join(GENERATED_CFLAGS)} -c <module>.c` by each of "
              f"{', '.join(f'`{c}`' for c in C_COMPILERS)}, and again with `{' '.join(FUSED)}` (the builds named "
              "`fused`, as the generated bindings compile), linked into `codegen_timing.c` "
              "built with `-DDERIVATIVES` by the same compiler; ops: the straight-line mul + add, library flops: "
              "those of the library loops (factors and solves; the banded products: the closed form's, and those with the mass matrix's inverse), as `ops.json` counts them (one state per call; the lanes of the `_batch` entries "
              "are not built); generated C ns: the fastest build per round (median), each build's median in brackets, "
              "every build's outputs in the max rel diff. "
              "Pinocchio builds (the fastest per round in its own column): " + "; ".join(notes) + " (PREFIX = pinocchio's cmeel.prefix).", ""]
    return "\n".join(lines)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="chain:n=6 only, 3 rounds")
    parser.add_argument("--work", type=Path, help="build directory kept between runs")
    parser.add_argument("--scenes", nargs="+", help=f"scenes to time (default: {' '.join(SCENES)})")
    args = parser.parse_args(argv)
    import pinocchio as pin

    scenes, rounds, repeats = (["chain:n=6"], 3, 5) if args.quick else (SCENES, 7, 9)
    scenes = args.scenes or scenes
    with tempfile.TemporaryDirectory() as tmp:
        work = args.work or Path(tmp)
        work.mkdir(parents=True, exist_ok=True)
        pin_bins, notes = compile_pinocchio(pin, work)
        if not pin_bins:
            raise SystemExit("no Pinocchio build: " + "; ".join(notes))
        rows = []
        for spec in scenes:
            rows += bench(prepare(spec, pin, work), pin_bins, rounds, repeats, work)
    meta = f"{rounds} rounds of {repeats} repeats; {machine()}; Pinocchio {pin.__version__}."
    left = [spec for spec in SCENES if spec not in scenes]
    if left and not args.quick:
        meta += f" Not timed in this run: {', '.join(left)} (`--scenes` chose {' '.join(scenes)})."
    suffix = "_quick" if args.quick else ""
    (HERE / f"derivative_speed{suffix}.md").write_text(markdown(rows, notes, meta))
    with open(HERE / f"derivative_speed{suffix}.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


if __name__ == "__main__":
    main()
