"""Run the stability cases: evaluate each state, judge the answer, integrate a short run.

For every case (:mod:`symgen.stability.cases`):

1. the condition numbers of the matrices model (32) inverts (:func:`~.metrics.conditions`);
2. the generated forward dynamics at the case's state: its equation-of-motion residual and its
   error against the 50-digit model (:mod:`~.metrics`);
3. the verdict: ``"accurate"`` when both are finite and within :func:`tolerance` -- what a
   backward-stable evaluation allows at that conditioning --, ``"error"`` when the generated code
   or the model raised a typed error (the message names the matrix and its condition number),
   ``"inaccurate"`` otherwise (a failure of the suite's expectations: it is never expected);
4. above :data:`WARN_CONDITION` an :class:`IllConditionedWarning` with the condition number;
5. a run of ``t_end`` seconds with each integrator of :data:`METHODS`: succeeded or not (with the
   typed error's message: a stiff problem under an explicit method gets
   :class:`~symgen.simulation.StiffnessError`, which suggests Radau or BDF), right-hand-side calls,
   wall time, and the final state's distance to the Radau run's.
"""
from __future__ import annotations

import warnings
from dataclasses import asdict, dataclass, field

import numpy as np

from ..errors import SymgenError
from .cases import Case
from .metrics import FUNCTIONS, conditions, eom_residual, reference_error

#: double precision unit roundoff
EPS = float(np.finfo(float).eps)
#: an answer is accurate when its errors are below ``max(FLOOR, FACTOR * EPS * cond)``
FACTOR = 100.0
FLOOR = 1e-12
#: condition number above which the suite warns
WARN_CONDITION = 1e8
#: the integrators every case is run with, and their settings
METHODS = {"RK45": {"rtol": 1e-8}, "DOP853": {"rtol": 1e-8}, "Radau": {"rtol": 1e-8}, "BDF": {"rtol": 1e-8},
           "rk4": {"steps": 200}}
#: right-hand-side calls after which an explicit run is declared stiff
MAX_RHS_CALLS = 20_000


class IllConditionedWarning(UserWarning):
    """A case's state is ill-conditioned: its answer holds only to about ``cond * eps``."""


def tolerance(condition: float) -> float:
    """The error a backward-stable evaluation may make at ``condition``."""
    return max(FLOOR, FACTOR * EPS * condition)


@dataclass
class RunResult:
    method: str
    ok: bool
    rhs_calls: int | None = None
    wall_time: float | None = None
    difference: float | None = None   # max |x_end - x_end(Radau)|, when both finished
    message: str = ""


@dataclass
class CaseResult:
    name: str
    kind: str
    description: str
    expect: str
    reference: str = "mp"
    backend: str = "c"
    status: str = ""
    conditions: dict = field(default_factory=dict)
    residual: float | None = None
    error: float | None = None
    tolerance: float | None = None
    message: str = ""
    runs: list = field(default_factory=list)

    @property
    def as_expected(self) -> bool:
        return self.status == self.expect

    def as_dict(self) -> dict:
        return asdict(self)


def _typed(exc: BaseException) -> bool:
    """A typed error: symgen's own, or the generated code's ``SingularSolveError`` and
    ``NonFiniteOutputError`` (classes of each generated module, so known by name)."""
    return isinstance(exc, SymgenError) or type(exc).__name__ in ("SingularSolveError", "NonFiniteOutputError")


def _describe(exc: BaseException) -> str:
    return f"{type(exc).__name__}: {exc}"


def evaluate(case: Case, backend: str = "c") -> CaseResult:
    """Steps 1-4 for ``case`` (no integration)."""
    from ..codegen.generate import trace_all
    from ..codegen.runtime import load_generated

    backend = case.backend or backend
    result = CaseResult(case.name, case.kind, case.description, case.expect, case.reference, backend)
    setup = case.setup
    result.conditions = conditions(setup.model, setup.config)
    worst = max(result.conditions.values())
    result.tolerance = tolerance(worst)
    lowered = trace_all(setup.model, FUNCTIONS, {"method": case.method})
    module = load_generated(setup.model, backend, lowered=lowered)
    try:
        state = setup.state()
        result.residual = eom_residual(module, state)
        result.error = reference_error(setup.model, module, state, reference=case.reference)
    except Exception as exc:  # noqa: BLE001 - sorted into typed and untyped below
        if not _typed(exc):
            raise
        result.status, result.message = "error", _describe(exc)
        return result
    finite = np.isfinite(result.residual) and np.isfinite(result.error)
    good = finite and result.residual <= result.tolerance and result.error <= result.tolerance
    result.status = "accurate" if good else "inaccurate"
    if worst > WARN_CONDITION:
        result.message = f"ill-conditioned: condition number {worst:.3g}; answer good to about {result.tolerance:.1g}"
        warnings.warn(IllConditionedWarning(f"{case.name}: {result.message}"), stacklevel=2)
    return result


def _run(case: Case, method: str, backend: str) -> tuple[RunResult, np.ndarray | None]:
    from ..simulation import StateLayout, simulate

    setup, backend = case.setup, case.backend or backend
    settings = dict(METHODS[method])
    if "steps" in settings:
        settings = {"step": case.t_end / settings.pop("steps")}
    x0 = StateLayout(setup.model).initial_state(setup.config, setup.V_m)
    tau = setup.tau
    try:
        traj = simulate(setup.model, case.t_end, method, backend=backend, x0=x0, tau=lambda t, q, v: tau,
                        eta_m=setup.eta_m, energy=False, max_rhs_calls=MAX_RHS_CALLS, **settings)
    except Exception as exc:  # noqa: BLE001
        if not _typed(exc):
            raise
        return RunResult(method, False, message=_describe(exc)), None
    final = traj.final_state
    if not np.all(np.isfinite(final)):
        return RunResult(method, False, traj.rhs_calls, traj.wall_time, message="non-finite final state"), None
    return RunResult(method, True, traj.rhs_calls, traj.wall_time), final


def integrate(case: Case, backend: str = "c", methods=None) -> list[RunResult]:
    """Step 5: a run of ``case.t_end`` with each method; differences taken against Radau's run."""
    runs, finals = [], {}
    for method in methods or METHODS:
        run, final = _run(case, method, backend)
        runs.append(run)
        if final is not None:
            finals[method] = final
    if "Radau" in finals:
        for run in runs:
            if run.method in finals:
                run.difference = float(np.max(np.abs(finals[run.method] - finals["Radau"])))
    return runs


def run_case(case: Case, backend: str = "c", integrators: bool = True) -> CaseResult:
    """Evaluate ``case`` and, unless its state is refused, integrate it."""
    result = evaluate(case, backend)
    if integrators and result.status != "error":
        result.runs = integrate(case, backend)
    return result
