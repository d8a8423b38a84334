"""Speed of symgen's generated adaptive control law (eq. 34) against the generated inverse dynamics
and Pinocchio's C++ ``rnea``, side by side in one run; plus operation counts.

On ``chain:n=6``, per call from C over the same 1000 random states: the generated C ``control``
with every parameter uncertain (``P_hat`` of 78 entries; ``control_timing.c``) and with none
(all folded), the generated C ``inverse_dynamics`` (``codegen_timing.c``) and Pinocchio's ``rnea``
built from C++ (``rnea_timing.cpp``, both variants of :mod:`codegen_speed`), interleaved round by
round; the ratios are taken per round, then the median. Operation counts of ``control``,
``adaptation`` and ``inverse_dynamics`` on ``chain:n=6`` and the per-arm increments on
``multi_arm:h=H``. Writes ``control_speed.md`` beside this file.

    python benchmarks/control_speed.py [--quick]
"""
from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import codegen_speed as cs  # noqa: E402  (the shared harness pieces: states, timers, Pinocchio build)

SCENE = "chain:n=6"
ARMS = (1, 2, 3, 4, 5, 6)
#: uncertain-parameter choices timed: every parameter an input, or all folded
CHOICES = {"all": "all", "none": "none"}


def control_states(model, q, qd, qdd, count: int, uncertain) -> list[np.ndarray]:
    """``[q, V_m, V_mr, dV_mr, P_hat]`` per state: ``V_m = qd`` (the chain's motion is its joints),
    ``V_mr`` off by up to 0.5, ``dV_mr = qdd``, estimates off the scene's values by up to 30 %."""
    from symgen.control.law import default_parameters
    rng = np.random.default_rng(cs.SEED + 1)
    params = default_parameters(model)
    true = np.array([float(params.values[params.index(n)]) for n in uncertain])
    v_mr = qd[:count] + rng.uniform(-0.5, 0.5, qd[:count].shape)
    p_hat = true * (1 + 0.3 * rng.uniform(-1, 1, (count, true.size)))
    return [q[:count], qd[:count], v_mr, qdd[:count], p_hat]


def build_control(model, choice: str, work: Path, states) -> dict:
    """Generate ``control`` for one choice, compile its timer, check it against the dense law."""
    from symgen.codegen.generate import generate, trace_all
    from symgen.codegen.runtime import load_generated
    lowered = trace_all(model, ["control"], {"uncertain": CHOICES[choice]})
    fn = lowered[0].function
    uncertain = fn.metadata["P_hat"]
    gen = generate(model, "c", lowered=lowered)
    src = cs.write_generated(gen, work / f"control_{choice}")
    nq, nv, npar = model_sizes(model) + (len(uncertain),)
    args = control_states(model, *states, cs.N_SINGLE, uncertain)
    states_file = work / f"control_{choice}.bin"
    np.concatenate([a.ravel() for a in args]).tofile(states_file)
    binary = work / f"timer_control_{choice}"
    cmd = [cs.CC, *cs.CFLAGS, "-Wall", "-Wextra", f"-DFUNC=symgen_{gen.module}_control", f"-DNQ={nq}", f"-DNV={nv}",
           f"-DNP={npar}", HERE / "control_timing.c", src / f"{gen.module}.c", "-lm", "-o", binary]
    result = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, check=True)
    module = load_generated(model, "numpy", lowered=lowered)
    want = np.array([module.control(*(a[i] for a in args[:4]), *([args[4][i]] if npar else [])) for i in range(5)])
    dense = [fn.reference(dict(config=cfg, **s))["tau"] for cfg, s in dense_inputs(model, args, uncertain)]
    return dict(binary=binary, states=states_file, want=want, ops=lowered[0].ops, uncertain=len(uncertain),
                err_dense=cs.rel_err(want, np.array(dense)),
                warnings=[line for line in result.stderr.splitlines() if "warning:" in line])


def dense_inputs(model, args, uncertain):
    """The first five states as inputs of the dense controller (:mod:`symgen.control.law`)."""
    from symgen.math.configuration import Configuration
    names = [j.name for j in model.scene.joints.values() if j.kind.position_size]
    for i in range(5):
        cfg = Configuration(dict(zip(names, (float(x) for x in args[0][i]))))
        yield cfg, dict(V_m=args[1][i], V_mr=args[2][i], dV_mr=args[3][i], eta_fr=np.zeros(0),
                        P_hat=args[4][i] if uncertain else np.zeros(0))


def model_sizes(model) -> tuple[int, int]:
    from symgen.codegen.trace import position_layout
    return sum(s for *_, s in position_layout(model)), model.counts.n


