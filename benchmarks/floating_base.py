"""Floating-base robots: how long symgen takes to derive, generate and compile them, and the
generated C inverse dynamics against Pinocchio's C++ ``rnea`` on a ``JointModelFreeFlyer`` root.

For every scene of ``SCENES`` (built-ins of ``symgen.io.urdf.legged``), in one run:

* derive (Steps 1-12), trace and write every default generated function in C, and compile the C
  file (``cc -O2 -c``, as the ctypes binding builds it), each in a fresh interpreter, median of
  ``--repeats``;
* for the contact-free robots: the generated C ``inverse_dynamics`` called once per state from C
  (``codegen_timing.c``, built by ``cc`` and by ``clang``) and Pinocchio's ``rnea`` timed from C++
  (``rnea_timing.cpp``, header-only by ``c++`` and ``clang++`` and the wheel's library; the model
  rebuilt with a ``JointModelFreeFlyer`` root from Pinocchio's own parse of the URDF), on the same
  1000 random states, interleaved round by round; the ratio of the faster builds per round, then
  the median. The
  states map between the two conventions (symgen: ``x y z, qw qx qy qz``, velocity ``[pd; w]``
  with ``pd`` in world axes; Pinocchio: ``x y z, qx qy qz qw``, ``[R^T pd; w]``), and the outputs
  are compared through the same map.

Writes ``floating_base.md`` and ``floating_base.csv`` beside this file.

With ``--part constrained`` (or ``all``), for the robots standing on the ground (``STANDING``):
the generated C ``forward_dynamics`` (``constrained_timing.c``, from ``constrained_forward.py``)
against Pinocchio's constrained routes timed from C++ (``constrained_timing.cpp``: ``constraintDynamics``
with one ``CONTACT_3D`` per point foot or ``CONTACT_6D`` per sole, and the KKT solve from ``crba``,
``nonLinearEffects`` and the feet's frame Jacobians), on a ``JointModelFreeFlyer`` root built by
Pinocchio's own URDF parser. Each harness is compiled with ``c++`` and ``clang++`` (Pinocchio's)
and with ``cc`` and ``clang`` (the generated C), when installed, and the faster build of each
route is taken. The same loop-closed states go to
both sides through :class:`symgen.io.coordinates.CoordinateMap`; Pinocchio's base acceleration
``a = [R^T pdd - w x R^T pd; wd]`` is mapped back to symgen's ``dV_m = [pdd; wd]`` outside the
timed call and compared. Writes ``floating_base_constrained.md`` and ``.csv``.

    python benchmarks/floating_base.py [--quick] [--part build|constrained|all]
"""
from __future__ import annotations

import argparse
import csv
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import codegen_speed as cs  # noqa: E402  (the C and C++ timing harnesses and their builders)
import constrained_forward as cf  # noqa: E402  (the constrained harnesses: generated C and Pinocchio C++)

from symgen.math.configuration import quaternion_rotation  # noqa: E402

SCENES = ["solo12", "solo12_standing", "talos", "talos_double_support", "space_ur5"]
#: scene -> example-robot-data URDF (space_ur5 is not timed: rnea_timing.cpp keeps Pinocchio's gravity)
TIMED = {"solo12": "solo12", "talos": "talos"}
N_STATES, SEED = 1000, 11
#: robots on the ground -> (example robot, locked joints of Pinocchio's model: "talos" = the grippers)
STANDING = {"solo12_standing": "solo12", "anymal_standing": "anymal", "talos_double_support": "talos"}
#: loop-closed states of the constrained comparison, their spread about q0, states checked against the dense model
N_CONSTRAINED, SPREAD, CHECK_DENSE = 200, 0.1, 5


# ---------------------------------------------------------------- build times
def build_worker(spec: str, work: str) -> None:
    """Subprocess body: seconds to derive, to generate C (all default functions) and to compile."""
    from symgen.codegen.generate import generate
    from symgen.io.builtin import get_scene
    from symgen.model import derive

    t0 = time.perf_counter()
    model = derive(get_scene(spec))
    t1 = time.perf_counter()
    gen = generate(model, "c")
    folder = cs.write_generated(gen, Path(work) / gen.module)
    t2 = time.perf_counter()
    subprocess.run([cs.CC, "-O2", "-std=c99", "-c", str(folder / f"{gen.module}.c"), "-o",
                    str(folder / f"{gen.module}.o")], check=True)
    t3 = time.perf_counter()
    print(t1 - t0, t2 - t1, t3 - t2, len(gen.ops), gen.ops.get("forward_dynamics", {}).get("total", 0),
          gen.ops["inverse_dynamics"]["total"])


