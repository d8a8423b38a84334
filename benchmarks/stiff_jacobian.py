"""SciPy's stiff integrators with the generated Jacobian against SciPy's finite-difference one.

The stiff cases of the stability suite (``symgen.stability.cases``): the chain with viscous
friction 1e5 and ``arm_on_plane`` held by a compliant anchor of stiffness K (its contact force
``eta_m`` depends on the state, so the Jacobian takes the chain rule through it). These settle
within the run, and SciPy evaluates their Jacobian once or twice. One case is added here whose
Jacobian changes along the run: :func:`swinging_chain`, the suite's three-link chain with viscous
friction 1e5 on its first joint only, the other two swinging freely under gravity for 2 s. Each is run
with ``Radau`` and ``BDF`` at ``rtol = atol = 1e-8``, once with ``jacobian="finite-difference"``
(SciPy's, whose right-hand-side calls are counted) and once with ``jacobian="generated"``
(``state_derivative_jacobian``), side by side in one run on the same backend. The error is
``max |x(t_end) - x_ref(t_end)|`` against Radau at ``rtol = atol = 1e-12`` with the generated
Jacobian (a Jacobian changes the Newton iterations, not the solution a tolerance asks for).

    python benchmarks/stiff_jacobian.py [--backend c] [--rounds 5]   # writes benchmarks/stiff_jacobian.md and .csv
"""
import argparse
import statistics
import time
from pathlib import Path

import numpy as np

from symgen.math.configuration import Configuration
from symgen.model import derive
from symgen.simulation import simulate
from symgen.stability.cases import Case, Setup, get_case
from symgen.stability.scenes import scaled_chain

from codegen_speed import write_table


def swinging_chain() -> Setup:
    """The suite's three-link benchmark chain (``scaled_chain``) with viscous friction 1e5 N m s/rad
    on its first joint (axis z) only; the second and third joints swing freely under gravity from
    seeded positions and rates in [-0.5, 0.5] and [-2, 2]: one stiff mode beside a large nonlinear
    motion, so the integrators' Newton iterations ask for a new Jacobian as the arm moves."""
    scene = scaled_chain(3, viscous=(100_000, 0, 0), name="chain_n3_swinging")
    model = derive(scene)
    rng = np.random.default_rng(0)
    config = Configuration({j: float(v) for j, v in zip(scene.joints, rng.uniform(-0.5, 0.5, 3))})
    return Setup(model, config, rng.uniform(-2, 2, 3), np.zeros(3))


SWINGING = Case("swinging_stiff_joint", "stiff", "chain n=3, viscous friction 1e5 on its first joint only, "
                "swinging", swinging_chain, "accurate", t_end=2.0)
CASES = ["stiff_friction", "stiff_contact_K1e+04", "stiff_contact_K1e+06", "stiff_contact_K1e+08", SWINGING.name]
METHODS = ["Radau", "BDF"]
JACOBIANS = ["finite-difference", "generated"]
RTOL = 1e-8
REFERENCE_RTOL = 1e-12
#: timed rounds of each (case, method) pair, finite differences and generated interleaved
ROUNDS = 5


def run(case, method: str, jacobian: str, rtol: float, backend: str):
    st = case.setup
    start = time.perf_counter()
    traj = simulate(st.model, case.t_end, method, rtol=rtol, backend=backend, x0=st.config, V_m=st.V_m,
                    tau=lambda t, q, v: st.tau, eta_m=st.eta_m, jacobian=jacobian, energy=False)
    return traj, time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--backend", default="c", choices=["numpy", "c"])
    parser.add_argument("--rounds", type=int, default=ROUNDS, help=f"timed rounds per pair (default {ROUNDS})")
    args = parser.parse_args()
    rows = []
    for name in CASES:
        case = SWINGING if name == SWINGING.name else get_case(name)
        run(case, "Radau", "generated", RTOL, args.backend)             # compile and trace outside the timing
        reference, _ = run(case, "Radau", "generated", REFERENCE_RTOL, args.backend)
        for method in METHODS:
            walls = {j: [] for j in JACOBIANS}
            for r in range(args.rounds):         # interleaved, the order alternating round by round
                for jacobian in (JACOBIANS if r % 2 == 0 else JACOBIANS[::-1]):
                    traj, wall = run(case, method, jacobian, RTOL, args.backend)
                    walls[jacobian].append(wall)
                    if r == 0:
                        rows.append({"case": name, "t_end": case.t_end, "method": method, "jacobian": jacobian,
                                     "rhs_calls": traj.rhs_calls, "jacobian_calls": traj.settings["jacobian_calls"],
                                     "error": float(np.max(np.abs(traj.states[-1] - reference.states[-1])))})
            ratios = [g / f for g, f in zip(walls["generated"], walls["finite-difference"])]
            for row in rows[-2:]:
                row["wall_s"] = statistics.median(walls[row["jacobian"]])
                row["wall_ratio"] = statistics.median(ratios) if row["jacobian"] == "generated" else 1.0
    lines = ["# Stiff integrators: generated Jacobian against finite differences", "",
             f"`python benchmarks/stiff_jacobian.py --backend {args.backend}`: SciPy's Radau and BDF at rtol = atol = "
             f"{RTOL:g} on the stiff cases of the stability suite and on a chain swinging beside one stiff joint "
             "(`swinging_stiff_joint`: viscous friction 1e5 on its first joint only, 2 s; its Jacobian changes "
             "along the run), with SciPy's finite-difference Jacobian and with "
             "the generated `state_derivative_jacobian`, side by side in one run on the generated "
             f"{'C' if args.backend == 'c' else 'NumPy'}. *rhs calls* counts every right-hand side, those SciPy "
             "spends on finite differences included; *Jacobians* is SciPy's count of Jacobian evaluations; *error* "
             f"is the final state's max difference to Radau at rtol = atol = {REFERENCE_RTOL:g}. *wall*: the median "
             f"of {args.rounds} runs of each, the two Jacobians interleaved (order alternating); *wall ratio*: the "
             "median over the rounds of generated / finite-difference.", "",
             "| case | t_end (s) | method | Jacobian | rhs calls | Jacobians | wall (s) | error | wall ratio |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['case']} | {r['t_end']:g} | {r['method']} | {r['jacobian']} | {r['rhs_calls']} | "
                     f"{r['jacobian_calls']} | {r['wall_s']:.3f} | {r['error']:.2e} | {r['wall_ratio']:.2f} |")
    write_table(Path(__file__).parent / "stiff_jacobian", lines, rows)


if __name__ == "__main__":
    main()
