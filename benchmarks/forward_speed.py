"""Speed of symgen's generated forward dynamics against Pinocchio's C++ ``aba``.

For each chain of ``SCENES``, in one run and round by round (side by side): the generated C
``forward_dynamics`` traced by the articulated-body recursion (``symgen.codegen.aba``), by the
joint-space route (``M_mm = W_m^T M_q W_m``, one recursion for the right-hand side) and by the dense
route (``M`` formed), ``M_mm`` factored by LDL^T up to 16 x 16, else LU, each called once per state from C
(``codegen_timing.c``), and Pinocchio's ``aba`` timed from C++ (``rnea_timing.cpp`` built with
``-DTIME_ABA``), header-only (GCC and clang) and against the wheel's library. Also: the route ``generate`` keeps
by the measured operation counts, and every count. Writes ``forward_speed.md`` and
``forward_speed.csv`` beside this file.

    python benchmarks/forward_speed.py [--quick]

Needs Pinocchio's headers for the C++ timing: ``pip install pin cmeel-eigen``.
"""
from __future__ import annotations

import argparse
import csv
import statistics
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from codegen_speed import (C_COMPILERS, CFLAGS, N_SINGLE, SEED, Settings, compile_c_timers, compile_rnea,  # noqa: E402
                           draw_states, fmt, machine, pinocchio_chain, rel_err, run_timer, write_generated)

SCENES = ["chain:n=6", "chain:n=12", "chain:n=32", "chain:n=64"]
ROUTES = ("articulated-body", "joint-space", "dense")
#: the column key of each route
KEYS = {"articulated-body": "aba", "joint-space": "joint", "dense": "dense"}
TARGETS = {6: 0.5, 64: 1.0}
#: the matrix routes' C is timed up to this N (the dense one at N = 64: about 226 000 operations, cut into blocks)
DENSE_TIMED_UP_TO = 64


def prepare(spec: str, work: Path) -> dict:
    """Generate both routes of one chain, compile their timers, write the states; the route kept
    by ``generate`` (both routes traced, the cheaper kept) and the counts."""
    from symgen.io.builtin import get_scene
    from symgen.codegen.generate import generate, trace_all
    from symgen.model import derive

    model = derive(get_scene(spec))
    n = model.counts.n
    row = {"scene": spec, "dof": n, "kept": trace_all(model, ["forward_dynamics"])[0].function.metadata["method"]}
    timers = {}
    for route in ROUTES:
        gen = generate(model, "c", lowered=trace_all(model, ["forward_dynamics"], {"method": route}))
        ops = gen.ops["forward_dynamics"]
        key = KEYS[route]
        row.update({f"{key}_mul": ops["mul"], f"{key}_add": ops["add"], f"{key}_solve_flops": ops["solve_flops"],
                    f"{key}_ops": ops["total"] + ops["solve_flops"]})
        if key != "aba" and n > DENSE_TIMED_UP_TO:
            continue
        src = write_generated(gen, work / f"{gen.module}_{key}")
        timers[key], _ = compile_c_timers(src, gen.module, n, n, work, "forward_dynamics", key)
    q, v, tau = draw_states(n, n, N_SINGLE)
    states = work / f"{spec.replace(':', '_').replace('=', '')}.bin"
    np.concatenate([q.ravel(), v.ravel(), tau.ravel()]).tofile(states)
    return dict(row=row, timers=timers, states=states, inputs=(q, v, tau), n=n)


def bench(spec: str, settings: Settings, pin, aba_bins: dict, work: Path) -> dict:
    sc = prepare(spec, work)
    row, n, out = sc["row"], sc["n"], work / "out.bin"
    model = pinocchio_chain(pin, n) if pin is not None else None
    if model is not None:
        data = model.createData()
        want = np.array([pin.aba(model, data, *s) for s in zip(*sc["inputs"])])
    samples = {k: [] for k in (*sc["timers"], *aba_bins)}
    for _ in range(settings.rounds):
        for key, binaries in sc["timers"].items():      # per round, the faster build; every build checked
            times = []
            for binary in binaries.values():
                ns, got = run_timer([binary, sc["states"], N_SINGLE, settings.repeats, out], out, n)
                times.append(ns)
                if model is not None:
                    row[f"err_{key}"] = max(row.get(f"err_{key}", 0.0), rel_err(got, want))
            samples[key].append(min(times))
        for variant, binary in aba_bins.items():
            ns, got = run_timer([binary, n, sc["states"], N_SINGLE, settings.repeats, out], out, n)
            samples[f"pin_{variant}"] = samples.get(f"pin_{variant}", []) + [ns]
            row[f"err_pin_{variant}"] = rel_err(got, want)
    row.update({f"{key}_ns": statistics.median(values) for key, values in samples.items() if values})
    pins = [k for k in samples if k.startswith("pin_") and samples[k]]
    if pins:
        best = [min(samples[k][r] for k in pins) for r in range(settings.rounds)]
        for key in sc["timers"]:
            row[f"{key}_over_pin"] = statistics.median(c / p for c, p in zip(samples[key], best))
    print(f"{spec:<12} kept {row['kept']:<16} ABA {row['aba_ns']:8.1f} ns  joint-space {row.get('joint_ns', float('nan')):8.1f} ns  "
          f"dense {row.get('dense_ns', float('nan')):8.1f} ns  "
          f"Pin. {min((row[k + '_ns'] for k in pins), default=float('nan')):8.1f} ns  "
          f"ABA/Pin. {row.get('aba_over_pin', float('nan')):.3f}  kept/Pin. {row.get(KEYS[row['kept']] + '_over_pin', float('nan')):.3f}",
          flush=True)
    row["kept_over_pin"] = row.get(f"{KEYS[row['kept']]}_over_pin")
    return row


