"""The space robot's momentum over a simulation: how far the integrator lets it drift.

``space_ur5`` (a UR5 on a free-floating base, zero gravity) driven by internal joint torques
``tau_j = sin(2 t + j)`` from a tumbling start conserves its linear and angular momentum
exactly. The simulation (generated C, ``DOP853``) is run for ``T_END`` seconds at several
tolerances, and the centroidal momentum is computed at every accepted step by Pinocchio
(``computeCentroidalMomentum`` on the robot rebuilt from the URDF by Pinocchio's own parser,
:func:`symgen.oracle.pinocchio_model.pinocchio_robot`, symgen's state mapped to its ``q`` and
``v``): the drift is ``max_t max_k |h_k(t) - h_k(0)|`` (N s, N m s; the momentum is about 2).

What limits it is the integrator's tolerance: DOP853 keeps each step's error below ``rtol |y| +
atol``, and the errors add up over the steps. SciPy clips ``rtol`` at ``100 eps`` (2.2e-14), and
the relative part is loose on the shoulder joint, which spins up to ~670 rad in 10 s, so ``atol``
must be small too. (The model's own momentum rate is zero to rounding,
``tests/test_floating_base.py``; the quaternion stays unit to 2e-16.)

Writes ``space_momentum.md`` and ``space_momentum.csv`` beside this file.

    python benchmarks/space_momentum.py
"""
from __future__ import annotations

import csv
import os
import platform
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
T_END = 10.0
#: (rtol, atol) of the rows: the earlier setting, then rtol at SciPy's floor with two atol
TOLERANCES = [(1e-13, 1e-13), (2.3e-14, 1e-14), (2.3e-14, 1e-16)]
#: the initial base twist (pd in world axes, w in body axes), then the six joint rates
V0 = np.array([0.05, -0.02, 0.01, 0.2, -0.1, 0.3, 0.5, -0.4, 0.3, 0.2, -0.6, 0.8])


def space_robot():
    """``(model, Pinocchio robot, Pinocchio velocity index of each coordinate, 0/1 joint mask)``."""
    from symgen.io.urdf.legged import space_ur5
    from symgen.model import derive
    from symgen.oracle.pinocchio_model import pinocchio_robot

    model = derive(space_ur5())
    robot = pinocchio_robot(model.scene)
    labels = [c.label for c in model.tree.coordinates]
    independent = [labels[i] for i in model.partition.independent]
    base = model.scene.free_joints["floating_base"].velocity_labels
    drive = np.array([0.0 if lab in base else 1.0 for lab in independent])
    return model, robot, robot.v_index(labels), drive


def momentum_drift(t_end: float, rtol: float, atol: float, robot: tuple | None = None) -> dict:
    """Simulate ``space_ur5`` for ``t_end`` s; the largest change of Pinocchio's centroidal momentum
    over the accepted steps (``drift``), its size at the start, steps, calls and seconds.
    ``robot``: what :func:`space_robot` returns (default: built here)."""
    import pinocchio as pin

    from symgen.simulation import simulate

    model, robot, v_idx, drive = robot or space_robot()
    data = robot.model.createData()

    def tau(t, q, v_m):
        return drive * np.sin(2.0 * t + np.arange(len(drive)))

    start = time.perf_counter()
    traj = simulate(model, t_end, "DOP853", rtol=rtol, atol=atol, tau=tau, V_m=V0, energy=False, backend="c")
    seconds = time.perf_counter() - start
    momenta = []
    for x in traj.states:
        q, v_m = traj.layout.split(x)
        config = traj.layout.configuration(q)
        v = np.zeros(robot.model.nv)
        v[v_idx] = model.joint_rates(config, v_m)
        momenta.append(np.array(pin.computeCentroidalMomentum(robot.model, data, robot.q_vector(config), v).vector))
    momenta = np.array(momenta)
    return {"t_end": t_end, "rtol": rtol, "atol": atol, "drift": float(np.abs(momenta - momenta[0]).max()),
            "momentum": float(np.abs(momenta[0]).max()), "steps": traj.steps, "rhs_calls": traj.rhs_calls,
            "seconds": seconds, "integrate_s": traj.wall_time}


def main() -> None:
    rows = []
    for rtol, atol in TOLERANCES:
        rows.append(momentum_drift(T_END, rtol, atol))
        print(rows[-1], flush=True)
    keys = list(rows[0])
    with open(HERE / "space_momentum.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, keys)
        writer.writeheader()
        writer.writerows(rows)
    lines = ["# Space robot: momentum drift over a simulation", "",
             f"`space_ur5`, zero gravity, joint torques `sin(2 t + j)`, {T_END:g} s with `DOP853` on generated C; the "
             "momentum by Pinocchio's `computeCentroidalMomentum` at every accepted step. Measured in one run by "
             f"`python benchmarks/space_momentum.py` on {platform.machine()}, {os.cpu_count()} cores shared with other jobs, "
             f"Python {platform.python_version()}. rtol = 2.3e-14 is just above SciPy's floor of 100 eps, to which it "
             "clips smaller values. "
             "**seconds**: the whole `simulate` call (code loading included); **integrate**: the integration alone.",
             "", "| rtol | atol | duration (s) | steps | RHS calls | seconds | integrate (s) | momentum | drift |",
             "|---|---|---|---|---|---|---|---|---|"]
    lines += [f"| {r['rtol']:.2g} | {r['atol']:.2g} | {r['t_end']:g} | {r['steps']} | {r['rhs_calls']} | "
              f"{r['seconds']:.1f} | {r['integrate_s']:.1f} | {r['momentum']:.3f} | {r['drift']:.2e} |" for r in rows]
    (HERE / "space_momentum.md").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
