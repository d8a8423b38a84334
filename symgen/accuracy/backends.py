"""The implementations compared with the extended-precision reference, and how they are timed.

A *backend* turns one state (a dict of :func:`symgen.codegen.reference.reference_states`) into
the outputs of one generated function. :func:`generated_backend` wraps a module of
:func:`symgen.codegen.runtime.load_generated` (NumPy or C); :func:`dense_float_backend` the
dense float model of :func:`symgen.codegen.reference.reference_outputs`. :func:`per_call_seconds`
is the timing every column uses, the ``lambdify`` worker included.
"""
from __future__ import annotations

import inspect
import statistics
import time
from dataclasses import dataclass
from typing import Callable

import numpy as np

#: timed rounds per backend and function (each round calls once per state; the median is kept)
ROUNDS = 5


@dataclass
class Backend:
    """A callable per function: ``prepare(state) -> args`` (untimed) and ``call(*args) ->
    tuple of arrays`` (timed), outputs in the order of the reference's output names."""

    name: str
    prepare: Callable[[dict], tuple]
    call: Callable[..., tuple]


def generated_backend(label: str, module, function: str) -> Backend:
    """Generated function ``function`` of ``module``; arguments by the names it declares."""
    fn = getattr(module, function)
    params = list(inspect.signature(fn).parameters)

    def call(*args):
        out = fn(*args)
        return out if isinstance(out, tuple) else (out,)

    return Backend(label, lambda s: tuple(np.asarray(s[p], dtype=float) for p in params), call)


def dense_float_backend(model, function: str) -> Backend:
    """The dense ``O(n^3)`` float model (32) behind the equivalence tests."""
    from ..codegen.reference import reference_outputs

    return Backend("dense float", lambda s: (s,),
                   lambda s: tuple(reference_outputs(model, function, s).values()))


def per_call_seconds(call: Callable, arg_list: list[tuple], rounds: int = ROUNDS) -> float:
    """Median over ``rounds`` of (time of one call per argument tuple) / (number of tuples),
    measured with :func:`time.perf_counter` after one untimed warm-up pass."""
    for args in arg_list:
        call(*args)
    samples = []
    for _ in range(rounds):
        start = time.perf_counter()
        for args in arg_list:
            call(*args)
        samples.append((time.perf_counter() - start) / len(arg_list))
    return statistics.median(samples)


def run_backend(backend: Backend, states: list[dict], rounds: int = ROUNDS) -> tuple[list[tuple], float]:
    """Outputs at every state, and the per-call time."""
    args = [backend.prepare(s) for s in states]
    outputs = [tuple(np.asarray(o, dtype=float) for o in backend.call(*a)) for a in args]
    return outputs, per_call_seconds(backend.call, args, rounds)