def markdown(rows, meta) -> str:
    s = meta["settings"]
    lines = [f"# Generated forward dynamics against Pinocchio's aba{' (--quick run)' if meta['quick'] else ''}", "",
             f"Machine: {meta['machine']}; {meta['pinocchio']}. Every time (the thread's CPU clock, `CLOCK_THREAD_CPUTIME_ID`) is the median of {s.repeats} repeats "
             f"inside one timer run, then the median over {s.rounds} interleaved rounds; the ratios are taken "
             "per round (side by side), then the median. Reproduce with `python benchmarks/forward_speed.py` "
             "(`--quick`: 1 round, 3 repeats).", "",
             f"* **ABA C**, **joint-space C**, **dense C**: the generated C `forward_dynamics(q, V_m, tau)` of `chain:n=N` traced by "
             "the articulated-body recursion (`symgen/codegen/aba.py`), by the joint-space route (M_mm = W_m^T M_q W_m, "
             "M_q by the composite-rigid-body algorithm, `symgen/dynamics/crba.py`, the right-hand side from one "
             "recursion) or by the dense route (M of (32) formed), M_mm factored by straight-line LDL^T up to 16 x 16, by the library symmetric factor (no row exchanges) above; called once per state from C (`benchmarks/codegen_timing.c`) "
             f"over {N_SINGLE} random states (q, qd, tau uniform in [-1, 1], seed {SEED}); "
             f"`{' '.join(CFLAGS)}` by each of {', '.join(f'`{c}`' for c in C_COMPILERS)}, the faster build per round.",
             "* **Pin. aba**: Pinocchio's C++ `aba` on the same chain and states (`benchmarks/rnea_timing.cpp` "
             "built with `-DTIME_ABA`); `header`: templates compiled here with `-O3 -march=native`; `clang`: the "
             "same with clang++; `lib`: the wheel's precompiled library. **/ Pin.** = the generated C over the "
             "fastest of these builds, round by round.",
             "* **kept**: the route `symgen generate` keeps for this scene (all traced; fewer operations wins); **kept / Pin.**: its ratio. "
             "**ops**: mul + add of the traced function plus the library solves' flops (LU 2n^3/3, the symmetric factor n^3/3, 2n^2 per "
             "right-hand side), as in `ops.json`. RBDA: Featherstone's Table 10.1 count of the articulated-body "
             "algorithm, (224N - 259) mul + (205N - 248) add.",
             "* **err.**: worst relative error of each against Pinocchio's Python `aba` on the same states.",
             "* **kept** is chosen by operation counts, a proxy: where the counts are close the "
             "route kept can be the slower one per call.", "",
             "| scene | DOF | kept | ops ABA | ops joint-space | ops dense | RBDA ABA | ABA C (ns/call) | joint-space C (ns/call) | dense C (ns/call) | "
             "Pin. aba header (ns/call) | Pin. aba clang (ns/call) | Pin. aba lib (ns/call) | ABA / Pin. | joint-space / Pin. | dense / Pin. | kept / Pin. | "
             "err. ABA, joint-space, dense, Pin. |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        n = r["dof"]
        rbda = (224 * n - 259) + (205 * n - 248)
        errs = ", ".join(fmt(r.get(k)) or "-" for k in ("err_aba", "err_joint", "err_dense", "err_pin_header"))
        lines.append(f"| `{r['scene']}` | {n} | {r['kept']} | {r['aba_ops']} | {r['joint_ops']} | {r['dense_ops']} | {rbda} | "
                     f"{fmt(r['aba_ns'])} | {fmt(r.get('joint_ns')) or 'not timed'} | {fmt(r.get('dense_ns')) or 'not timed'} | "
                     f"{fmt(r.get('pin_header_ns')) or 'n/a'} | {fmt(r.get('pin_clang_ns')) or 'n/a'} | "
                     f"{fmt(r.get('pin_lib_ns')) or 'n/a'} | {fmt(r.get('aba_over_pin')) or 'n/a'} | "
                     f"{fmt(r.get('joint_over_pin')) or '-'} | {fmt(r.get('dense_over_pin')) or '-'} | "
                     f"{fmt(r.get('kept_over_pin')) or '-'} | {errs} |")
    lines += ["", "## Targets", ""]
    by = {r["dof"]: r for r in rows}
    for n, limit in TARGETS.items():
        ratio = by.get(n, {}).get("kept_over_pin")
        lines.append(f"* generated C (the route kept) / Pinocchio C++ aba at N={n}: " + (
            f"{ratio:.3f} (target <= {limit}): {'met' if ratio <= limit else 'MISSED'}" if ratio is not None
            else "not measured (no Pinocchio C++ build)"))
    if meta["notes"]:
        lines += ["", "## Notes", "", f"* Pinocchio builds: {meta['notes']}"]
    return "\n".join(lines) + "\n"


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args(argv)
    settings = Settings(rounds=1 if args.quick else 5, repeats=3 if args.quick else 9, gen_repeats=1, gen_sizes=())
    try:
        import pinocchio as pin
    except ImportError:
        pin = None
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        bins, notes = compile_rnea(pin, work, ["-DTIME_ABA"], "aba") if pin is not None else ({}, "")
        rows = [bench(spec, settings, pin, bins, work) for spec in SCENES]
    meta = dict(settings=settings, quick=args.quick, machine=machine(), notes=notes,
                pinocchio=f"Pinocchio {pin.__version__}" if pin is not None else "Pinocchio not installed")
    (HERE / "forward_speed.md").write_text(markdown(rows, meta))
    keys = sorted({k for r in rows for k in r})
    with open(HERE / "forward_speed.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=keys)
        writer.writeheader()
        writer.writerows(rows)


if __name__ == "__main__":
    main()
