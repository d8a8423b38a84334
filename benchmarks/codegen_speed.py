"""Speed of symgen's generated inverse dynamics against Pinocchio's rnea and sympy.lambdify.

For every scene of ``SCENES``, in one run: generated C once per state (timed from C,
``codegen_timing.c``), generated C batched via its ctypes binding, the generated NumPy module
batched, ``sympy.lambdify`` of the dense symbolic model (subprocess, hard time limit) and
Pinocchio's C++ ``rnea`` (timed from C++, ``rnea_timing.cpp``, when ``import pinocchio`` works);
plus generation times and operation counts. Writes ``codegen_speed.md`` and ``codegen_speed.csv``
beside this file; generated code and binaries go to a temporary directory.

    python benchmarks/codegen_speed.py [--quick]

C++ timing of Pinocchio needs its headers: ``pip install pin cmeel-eigen``.
"""
from __future__ import annotations

import argparse
import csv
import importlib.util
import json
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
SCENES = ["chain:n=6", "chain:n=12", "chain:n=24", "chain:n=48", "chain:n=64", "multi_arm:h=2", "ur5", "panda",
          "general_chain:n=7"]
#: real robots from example-robot-data's URDF files; Pinocchio gets the same files (symgen.oracle)
URDF_SCENES = ("ur5", "panda")
N_SINGLE, N_BATCH, SEED, LAMBDIFY_TIMEOUT = 1_000, 10_000, 7, 60
#: the NumPy module is also timed on this many states per call (workspace far beyond the cache
#: without chunking)
N_BIG = 100_000
CC, CXX = os.environ.get("CC", "cc"), os.environ.get("CXX", "c++")
# Pinocchio's maintainers build with clang where they can: its header-only templates are timed with
# both compilers, and every ratio is taken over the faster build (set CLANGXX="" to leave clang out)
CLANGXX = os.environ.get("CLANGXX", shutil.which("clang++") or "")
CFLAGS = ["-O3", "-march=native", "-std=c99"]
# the generated C is built the same way, by the default C compiler and by clang (set CLANG="" to
# leave it out); a timing that names its build takes the faster one (here clang compiles the
# straight-line code about a fifth faster than GCC 12)
CLANG = os.environ.get("CLANG", shutil.which("clang") or "")
C_COMPILERS = tuple(dict.fromkeys(c for c in (CC, CLANG) if c))
#: the flags the derivative benchmarks build both sides with once more: fused multiply-adds across
#: statements, as the generated bindings compile
FUSED = ["-ffp-contract=fast"]
#: ``{suffix of a build's name: its extra flags}``
VARIANTS = {"": [], " fused": FUSED}


def compiler_name(cc: str) -> str:
    """How a build is named in the tables: the compiler's file name (``cc``, ``clang``)."""
    return Path(cc).name


def vector_width(cc: str, flags, source: Path, macro: str = "SYMGEN_VECTOR") -> int:
    """A width as the generated ``source``'s own preprocessor logic decides it for ``cc`` with
    ``flags``: ``SYMGEN_VECTOR``, the scalar functions' sines and cosines per vector (4 with AVX2,
    8 with AVX-512F under ``-DSYMGEN_VECTOR_512``, else 1), or ``SYMGEN_LANES``, the states per lane
    kernel (8 with AVX-512F, 4 with AVX2, else 1)."""
    out = subprocess.run([cc, *map(str, flags), "-dM", "-E", str(source)], capture_output=True, text=True,
                         check=True).stdout
    found = re.search(rf"^#define {macro} (\d+)$", out, re.M)
    return int(found.group(1)) if found else 1


def fastest(times: dict) -> tuple:
    """``(build, median)`` of the build with the smallest median time, ``times`` mapping each build's
    name to its per-round times."""
    medians = {name: statistics.median(values) for name, values in times.items()}
    best = min(medians, key=medians.get)
    return best, medians[best]
CXXFLAGS = ["-O3", "-march=native", "-DNDEBUG", "-std=c++17"]
# the wheel's library is built without -march=native; mixing the two breaks Eigen's alignment ABI
LIB_CXXFLAGS = ["-O3", "-DNDEBUG", "-std=c++17", "-DPINOCCHIO_ENABLE_TEMPLATE_INSTANTIATION"]
# definitions exported by Pinocchio's CMake target (its joint variant has more than 20 types)
PIN_DEFINES = ["-DBOOST_MPL_LIMIT_LIST_SIZE=30", "-DBOOST_MPL_LIMIT_VECTOR_SIZE=30",
               "-DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS", "-DBOOST_FUSION_INVOKE_MAX_ARITY=12"]


@dataclass
class Settings:
    rounds: int          # interleaved rounds of all timers of one scene (median taken)
    repeats: int         # repeats inside one timer run (median taken)
    gen_repeats: int
    gen_sizes: tuple


# ---------------------------------------------------------------- helpers
def draw_states(nq: int, nv: int, count: int):
    """(q, qd, qdd) uniform in [-1, 1], drawn in that order from ``default_rng(SEED)``."""
    rng = np.random.default_rng(SEED)
    return rng.uniform(-1, 1, (count, nq)), rng.uniform(-1, 1, (count, nv)), rng.uniform(-1, 1, (count, nv))


