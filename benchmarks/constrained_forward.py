"""Constrained forward dynamics: symgen's generated C against Pinocchio's C++, side by side.

For every scene of ``SCENES``, in one run, on the same robot and the same loop-closed states:

* **symgen**: the generated C ``<module>_forward_dynamics`` (``symgen generate SCENE --target c``),
  called once per state from C (``constrained_timing.c``). The harness uses only the function's
  public signature ``(q, V_m, tau, [eta_m,] dV_m, [eta_f,] cond)``, read from the generated header.
* **Pinocchio ``constraintDynamics``** (``initConstraintDynamics`` outside the loop) when every
  constraint is a weld (``CONTACT_6D``) or a ball (``CONTACT_3D``), then ``dV_m`` from ``ddq``;
* **Pinocchio KKT**: ``forwardKinematics(q, v, 0)``, ``computeJointJacobians``, frame Jacobians and
  drifts of the constraints' selected components, ``crba``, ``nonLinearEffects``, and the
  ``(nv + nc)`` KKT system solved by Eigen's ``PartialPivLU`` (for every constrained scene: it is
  the only Pinocchio route for ``planar_weld`` and ``plane_contact``);
* **Pinocchio ``aba``** for the open chains;

all timed from C++ (``constrained_timing.cpp``, header-only, the same ``-O3 -march=native``).
The robot is :func:`symgen.oracle.pinocchio_tree.tree_robot` with massless spherical leaves
dropped (the Stewart platform's sockets: each leg's weld becomes a ball at the spherical joint),
exported as text and rebuilt in C++ with ``addJoint`` / ``appendBodyToJoint`` / ``addFrame``.
Pinocchio receives every joint rate ``v`` (symgen's ``qd_all = P Omega V_m``, computed here in
Python); symgen's function receives ``V_m`` and computes the dependent rates itself.

Each C++ result is checked against the generated C's on every state (max relative difference of
``dV_m`` and, where the constraints have forces in model (32), ``eta_f = -lambda``), and the
generated C against ``Model.forward_dynamics`` on the first states. Writes
``constrained_forward.md`` and ``.csv`` beside this file.

    nice python benchmarks/constrained_forward.py [--quick] [--scenes a,b] [--pin-binary PATH]

Needs ``pip install pin cmeel-eigen`` (Pinocchio's headers and Eigen's).
"""
from __future__ import annotations

import argparse
import csv
import os
import platform
import re
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))
from codegen_speed import (C_COMPILERS, CFLAGS, CLANGXX, CXX, CXXFLAGS, PIN_DEFINES, compiler_name, fastest,  # noqa: E402
                           joint_lines, rel_err)

SCENES = ["four_bar", "five_bar", "stewart", "arm_on_plane", "multi_arm:h=2", "chain:n=6", "chain:n=64"]
COUNT, SEED, CHECK_DENSE = 200, 11, 10
COMPILE_TIMEOUT = 1800      # seconds for one generated C file (chain:n=64's forward dynamics is ~7 MB)
COMPONENT_INDEX = {c: k for k, c in enumerate(("vx", "vy", "vz", "wx", "wy", "wz"))}


# ---------------------------------------------------------------- symgen side
def generate(spec: str, work: Path, function: str = "forward_dynamics") -> tuple[Path, str]:
    """``symgen generate SPEC --target c --functions FUNCTION``; return (dir, module name)."""
    out = work / (re.sub(r"\W", "_", spec) + ("" if function == "forward_dynamics" else f"_{function}"))
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    subprocess.run([sys.executable, "-m", "symgen", "generate", spec, "--target", "c", "--out", str(out),
                    "--functions", function], check=True, capture_output=True, text=True, env=env)
    header = next(out.glob("*.h"))
    return out, header.stem


