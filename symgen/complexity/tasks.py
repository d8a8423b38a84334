"""What one measurement does, stage by stage, inside the measuring subprocess.

A *task* is a JSON-able dict: ``{"method": ..., "spec": "chain:n=6", "stages": [...]}`` plus
``"function"`` for symgen. Methods and their stages, in order:

* ``symgen`` (this formulation): ``derive`` (``derive(load(spec))``, Steps 1-12) then ``ops``
  (trace of one generated function and its op counts, ``operation_counts(model, [function])``,
  which is what ``symgen ops SCENE --json`` prints);
* ``kane`` / ``lagrange`` (``sympy.physics.mechanics``): ``derive`` (mass matrix and forcing),
  ``raw`` (their op counts as expression trees), ``cse`` (op counts after ``sympy.cse``).

Imports happen before the ``start`` record, whose ``rss_kib`` is the resident memory then (the
baseline); the peak is reset there (:func:`reset_peak`). Each finished stage is reported at once
through ``emit(record)`` with its wall time and the peak resident memory so far (``rss_kib``), so
a stage that runs out of time loses only itself.
"""
from __future__ import annotations

import resource
import time

SYMGEN_STAGES = ("derive", "ops")
SYMPY_STAGES = ("derive", "raw", "cse")


def stages_of(method: str) -> tuple[str, ...]:
    """The stages of ``method`` (``symgen``, ``kane`` or ``lagrange``)."""
    if method == "symgen":
        return SYMGEN_STAGES
    if method in ("kane", "lagrange"):
        return SYMPY_STAGES
    raise ValueError(f"unknown method {method!r}; choose symgen, kane or lagrange")


def memory_kib() -> tuple[int, int]:
    """``(current, peak)`` resident set size in KiB: ``VmRSS`` / ``VmHWM`` of ``/proc/self/status``
    on Linux, else ``ru_maxrss`` for both."""
    try:
        with open("/proc/self/status") as fh:
            fields = dict(line.split(":", 1) for line in fh if line.startswith(("VmRSS", "VmHWM")))
        return int(fields["VmRSS"].split()[0]), int(fields["VmHWM"].split()[0])
    except (OSError, KeyError, ValueError):
        peak = int(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)
        return peak, peak


def reset_peak() -> bool:
    """Reset the peak resident set to the current one (Linux ``/proc/self/clear_refs``, value 5),
    so that the imports' transient peak does not hide the work's; False where unsupported."""
    try:
        with open("/proc/self/clear_refs", "w") as fh:
            fh.write("5")
        return True
    except OSError:
        return False


def run_task(task: dict, emit) -> None:
    """Run ``task``'s stages in order, calling ``emit`` with one record per finished stage
    (and a ``start`` record, after the imports, whose memory is the baseline)."""
    method = task["method"]
    wanted = tuple(task.get("stages") or stages_of(method))
    runner = _symgen_stages(task) if method == "symgen" else _sympy_stages(task)
    next(runner)   # the imports, before the baseline
    reset = reset_peak()
    emit({"stage": "start", "rss_kib": memory_kib()[0], "peak_reset": reset})
    for name in stages_of(method):
        if name not in wanted:
            return
        start = time.perf_counter()
        data = next(runner)
        emit({"stage": name, "seconds": time.perf_counter() - start, "rss_kib": memory_kib()[1], **data})


def _symgen_stages(task):
    from ..io.loading import load
    from ..codegen.generate import operation_counts
    from ..model import derive

    yield None
    model = derive(load(task["spec"]))
    yield {"dof": model.counts.n}
    function = task["function"]
    yield {"ops": operation_counts(model, [function])[function]}


def _sympy_stages(task):
    from . import mechanics
    from .sympy_ops import cse_operation_counts, operation_counts, sympy_count_ops

    yield None
    n = int(task["n"])
    M, forcing = mechanics.EQUATIONS[task["method"]](n)
    exprs = list(M) + list(forcing)
    yield {"dof": n}
    yield {"ops": operation_counts(exprs), "count_ops": sympy_count_ops(exprs)}
    ops, replacements = cse_operation_counts(exprs)
    yield {"ops": ops, "replacements": replacements}