def write_table(stem: Path, lines: list[str], rows: list[dict]) -> None:
    """``<stem>.md`` from the markdown ``lines``, ``<stem>.csv`` from ``rows`` (the first row's keys
    are the columns); the markdown printed too."""
    stem.with_suffix(".md").write_text("\n".join(lines) + "\n")
    with open(stem.with_suffix(".csv"), "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]), lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
    print("\n".join(lines))


def write_generated(gen, directory: Path) -> Path:
    directory.mkdir(parents=True, exist_ok=True)
    for name, text in gen.files.items():
        (directory / name).write_text(text)
    return directory


def load_module(path: Path):
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def signature_sizes(header: str) -> tuple[int, int]:
    """(len q, len qd) from the generated C prototype of inverse_dynamics."""
    m = re.search(r"_inverse_dynamics\(const double q\[(\d+)\], const double qd\[(\d+)\]", header)
    return int(m.group(1)), int(m.group(2))


def rel_err(a, b) -> float:
    return float(np.max(np.abs(np.asarray(a) - b)) / max(np.max(np.abs(b)), 1e-300))


def run_timer(cmd: list, out: Path, nv: int) -> tuple[float, np.ndarray]:
    """Run a timing binary; return (median ns per call, tau it computed)."""
    result = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, check=True)
    return float(result.stdout.split()[0]), np.fromfile(out).reshape(-1, nv)


def time_batch(fn, args, repeats: int) -> float:
    """ns per state of ``fn(*args)`` on a batch: the best of ``repeats`` calls (a batch call lasts
    milliseconds; on a shared machine most calls lose time slices to other processes, the best
    one is the cost of the code)."""
    fn(*args)
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn(*args)
        times.append(time.perf_counter() - t0)
    return min(times) * 1e9 / len(args[0])


# ---------------------------------------------------------------- C harness
def compile_c_timer(src: Path, module: str, nq: int, nv: int, work: Path, cc: str = CC,
                    function: str = "inverse_dynamics", tag: str = ""):
    """Compile codegen_timing.c with the generated source's ``function`` by ``cc``; return (binary,
    warnings). ``tag`` tells apart the binaries of one module traced several ways."""
    binary = work / f"timer_{module}{tag and '_' + tag}_{compiler_name(cc)}"
    cmd = [cc, *CFLAGS, "-Wall", "-Wextra", f"-DFUNC=symgen_{module}_{function}", f"-DNQ={nq}",
           f"-DNV={nv}", HERE / "codegen_timing.c", src / f"{module}.c", "-lm", "-o", binary]
    result = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, check=True)
    warnings = [line for line in result.stderr.splitlines() if "warning:" in line]
    return binary, warnings


def compile_c_timers(src: Path, module: str, nq: int, nv: int, work: Path, function: str = "inverse_dynamics",
                     tag: str = "") -> tuple[dict, list]:
    """:func:`compile_c_timer` by each of ``C_COMPILERS``: ``({build: binary}, warnings of all)``."""
    binaries, warnings = {}, []
    for cc in C_COMPILERS:
        binaries[compiler_name(cc)], found = compile_c_timer(src, module, nq, nv, work, cc, function, tag)
        warnings += found
    return binaries, warnings


# ---------------------------------------------------------------- NumPy
def numpy_worker(path: str, nq: int, nv: int, repeats: int, count: int) -> None:
    """Subprocess body (a fresh interpreter with the default allocator, as a user's script): ns
    per state of the generated NumPy module on ``count`` states per call."""
    fn = load_module(Path(path)).inverse_dynamics
    print(time_batch(fn, draw_states(nq, nv, count), repeats))


def run_numpy(path: Path, nq: int, nv: int, repeats: int, count: int) -> float:
    cmd = [sys.executable, __file__, "--worker", "numpy", path, nq, nv, repeats, count]
    result = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, check=True)
    return float(result.stdout)


# ---------------------------------------------------------------- Pinocchio
def pinocchio_chain(pin, n: int):
    """The benchmark chain as a pinocchio.Model (same numbers as rnea_timing.cpp)."""
    model, parent, L = pin.Model(), 0, 0.1
    for i in range(n):
        joint = pin.JointModelRZ() if i % 2 == 0 else pin.JointModelRY()
        jid = model.addJoint(parent, joint, pin.SE3(np.eye(3), np.array([0.0 if i == 0 else L, 0, 0])), f"j{i}")
        inertia = pin.Inertia(1.0 + 0.1 * i, np.array([L / 2, 0, 0]), np.diag([0.01, 0.02, 0.03]) * (1 + 0.1 * i))
        model.appendBodyToJoint(jid, inertia, pin.SE3.Identity())
        parent = jid
    return model