def build_times(spec: str, repeats: int, work: Path) -> dict:
    runs = []
    for _ in range(repeats):
        out = subprocess.run([sys.executable, __file__, "--worker", spec, str(work)], capture_output=True,
                             text=True, check=True).stdout.split()
        runs.append([float(v) for v in out])
    med = [statistics.median(col) for col in zip(*runs)]
    return {"derive_s": med[0], "generate_s": med[1], "compile_s": med[2], "functions": int(med[3]),
            "fd_ops": int(med[4]), "id_ops": int(med[5])}


# ---------------------------------------------------------------- Pinocchio's model
def free_flyer_model(robot: str):
    """Pinocchio's parse of an example robot's URDF on a ``JointModelFreeFlyer`` root: the text
    symgen reads (ANYmal's without its placeholder inertial), Talos with its grippers removed as
    symgen locks them (``buildReducedModel``)."""
    import pinocchio as pin

    from symgen.io.urdf import legged
    from symgen.io.urdf.examples import example_path

    if robot == "anymal":
        return pin.buildModelFromXML(legged.anymal_robot().text, pin.JointModelFreeFlyer())
    pmodel = pin.buildModelFromUrdf(str(example_path(robot)), pin.JointModelFreeFlyer())
    if robot == "talos":
        pmodel = pin.buildReducedModel(pmodel, [pmodel.getJointId(j) for j in legged._talos_lock()],
                                       pin.neutral(pmodel))
    return pmodel


# ---------------------------------------------------------------- states in both conventions
class StatePair:
    """Random states in symgen's generated-code layout and in Pinocchio's."""

    def __init__(self, model, pmodel, count: int):
        rng = np.random.default_rng(SEED)
        labels = [c.label for c in model.tree.coordinates]
        free = next(iter(model.scene.free_joints.values()))
        joints = [j.name for j in model.scene.joints.values() if j.dof == 1 and j.name not in free.joints]
        independent = [labels[i] for i in model.partition.independent]
        pin_v = {name: pmodel.joints[pmodel.getJointId(name)].idx_v for name in joints}
        pin_q = {name: pmodel.joints[pmodel.getJointId(name)].idx_q for name in joints}
        n, nv = len(independent), pmodel.nv
        self.q, self.qd, self.qdd = np.zeros((count, 7 + len(joints))), np.zeros((count, n)), np.zeros((count, n))
        self.pq, self.pv, self.pa = np.zeros((count, pmodel.nq)), np.zeros((count, nv)), np.zeros((count, nv))
        self.rot = np.zeros((count, 3, 3))
        base = [independent.index(label) for label in free.velocity_labels]
        self.base, self.joint_cols = base, [independent.index(j) for j in joints]
        self.pin_joint_cols = [pin_v[j] for j in joints]
        for k in range(count):
            quat = rng.normal(size=4)
            quat /= np.linalg.norm(quat)
            pos, qj = rng.uniform(-1, 1, 3), rng.uniform(-1, 1, len(joints))
            qd, qdd = rng.uniform(-1, 1, n), rng.uniform(-1, 1, n)
            r = quaternion_rotation(quat)
            self.rot[k] = r
            self.q[k] = [*pos, *quat, *qj]
            self.qd[k], self.qdd[k] = qd, qdd
            self.pq[k, :3], self.pq[k, 3:7] = pos, [quat[1], quat[2], quat[3], quat[0]]
            for j, value in zip(joints, qj):
                self.pq[k, pin_q[j]] = value
            pd, w, pdd, wd = qd[base[:3]], qd[base[3:]], qdd[base[:3]], qdd[base[3:]]
            self.pv[k, :3], self.pv[k, 3:6] = r.T @ pd, w
            self.pa[k, :3], self.pa[k, 3:6] = r.T @ pdd - np.cross(w, r.T @ pd), wd
            for j, col in zip(joints, self.joint_cols):
                self.pv[k, pin_v[j]], self.pa[k, pin_v[j]] = qd[col], qdd[col]

    def pinocchio_tau(self, tau):
        """symgen's inverse-dynamics output (independent order) in Pinocchio's layout."""
        out = np.zeros_like(self.pv)
        for k in range(len(tau)):
            out[k, :3] = self.rot[k].T @ tau[k, self.base[:3]]
            out[k, 3:6] = tau[k, self.base[3:]]
            out[k, self.pin_joint_cols] = tau[k, self.joint_cols]
        return out