def signature(directory: Path, module: str) -> dict:
    """Argument sizes of ``<module>_forward_dynamics`` from the generated header."""
    text = (directory / f"{module}.h").read_text()
    args = re.search(rf"int (\w*{module}_forward_dynamics)\(([^)]*)\);", text)
    sizes = dict(re.findall(r"double \*?(\w+)\[(\d+)\]", args.group(2)))
    return dict(func=args.group(1), NQ=int(sizes["q"]), NM=int(sizes["V_m"]), NT=int(sizes["tau"]),
                NE=int(sizes.get("eta_m", 0)), NF=int(sizes.get("eta_f", 0)))


def compile_timers(directory: Path, module: str, flags: list, work: Path, stem: str,
                   variants: dict | None = None) -> dict[str, Path]:
    """``{build: binary}``: constrained_timing.c with the generated source and ``flags`` (its
    ``-D`` sizes and mode), by each of ``C_COMPILERS`` in each of ``variants`` (``{suffix of the
    build's name: extra flags}``; the plain build only by default). The timing takes the fastest
    build, as for Pinocchio's."""
    binaries = {}
    for cc in C_COMPILERS:
        for suffix, extra in (variants or {"": []}).items():
            build = compiler_name(cc) + suffix
            binary = work / f"{stem}_{module}_{build.replace(' ', '_')}"
            cmd = [cc, *CFLAGS, *extra, *flags, HERE / "constrained_timing.c", directory / f"{module}.c", "-lm",
                   "-o", binary]
            subprocess.run([str(c) for c in cmd], check=True, capture_output=True, text=True, timeout=COMPILE_TIMEOUT)
            binaries[build] = binary
    return binaries


def compile_symgen(directory: Path, module: str, sig: dict, work: Path) -> dict[str, Path]:
    """:func:`compile_timers` of the generated ``forward_dynamics``."""
    defines = [f"-D{k}={sig[k]}" for k in ("NQ", "NM", "NT", "NE", "NF")]
    return compile_timers(directory, module, [f"-DFUNC={sig['func']}", *defines], work, "symgen")


# ---------------------------------------------------------------- Pinocchio side
def pinocchio_command(pin, binary: Path, cxx: str = CXX, extra: tuple = ()) -> tuple[list | None, str]:
    """The header-only C++ build of constrained_timing.cpp by ``cxx`` with the ``extra`` flags, and
    how to show it."""
    prefix = next((p for p in Path(pin.__file__).resolve().parents if p.name == "cmeel.prefix"), None)
    if prefix is None:
        return None, "no cmeel.prefix beside the pinocchio package"
    eigen = next((p for p in (prefix / "include" / "eigen3", Path("/usr/include/eigen3")) if p.is_dir()), None)
    if eigen is None:
        return None, "Eigen headers missing (pip install cmeel-eigen)"
    cmd = [cxx, *CXXFLAGS, *extra, *PIN_DEFINES, "-I", prefix / "include", "-I", eigen,
           HERE / "constrained_timing.cpp", "-o", binary]
    shown = " ".join(map(str, cmd)).replace(str(prefix), "$PREFIX").replace(str(binary.parent), "$TMP")
    return cmd, f"`{shown.replace(str(HERE), 'benchmarks')}` (PREFIX = pinocchio's cmeel.prefix)"


def compile_pinocchio(pin, work: Path, prebuilt: Path | None = None,
                      variants: dict | None = None) -> tuple[dict, str]:
    """``({build: binary}, how they were built)``: constrained_timing.cpp by the default C++
    compiler and by clang++ (``CLANGXX``; Pinocchio's maintainers build with clang where they can),
    each in each of ``variants`` (``{suffix of the build's name: extra flags}``; the plain build
    only by default): every Pinocchio time is the fastest build's. ``prebuilt``: a folder where an
    earlier run's binaries are (the header-only builds take minutes each)."""
    binaries, notes = {}, []
    for cxx in dict.fromkeys(c for c in (CXX, CLANGXX) if c):
        for suffix, extra in (variants or {"": []}).items():
            build = Path(cxx).name + suffix
            binary = (prebuilt or work) / f"constrained_pin_{build.replace(' ', '_')}"
            cmd, shown = pinocchio_command(pin, binary, cxx, tuple(extra))
            if cmd is None:
                return {}, shown
            if prebuilt is not None:
                if binary.is_file():
                    binaries[build] = binary
                    notes.append("prebuilt as " + shown)
                continue
            result = subprocess.run([str(c) for c in cmd], capture_output=True, text=True)
            if result.returncode:
                notes.append(f"{build} failed to compile: {(result.stderr.strip().splitlines() or ['?'])[-1]}")
                continue
            binaries[build] = binary
            notes.append(shown)
    return binaries, "; ".join(notes) + (" (each Pinocchio time: the fastest build)" if len(binaries) > 1 else "")