def pin_python(pin, model, extra=None):
    """pinocchio.rnea from Python over a batch, one call per state (the Python call overhead is in);
    ``extra(qd)`` adds what symgen's inverse dynamics has and rnea has not (URDF joint friction)."""
    data = model.createData()
    extra = extra or (lambda qd: 0.0)
    return lambda q, qd, qdd: np.array([pin.rnea(model, data, *s) + extra(s[1]) for s in zip(q, qd, qdd)])


#: Pinocchio joint models that the C++ harnesses rebuild, and their codes there (pinocchio_joints.hpp)
JOINT_CODES = {"JointModelRX": "RX", "JointModelRY": "RY", "JointModelRZ": "RZ", "JointModelRevoluteUnaligned": "RU",
               "JointModelPX": "PX", "JointModelPY": "PY", "JointModelPZ": "PZ", "JointModelPrismaticUnaligned": "PU",
               "JointModelSpherical": "S", "JointModelFreeFlyer": "FF"}


def urdf_robot(spec: str):
    """Pinocchio's model of a URDF example, parsed by Pinocchio from the same file
    (:func:`symgen.oracle.pinocchio_robot`: fingers locked with buildReducedModel, as symgen locks
    them); its joints must be in the order of symgen's coordinates."""
    from symgen.io.builtin import get_scene
    from symgen.model import derive
    from symgen.oracle import pinocchio_robot
    scene = get_scene(spec)
    robot = pinocchio_robot(scene)
    if list(robot.v_index(derive(scene).coordinate_names())) != list(range(robot.model.nv)):
        raise RuntimeError(f"{spec}: Pinocchio's joint order differs from symgen's")
    return robot


def joint_lines(model) -> list[str]:
    """One line per joint of a Pinocchio ``model`` as the C++ harnesses read it: ``parent type ax ay
    az R(9) p(3) mass c(3) Ixx Ixy Iyy Ixz Iyz Izz``, every number in full precision."""
    lines = []
    for i in range(1, model.njoints):
        code = JOINT_CODES[model.joints[i].shortname()]
        axis = np.array(model.joints[i].extract().axis) if code.endswith("U") else np.zeros(3)
        x, inertia = model.jointPlacements[i], model.inertias[i]
        big = inertia.inertia
        values = [*axis, *x.rotation.ravel(), *x.translation, inertia.mass, *inertia.lever,
                  big[0, 0], big[0, 1], big[1, 1], big[0, 2], big[1, 2], big[2, 2]]
        lines.append(f"{model.parents[i]} {code} " + " ".join(repr(float(v)) for v in values))
    return lines


def open_chain(spec: str) -> bool:
    """Whether Pinocchio times the scene: the chains (the benchmark one built here, the general one
    from symgen's tree) and the URDF arms; not the closed chains."""
    return spec.startswith(("chain:", "general_chain:")) or spec in URDF_SCENES


def published_share(row: dict) -> float:
    """A row's ``inverse_dynamics`` operations over the best published RNEA count for its DOF."""
    return row["total"] / (row["rnea_mul"] + row["rnea_add"])


def general_robot(spec: str):
    """Pinocchio's model of ``general_chain:n=N``, built from symgen's spanning tree
    (:func:`symgen.oracle.pinocchio_tree.tree_robot`: the joints about z, as the tree has them)."""
    from symgen.io.builtin import get_scene
    from symgen.model import derive
    from symgen.oracle.pinocchio_tree import tree_robot
    return tree_robot(derive(get_scene(spec))).model


def write_model_file(model, path: Path) -> Path:
    """The model as the text rnea_timing.cpp reads (see there)."""
    path.write_text("\n".join([str(model.njoints - 1), *joint_lines(model)]) + "\n")
    return path


def compile_rnea(pin, work: Path, defines=(), stem: str = "rnea") -> tuple[dict, str]:
    """Build rnea_timing.cpp header-only (same flags as the C harness) with ``CXX`` (``header``) and
    with clang (``clang``, when ``CLANGXX`` names one), and against the wheel's library (``lib``)
    (``defines``: e.g. ``["-DTIME_ABA"]``); return ({variant: binary}, notes)."""
    prefix = next((p for p in Path(pin.__file__).resolve().parents if p.name == "cmeel.prefix"), None)
    if prefix is None:
        return {}, "no cmeel.prefix beside the pinocchio package"
    eigen = next((p for p in (prefix / "include" / "eigen3", Path("/usr/include/eigen3")) if p.is_dir()), None)
    if eigen is None:
        return {}, "Eigen headers missing (pip install cmeel-eigen)"
    libs = ["-L", prefix / "lib", f"-Wl,-rpath,{prefix / 'lib'}", "-lpinocchio_default"]
    common = [*PIN_DEFINES, *defines, "-I", prefix / "include", "-I", eigen, HERE / "rnea_timing.cpp"]
    binaries, notes = {}, []
    builds = [("header", CXX, CXXFLAGS), ("clang", CLANGXX, CXXFLAGS), ("lib", CXX, LIB_CXXFLAGS)]
    for variant, compiler, flags in (b for b in builds if b[1]):
        cmd = [compiler, *flags, *common, "-o", work / f"{stem}_{variant}", *libs]
        result = subprocess.run([str(c) for c in cmd], capture_output=True, text=True)
        if result.returncode == 0:
            binaries[variant] = work / f"{stem}_{variant}"
            shown = " ".join(map(str, cmd)).replace(str(prefix), "$PREFIX").replace(str(work), "$TMP")
            notes.append(f"`{variant}`: `{shown.replace(str(HERE), 'benchmarks')}`")
        else:
            notes.append(f"`{variant}` failed to compile (exit {result.returncode}): "
                         f"{(result.stderr.strip().splitlines() or ['no message'])[-1]}")
    return binaries, "; ".join(notes) + " (PREFIX = pinocchio's cmeel.prefix)"


