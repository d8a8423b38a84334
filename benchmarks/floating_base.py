"""Floating-base robots: how long symgen takes to derive, generate and compile them, and the
generated C inverse dynamics against Pinocchio's C++ ``rnea`` on a ``JointModelFreeFlyer`` root.

For every scene of ``SCENES`` (built-ins of ``symgen.io.urdf.legged``), in one run:

* derive (Steps 1-12), trace and write every default generated function in C, and compile the C
  file (``cc -O2 -c``, as the ctypes binding builds it), each in a fresh interpreter, median of
  ``--repeats``;
* for the contact-free robots: the generated C ``inverse_dynamics`` called once per state from C
  (``codegen_timing.c``) and Pinocchio's ``rnea`` timed from C++ (``rnea_timing.cpp``, the model
  rebuilt with a ``JointModelFreeFlyer`` root from Pinocchio's own parse of the URDF), on the same
  1000 random states, interleaved round by round; the ratio per round, then the median. The
  states map between the two conventions (symgen: ``x y z, qw qx qy qz``, velocity ``[pd; w]``
  with ``pd`` in world axes; Pinocchio: ``x y z, qx qy qz qw``, ``[R^T pd; w]``), and the outputs
  are compared through the same map.

Writes ``floating_base.md`` and ``floating_base.csv`` beside this file.

    python benchmarks/floating_base.py [--quick]
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

from symgen.math.configuration import quaternion_rotation  # noqa: E402

SCENES = ["solo12", "solo12_standing", "talos", "talos_double_support", "space_ur5"]
#: scene -> example-robot-data URDF (space_ur5 is not timed: rnea_timing.cpp keeps Pinocchio's gravity)
TIMED = {"solo12": "solo12", "talos": "talos"}
N_STATES, SEED = 1000, 11


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
    from symgen.io.urdf.examples import example_path
    from symgen.model import derive

    model = derive(get_scene(spec))
    pmodel = pin.buildModelFromUrdf(str(example_path(robot)), pin.JointModelFreeFlyer())
    if spec == "talos":
        from symgen.io.urdf.legged import _talos_lock

        pmodel = pin.buildReducedModel(pmodel, [pmodel.getJointId(j) for j in _talos_lock()], pin.neutral(pmodel))
    pair = StatePair(model, pmodel, N_STATES)
    gen = generate(model, "c", ["inverse_dynamics"])
    src = cs.write_generated(gen, work / gen.module)
    nq, nv = cs.signature_sizes(gen.files[f"{gen.module}.h"])
    c_bin, _ = cs.compile_c_timer(src, gen.module, nq, nv, work)
    c_states, p_states = work / f"{spec}_c.bin", work / f"{spec}_pin.bin"
    np.concatenate([pair.q.ravel(), pair.qd.ravel(), pair.qdd.ravel()]).tofile(c_states)
    np.concatenate([pair.pq.ravel(), pair.pv.ravel(), pair.pa.ravel()]).tofile(p_states)
    model_file = cs.write_model_file(pmodel, work / f"{spec}_model.txt")
    bins, notes = cs.compile_rnea(pin, work, stem=f"rnea_{spec}")
    header = bins.get("header")
    out_c, out_p = work / "tau_c.bin", work / "tau_p.bin"
    c_ns, p_ns, ratio = [], [], []
    for _ in range(rounds):
        ns_c, tau_c = cs.run_timer([c_bin, c_states, N_STATES, repeats, out_c], out_c, nv)
        ns_p, tau_p = cs.run_timer([header, model_file, p_states, N_STATES, repeats, out_p], out_p, pmodel.nv)
        c_ns.append(ns_c)
        p_ns.append(ns_p)
        ratio.append(ns_c / ns_p)
    err = cs.rel_err(pair.pinocchio_tau(tau_c), tau_p)
    return {"c_ns": statistics.median(c_ns), "pin_ns": statistics.median(p_ns), "ratio": statistics.median(ratio),
            "err": err, "dof": nv, "notes": notes}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="one build, one round, 3 repeats")
    parser.add_argument("--worker", nargs=2, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker:
        build_worker(*args.worker)
        return
    builds, rounds, repeats = (1, 1, 3) if args.quick else (3, 5, 9)
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
    cc = subprocess.run([cs.CC, "--version"], capture_output=True, text=True).stdout.splitlines()[0]
    lines = ["# Floating-base robots: build times and inverse dynamics against Pinocchio", "",
             f"Machine: {os.cpu_count()} cores, {platform.python_version()}, {cc}. Build times: median of "
             f"{builds} fresh interpreters (imports excluded). C / Pin.: the median over {rounds} interleaved "
             f"rounds of the per-round ratio; each timer the median of {repeats} repeats over {N_STATES} random "
             "states (seed 11). Reproduce with `python benchmarks/floating_base.py` (`--quick`: 1 build, 1 round).",
             "",
             "* **derive**: `derive(scene)`, Steps 1-12 decided. **generate**: every default function traced "
             "and written as C. **compile**: `cc -O2 -std=c99 -c` of the generated file.",
             "* **C**: generated `inverse_dynamics` once per state from C (`codegen_timing.c`, `cc -O3 "
             "-march=native`). **Pin.**: Pinocchio's `rnea` from C++ (`rnea_timing.cpp`, header-only build, "
             "`-O3 -march=native`) on a `JointModelFreeFlyer` root. **err.**: max |symgen - Pinocchio| / max "
             "|Pinocchio| through the coordinate map.",
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
