"""Jacobians of constrained forward dynamics: symgen's generated C against Pinocchio's
``computeConstraintDynamicsDerivatives``, side by side.

For every scene of ``SCENES`` (closed chains whose constraints Pinocchio can hold as
``CONTACT_6D`` / ``CONTACT_3D``), in one run, on the same robot and the same loop-closed states:

* **symgen**: the generated C ``<module>_forward_dynamics_derivatives`` (``dV_m`` and ``eta_f``
  differentiated in ``q``, ``V_m`` and ``tau``), called once per state from C
  (``constrained_timing.c`` with ``-DDERIVATIVES``), built by each of ``cc`` and ``clang``, each
  also with ``-ffp-contract=fast`` (``codegen_speed.VARIANTS``; the Pinocchio builds likewise);
* **Pinocchio**: ``constraintDynamics`` followed by ``computeConstraintDynamicsDerivatives``
  (``ddq`` and ``lambda_c`` differentiated in ``q``, ``v`` and ``tau``; mode ``cdd`` of
  ``constrained_timing.cpp``), and ``constraintDynamics`` alone (mode ``cd``) for the cost of the
  primal, each by ``c++`` and ``clang++``, header-only, on the spanning tree of
  ``constrained_forward.py`` (massless spherical leaves dropped: Stewart's sockets).

The two compute different but equivalent Jacobians: Pinocchio's in every joint's ``(q, v)``,
symgen's in ``(q, V_m)`` with the dependent rates eliminated (eq. 10), so the table states what
each returns. Checks: Pinocchio's primal outputs against the generated primal at every state
(``dV_m``, ``eta_f = -lambda_c``), and the generated Jacobians against
``Model.forward_dynamics_derivatives`` (central differences of the dense model in 50-digit
arithmetic) at the first state. Writes ``constrained_derivatives.md`` and ``.csv``.

    python benchmarks/constrained_derivatives.py [--quick] [--scenes a,b]

Needs ``pip install pin cmeel-eigen`` (Pinocchio's headers and Eigen's).
"""
from __future__ import annotations

import argparse
import os
import platform
import re
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import constrained_forward as cf  # noqa: E402
from codegen_speed import C_COMPILERS, CFLAGS, FUSED, VARIANTS, compiler_name, fastest, rel_err  # noqa: E402

SCENES = ["multi_arm:h=2", "stewart"]
FUNCTION = "forward_dynamics_derivatives"
COUNT, CHECKED = 200, 1
INPUTS = ("q", "V_m", "tau")


def signature(directory: Path, module: str) -> dict:
    """The function's name, input sizes and its output matrices ``[(name, size)]`` in argument order."""
    text = (directory / f"{module}.h").read_text()
    args = re.search(rf"int (\w*{module}_{FUNCTION})\(([^)]*)\);", text)
    arrays = re.findall(r"(const )?double \*?(\w+)\[(\d+)\]", args.group(2))
    sizes = {name: int(size) for _, name, size in arrays}
    if "eta_m" in sizes:
        raise SystemExit(f"{module}: contact forces eta_m are not timed here")
    outputs = [(name, int(size)) for const, name, size in arrays if not const]
    return dict(func=args.group(1), NQ=sizes["q"], NM=sizes["V_m"], NT=sizes["tau"], outputs=outputs)


def compile_symgen(directory: Path, module: str, sig: dict, work: Path) -> dict[str, Path]:
    """``{build: binary}``: constrained_timing.c in its derivative mode with the generated source."""
    offsets, total = [], 0
    for _, size in sig["outputs"]:
        offsets.append(total)
        total += size
    deriv_args = ", ".join(f"o + {k}" if k else "o" for k in offsets)
    flags = ["-DSYMGEN_NO_LANES", "-DDERIVATIVES", f"-DFUNC={sig['func']}", f"-DNQ={sig['NQ']}", f"-DNM={sig['NM']}",
             f"-DNT={sig['NT']}", "-DNE=0", "-DNF=0", f"-DNOUT={total}", f"-DDERIV_ARGS(o)={deriv_args}",
             "-include", directory / f"{module}.h"]
    return cf.compile_timers(directory, module, flags, work, "deriv", VARIANTS)


