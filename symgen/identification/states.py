"""Loop-closed states ``(q, qd, qdd)`` for identification, from free coordinates or at random.

The *free coordinates* are the positions of ``q_a2`` and ``q_u2`` (Step 5, eq. 8): every other
position follows from closing the loops (:func:`symgen.closure.solve_closure`). The rates ``qd``
(eq. 14, on the independent coordinates) of a motion whose free rates are ``qd_free`` solve

    [S; J_f] qd = [qd_free; 0],          [S; J_f] qdd = [qdd_free; -dJ_f/dt qd]

(``S`` picks the free coordinates out of ``qd``; ``J_f qd = 0`` is eq. 12 with the environment
at rest), so the motion keeps ``V = [J_m; J_f] qd = [V_m; 0]`` as model (32) assumes. For open
chains ``S`` is the identity and the free coordinates are ``qd`` itself.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..closure import random_consistent_states, solve_closure
from ..math.configuration import Configuration
from .errors import IdentificationError


@dataclass(frozen=True)
class State:
    """One sample of motion: every joint position, and ``qd``, ``qdd`` on the independent coordinates."""

    config: Configuration
    qd: np.ndarray
    qdd: np.ndarray


def check_one_dof(model) -> None:
    """Identification data name one column per joint: spherical joints are not supported."""
    for c in model.tree.coordinates:
        if not c.kind.is_one_dof:
            raise IdentificationError(f"joint {c.joint!r}: identification supports revolute and prismatic "
                                      "joints only (a spherical joint has no single position column)")


def free_coordinates(model) -> tuple[int, ...]:
    """All-coordinate indices of the free positions ``q_a2, q_u2`` (eq. 8)."""
    part = model.partition
    return tuple(sorted(part.a2 + part.u2))


def free_names(model) -> list[str]:
    return [model.tree.coordinates[c].label for c in free_coordinates(model)]


def close_configuration(model, positions: dict, guess: Configuration) -> Configuration:
    """Every joint position: ``positions`` where given, the rest from ``guess`` and then the loop
    closure (Newton on ``q_u1, q_a1`` from there). With every position given, no solve."""
    pos = dict(guess.as_float().positions)
    pos.update({k: float(v) for k, v in positions.items()})
    config = Configuration(pos)
    needs = [model.tree.coordinates[c].joint for c in model.partition.u1 + model.partition.a1]
    if all(j in positions for j in needs):
        return config
    return solve_closure(model, config)


def _selector(model) -> np.ndarray:
    """``S``: rows of the identity picking the free coordinates out of ``qd``."""
    indep = list(model.partition.independent)
    free = free_coordinates(model)
    s = np.zeros((len(free), len(indep)))
    for row, c in enumerate(free):
        s[row, indep.index(c)] = 1.0
    return s


def state_from_free(model, config: Configuration, qd_free, qdd_free):
    """``(State, data)`` with free rates ``qd_free`` and accelerations ``qdd_free`` at a loop-closed
    ``config`` (module docstring); ``data`` is the model evaluated at that state."""
    m = model.counts.m
    s = _selector(model)
    if model.counts.n == m:              # no J_f: qd is the free rates (one evaluation, not two)
        qd = np.linalg.solve(s, np.asarray(qd_free, float))
        return State(config, qd, np.linalg.solve(s, np.asarray(qdd_free, float))), model.evaluate(config, qd=qd)
    data = model.evaluate(config, qd=np.zeros(model.counts.n))
    lhs = np.vstack([s, data.maps.A.v[m:]])
    qd = np.linalg.solve(lhs, np.concatenate([np.asarray(qd_free, float), np.zeros(model.counts.n - m)]))
    data = model.evaluate(config, qd=qd)
    rhs = np.concatenate([np.asarray(qdd_free, float), -data.maps.A.d[m:] @ qd])
    return State(config, qd, np.linalg.solve(lhs, rhs)), data


def random_states(model, count: int, *, seed: int = 0, spread: float | None = None) -> list[State]:
    """``count`` random loop-closed states: positions within ``spread`` of the reference (default
    pi for open chains, 0.3 for closed ones, where the loops must still close), ``V_m`` and
    ``dV_m`` uniform in ``[-1, 1]``, ``qd = Omega V_m``, ``qdd`` from eq. (18) differentiated."""
    rng = np.random.default_rng(seed + 1)
    closed = bool(model.partition.u1 or model.partition.a1)
    spread = (0.3 if closed else np.pi) if spread is None else spread
    n, m = model.counts.n, model.counts.m
    out = []
    for config, v_m in random_consistent_states(model, count, seed=seed, spread=spread):
        data = model.evaluate(config, V_m=v_m)
        dv = np.concatenate([rng.uniform(-1, 1, m), np.zeros(n - m)])
        qdd = data.maps.A_inv.v @ (dv - data.maps.A.d @ data.qd)
        out.append(State(config, np.asarray(data.qd, float), qdd))
    return out
