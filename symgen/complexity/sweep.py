"""A sweep: every method at every size, each (method, size) in its own time-limited subprocess.

Once a stage of a method runs out of time (or fails) at some size, that stage and the ones after
it are not attempted at larger sizes: they are recorded as ``skipped`` (the tables print them as
"> limit", like the timeout itself), never dropped.

Families and methods:

* ``chain`` (``chain:n=N``): ``symgen:inverse_dynamics``, ``symgen:mass_matrix``,
  ``symgen:forward_dynamics`` (this formulation's generated functions), ``kane``, ``lagrange``
  (``sympy.physics.mechanics`` on the same robot);
* ``multi_arm`` (``multi_arm:h=H``, 6H DOF): ``symgen:inverse_dynamics``,
  ``symgen:task_inverse_dynamics``.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from ..errors import SymgenError
from .measure import ERROR, NOT_REACHED, OK, TIMEOUT, Outcome, measure
from .tasks import stages_of

SKIPPED = "skipped"
DEFAULT_SIZES = {"chain": (1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64, 100), "multi_arm": (1, 2, 3, 4, 5, 6, 7, 8)}
SYMGEN_FUNCTIONS = {"chain": ("inverse_dynamics", "mass_matrix", "forward_dynamics"),
                    "multi_arm": ("inverse_dynamics", "task_inverse_dynamics")}
SYMPY_METHODS = ("kane", "lagrange")
SIZE_KEY = {"chain": "n", "multi_arm": "h"}


@dataclass
class Sweep:
    """Outcomes of a family's sweep: ``cells[(method, size)]`` is an :class:`Outcome`."""

    family: str
    sizes: list
    methods: list
    time_limit: float
    cells: dict = field(default_factory=dict)
    causes: dict = field(default_factory=dict)   # (method, stage) -> (status, size) that dropped it

    def display(self, method: str, size: int, stage: str) -> str:
        """``ok``, ``limit`` (ran out of time here, or at a smaller size) or ``error``."""
        cell = self.cells[(method, size)]
        for name in method_stages(method):
            status = cell.status(name)
            if status == SKIPPED:
                status = self.causes[(method, name)][0]
            if status in (TIMEOUT, ERROR):
                return "limit" if status == TIMEOUT else "error"
            if name == stage:
                return "ok"
        raise KeyError(stage)

    def status(self, method: str, size: int, stage: str) -> str:
        return self.cells[(method, size)].status(stage)

    def record(self, method: str, size: int, stage: str) -> dict:
        return self.cells[(method, size)].record(stage)

    def ops(self, method: str, size: int, stage: str) -> dict | None:
        """The op counts of ``stage`` if it finished, else None."""
        if self.status(method, size, stage) != OK:
            return None
        return self.record(method, size, stage)["ops"]


def dof(family: str, size: int) -> int:
    """Degrees of freedom of ``family`` at ``size`` (``chain:n=N``: N; ``multi_arm:h=H``: 6H)."""
    return size if family == "chain" else 6 * size


def methods_for(family: str, chosen=("symgen", "kane", "lagrange")) -> list[str]:
    """Sweep methods for the user's choice (``symgen`` expands to the family's functions)."""
    if family not in SIZE_KEY:
        raise SymgenError(f"unknown family {family!r}; choose chain or multi_arm")
    out = []
    for name in chosen:
        if name == "symgen":
            out += [f"symgen:{fn}" for fn in SYMGEN_FUNCTIONS[family]]
        elif name in SYMPY_METHODS:
            if family != "chain":
                raise SymgenError(f"method {name!r} is only measured on the chain family")
            out.append(name)
        else:
            raise SymgenError(f"unknown method {name!r}; choose from symgen, kane, lagrange")
    return out


def method_stages(method: str) -> tuple[str, ...]:
    return stages_of(method.split(":")[0])


def task_for(family: str, method: str, size: int) -> dict:
    spec = f"{family}:{SIZE_KEY[family]}={size}"
    if method.startswith("symgen:"):
        return {"method": "symgen", "spec": spec, "function": method.split(":", 1)[1]}
    return {"method": method, "spec": spec, "n": size}


def run_sweep(family: str, sizes, methods, time_limit: float, progress=None) -> Sweep:
    """Measure every method at every size (sizes ascending), skipping what exceeded earlier."""
    sweep = Sweep(family, sorted(set(sizes)), list(methods), time_limit)
    dropped = {m: len(method_stages(m)) for m in methods}   # first stage index not attempted any more
    for size in sweep.sizes:
        for method in methods:
            stages = method_stages(method)
            attempt = stages[:dropped[method]]
            outcome = measure(task_for(family, method, size), attempt, time_limit) if attempt else \
                Outcome(task_for(family, method, size))
            for i, stage in enumerate(stages):
                if stage not in outcome.stages:
                    outcome.stages[stage] = (SKIPPED, {})
                elif outcome.status(stage) in (TIMEOUT, ERROR):
                    dropped[method] = min(dropped[method], i)
                    for later in stages[i:]:
                        sweep.causes.setdefault((method, later), (outcome.status(stage), size))
            sweep.cells[(method, size)] = outcome
            if progress:
                progress(method, size, outcome)
    return sweep


__all__ = ["DEFAULT_SIZES", "ERROR", "NOT_REACHED", "OK", "SKIPPED", "Sweep", "dof", "methods_for",
           "run_sweep", "task_for"]