def bench_scene(spec: str, pin_bins: dict, work: Path, count: int, rounds: int, repeats: int) -> dict:
    import symgen
    from symgen.oracle.pinocchio_tree import tree_robot

    model = symgen.derive(symgen.load(spec))
    robot = tree_robot(model, drop_massless_spherical_leaves=True)
    directory, module = cf.generate(spec, work, FUNCTION)
    sig = signature(directory, module)
    sym_bins = compile_symgen(directory, module, sig, work)
    states = cf.draw_states(model, robot, count)
    sym_states = cf.write_states(states, ("q", "V_m", "tau", "eta_m"), work / f"{module}_dsym.bin")
    pin_states = cf.write_states(states, ("q_pin", "v_pin", "tau_pin", "eta_m"), work / f"{module}_dpin.bin")
    model_file = work / f"{module}.model"
    nc = cf.write_model(robot, model_file)
    sym_times = {build: [] for build in sym_bins}
    pin_times = {(mode, cxx): [] for mode in ("cd", "cdd") for cxx in pin_bins}
    for _ in range(rounds):          # interleaved rounds, median taken
        for build, binary in sym_bins.items():
            sym_times[build].append(cf.run_timer([binary, sym_states, count, repeats, work / f"dout_{build}.bin"]))
        for (mode, cxx), times in pin_times.items():
            times.append(cf.run_timer([pin_bins[cxx], model_file, mode, pin_states, count, repeats,
                                       work / f"dout_{mode}_{cxx}.bin"]))
    total = sum(size for _, size in sig["outputs"])
    row = dict(scene=spec, nv_symgen_tree=model.tree.n_coords, nv_pinocchio=robot.model.nv, nc_pinocchio=nc,
               m=model.counts.m, outputs=" ".join(name for name, _ in sig["outputs"]))
    # the generated Jacobians (every build) against the 50-digit central differences of the dense model
    want = [model.forward_dynamics_derivatives(states["config"][i], states["V_m"][i], states["tau"][i])
            for i in range(CHECKED)]
    row["err_symgen_vs_mp"] = 0.0
    for build in sym_bins:
        out = np.fromfile(work / f"dout_{build}.bin").reshape(count, total)
        for i, ref in enumerate(want):
            start = 0
            for name, size in sig["outputs"]:
                got = out[i, start:start + size]
                start += size
                row["err_symgen_vs_mp"] = max(row["err_symgen_vs_mp"],
                                              rel_err(got, np.asarray(ref[name], float).ravel()))
    row["build_symgen"], row["ns_symgen"] = fastest(sym_times)
    # Pinocchio's primal (ddq -> dV_m, -lambda_c) in both modes against the generated forward dynamics
    primal = [model.forward_dynamics(states["config"][i], states["V_m"][i], states["tau"][i])
              for i in range(min(cf.CHECK_DENSE, count))]
    m = model.counts.m
    for mode in ("cd", "cdd"):
        build, row[f"ns_pin_{mode}"] = fastest({cxx: pin_times[mode, cxx] for cxx in pin_bins})
        row[f"build_pin_{mode}"] = build
        out = np.fromfile(work / f"dout_{mode}_{build}.bin").reshape(count, -1)
        row[f"err_pin_{mode}"] = max(
            max(rel_err(out[i, :m], p[0]), rel_err(out[i, m:], p[1]) if len(p[1]) == nc else 0.0)
            for i, p in enumerate(primal))
    row["ratio"] = row["ns_symgen"] / row["ns_pin_cdd"]
    row["pin_cdd_over_cd"] = row["ns_pin_cdd"] / row["ns_pin_cd"]
    return row


FIELDS = ["scene", "nv_symgen_tree", "nv_pinocchio", "nc_pinocchio", "m", "outputs", "ns_symgen", "build_symgen",
          "ns_pin_cdd", "build_pin_cdd", "ns_pin_cd", "build_pin_cd", "ratio", "pin_cdd_over_cd",
          "err_symgen_vs_mp", "err_pin_cd", "err_pin_cdd"]