def timing(spec: str, robot: str, rounds: int, repeats: int, work: Path) -> dict:
    import pinocchio as pin

    from symgen.codegen.generate import generate
    from symgen.io.builtin import get_scene
    from symgen.model import derive

    model = derive(get_scene(spec))
    pmodel = free_flyer_model(robot)
    pair = StatePair(model, pmodel, N_STATES)
    gen = generate(model, "c", ["inverse_dynamics"])
    src = cs.write_generated(gen, work / gen.module)
    nq, nv = cs.signature_sizes(gen.files[f"{gen.module}.h"])
    c_bins, _ = cs.compile_c_timers(src, gen.module, nq, nv, work)
    c_states, p_states = work / f"{spec}_c.bin", work / f"{spec}_pin.bin"
    np.concatenate([pair.q.ravel(), pair.qd.ravel(), pair.qdd.ravel()]).tofile(c_states)
    np.concatenate([pair.pq.ravel(), pair.pv.ravel(), pair.pa.ravel()]).tofile(p_states)
    model_file = cs.write_model_file(pmodel, work / f"{spec}_model.txt")
    bins, notes = cs.compile_rnea(pin, work, stem=f"rnea_{spec}")
    if not bins:
        raise SystemExit(f"no build of Pinocchio's rnea harness to time against: {notes}")
    out_c, out_p = work / "tau_c.bin", work / "tau_p.bin"
    c_ns, p_ns, ratio, err = [], [], [], 0.0
    for _ in range(rounds):          # per round, the fastest build of each side; every pair compared
        c_round, p_round, c_taus = [], [], []
        for c_bin in c_bins.values():
            ns_c, tau_c = cs.run_timer([c_bin, c_states, N_STATES, repeats, out_c], out_c, nv)
            c_round.append(ns_c)
            c_taus.append(pair.pinocchio_tau(tau_c))
        for p_bin in bins.values():
            ns_p, tau_p = cs.run_timer([p_bin, model_file, p_states, N_STATES, repeats, out_p], out_p, pmodel.nv)
            p_round.append(ns_p)
            err = max(err, *(cs.rel_err(tau_c, tau_p) for tau_c in c_taus))
        c_ns.append(min(c_round))
        p_ns.append(min(p_round))
        ratio.append(c_ns[-1] / p_ns[-1])
    return {"c_ns": statistics.median(c_ns), "pin_ns": statistics.median(p_ns), "ratio": statistics.median(ratio),
            "err": err, "dof": nv, "notes": notes}



# ---------------------------------------------------------------- constrained forward dynamics
#: symgen's contact kinds -> constrained_timing.cpp's constraint type (3: CONTACT_3D, 6: CONTACT_6D)
CONTACT_TYPES = {"point": 3, "weld": 6}


def contact_model_file(model, pmodel, cmap, path: Path) -> int:
    """``pmodel`` (a free flyer) and the scene's ground contacts as ``constrained_timing.cpp``
    reads them: each contact the robot frame of the same name held to the world (LOCAL rows), the
    motion ``V_m``'s rates at their Pinocchio indices (``cmap``: the coordinate map). Returns the
    number of constraint rows."""
    import pinocchio as pin

    data = pmodel.createData()
    pin.framesForwardKinematics(pmodel, data, pin.neutral(pmodel))
    lines = [f"{pmodel.nq} {pmodel.nv} {pmodel.njoints - 1}", *cs.joint_lines(pmodel),
             " ".join(repr(float(v)) for v in pmodel.armature), " ".join(["0"] * pmodel.nv),
             " ".join(["0"] * pmodel.nv), " ".join(repr(float(v)) for v in pmodel.gravity.linear),
             str(len(model.scene.constraints))]
    rows = 0
    for con in model.scene.constraints.values():
        fid = pmodel.getFrameId(con.frame_a)
        frame = pmodel.frames[fid]
        lines.append(f"{CONTACT_TYPES[con.kind]} {frame.parentJoint} {cf._se3_text(frame.placement)} 0 "
                     f"{cf._se3_text(data.oMf[fid])} {cf._comps(con.components)}")
        rows += len(con.components)
    motion = cmap.velocity_indices(motion_labels(model))
    lines += [f"0 {len(motion)} " + " ".join(map(str, motion)), "0"]
    path.write_text("\n".join(lines) + "\n")
    return rows