def time_all(settings, model, work: Path, rnea_bins: dict) -> dict:
    """Every timer of ``chain:n=6`` interleaved round by round: ns per call and per-round ratios."""
    from symgen.codegen.generate import generate
    nq, nv = model_sizes(model)
    q, qd, qdd = cs.draw_states(nq, nv, cs.N_SINGLE)
    id_states = work / "id.bin"
    np.concatenate([a.ravel() for a in (q, qd, qdd)]).tofile(id_states)
    gen = generate(model, "c", ["inverse_dynamics"])
    id_src = cs.write_generated(gen, work / "id")
    id_bin, id_warn = cs.compile_c_timer(id_src, gen.module, nq, nv, work)
    controls = {c: build_control(model, c, work, (q, qd, qdd)) for c in CHOICES}
    out = work / "tau.bin"
    samples = {k: [] for k in ("id", *(f"control_{c}" for c in CHOICES), *rnea_bins)}
    errors = {}
    for _ in range(settings.rounds):
        ns, tau_id = cs.run_timer([id_bin, id_states, cs.N_SINGLE, settings.repeats, out], out, nv)
        samples["id"].append(ns)
        for c, info in controls.items():
            ns, tau = cs.run_timer([info["binary"], info["states"], cs.N_SINGLE, settings.repeats, out], out, nv)
            samples[f"control_{c}"].append(ns)
            errors[f"control_{c}"] = cs.rel_err(tau[:5], info["want"])
        for variant, binary in rnea_bins.items():
            ns, tau = cs.run_timer([binary, nv, id_states, cs.N_SINGLE, settings.repeats, out], out, nv)
            samples[variant].append(ns)
            errors[f"pin_{variant}"] = cs.rel_err(tau, tau_id)
    return dict(samples=samples, errors=errors, controls=controls, id_warnings=id_warn)


def ratio(samples, num, dens) -> float:
    """Median over rounds of ``num / (fastest of dens)`` in that round."""
    rounds = len(samples[num])
    return statistics.median(samples[num][r] / min(samples[d][r] for d in dens) for r in range(rounds))


def arm_increments(arms) -> list[tuple[int, int, int]]:
    """``(H, control total, task_inverse_dynamics total)`` on ``multi_arm:h=H``."""
    from symgen.codegen.linearity import family_counts
    ctl = family_counts("multi_arm", arms, "control")
    task = family_counts("multi_arm", arms, "task_inverse_dynamics")
    return [(h, c["total"], t["total"]) for (h, c), (_, t) in zip(ctl, task)]


def op_rows(model) -> list[tuple[str, dict]]:
    from symgen.codegen.generate import operation_counts
    rows = [("inverse_dynamics", operation_counts(model, ["inverse_dynamics"])["inverse_dynamics"])]
    for choice in CHOICES:
        functions = ["control", "adaptation"] if choice == "all" else ["control"]
        counts = operation_counts(model, functions, {"uncertain": CHOICES[choice]})
        rows.append((f"control, {choice} uncertain", counts["control"]))
        if choice == "all":
            rows.append(("adaptation, all uncertain", counts["adaptation"]))
    return rows


