"""Fuzzing the Python API's states: a state with one hostile entry (NaN, infinities, huge or tiny
numbers, strings, booleans, complex numbers, wrong shapes, non-rotations, zero quaternions) gives a
typed :class:`~symgen.errors.SymgenError` or a finite result -- never another exception, never NaN.

The CI share is a hundred cases; ``python tests/test_fuzz_api_states.py N SEED`` runs ``N`` more
and prints the counts.
"""
from __future__ import annotations

import sys
from fractions import Fraction

import numpy as np
import pytest

import symgen
from symgen.errors import SymgenError

SCENES = ("four_bar", "stewart")
HOSTILE = (np.nan, np.inf, -np.inf, 1e308, -1e308, 1e200, 1e-320, 0.0, "0.5", None, True, 1j, Fraction(1, 3),
           [], [0.1, 0.2], np.eye(3) * 2, -np.eye(3), np.zeros(4), np.full(4, 1e308), np.eye(2), object())
CALLS = ("evaluate", "forward_dynamics", "inverse_dynamics", "joint_rates", "joint_accelerations", "loop_forces")


def _models():
    return {name: symgen.derive(symgen.load(name)) for name in SCENES}


def _case(models, rng) -> tuple:
    """(model, call name, arguments) with one hostile entry."""
    model = models[SCENES[int(rng.integers(len(SCENES)))]]
    m, n = model.counts.m, model.counts.n
    pos = dict(model.reference.positions)
    v_m, tau, dv_m = list(rng.uniform(-1, 1, m)), list(rng.uniform(-1, 1, n)), list(rng.uniform(-1, 1, m))
    bad = HOSTILE[int(rng.integers(len(HOSTILE)))]
    where = int(rng.integers(4))
    if where == 0:
        joint = list(pos)[int(rng.integers(len(pos)))]
        pos[joint] = bad
    elif where == 1:
        v_m[int(rng.integers(m))] = bad
    elif where == 2:
        tau[int(rng.integers(n))] = bad
    else:
        dv_m = bad
    call = CALLS[int(rng.integers(len(CALLS)))]
    args = {"evaluate": ((pos,), dict(V_m=v_m)), "forward_dynamics": ((pos, v_m, tau), {}),
            "inverse_dynamics": ((pos, v_m, dv_m), {}), "joint_rates": ((pos, v_m), {}),
            "joint_accelerations": ((pos, v_m, tau), {}), "loop_forces": ((pos, v_m, tau), {})}[call]
    return model, call, args


def _outputs(result) -> list[np.ndarray]:
    if hasattr(result, "M"):
        return [result.M, result.C, result.G]
    return list(result) if isinstance(result, tuple) else [result]


def run_case(models, rng) -> str:
    """``"typed"``, ``"finite"``, or raises on an untyped exception or a non-finite result."""
    model, call, (args, kwargs) = _case(models, rng)
    try:
        with np.errstate(all="ignore"):
            result = getattr(model, call)(*args, **kwargs)
    except SymgenError:
        return "typed"
    for out in _outputs(result):
        arr = np.asarray(out, dtype=float)
        assert np.all(np.isfinite(arr)), f"{call} returned a non-finite result for {args!r}"
    return "finite"


@pytest.fixture(scope="module")
def models():
    return _models()


def test_hostile_api_states_give_typed_errors_or_finite_results(models):
    rng = np.random.default_rng(11)
    outcomes = [run_case(models, rng) for _ in range(100)]
    assert {"typed", "finite"} <= set(outcomes)          # the mutations reach both outcomes


if __name__ == "__main__":
    count = int(sys.argv[1]) if len(sys.argv) > 1 else 1000
    seed = int(sys.argv[2]) if len(sys.argv) > 2 else 0
    generator, found = np.random.default_rng(seed), {"typed": 0, "finite": 0}
    every = _models()
    for _ in range(count):
        found[run_case(every, generator)] += 1
    print(f"{count} cases: {found['typed']} typed errors, {found['finite']} finite results, 0 untyped, 0 non-finite")