def motion_labels(model) -> list[str]:
    """The rate labels of ``V_m`` in order: the motion joints, a free joint as its six rates."""
    scene = model.scene
    return [label for joint in scene.motion.joints
            for label in (scene.free_joints[joint].velocity_labels if joint in scene.free_joints else (joint,))]


def constrained_states(model, cmap, count: int) -> dict:
    """Loop-closed states for both sides: symgen's (q, V_m, tau), Pinocchio's (q, v, tau)."""
    from symgen.closure import random_consistent_states
    from symgen.codegen.reference import position_vector

    rng = np.random.default_rng(SEED)
    names, n = model.all_coordinate_names(), model.counts.n
    tau_idx = cmap.velocity_indices(model.coordinate_names())
    out = {k: [] for k in ("config", "q", "V_m", "tau", "q_pin", "v_pin", "tau_pin")}
    for config, v_m in random_consistent_states(model, count, seed=SEED, spread=SPREAD):
        tau = rng.uniform(-1, 1, n) * 5
        q_pin, v_pin = cmap.from_symgen(config, dict(zip(names, model.joint_rates(config, v_m))))
        u = np.zeros(cmap.nv)
        u[tau_idx] = tau
        for key, value in (("config", config), ("q", position_vector(model, config)), ("V_m", np.asarray(v_m, float)),
                           ("tau", tau), ("q_pin", q_pin), ("v_pin", v_pin), ("tau_pin", u)):
            out[key].append(value)
    return out


def base_acceleration(model, states: dict, a_pin: np.ndarray) -> np.ndarray:
    """symgen's ``dV_m`` of Pinocchio's accelerations at the ``V_m`` rates (``a_pin``, in the order of
    :func:`motion_labels`): the base's ``[pdd (world); wd]`` of the free flyer's ``a = [R^T pdd -
    w x R^T pd; wd]``, the other rates as they are."""
    from symgen.math.configuration import quaternion_rotation

    labels = motion_labels(model)
    base = [labels.index(label) for label in next(iter(model.scene.free_joints.values())).velocity_labels]
    out = np.array(a_pin, dtype=float)
    for k, (q, v) in enumerate(zip(states["q_pin"], states["v_pin"])):
        rot = quaternion_rotation([q[6], q[3], q[4], q[5]])
        out[k, base[:3]] = rot @ (a_pin[k, base[:3]] + np.cross(v[3:6], v[:3]))
    return out


def constrained_timing(spec: str, robot: str, pin_bins: dict, rounds: int, repeats: int, count: int,
                       work: Path) -> dict:
    """One standing robot: the generated C forward_dynamics against constraintDynamics and the KKT solve."""
    import symgen
    from symgen.io.coordinates import CoordinateMap

    model = symgen.derive(symgen.load(spec))
    pmodel = free_flyer_model(robot)
    cmap = CoordinateMap.pinocchio(model.scene, pmodel)
    directory, module = cf.generate(spec, work)
    sig = cf.signature(directory, module)
    sym_bins = cf.compile_symgen(directory, module, sig, work)
    states = constrained_states(model, cmap, count)
    states["eta_m"] = [np.zeros(0)] * count
    sym_states = cf.write_states(states, ("q", "V_m", "tau", "eta_m"), work / f"{module}_sym.bin")
    pin_states = cf.write_states(states, ("q_pin", "v_pin", "tau_pin", "eta_m"), work / f"{module}_pin.bin")
    nc = contact_model_file(model, pmodel, cmap, work / f"{module}.model")
    routes = [(mode, variant) for mode in ("cd", "kkt") for variant in pin_bins]
    sym_times = {build: [] for build in sym_bins}
    times = {route: [] for route in routes}
    for _ in range(rounds):          # interleaved rounds, median taken
        for build, sym_bin in sym_bins.items():
            sym_times[build].append(cf.run_timer([sym_bin, sym_states, count, repeats, work / f"out_sym_{build}.bin"]))
        for mode, variant in routes:
            times[(mode, variant)].append(cf.run_timer([pin_bins[variant], work / f"{module}.model", mode, pin_states,
                                                        count, repeats, work / f"out_{mode}_{variant}.bin"]))
    m = sig["NM"]
    dense = [model.forward_dynamics(states["config"][i], states["V_m"][i], states["tau"][i])[0]
             for i in range(CHECK_DENSE)]
    build, ns_symgen = cs.fastest(sym_times)
    row = dict(scene=spec, nv=pmodel.nv, nc=nc, m=m, ns_symgen=ns_symgen, build_symgen=build, err_dense=max(
        cs.rel_err(np.fromfile(work / f"out_sym_{b}.bin")[:count * m].reshape(count, m)[i], d)
        for b in sym_bins for i, d in enumerate(dense)))      # every build checked
    dv_sym = np.fromfile(work / f"out_sym_{build}.bin")[:count * m].reshape(count, m)
    for mode in ("cd", "kkt"):
        medians = {variant: statistics.median(times[(mode, variant)]) for variant in pin_bins}
        best = min(medians, key=medians.get)
        out = np.fromfile(work / f"out_{mode}_{best}.bin").reshape(count, -1)
        row[f"ns_{mode}"], row[f"build_{mode}"] = medians[best], best
        row[f"err_{mode}"] = cs.rel_err(base_acceleration(model, states, out[:, :m]), dv_sym)
    row["best"] = min(("cd", "kkt"), key=lambda mode: row[f"ns_{mode}"])
    row["ratio"] = row["ns_symgen"] / row[f"ns_{row['best']}"]
    return row