def _se3_text(x) -> str:
    return " ".join(f"{v:.17g}" for v in (*np.asarray(x.rotation).ravel(), *np.asarray(x.translation)))


def _comps(components) -> str:
    return f"{len(components)} " + " ".join(str(COMPONENT_INDEX[c]) for c in components)


def write_model(robot, path: Path) -> int:
    """The model file of ``constrained_timing.cpp``; returns the number of constraint rows."""
    from symgen.oracle.pinocchio_tree import PINOCCHIO_CONSTRAINTS, _ball_at_dropped_joint, frame_placement

    model, scene = robot.model, robot.scene
    lines = [f"{model.nq} {model.nv} {model.njoints - 1}", *joint_lines(model)]
    if robot.spherical_friction:
        raise SystemExit(f"{scene.name}: spherical-joint friction is not exported to constrained_timing.cpp")
    for values in (model.armature, robot.damping, robot.coulomb):
        lines.append(" ".join(f"{v:.17g}" for v in values))
    lines.append(" ".join(f"{v:.17g}" for v in model.gravity.linear))
    lines.append(str(len(scene.constraints)))
    rows = 0
    for con in scene.constraints.values():
        if robot.frame_on_dropped(con.frame_a) or robot.frame_on_dropped(con.frame_b):
            (ja, xa), (jb, xb), _ = _ball_at_dropped_joint(robot, con)
            ctype, comps = 3, ("vx", "vy", "vz")
        else:
            (ja, xa), (jb, xb) = frame_placement(robot, con.frame_a), frame_placement(robot, con.frame_b)
            spec = PINOCCHIO_CONSTRAINTS.get(con.kind)
            ctype = int(spec[0][-2]) if spec and tuple(con.components) == spec[1] else 0
            comps = con.components
        rows += len(comps)
        lines.append(f"{ctype} {ja} {_se3_text(xa)} {jb} {_se3_text(xb)} {_comps(comps)}")
    motion = scene.motion
    if motion.joints:
        idx = robot.v_index(motion.joints)
        lines.append(f"0 {len(idx)} " + " ".join(map(str, idx)))
    else:
        frames = [f"{j} {_se3_text(x)} {scene.value_of(g):.17g}"
                  for (j, x), (_, g) in ((frame_placement(robot, f), (f, g)) for f, g in motion.frames)]
        lines.append(f"1 {len(frames)} " + " ".join(frames) + f" {_comps(motion.components)}")
    cf = scene.contact_forces
    if cf is None:
        lines.append("0")
    else:
        j, x = frame_placement(robot, cf.frame)
        lines.append(f"{len(cf.components)} {j} {_se3_text(x)} " + " ".join(str(COMPONENT_INDEX[c]) for c in cf.components))
    path.write_text("\n".join(lines) + "\n")
    return rows