# ---------------------------------------------------------------- sympy.lambdify
def lambdify_worker(spec: str, repeats: int) -> None:
    """Subprocess body: dense symbolic tau -> lambdify -> time on a batch; print JSON."""
    import sympy as sp
    from symgen.io.builtin import get_scene
    from symgen.model import derive
    t0 = time.perf_counter()
    try:
        model = derive(get_scene(spec))
        cfg = model.symbolic_configuration()
        qd = model.symbolic_velocity()
        d = model.evaluate(cfg, qd=qd, field="symbolic")
    except Exception as exc:  # report e.g. SymbolicTooLargeError as the result
        print(json.dumps({"status": f"fails: {type(exc).__name__}", "detail": str(exc)}))
        return
    qdd = list(sp.symbols(f"qdd0:{len(qd)}", real=True))
    tau = d.M_q @ np.array(qdd) + d.C_q @ np.array(qd) + d.G_q
    pos = cfg.positions.values()
    cs, ss = [p.c for p in pos], [p.s for p in pos]
    t1 = time.perf_counter()
    fn = sp.lambdify([cs, ss, qd, qdd], list(tau), "numpy")
    t2 = time.perf_counter()
    q, v, a = draw_states(len(cs), len(qd), N_BATCH)
    def call(q, v, a):  # a constant entry of tau comes back as a scalar: broadcast it
        return np.stack(np.broadcast_arrays(*fn(list(np.cos(q).T), list(np.sin(q).T), list(v.T), list(a.T))), -1)
    ns = time_batch(call, (q, v, a), repeats)
    print(json.dumps({"status": "ok", "ns": ns, "build_s": t1 - t0, "lambdify_s": t2 - t1,
                      "tau": call(q[:5], v[:5], a[:5]).tolist()}))


def run_lambdify(spec: str, repeats: int) -> dict:
    cmd = [sys.executable, __file__, "--worker", "lambdify", spec, str(repeats)]
    try:
        result = subprocess.run(cmd, capture_output=True, text=True, timeout=LAMBDIFY_TIMEOUT)
    except subprocess.TimeoutExpired:
        return {"status": f"> {LAMBDIFY_TIMEOUT} s"}
    if result.returncode != 0:
        return {"status": "crashed", "detail": result.stderr.strip().splitlines()[-1:]}
    return json.loads(result.stdout.strip().splitlines()[-1])


# ---------------------------------------------------------------- generation time
def gen_worker(spec: str, which: str) -> None:
    """Subprocess body: seconds for derive + generate(c), imports excluded."""
    from symgen.io.builtin import get_scene
    from symgen.codegen.generate import generate
    from symgen.model import derive
    t0 = time.perf_counter()
    generate(derive(get_scene(spec)), "c", ["inverse_dynamics"] if which == "id" else None)
    print(time.perf_counter() - t0)


def generation_times(settings: Settings) -> list[dict]:
    rows = []
    for n in settings.gen_sizes:
        row = {"scene": f"chain:n={n}"}
        for which in ("id", "all"):
            runs = [float(subprocess.run([sys.executable, __file__, "--worker", "gen", row["scene"], which],
                                         capture_output=True, text=True, check=True).stdout)
                    for _ in range(settings.gen_repeats)]
            row[which] = statistics.median(runs)
        print(f"generation {row['scene']:<12} id {row['id']:6.2f} s  all {row['all']:6.2f} s", flush=True)
        rows.append(row)
    return rows


# ---------------------------------------------------------------- one scene
@dataclass
class Scene:
    spec: str
    module: str
    src: Path            # generated C, its ctypes binding
    numpy_path: Path     # generated NumPy module
    nq: int
    nv: int
    states: tuple        # (q, qd, qdd), N_BATCH each; the first N_SINGLE also in states_file
    states_file: Path
    want: np.ndarray     # tau of the generated NumPy module: the reference of every error column
    pin_arg: object = None       # rnea_timing.cpp's MODEL: N for a chain, a model file for a URDF robot
    pin_extra: np.ndarray = None  # per state, what symgen's tau has on top of rnea (URDF joint friction)


