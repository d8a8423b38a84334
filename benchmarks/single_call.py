"""One state per call from Python: the generated CPython extension, the ctypes binding and
Pinocchio's ``rnea``, side by side in one process.

The UR10 of example-robot-data (``ur_description/urdf/ur10_robot.urdf``, the UR5's neighbour in
the package) is read by symgen (``scene_from_urdf``) and by Pinocchio (``buildModelFromUrdf``)
from the same file. symgen generates its inverse dynamics in C with the extension module
(``generate(..., python_extension=True)``), and the same source is loaded twice: as the extension
and through the ctypes binding (both ``cc -std=c99 -O2 -march=native``). Each of the three is
timed with :mod:`timeit` on one state (uniform in [-1, 1], seed ``SEED``; NumPy float64 arrays of
shape (6,), as a user's script holds them) in interleaved rounds of ``NUMBER`` calls, the order
rotating from round to round, by the thread's CPU clock; a row gives the fastest and the median
round, per call.

    python benchmarks/single_call.py            # writes single_call.md
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
import timeit
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

SEED = 0
ROUNDS = 30
NUMBER = 5000


def ur10_path() -> Path:
    from symgen.io.urdf.examples import example_path
    return example_path("ur5").with_name("ur10_robot.urdf")


def load(path: Path):
    import pinocchio as pin

    from symgen.codegen.generate import trace_all
    from symgen.codegen.runtime import load_generated
    from symgen.io.urdf.build import scene_from_urdf
    from symgen.model import derive

    model = derive(scene_from_urdf(path, name="ur10"))
    lowered = trace_all(model, ["inverse_dynamics"])
    ext = load_generated(model, "c", lowered=lowered, python_extension=True)
    binding = load_generated(model, "c", lowered=lowered)
    pmodel = pin.buildModelFromUrdf(str(path))
    return ext, binding, pin, pmodel, pmodel.createData()


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(HERE / "single_call.md"))
    args = parser.parse_args(argv)
    path = ur10_path()
    ext, binding, pin, pmodel, pdata = load(path)
    rng = np.random.default_rng(SEED)
    q, qd, qdd = (rng.uniform(-1, 1, 6) for _ in range(3))
    results = {"extension": ext.inverse_dynamics(q, qd, qdd), "ctypes": binding.inverse_dynamics(q, qd, qdd),
               "rnea": np.array(pin.rnea(pmodel, pdata, q, qd, qdd))}
    diff = {k: float(np.max(np.abs(v - results["rnea"])) / np.max(np.abs(results["rnea"]))) for k, v in results.items()}
    calls = {"extension": lambda: ext.inverse_dynamics(q, qd, qdd),
             "ctypes": lambda: binding.inverse_dynamics(q, qd, qdd),
             "rnea": lambda: pin.rnea(pmodel, pdata, q, qd, qdd)}
    timers = {k: timeit.Timer(f, timer=time.thread_time) for k, f in calls.items()}
    names = list(calls)
    times = {k: [] for k in names}
    for r in range(ROUNDS):
        for k in names[r % 3:] + names[:r % 3]:
            times[k].append(timers[k].timeit(NUMBER) / NUMBER * 1e9)
    ratio = {k: statistics.median(a / b for a, b in zip(times[k], times["rnea"])) for k in names}
    labels = {"extension": "symgen, CPython extension (`ur10_ext.inverse_dynamics`)",
              "ctypes": "symgen, ctypes binding (`ur10_ctypes.inverse_dynamics`)",
              "rnea": "Pinocchio `pinocchio.rnea(model, data, q, v, a)`"}
    lines = ["# One state per call from Python: UR10 inverse dynamics", "",
             f"Python {sys.version.split()[0]}, NumPy {np.__version__}, Pinocchio {pin.__version__}; one core.", "",
             "| call | min (ns) | median (ns) | / rnea (median of rounds) | rel. diff to rnea |",
             "|---|---|---|---|---|"]
    for k in names:
        lines.append(f"| {labels[k]} | {min(times[k]):.0f} | {statistics.median(times[k]):.0f} | "
                     f"{ratio[k]:.3f}× | {diff[k]:.1e} |")
    lines += ["", f"- `{path.relative_to(path.parents[3])}` of example-robot-data, read by both; one state "
              f"(seed {SEED}), float64 arrays of shape (6,). {ROUNDS} interleaved rounds of {NUMBER} calls "
              "(`timeit`, the order rotating), timed by the thread's CPU clock; per call: the fastest and "
              "the median round; */ rnea*: the median of the per-round ratios.",
              "- Each symgen call checks its arguments (shape, real, finite) and its outputs (finite), and "
              "returns a new array; `rnea` returns a NumPy array too (through eigenpy).",
              "- `python benchmarks/single_call.py` rewrites this file.", ""]
    Path(args.out).write_text("\n".join(lines))
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