# ---------------------------------------------------------------- states
def draw_states(model, robot, count: int) -> dict:
    """Loop-closed states for both sides: symgen's (q, V_m, tau, eta_m), Pinocchio's (q, v, tau, eta_m)."""
    from symgen.closure import random_consistent_states
    from symgen.codegen.reference import position_vector

    rng = np.random.default_rng(SEED)
    n, cf = model.counts.n, model.scene.contact_forces
    ne = len(cf.components) if cf else 0
    tau_idx = robot.v_index(model.coordinate_names())
    out = {k: [] for k in ("config", "q", "V_m", "tau", "eta_m", "q_pin", "v_pin", "tau_pin")}
    for config, v_m in random_consistent_states(model, count, seed=SEED, spread=0.3):
        tau, eta_m = rng.uniform(-1, 1, n), rng.uniform(-1, 1, ne)
        u = np.zeros(robot.model.nv)
        u[tau_idx] = tau
        for key, value in (("config", config), ("q", position_vector(model, config)), ("V_m", np.asarray(v_m, float)),
                           ("tau", tau), ("eta_m", eta_m), ("q_pin", robot.q_vector(config)),
                           ("v_pin", robot.v_vector(model.joint_rates(config, v_m))), ("tau_pin", u)):
            out[key].append(value)
    return out


def write_states(states: dict, keys, path: Path) -> Path:
    np.concatenate([np.asarray(states[k], float).ravel() for k in keys]).tofile(path)
    return path


def run_timer(cmd: list) -> float:
    result = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, check=True)
    return float(result.stdout.split()[0])


# ---------------------------------------------------------------- one scene
def bench_scene(spec: str, pin, pin_bins: dict, work: Path, count: int, rounds: int, repeats: int) -> dict:
    import symgen
    from symgen.oracle.pinocchio_tree import maps_to_pinocchio, tree_robot

    model = symgen.derive(symgen.load(spec))
    robot = tree_robot(model, drop_massless_spherical_leaves=True)
    directory, module = generate(spec, work)
    sig = signature(directory, module)
    sym_bins = compile_symgen(directory, module, sig, work)
    states = draw_states(model, robot, count)
    sym_states = write_states(states, ("q", "V_m", "tau", "eta_m"), work / f"{module}_sym.bin")
    pin_states = write_states(states, ("q_pin", "v_pin", "tau_pin", "eta_m"), work / f"{module}_pin.bin")
    model_file = work / f"{module}.model"
    nc = write_model(robot, model_file)
    modes = ["aba"] if not model.scene.constraints else (["cd", "kkt"] if maps_to_pinocchio(model.scene) else ["kkt"])
    row = dict(scene=spec, nv_symgen_tree=model.tree.n_coords, nv_pinocchio=robot.model.nv, nc_pinocchio=nc,
               m=model.counts.m)
    sym_times = {build: [] for build in sym_bins}
    times = {(mode, cxx): [] for mode in modes for cxx in pin_bins}
    for _ in range(rounds):          # interleaved rounds, median taken
        for build, sym_bin in sym_bins.items():
            sym_times[build].append(run_timer([sym_bin, sym_states, count, repeats, work / f"out_sym_{build}.bin"]))
        for mode in modes:
            for cxx, pin_bin in pin_bins.items():
                times[mode, cxx].append(run_timer([pin_bin, model_file, mode, pin_states, count, repeats,
                                                   work / f"out_{mode}.bin"]))
    m, nf = sig["NM"], sig["NF"]
    dense = [model.forward_dynamics(states["config"][i], states["V_m"][i], states["tau"][i],
                                    states["eta_m"][i] if sig["NE"] else None) for i in range(min(CHECK_DENSE, count))]
    row["err_symgen_c_vs_dense"] = 0.0
    for build in sym_bins:           # every build checked, the faster one's results compared below
        sym_out = np.fromfile(work / f"out_sym_{build}.bin")
        dv_sym, eta_sym = sym_out[:count * m].reshape(count, m), sym_out[count * m:].reshape(count, nf)
        row["err_symgen_c_vs_dense"] = max(row["err_symgen_c_vs_dense"], *(
            max(rel_err(dv_sym[i], d[0]), rel_err(eta_sym[i], d[1]) if nf else 0.0) for i, d in enumerate(dense)))
    row["build_symgen"], row["ns_symgen"] = fastest(sym_times)
    sym_out = np.fromfile(work / f"out_sym_{row['build_symgen']}.bin")
    dv_sym, eta_sym = sym_out[:count * m].reshape(count, m), sym_out[count * m:].reshape(count, nf)
    for mode in modes:
        if not pin_bins:
            continue
        row[f"ns_pin_{mode}"] = min(statistics.median(times[mode, cxx]) for cxx in pin_bins)
        out = np.fromfile(work / f"out_{mode}.bin").reshape(count, -1)
        err = rel_err(out[:, :m], dv_sym)
        if nf and nf == nc:          # eta_f of model (32) are the constraint multipliers
            err = max(err, rel_err(out[:, m:], eta_sym))
        row[f"err_pin_{mode}"] = err
    pins = [row[f"ns_pin_{mode}"] for mode in modes if f"ns_pin_{mode}" in row]
    if pins:
        row["best_pinocchio"] = min(modes, key=lambda mode: row.get(f"ns_pin_{mode}", np.inf))
        row["ratio_symgen_over_best"] = row["ns_symgen"] / min(pins)
    return row