def write_tables(rows: list, notes: dict, count: int, rounds: int, repeats: int) -> None:
    cf.write_csv(HERE / "constrained_derivatives.csv", FIELDS, rows)
    lines = [
        "# Jacobians of constrained forward dynamics: generated C against computeConstraintDynamicsDerivatives",
        "",
        "Written by `python benchmarks/constrained_derivatives.py` (see its docstring). Nanoseconds per call, one "
        f"call per state over {count} loop-closed states, the median of {rounds} interleaved rounds (each timer the "
        f"median of {repeats} repeats), every column from the same run on the same robot and states.",
        "",
        "* **symgen C**: the generated `forward_dynamics_derivatives` (`q, V_m, tau` -> the outputs named: "
        "`dV_m` and, where model (32) has them, `eta_f`, differentiated in `q`, `V_m`, `tau`; it computes the "
        f"dependent rates itself), `{' '.join(CFLAGS)} -DSYMGEN_NO_LANES`, the fastest of the "
        f"{' and '.join(f'`{compiler_name(c)}`' for c in C_COMPILERS)} builds, each also with "
        f"`{' '.join(FUSED)}` (named `fused`: multiply-adds fused across statements, as the generated bindings "
        "compile).",
        "* **Pinocchio**: `constraintDynamics` then `computeConstraintDynamicsDerivatives` (`ddq` and `lambda_c` "
        "differentiated in every joint's `q`, `v`, `tau`), `ProximalSettings(1e-14, mu = 0, 1 iteration)`, "
        "`initConstraintDynamics` outside the loop; **constraintDynamics**: the primal alone, for scale. "
        "Header-only C++ on the spanning tree (`constrained_timing.cpp`), the fastest of the `c++` and `clang++` "
        f"builds, each also with `{' '.join(FUSED)}` (named). **ratio**: symgen C / Pinocchio's derivatives.",
        "* **err mp**: the generated Jacobians (every build) against `Model.forward_dynamics_derivatives` "
        f"(50-digit central differences of the dense model) at {CHECKED} state(s), max |diff| / max |reference| per "
        "matrix; **err cd / cdd**: Pinocchio's `dV_m` and `eta_f = -lambda_c` from either mode against "
        f"`Model.forward_dynamics` on {cf.CHECK_DENSE} states (its Jacobians are in other coordinates: the "
        "suite compares them along the closure, see the guide).",
        "",
        "| scene | nv (symgen tree / Pinocchio) | nc | m | outputs | symgen C ns | Pinocchio derivatives ns "
        "| constraintDynamics ns | ratio | Pinocchio derivatives / primal | err mp | err cd | err cdd |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| `{r['scene']}` | {r['nv_symgen_tree']} / {r['nv_pinocchio']} | {r['nc_pinocchio']} | {r['m']} "
            f"| {len(r['outputs'].split())} | {r['ns_symgen']:,.0f} ({r['build_symgen']}) "
            f"| {r['ns_pin_cdd']:,.0f} ({r['build_pin_cdd']}) | {r['ns_pin_cd']:,.0f} ({r['build_pin_cd']}) "
            f"| {r['ratio']:.2f} | {r['pin_cdd_over_cd']:.2f} | {r['err_symgen_vs_mp']:.1e} "
            f"| {r['err_pin_cd']:.1e} | {r['err_pin_cdd']:.1e} |")
    lines += ["", f"Pinocchio builds: {notes['pin']}.",
              *([f"Not measured in this run: {', '.join(notes['skipped'])}."] if notes.get("skipped") else []),
              f"Machine: {platform.machine()}, {os.cpu_count()} logical CPUs, shared; Python "
              f"{platform.python_version()}, Pinocchio {notes['pin_version']}."]
    (HERE / "constrained_derivatives.md").write_text("\n".join(lines) + "\n")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer states and rounds")
    parser.add_argument("--scenes", default=",".join(SCENES))
    args = parser.parse_args()
    import pinocchio as pin

    count, rounds, repeats = (50, 1, 5) if args.quick else (COUNT, 5, 11)
    with tempfile.TemporaryDirectory(prefix="symgen-constrained-derivatives-") as tmp:
        work = Path(tmp)
        pin_bins, pin_note = cf.compile_pinocchio(pin, work, variants=VARIANTS)
        if not pin_bins:
            raise SystemExit(f"no Pinocchio build: {pin_note}")
        rows, skipped = [], []
        for spec in args.scenes.split(","):
            try:
                row = bench_scene(spec, pin_bins, work, count, rounds, repeats)
            except (subprocess.CalledProcessError, subprocess.TimeoutExpired) as err:
                print(f"{spec}: {type(err).__name__}", flush=True)
                skipped.append(f"`{spec}` ({type(err).__name__} while generating, compiling or timing)")
                continue
            print(row, flush=True)
            rows.append(row)
    write_tables(rows, dict(pin=pin_note, pin_version=pin.__version__, skipped=skipped), count, rounds, repeats)


if __name__ == "__main__":
    main()