def prepare(spec: str, work: Path) -> tuple[Scene, dict]:
    """Generate C and NumPy code of one scene into ``work``; return it and the op-count row."""
    from symgen.io.builtin import get_scene
    from symgen.codegen.generate import generate
    from symgen.model import derive
    model = derive(get_scene(spec))
    gen_c, gen_np = generate(model, "c", ["inverse_dynamics"]), generate(model, "numpy", ["inverse_dynamics"])
    src, module = write_generated(gen_c, work / gen_c.module), gen_c.module
    numpy_path = write_generated(gen_np, work / f"{module}_numpy") / f"{module}.py"
    nq, nv = signature_sizes(gen_c.files[f"{module}.h"])
    q, qd, qdd = draw_states(nq, nv, N_BATCH)
    states_file = work / f"{module}.bin"
    np.concatenate([a[:N_SINGLE].ravel() for a in (q, qd, qdd)]).tofile(states_file)
    want = load_module(numpy_path).inverse_dynamics(q, qd, qdd)
    ops = gen_c.ops["inverse_dynamics"]
    row = {"scene": spec, "dof": nv, "mul": ops["mul"], "add": ops["add"], "total": ops["total"],
           "rnea_mul": 93 * nv - 69, "rnea_add": 81 * nv - 66,
           "numpy_rows": int(re.search(r"work = np.empty\(\((\d+), ", numpy_path.read_text()).group(1)),
           "numpy_chunk": int(re.search(r"^CHUNK = (\d+)", numpy_path.read_text(), re.M).group(1))}
    return Scene(spec, module, src, numpy_path, nq, nv, (q, qd, qdd), states_file, want), row


def time_rounds(sc: Scene, settings: Settings, rnea_bins: dict, work: Path, row: dict) -> dict:
    """All timers of one scene, interleaved round by round (so drifts hit every column alike);
    returns {timer: [ns per round]} and puts the error columns into ``row``."""
    binaries, row["warnings"] = compile_c_timers(sc.src, sc.module, sc.nq, sc.nv, work)
    ctypes_fn = load_module(sc.src / f"{sc.module}_ctypes.py").inverse_dynamics
    row["err_ctypes"] = rel_err(ctypes_fn(*sc.states), sc.want)
    out, first = work / "tau.bin", sc.want[:N_SINGLE]
    samples = {k: [] for k in ("c", *(f"c_{b}" for b in binaries), "ctypes", "numpy", "numpy_big", *rnea_bins)}
    row["err_c"] = 0.0
    for _ in range(settings.rounds):
        for build, binary in binaries.items():      # every build checked; per round, the faster one
            ns, tau = run_timer([binary, sc.states_file, N_SINGLE, settings.repeats, out], out, sc.nv)
            samples[f"c_{build}"].append(ns)
            row["err_c"] = max(row["err_c"], rel_err(tau, first))
        samples["c"].append(min(samples[f"c_{b}"][-1] for b in binaries))
        for variant, rnea_bin in rnea_bins.items():
            ns, tau = run_timer([rnea_bin, sc.pin_arg, sc.states_file, N_SINGLE, settings.repeats, out], out, sc.nv)
            samples[variant].append(ns)
            row[f"err_pin_{variant}"] = rel_err(tau + sc.pin_extra[:N_SINGLE], first)
        samples["ctypes"].append(time_batch(ctypes_fn, sc.states, settings.repeats))
        for key, count in (("numpy", N_BATCH), ("numpy_big", N_BIG)):
            samples[key].append(run_numpy(sc.numpy_path, sc.nq, sc.nv, settings.repeats, count))
    return samples


def bench_scene(spec: str, settings: Settings, pin, rnea_bins: dict, work: Path) -> dict:
    """One row of the runtime table (plus op counts and error columns)."""
    sc, row = prepare(spec, work)
    has_pin = open_chain(spec)
    rnea_bins = rnea_bins if has_pin else {}
    sc.pin_extra = np.zeros_like(sc.want)
    if pin is not None and has_pin:
        if spec in URDF_SCENES:
            robot = urdf_robot(spec)
            model, sc.pin_arg = robot.model, write_model_file(robot.model, work / f"{sc.module}_pinocchio.txt")
            extra = lambda qd: robot.damping * qd + robot.coulomb * np.sign(qd)  # noqa: E731
            sc.pin_extra = extra(sc.states[1])
        elif spec.startswith("general_chain:"):
            model, extra = general_robot(spec), None
            sc.pin_arg = write_model_file(model, work / f"{sc.module}_pinocchio.txt")
        else:
            model, sc.pin_arg, extra = pinocchio_chain(pin, sc.nv), sc.nv, None
        row["err_pin_py"] = rel_err(pin_python(pin, model, extra)(*(a[:5] for a in sc.states)), sc.want[:5])
    samples = time_rounds(sc, settings, rnea_bins, work, row)
    row.update({f"{key}_ns": statistics.median(values) for key, values in samples.items()})
    if rnea_bins:
        best = [min(samples[v][r] for v in rnea_bins) for r in range(settings.rounds)]
        row["c_over_pin"] = statistics.median(c / p for c, p in zip(samples["c"], best))
    elif has_pin and pin is not None:
        row["pin_py_ns"] = time_batch(pin_python(pin, model, extra), tuple(a[:N_SINGLE] for a in sc.states),
                                      settings.repeats)
    lam = run_lambdify(spec, settings.repeats)
    row["lambdify"], row["lambdify_detail"] = lam["status"], lam.get("detail", "")
    if lam["status"] == "ok":
        row["lambdify_ns"], row["err_lambdify"] = lam["ns"], rel_err(lam["tau"], sc.want[:5])
    print(f"{spec:<14} C {row['c_ns']:9.1f} ns  ratio {row.get('c_over_pin', float('nan')):.3f}  "
          f"numpy {row['numpy_ns']:8.1f} / {row['numpy_big_ns']:8.1f} ns/state  lambdify {lam['status']}", flush=True)
    return row