CONSTRAINED_KEYS = ["scene", "nv", "nc", "m", "ns_symgen", "build_symgen", "ns_cd", "build_cd", "ns_kkt", "build_kkt", "best", "ratio",
                    "err_cd", "err_kkt", "err_dense"]


def write_constrained(rows: list[dict], notes: str, rounds: int, repeats: int, count: int) -> None:
    import pinocchio as pin

    names = {"cd": "constraintDynamics", "kkt": "KKT"}
    lines = ["# Floating-base robots on the ground: constrained forward dynamics against Pinocchio", "",
             f"Machine: {os.cpu_count()} cores (shared), Python {platform.python_version()}, Pinocchio {pin.__version__}. "
             f"Nanoseconds per call over {count} loop-closed states (seed {SEED}, spread {SPREAD} about q0), the median "
             f"of {rounds} interleaved rounds, each timer the median of {repeats} repeats. Reproduce with "
             "`python benchmarks/floating_base.py --part constrained`.", "",
             "* **symgen C**: the generated `forward_dynamics` (`q, V_m, tau -> dV_m, eta_f`: it computes every joint "
             "rate itself) from C (`constrained_timing.c`, `-O3 -march=native`), the faster of the "
             f"{' and '.join(f'`{cs.compiler_name(c)}`' for c in cs.C_COMPILERS)} builds (named; every build "
             "checked against the dense model).",
             "* **constraintDynamics**: Pinocchio's, one `CONTACT_3D` per point foot or `CONTACT_6D` per sole, "
             "`ProximalSettings(1e-14, mu = 0, 1 iteration)` (the exact solve), `initConstraintDynamics` outside the "
             "loop; **KKT**: `crba`, `nonLinearEffects`, the feet's LOCAL frame Jacobians and drifts, and the "
             "(nv + nc) system by `PartialPivLU`; both from C++ (`constrained_timing.cpp`, header-only, "
             "`-O3 -march=native`) on a `JointModelFreeFlyer` root, given every joint rate; the faster of the `c++` "
             "and `clang++` builds of each (named). **ratio**: symgen C / the faster Pinocchio route.",
             "* **err**: max |dV_m (Pinocchio, mapped) - dV_m (symgen C)| / max |dV_m (symgen C)| over all states; "
             f"**err dense**: the generated C against `Model.forward_dynamics` on {CHECK_DENSE} states.",
             f"* Pinocchio builds: {notes}", "",
             "| scene | nv | nc | m | symgen C (ns) | constraintDynamics (ns) | KKT (ns) | ratio | err constraintDynamics "
             "| err KKT | err dense |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| `{r['scene']}` | {r['nv']} | {r['nc']} | {r['m']} | {r['ns_symgen']:.0f} ({r['build_symgen']}) | "
                     f"{r['ns_cd']:.0f} ({r['build_cd']}) | {r['ns_kkt']:.0f} ({r['build_kkt']}) | "
                     f"{r['ratio']:.3f} vs {names[r['best']]} | {r['err_cd']:.1e} | {r['err_kkt']:.1e} | "
                     f"{r['err_dense']:.1e} |")
    (HERE / "floating_base_constrained.md").write_text("\n".join(lines) + "\n")
    with open(HERE / "floating_base_constrained.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, CONSTRAINED_KEYS, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)


def run_constrained(rounds: int, repeats: int, count: int, scenes: list[str], prebuilt: Path | None) -> None:
    import pinocchio as pin

    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        pin_bins, notes = cf.compile_pinocchio(pin, work, prebuilt)
        rows = []
        for spec in scenes:
            rows.append(constrained_timing(spec, STANDING[spec], pin_bins, rounds, repeats, count, work))
            print(rows[-1], flush=True)
    write_constrained(rows, notes, rounds, repeats, count)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="one build, one round, 3 repeats")
    parser.add_argument("--part", choices=("build", "constrained", "all"), default="all",
                        help="build times and inverse dynamics (floating_base.md), the standing robots' constrained "
                             "forward dynamics (floating_base_constrained.md), or both")
    parser.add_argument("--scenes", default=",".join(STANDING), help="the standing robots of --part constrained")
    parser.add_argument("--prebuilt", type=Path, help="a folder where the commands of constrained_forward.compile_pinocchio wrote "
                        "their binaries before (the header-only builds take minutes each)")
    parser.add_argument("--worker", nargs=2, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker:
        build_worker(*args.worker)
        return
    builds, rounds, repeats = (1, 1, 3) if args.quick else (3, 5, 9)
    if args.part in ("constrained", "all"):
        run_constrained(rounds, repeats, 50 if args.quick else N_CONSTRAINED, args.scenes.split(","), args.prebuilt)
    if args.part == "constrained":
        return
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        for spec in SCENES:
            row = {"scene": spec, **build_times(spec, builds, work)}
            if spec in TIMED:
                row.update(timing(spec, TIMED[spec], rounds, repeats, work))
            print(row, flush=True)
            rows.append(row)
    write(rows, builds, rounds, repeats)


def write(rows: list[dict], builds: int, rounds: int, repeats: int) -> None:
    notes = next((r["notes"] for r in rows if "notes" in r), "")
    cc = ", ".join(subprocess.run([c, "--version"], capture_output=True, text=True).stdout.splitlines()[0]
                   for c in cs.C_COMPILERS)
    lines = ["# Floating-base robots: build times and inverse dynamics against Pinocchio", "",
             f"Machine: {os.cpu_count()} cores, {platform.python_version()}, {cc}. Build times: median of "
             f"{builds} fresh interpreters (imports excluded). C / Pin.: the median over {rounds} interleaved "
             f"rounds of the per-round ratio; each timer the median of {repeats} repeats over {N_STATES} random "
             "states (seed 11). Reproduce with `python benchmarks/floating_base.py` (`--quick`: 1 build, 1 round).",
             "",
             "* **derive**: `derive(scene)`, Steps 1-12 decided. **generate**: every default function traced "
             "and written as C. **compile**: `cc -O2 -std=c99 -c` of the generated file.",
             "* **C**: generated `inverse_dynamics` once per state from C (`codegen_timing.c`, `-O3 "
             f"-march=native` by {' and '.join(f'`{cs.compiler_name(c)}`' for c in cs.C_COMPILERS)}). **Pin.**: "
             "Pinocchio's `rnea` from C++ (`rnea_timing.cpp`, the builds below) on a `JointModelFreeFlyer` root. "
             "Each round takes the faster build of each side. **err.**: max |symgen - Pinocchio| / max "
             "|Pinocchio| through the coordinate map, over every pair of builds.",
             f"* Pinocchio build: {notes}", "",
             "| scene | DOF | derive (s) | generate (s) | compile (s) | functions | ops ID | ops FD | C (ns) | "
             "Pin. (ns) | C / Pin. | err. |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        timed = "c_ns" in r
        lines.append(f"| `{r['scene']}` | {r.get('dof', '')} | {r['derive_s']:.2f} | {r['generate_s']:.2f} | "
                     f"{r['compile_s']:.2f} | {r['functions']} | {r['id_ops']} | {r['fd_ops']} | "
                     + (f"{r['c_ns']:.0f} | {r['pin_ns']:.0f} | {r['ratio']:.3f} | {r['err']:.1e} |" if timed
                        else "- | - | - | - |"))
    (HERE / "floating_base.md").write_text("\n".join(lines) + "\n")
    keys = ["scene", "dof", "derive_s", "generate_s", "compile_s", "functions", "id_ops", "fd_ops", "c_ns", "pin_ns",
            "ratio", "err"]
    with open(HERE / "floating_base.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, keys, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)


if __name__ == "__main__":
    main()
