"""Error against run time: a work-precision study of every integrator on one scene.

For each backend (generated NumPy and C), each method and each step size (fixed-step methods) or
tolerance ``rtol = atol`` (adaptive ones), :func:`work_precision` runs :func:`simulate` from the
same initial state and records

* ``error``: final-state error ``max_i |x_i - x_ref,i| / max(1, max_i |x_ref,i|)`` against a
  reference run (DOP853, ``rtol = atol = 1e-13``, Baumgarte-stabilised), itself checked against a
  tighter run (``rtol = 3e-14, atol = 1e-14``, close to SciPy's floor of ``100 eps``); their
  difference is reported as ``reference_difference`` and sets the noise floor;
* ``drift`` (max constraint residual), ``energy_drift`` (conservative runs only), ``wall_time``,
  ``rhs_calls`` and ``steps``.

:func:`monotonicity_violations` (:mod:`symgen.simulation.study`, with the :class:`Study` it checks)
tells whether the error falls as the step shrinks or the tolerance tightens, down to the noise floor. :func:`write_report` (:mod:`symgen.simulation.report`) writes
the table and the plot.
"""
from __future__ import annotations

import numpy as np

from ..codegen.targets import TARGETS, target
from ..errors import SymgenError
from .integrators import FIXED_METHODS, METHODS, resolve_method, simulate
from .report import write_study
from .study import FLOOR_FACTOR, FLOOR_MIN, Row, Study, monotonicity_violations, series

#: fixed step sizes (s), coarse to fine
DEFAULT_STEPS = (0.04, 0.02, 0.01, 0.005, 0.0025, 0.00125)
#: adaptive tolerances rtol = atol, loose to tight
DEFAULT_TOLERANCES = (1e-4, 1e-6, 1e-8, 1e-10)
REFERENCE = dict(method="DOP853", rtol=1e-13, atol=1e-13)
CHECK = dict(method="DOP853", rtol=3e-14, atol=1e-14)

__all__ = ["CHECK", "DEFAULT_STEPS", "DEFAULT_TOLERANCES", "FLOOR_FACTOR", "FLOOR_MIN", "REFERENCE", "Row", "Study",
           "monotonicity_violations", "series", "state_error", "work_precision", "write_report"]


def state_error(x, x_ref) -> float:
    """``max |x - x_ref| / max(1, max |x_ref|)`` (mixed absolute / relative, dimensionless)."""
    x, x_ref = np.asarray(x, float), np.asarray(x_ref, float)
    return float(np.max(np.abs(x - x_ref)) / max(1.0, float(np.max(np.abs(x_ref)))))


def _run(model, t_end, backend, method, setting, x_ref, common) -> Row:
    """One row; a run that fails with a typed error is kept, with its message as status."""
    kind = "step" if method in FIXED_METHODS else "tol"
    args = dict(step=setting) if kind == "step" else dict(rtol=setting, atol=setting)
    try:
        traj = simulate(model, t_end, method, backend=backend, **args, **common)
    except SymgenError as exc:
        return Row(backend, method, kind, setting, float("nan"), float("nan"), None, float("nan"), 0, 0,
                   f"failed: {exc}")
    return Row(backend, method, kind, setting, state_error(traj.final_state, x_ref), traj.max_drift,
               traj.energy_drift, traj.wall_time, traj.rhs_calls, traj.steps)


def work_precision(model, t_end: float, *, methods=METHODS, backends=TARGETS, steps=DEFAULT_STEPS,
                   tolerances=DEFAULT_TOLERANCES, tau=None, eta_m=None, x0=None, stabilization="auto",
                   reference_backend: str | None = None, progress=None) -> Study:
    """Run the study (see module docstring). ``progress``: optional callable taking a line of text.
    The reference runs on ``reference_backend``, default the first compiled target in ``backends``
    (C), else the first one."""
    methods = [resolve_method(m) for m in methods]
    common = dict(tau=tau, eta_m=eta_m, x0=x0, stabilization=stabilization)
    ref_backend = reference_backend or next((b for b in backends if target(b).compiled), backends[0])
    ref = simulate(model, t_end, backend=ref_backend, energy=False, **REFERENCE, **common)
    check = simulate(model, t_end, backend=ref_backend, energy=False, **CHECK, **common)
    x_ref = ref.final_state
    rows = []
    for backend in backends:
        for method in methods:
            for setting in (steps if method in FIXED_METHODS else tolerances):
                row = _run(model, t_end, backend, method, setting, x_ref, common)
                rows.append(row)
                if progress is not None:
                    progress(f"{backend:<6} {method:<20} {row.kind} {row.setting:<8.3g} error {row.error:.3g} "
                             f"time {row.wall_time:.3g} s  {row.status}")
    conservative = any(r.energy_drift is not None for r in rows)
    return Study(model.scene.name, float(t_end), rows, state_error(check.final_state, x_ref), ref.rhs_calls,
                 conservative, ref.stabilization)


def write_report(study: Study, out, *, force: bool = False, command: str | None = None):
    """Write ``work_precision.csv``, ``work_precision.md`` and ``work_precision.png`` into the
    directory ``out``, atomically (see :mod:`symgen.simulation.report`)."""
    return write_study(study, out, force=force, command=command)