def markdown(result, ops, arms, meta) -> str:
    s = result["samples"]
    med = {k: statistics.median(v) for k, v in s.items()}
    pins = [k for k in s if k in ("header", "lib")]
    lines = ["# Generated adaptive control law: speed", "",
             f"Machine: {meta['machine']}; {meta['pinocchio']}. Reproduce with `python benchmarks/control_speed.py` "
             f"(`--quick`: 1 round, 3 repeats). Every time is the median of {meta['settings'].repeats} repeats inside "
             f"one timer run, then the median over {meta['settings'].rounds} interleaved rounds of all timers; the "
             "ratios are taken per round (side by side), then the median.", "",
             f"* Scene `{SCENE}` (6 revolute joints, motion on the joints: `V_m = qd`), {cs.N_SINGLE} random states "
             f"(uniform in [-1, 1], seed {cs.SEED}), each function called once per state from C, "
             f"`{cs.CC} {' '.join(cs.CFLAGS)}`, separate translation unit.",
             "* `control`: eq. (34) generated with `symgen generate chain:n=6 --functions control` "
             "(`benchmarks/control_timing.c`); *all uncertain*: every parameter of `default_parameters` is an input "
             f"(`P_hat`, {result['controls']['all']['uncertain']} entries, estimates off by up to 30 %); "
             "*none uncertain*: all parameters folded as the scene's values (`--uncertain none`). `K_A` folded (1).",
             "* `inverse_dynamics`: `M_q qdd + C_q qd + G_q` (`benchmarks/codegen_timing.c`), the same states.",
             "* Pinocchio: C++ `rnea` (`benchmarks/rnea_timing.cpp`, built as in `codegen_speed.py`), the same "
             "states and robot.", "",
             "| function | ns/call | / inverse_dynamics | / Pinocchio rnea | target |", "|---|---|---|---|---|"]
    for key, label, target in (("control_all", "`control`, all uncertain", "<= 2x id, <= 1x Pin."),
                               ("control_none", "`control`, none uncertain", ""),
                               ("id", "`inverse_dynamics`", ""), *((p, f"Pinocchio `rnea` ({p})", "") for p in pins)):
        by_id = f"{ratio(s, key, ['id']):.2f}" if key != "id" and key not in pins else ""
        by_pin = f"{ratio(s, key, pins):.2f}" if pins and key not in pins else ""
        lines.append(f"| {label} | {med[key]:.0f} | {by_id} | {by_pin} | {target} |")
    errs = result["errors"]
    lines += ["", "Checks: generated C `control` against the generated NumPy module at 5 states "
              + ", ".join(f"{k}: {v:.2e}" for k, v in errs.items() if k.startswith("control"))
              + "; the NumPy module against the dense controller of `symgen.control.law`: "
              + ", ".join(f"{c}: {info['err_dense']:.2e}" for c, info in result["controls"].items())
              + (("; Pinocchio `rnea` against generated `inverse_dynamics`: "
                  + ", ".join(f"{k}: {v:.2e}" for k, v in errs.items() if k.startswith("pin")))
                 if pins else "") + ". Warnings compiling with `-Wall -Wextra`: "
              + str(sum(len(i["warnings"]) for i in result["controls"].values()) + len(result["id_warnings"])) + ".",
              "", f"## Operation counts on `{SCENE}`", "",
              "mul includes div, add includes sub, total = mul + add; sign and sin/cos apart.", "",
              "| function | mul | add | total | sign | sin/cos | total / inverse_dynamics |",
              "|---|---|---|---|---|---|---|"]
    base = ops[0][1]["total"]
    for name, o in ops:
        lines.append(f"| {name} | {o['mul']} | {o['add']} | {o['total']} | {o['cmp']} | {o['trig']} | "
                     f"{o['total'] / base:.2f} |")
    lines += ["", "## Per arm on `multi_arm:h=H` (every parameter uncertain)", "",
              "`control` shares the task-space solves with `[J_m; J_f]` (`symgen.codegen.arms`) with "
              "`task_inverse_dynamics`; their constants (the arms' placements, `gamma_i = 1/H`) fold differently "
              "with H, so both totals move by a few hundred operations from one H to the next. What the controller "
              "adds on top (regressor recursion, adaptation terms, `K_A e`) is nearly the same for every arm: each "
              "arm's 6 x 6 tool Jacobian is eliminated in line, in a pivot order chosen from its own sample values, so "
              "the extra right-hand sides the controller solves cost a few operations more or less per arm.", "",
              "| H | control | increment | task_inverse_dynamics | control - task_inverse_dynamics | increment |",
              "|---|---|---|---|---|---|"]
    prev = None
    for h, c, t in arms:
        inc = "" if prev is None else str(c - prev[0])
        own = "" if prev is None else str((c - t) - (prev[0] - prev[1]))
        lines.append(f"| {h} | {c} | {inc} | {t} | {c - t} | {own} |")
        prev = (c, t)
    from symgen.codegen.linearity import fit_line
    fit = fit_line([h for h, *_ in arms], [c for _, c, _ in arms])
    lines += ["", f"Fit of `control`: total = {fit.slope:.1f} H {fit.intercept:+.1f} (R^2 = {fit.r2:.6f}).",
              ""]
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="1 round, 3 repeats")
    args = parser.parse_args()
    from symgen.io.builtin import get_scene
    from symgen.model import derive
    try:
        import pinocchio as pin
    except ImportError:
        pin = None
    settings = cs.Settings(1, 3, 1, ()) if args.quick else cs.Settings(7, 9, 1, ())
    model = derive(get_scene(SCENE))
    with tempfile.TemporaryDirectory(prefix="symgen-control-bench-") as tmp:
        work = Path(tmp)
        os.environ["SYMGEN_CACHE"] = str(work / "cache")
        rnea_bins, pin_note = cs.compile_rnea(pin, work) if pin is not None else ({}, "")
        result = time_all(settings, model, work, rnea_bins)
    pin_desc = ("Pinocchio not installed" if pin is None else f"Pinocchio {pin.__version__}, C++ rnea timed from C++"
                if rnea_bins else f"Pinocchio {pin.__version__}: C++ build failed ({pin_note})")
    meta = {"machine": cs.machine(), "pinocchio": pin_desc, "settings": settings}
    text = markdown(result, op_rows(model), arm_increments(ARMS), meta)
    (HERE / "control_speed.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()