# ---------------------------------------------------------------- tables
MODE_NAMES = {"cd": "constraintDynamics", "kkt": "KKT (crba + NLE + Jacobians, LU)", "aba": "aba"}
FIELDS = ["scene", "nv_symgen_tree", "nv_pinocchio", "nc_pinocchio", "m", "ns_symgen", "build_symgen", "ns_pin_cd", "ns_pin_kkt",
          "ns_pin_aba", "best_pinocchio", "ratio_symgen_over_best", "err_pin_cd", "err_pin_kkt", "err_pin_aba",
          "err_symgen_c_vs_dense"]


def _fmt(value, kind="ns") -> str:
    if value is None or value == "":
        return "–"
    if kind == "ns":
        return f"{value:,.0f}"
    if kind == "ratio":
        return f"{value:.2f}"
    return f"{value:.1e}"


def write_csv(path: Path, fields: list[str], rows: list[dict]) -> None:
    """The rows' ``fields`` as CSV, floats to six significant digits, missing cells empty."""
    with open(path, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=fields)
        writer.writeheader()
        for row in rows:
            writer.writerow({k: (f"{row[k]:.6g}" if isinstance(row.get(k), float) else row.get(k, "")) for k in fields})


def write_tables(rows: list, notes: dict, count: int) -> None:
    write_csv(HERE / "constrained_forward.csv", FIELDS, rows)
    lines = [
        "# Constrained forward dynamics: symgen's generated C against Pinocchio's C++",
        "",
        "Written by `python benchmarks/constrained_forward.py` (see its docstring). Nanoseconds per call, one",
        f"call per state over {count} loop-closed states, median of interleaved rounds, every column from the",
        "same run on the same robot and states. symgen: the generated C `forward_dynamics` (inputs `q, V_m, tau`",
        "[, `eta_m`]; it computes the dependent joint rates itself). Pinocchio: C++ on the scene's spanning tree",
        "(`symgen.oracle.pinocchio_tree`, massless spherical leaves dropped), given every joint rate `v`; its",
        "`dV_m` is computed from `ddq` inside the timed call. `ratio` = symgen / the fastest Pinocchio column.",
        "`err`: max relative difference of the C++ result from the generated C's, over all states (`dV_m`, and",
        "`eta_f` where model (32) has constraint forces); `err C/dense`: generated C against",
        f"`Model.forward_dynamics` on {CHECK_DENSE} states.",
        "",
        "| scene | nv (symgen tree / Pinocchio) | nc | symgen C ns | constraintDynamics ns | KKT ns | aba ns "
        "| ratio symgen / best | err constraintDynamics | err KKT | err aba | err C/dense |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| `{r['scene']}` | {r['nv_symgen_tree']} / {r['nv_pinocchio']} | {r['nc_pinocchio']} "
            f"| {_fmt(r['ns_symgen'])} ({r['build_symgen']}) "
            f"| {_fmt(r.get('ns_pin_cd'))} | {_fmt(r.get('ns_pin_kkt'))} | {_fmt(r.get('ns_pin_aba'))} "
            f"| {_fmt(r.get('ratio_symgen_over_best'), 'ratio')} | {_fmt(r.get('err_pin_cd'), 'e')} "
            f"| {_fmt(r.get('err_pin_kkt'), 'e')} | {_fmt(r.get('err_pin_aba'), 'e')} "
            f"| {_fmt(r.get('err_symgen_c_vs_dense'), 'e')} |")
    lines += [
        "",
        "Notes:",
        "- `constraintDynamics` applies to welds and balls only (`multi_arm:h=2`: one `CONTACT_6D`; `stewart`: five",
        "  `CONTACT_3D`: each leg's weld on its massless socket is a ball at the spherical joint, which is left",
        "  out because Pinocchio's sparse Cholesky meets a zero pivot on it). It is called with",
        "  `ProximalSettings(1e-14, mu = 0, 1 iteration)`, the exact KKT solve, after `initConstraintDynamics`",
        "  outside the loop. `four_bar` and `five_bar` (planar welds) and `arm_on_plane` (plane contact, with",
        "  contact forces `eta_m`) have no Pinocchio constraint type: the KKT column is the Pinocchio route there.",
        "- The KKT is dense `PartialPivLU` of the (nv + nc) system: the tree's mass matrix is singular where a",
        "  massless body hangs on a joint (`four_bar`, `five_bar`: the pin), so no Cholesky of `M` alone.",
        f"- symgen C: `{' '.join(CFLAGS)}` by each of {', '.join(f'`{c}`' for c in C_COMPILERS)}, the faster build "
        "named beside its time (both builds checked against the dense model); Pinocchio: "
        f"{notes['pin']}.",
        *([f"- Not measured in this run: {', '.join(notes['skipped'])}."] if notes.get("skipped") else []),
        f"- Machine: {platform.machine()}, {os.cpu_count()} logical CPUs, shared with other jobs; Python "
        f"{platform.python_version()}, Pinocchio {notes['pin_version']}.",
    ]
    (HERE / "constrained_forward.md").write_text("\n".join(lines) + "\n")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer states and rounds, no chain:n=64")
    parser.add_argument("--scenes", default=",".join(SCENES))
    parser.add_argument("--pin-binary", type=Path, help="a constrained_timing.cpp binary built before (the "
                        "header-only build takes minutes); by default it is compiled here")
    args = parser.parse_args()
    import pinocchio as pin

    count, rounds, repeats = (50, 1, 5) if args.quick else (COUNT, 3, 11)
    scenes = [s for s in args.scenes.split(",") if not (args.quick and s == "chain:n=64")]
    with tempfile.TemporaryDirectory(prefix="symgen-constrained-") as tmp:
        work = Path(tmp)
        if args.pin_binary:
            pin_bins, pin_note = {"prebuilt": args.pin_binary}, "prebuilt as " + pinocchio_command(pin, args.pin_binary)[1]
        else:
            pin_bins, pin_note = compile_pinocchio(pin, work)
        rows, skipped = [], []
        for spec in scenes:
            try:
                row = bench_scene(spec, pin, pin_bins, work, count, rounds, repeats)
            except (subprocess.CalledProcessError, subprocess.TimeoutExpired) as err:
                print(f"{spec}: {type(err).__name__}", flush=True)
                skipped.append(f"`{spec}` ({type(err).__name__} while generating, compiling or timing)")
                continue           # the table is written with the scenes that ran
            print(row, flush=True)
            rows.append(row)
    write_tables(rows, dict(pin=pin_note, pin_version=pin.__version__, skipped=skipped), count)


if __name__ == "__main__":
    main()
