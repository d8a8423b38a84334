"""Per-call time of variants of one generated C function, through the ctypes binding: shared by the
benchmarks that compare two ways of generating the same function (``compile_scale.py``: whole
functions against blocks; ``small_dense_solves.py``: solves in line against the library LU).

Each variant is written to its own folder and imported through its ``<module>_ctypes.py`` binding
(which compiles the source with its own ``-O2``); the ``_batch`` entry point is called on the same
loop-closed states, variants alternating, and the best call of each is kept.
"""
from __future__ import annotations

import re
import time
from pathlib import Path

import numpy as np


def load_variant(gen, work: Path, tag: str):
    """The imported ctypes binding of generated C files ``gen`` (written to ``work/<tag>``)."""
    from symgen.codegen.targets import import_file

    folder = work / re.sub(r"[^A-Za-z0-9]", "_", tag)
    folder.mkdir(parents=True, exist_ok=True)
    for name, text in gen.files.items():
        (folder / name).write_text(text)
    return import_file(folder / f"{gen.module}_ctypes.py", f"variant_{folder.name}")


def state_batch(model, count: int, seed: int = 3) -> dict:
    """``count`` inputs per argument name, cycling through 100 loop-closed reference states."""
    from symgen.codegen.reference import reference_states

    states = reference_states(model, 100, seed=seed)
    picks = np.arange(count) % len(states)
    return {k: np.array([states[i][k] for i in picks]) for k in states[0] if k != "config"}


def best_ns_per_state(modules: dict, function: str, batch: dict, calls: int) -> dict:
    """ns per state of ``function`` in each module (variant name -> module), the best of ``calls``
    alternating batch calls."""
    from symgen.codegen.runtime import call_by_name

    count = len(next(iter(batch.values())))
    best = {v: float("inf") for v in modules}
    for _ in range(calls):
        for variant, module in modules.items():
            start = time.perf_counter()
            call_by_name(module, function, batch)
            best[variant] = min(best[variant], time.perf_counter() - start)
    return {v: t * 1e9 / count for v, t in best.items()}