# ---------------------------------------------------------------- output
def fmt(value, digits=3) -> str:
    if value is None or value == "":
        return ""
    if isinstance(value, float):
        if value != 0 and (abs(value) < 1e-2 or abs(value) >= 1e6):
            return f"{value:.2e}"
        return f"{value:.0f}" if abs(value) >= 100 else f"{value:.{digits}g}"
    return str(value)


def machine() -> str:
    cc = ", ".join(subprocess.run([c, "--version"], capture_output=True, text=True).stdout.splitlines()[0]
                   for c in C_COMPILERS)
    cpu = next((l.split(":", 1)[1].strip() for l in Path("/proc/cpuinfo").read_text().splitlines()
                if l.startswith("model name")), platform.processor())
    import sympy
    return (f"{os.cpu_count()} cores ({cpu}), {cc}, Python {platform.python_version()}, "
            f"NumPy {np.__version__}, SymPy {sympy.__version__}")


def runtime_table(rows, pin_missing: str) -> list[str]:
    def pin_cell(r, variant):
        if not open_chain(r["scene"]):
            return "n/a (closed chain)"
        return fmt(r.get(f"{variant}_ns")) if f"{variant}_ns" in r else pin_missing

    lines = ["| scene | DOF | C single (ns/call) | Pin. header (ns/call) | Pin. clang (ns/call) | Pin. lib (ns/call) | "
             "C / Pin. | "
             "ctypes batch (ns/state) | ctypes states/s | NumPy batch 1e4 / 1e5 (ns/state) | NumPy states/s 1e4 / 1e5 | "
             "lambdify (ns/state) | err. C, ctypes | err. Pin., lambdify |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        ratio = fmt(r.get("c_over_pin")) or (f"(Python fallback {fmt(r['pin_py_ns'])} ns)" if "pin_py_ns" in r else "")
        lam = fmt(r["lambdify_ns"]) if r["lambdify"] == "ok" else r["lambdify"]
        own = fmt(max(r["err_c"], r["err_ctypes"]))
        other = fmt(max((r[k] for k in r if k.startswith(("err_pin", "err_lambdify"))), default=None))
        rate = lambda key: f"{1e9 / r[key]:.2e}"
        builds = " / ".join(f"{compiler_name(cc)} {fmt(r[f'c_{compiler_name(cc)}_ns'])}" for cc in C_COMPILERS
                            if f"c_{compiler_name(cc)}_ns" in r)
        lines.append(f"| `{r['scene']}` | {r['dof']} | {fmt(r['c_ns'])} ({builds}) | {pin_cell(r, 'header')} | "
                     f"{pin_cell(r, 'clang')} | {pin_cell(r, 'lib')} | {ratio} | {fmt(r['ctypes_ns'])} | {rate('ctypes_ns')} | "
                     f"{fmt(r['numpy_ns'])} / {fmt(r['numpy_big_ns'])} | {rate('numpy_ns')} / {rate('numpy_big_ns')} | "
                     f"{lam} | {own} | "
                     f"{other or 'none'} |")
    return lines


def ops_table(rows) -> list[str]:
    lines = ["| scene | DOF | mul | add | total | total / DOF | RNEA mul | RNEA add | RNEA total | total / RNEA |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        best = r["rnea_mul"] + r["rnea_add"]
        lines.append(f"| `{r['scene']}` | {r['dof']} | {r['mul']} | {r['add']} | {r['total']} | "
                     f"{r['total'] / r['dof']:.1f} | {r['rnea_mul']} | {r['rnea_add']} | {best} | "
                     f"{published_share(r):.2f} |")
    return lines


def generation_table(gen_rows) -> list[str]:
    lines = ["| scene | inverse_dynamics only | all functions | target |", "|---|---|---|---|"]
    for g in gen_rows:
        limit = {"chain:n=35": 3.0, "chain:n=100": 20.0}.get(g["scene"])
        verdict = ", ".join(f"{what} {'met' if g[k] <= limit else 'MISSED'}" for k, what in
                            (("id", "inverse_dynamics"), ("all", "all functions"))) if limit else ""
        lines.append(f"| `{g['scene']}` | {g['id']:.2f} | {g['all']:.2f} | "
                     f"{f'<= {limit:g} s: {verdict}' if limit else ''} |")
    return lines


def targets(rows) -> list[str]:
    by = {r["scene"]: r for r in rows}
    out = []
    for n, limit in ((6, 0.5), (12, 0.5), (64, 1.0)):
        ratio = by.get(f"chain:n={n}", {}).get("c_over_pin")
        out.append(f"* C single / Pinocchio C++ rnea at N={n}: " + (
            f"{ratio:.3f} (target <= {limit}): {'met' if ratio <= limit else 'MISSED'}" if ratio is not None
            else "not measured (scene not in this run, or no Pinocchio C++ build)"))
    for key, what, goal in (("numpy_ns", f"NumPy states/s at N=6, batch {N_BATCH}", 1e6),
                            ("numpy_big_ns", f"NumPy states/s at N=6, batch {N_BIG}", 1e6),
                            ("ctypes_ns", f"compiled batch (ctypes) states/s at N=6, batch {N_BATCH}", 5e6)):
        rate = 1e9 / by["chain:n=6"][key]
        out.append(f"* {what}, default allocator: {rate:.3g} (target >= {goal:.0e}): "
                   f"{'met' if rate >= goal else 'MISSED'}")
    for spec in ("general_chain:n=7", "panda"):          # general geometry and inertia
        r = by.get(spec)
        if r is not None:
            share = published_share(r)
            out.append(f"* `{spec}` inverse_dynamics operations / the best published RNEA count: {share:.2f} "
                       f"(target <= 0.5): {'met' if share <= 0.5 else 'MISSED'}")
    return out


def markdown(rows, gen_rows, meta) -> str:
    s = meta["settings"]
    head = [f"# Generated inverse dynamics: speed{' (--quick run)' if meta['quick'] else ''}", "",
            f"Machine: {meta['machine']}; {meta['pinocchio']}. The machine is noisy: the C and C++ timers read the thread's CPU clock (`CLOCK_THREAD_CPUTIME_ID`), every single-call time is the "
            f"median of {s.repeats} repeats inside one timer run, every batch time the best of {s.repeats} calls, "
            f"then the median over {s.rounds} interleaved rounds of all timers of a scene; C / Pin. is taken per round (side by side), then the median. Reproduce with "
            "`python benchmarks/codegen_speed.py` (`--quick`: 1 round, 3 repeats).", "",
            f"* **C single**: the generated C called once per state from C (`benchmarks/codegen_timing.c`) over "
            f"{N_SINGLE} random states (uniform in [-1, 1], seed {SEED}); `{' '.join(CFLAGS)}` by each of "
            f"{', '.join(f'`{c}`' for c in C_COMPILERS)} (the call is not inlined: separate translation unit); "
            "the faster build per round, each build's median in brackets (both checked against NumPy).",
            f"* **Pin.**: Pinocchio's `rnea` timed from C++ (`benchmarks/rnea_timing.cpp`) on the same states and "
            f"robot (`ur5`, `panda`: see the notes). `header`: `{' '.join([CXX, *CXXFLAGS])}`, templates compiled here with the same flags; `clang`: the same with `{CLANGXX or 'clang++ (not found)'}`; `lib`: "
            f"the wheel's precompiled `rnea` (`{' '.join(LIB_CXXFLAGS)}`; `-march=native` breaks Eigen's alignment "
            "ABI with the wheel: `free(): invalid pointer`). **C / Pin.** = C single / the fastest of these builds, round by round.",
            f"* **ctypes batch**: the generated binding (compiles with its own `-O2`, checks its arguments), "
            f"{N_BATCH} states per call. **NumPy batch**: the generated module, {N_BATCH} / {N_BIG} states per call, "
            "in a fresh interpreter with the default allocator (see the notes).",
            f"* **lambdify**: `sympy.lambdify` (numpy) of M_q qdd + C_q qd + G_q from symgen's symbolic reference "
            f"evaluator, {N_BATCH} states per call, in a subprocess with a {LAMBDIFY_TIMEOUT} s limit on everything.",
            "* **err.**: worst relative error (max |diff| / max |tau|) against the generated NumPy module, of symgen's "
            "own C code (0 = bit-identical), and of the independent implementations (Pinocchio C++ and Python, "
            "lambdify).", ""]
    return "\n".join(
        head + runtime_table(rows, meta["pin_missing"])
        + ["", "## Operation counts of `inverse_dynamics`", "",
           "Reference: the best published RNEA count, (93N - 69) mul + (81N - 66) add, for N revolute joints.", ""] + ops_table(rows)
        + ["", "## Generation time", "", "derive + generate(target C), seconds, fresh interpreter, imports excluded, "
           f"median of {s.gen_repeats}.", ""] + generation_table(gen_rows)
        + ["", "## Targets", ""] + targets(rows) + ["", "## Notes", ""] + meta["notes"]) + "\n"


def write_csv(rows, gen_rows, path: Path) -> None:
    """Long format: table, scene, quantity, value."""
    with open(path, "w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(["table", "scene", "quantity", "value"])
        for r in rows:
            writer.writerows(["runtime", r["scene"], k, v] for k, v in r.items() if k not in ("scene", "warnings"))
            writer.writerow(["runtime", r["scene"], "compile_warnings", len(r["warnings"])])
        for g in gen_rows:
            writer.writerow(["generation", g["scene"], "seconds_inverse_dynamics", round(g["id"], 3)])
            writer.writerow(["generation", g["scene"], "seconds_all_functions", round(g["all"], 3)])


def notes(rows, pin, pin_note: str) -> list[str]:
    warnings = sorted({w for r in rows for w in r["warnings"]})
    pin_err = max((r["err_pin_py"] for r in rows if "err_pin_py" in r), default=None)
    return [f"* Pinocchio builds: {pin_note}." if pin is not None else "* Pinocchio: not installed.",
            "* `ur5`, `panda`: the URDF files of the `example-robot-data` package (Panda: the 7-joint arm, fingers "
            "locked closed). symgen reads them with `symgen.io.urdf`; Pinocchio's model comes from its own Python URDF "
            "parser on the same file (fingers removed by `buildReducedModel`), is written out as joint types, "
            "placements and inertias (17 digits) and rebuilt in `rnea_timing.cpp` with `addJoint` and "
            "`appendBodyToJoint`, so no object crosses to the precompiled library. symgen's inverse dynamics "
            "includes the files' joint damping `b qd` (eq. 22; Panda: b = 0.003, UR5: 0), which `rnea` leaves "
            "out: the error columns add it to Pinocchio's torques. RNEA counts are for N revolute joints.",
            "* `general_chain:n=7` (general geometry and inertia, `symgen.io.builtin.general_chain`): Pinocchio's "
            "model is built from symgen's spanning tree (`symgen.oracle.pinocchio_tree.tree_robot`, every joint "
            "about z, as the tree places it), written out and rebuilt the same way.",
            f"* Pinocchio's Python `rnea` against the generated NumPy module at 5 states per chain: max rel. err. "
            f"{fmt(pin_err) or 'not run'}.",
            f"* Warnings compiling the generated C with `-Wall -Wextra`: {len(warnings)}"
            + "".join(f"\n  * `{w}`" for w in warnings[:10]),
            "* lambdify `fails: X` is the exception symgen's symbolic reference evaluator raised; `> 60 s` is the "
            "subprocess time limit (symbolic build + lambdify + evaluation)."
            + "".join(f"\n  * {d}" for d in sorted({str(r["lambdify_detail"]) for r in rows if r["lambdify_detail"]})),
            "* NumPy memory: every statement is one ufunc writing into a row of one workspace allocated per call, "
            "rows reused by liveness, the batch worked through in chunks of CHUNK states (" + ", ".join(
                f"`{r['scene']}`: {r['numpy_rows']} rows x {r['numpy_chunk']} = "
                f"{r['numpy_rows'] * r['numpy_chunk'] * 8 / 1e6:.1f} MB" for r in rows)
            + "), so no statement allocates and the result does not depend on the allocator's settings."]


# ---------------------------------------------------------------- main
def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="1 round, 3 repeats, one generation run each")
    parser.add_argument("--scenes", help="comma-separated subset of SCENES (default: all)")
    parser.add_argument("--worker", nargs="+", help=argparse.SUPPRESS)  # subprocess bodies, see run_*
    args = parser.parse_args()
    if args.worker:
        kind, *rest = args.worker
        workers = {"numpy": numpy_worker, "lambdify": lambdify_worker, "gen": gen_worker}
        return workers[kind](*(int(a) if a.isdigit() else a for a in rest))
    try:
        import pinocchio as pin
    except ImportError:
        pin = None
    settings = Settings(1, 3, 1, (35, 100)) if args.quick else Settings(5, 9, 3, (35, 64, 100))
    with tempfile.TemporaryDirectory(prefix="symgen-bench-") as tmp:
        work = Path(tmp)
        os.environ["SYMGEN_CACHE"] = str(work / "cache")  # the ctypes bindings compile into here
        rnea_bins, pin_note = compile_rnea(pin, work) if pin is not None else ({}, "")
        specs = args.scenes.split(",") if args.scenes else SCENES
        rows = [bench_scene(spec, settings, pin, rnea_bins, work) for spec in specs]
    gen_rows = generation_times(settings)
    pin_desc = ("Pinocchio not installed" if pin is None else f"Pinocchio {pin.__version__}, C++ rnea timed from C++"
                if rnea_bins else f"Pinocchio {pin.__version__}: C++ build FAILED, the C / Pin. column holds a Python "
                "fallback that includes Python call overhead and is NOT the C++ comparison")
    meta = {"quick": args.quick, "machine": machine(), "pinocchio": pin_desc,
            "pin_missing": "not installed" if pin is None else "build failed",
            "settings": settings, "notes": notes(rows, pin, pin_note)}
    (HERE / "codegen_speed.md").write_text(markdown(rows, gen_rows, meta))
    write_csv(rows, gen_rows, HERE / "codegen_speed.csv")
    print(f"wrote {HERE / 'codegen_speed.md'} and {HERE / 'codegen_speed.csv'}")


if __name__ == "__main__":
    main()
