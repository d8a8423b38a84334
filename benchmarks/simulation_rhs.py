"""Cost of one simulation right-hand side: the generated ``state_derivative`` (one pass) against
``forward_dynamics`` + ``joint_rates`` (two calls that both solve with ``[J_m; J_f]``), through the
Python ``Dynamics`` wrapper. Ratios are taken side by side, interleaved over 5 rounds of 100 calls.

    python benchmarks/simulation_rhs.py      # writes benchmarks/simulation_rhs.md and .csv
"""
from __future__ import annotations

import pathlib
import time

import numpy as np

import symgen
from symgen.simulation import Dynamics, StateLayout

SCENES = ("chain:n=6", "four_bar", "arm_on_plane", "stewart")
ROUNDS, CALLS = 5, 100


def _time(fn) -> float:
    start = time.perf_counter()
    for _ in range(CALLS):
        fn()
    return (time.perf_counter() - start) / CALLS


def measure(spec: str, backend: str) -> tuple[float, float]:
    model = symgen.derive(symgen.load(spec))
    dyn = Dynamics(model, backend)
    x = StateLayout(model).initial_state(V_m=0.3 * np.ones(model.counts.m))
    q, v = dyn.layout.split(x)
    q = dyn.layout.normalized(q)

    def two_calls():
        return np.concatenate([dyn.layout.position_rates(q, dyn.joint_rates(0.0, q, v)), dyn.acceleration(0.0, q, v)])

    def one_pass():
        return dyn(0.0, x)

    assert np.allclose(two_calls(), one_pass(), rtol=1e-12, atol=1e-13)
    old, new = [], []
    for _ in range(ROUNDS):
        old.append(_time(two_calls))
        new.append(_time(one_pass))
    ratios = [n / o for n, o in zip(new, old)]
    return float(np.median(old)), float(np.median(new)), float(np.median(ratios))


def main() -> None:
    lines = ["# Simulation right-hand side: one pass against two calls", "",
             "Command: `python benchmarks/simulation_rhs.py`. Median time per right-hand side through "
             f"`symgen.simulation.Dynamics` ({ROUNDS} interleaved rounds of {CALLS} calls); ratio per round, then "
             "the median.", "",
             "| scene | backend | forward_dynamics + joint_rates (us) | state_derivative (us) | ratio |",
             "|---|---|---|---|---|"]
    rows = ["scene,backend,two_calls_us,state_derivative_us,ratio"]
    for spec in SCENES:
        for backend in ("c", "numpy"):
            old, new, ratio = measure(spec, backend)
            lines.append(f"| `{spec}` | {backend} | {old * 1e6:.0f} | {new * 1e6:.0f} | {ratio:.2f} |")
            rows.append(f"{spec},{backend},{old * 1e6!r},{new * 1e6!r},{ratio!r}")
    out = pathlib.Path(__file__).with_name("simulation_rhs.md")
    out.write_text("\n".join(lines) + "\n")
    out.with_suffix(".csv").write_text("\n".join(rows) + "\n")
    print(out.read_text())


if __name__ == "__main__":
    main()
