"""The loop-closure forces along a simulated trajectory: what a designer sizes bearings with.

At recorded states the dense model gives ``lam`` (:meth:`symgen.model.Model.loop_forces`): the
force and moment each closure constraint exerts on the body of its frame A, at A's origin, in A's
axes (``<constraint>.fx`` ... ``.mz``). ``symgen simulate`` prints them at the final state and the
largest magnitude of each component over the run.
"""
from __future__ import annotations

import numpy as np

#: at most this many recorded states are evaluated for the peak forces (evenly spaced, ends kept)
MAX_SAMPLES = 200


def _forces_at(model, traj, tau, k: int) -> np.ndarray:
    q, v_m = traj.q(k), traj.V_m(k)
    torque = np.asarray(tau(float(traj.times[k]), q, v_m), float) if tau is not None else np.zeros(model.counts.n)
    return model.loop_forces(traj.configuration(k), v_m, torque)


def loop_force_summary(model, traj, tau=None) -> dict:
    """``{"final": {label: value}, "peak": {label: max |value|}}`` over the recorded states
    (``tau(t, q, V_m)`` the actuator forces of the run, ``None`` for zero); empty without
    constraints."""
    labels = model.constraint_force_names()
    if not labels:
        return {}
    count = len(traj.times)
    picks = np.unique(np.linspace(0, count - 1, min(count, MAX_SAMPLES)).round().astype(int))
    values = np.array([_forces_at(model, traj, tau, int(k)) for k in picks])
    return {"final": dict(zip(labels, map(float, values[-1]))),
            "peak": dict(zip(labels, map(float, np.max(np.abs(values), axis=0))))}


def format_loop_forces(summary: dict) -> list[str]:
    """Printable lines of :func:`loop_force_summary`."""
    if not summary:
        return []
    lines = ["  loop-closure forces (N, N m; on frame A's body, in frame A's axes):",
             f"    {'component':<24} {'final':>16} {'peak |.|':>12}"]
    for label, value in summary["final"].items():
        lines.append(f"    {label:<24} {value: .9e} {summary['peak'][label]:12.4e}")
    return lines
