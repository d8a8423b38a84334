"""The table of ``symgen accuracy SCENE``: error against an extended-precision reference and
per-call time, for every generated function and every implementation.

For each function and backend -- the generated NumPy module, the generated C (ctypes binding),
``sympy.lambdify`` of the dense symbolic model and the dense float model (32) -- over ``K``
random loop-closed states (:func:`symgen.codegen.reference.reference_states`):

* the normwise relative error ``|got - ref|_inf / max(|ref|_inf, floor)`` of every output,
  against the unrounded mpmath reference of :mod:`symgen.accuracy.reference` (``dps`` digits) --
  the largest over the function's outputs at one state, then the max and median over states.
  The floor (default 1e-2, as the equivalence tests use) keeps an output that is zero in exact
  arithmetic (``C`` of a parallelogram, ``G`` of a planar mechanism under vertical gravity) from
  dividing rounding noise by nothing; outputs whose reference norm fell below it are listed, their
  figure is an absolute error;
* the time per call: the median of :data:`~symgen.accuracy.backends.ROUNDS` timed rounds, each
  calling once per state (``time.perf_counter``).
"""
from __future__ import annotations

import csv
import os
import statistics
import time
from dataclasses import asdict, dataclass, field

from ..codegen.targets import TARGETS
from . import AccuracyError
from .backends import ROUNDS, dense_float_backend, generated_backend, run_backend
from .lambdify import DEFAULT_TIMEOUT, run_lambdify
from .reference import REFERENCE_FUNCTIONS, MpState, check_dps, make_mp_field, relative_error

#: denominator floor of the relative error (units of the output)
FLOOR = 1e-2
#: the generated targets, then the references
BACKENDS = TARGETS + ("lambdify", "dense float")


@dataclass
class Row:
    """One function on one backend; ``note`` says why a backend was not measured."""

    function: str
    backend: str
    max_error: float | None = None
    median_error: float | None = None
    seconds: float | None = None
    note: str = ""


@dataclass
class AccuracyReport:
    spec: str
    scene: str
    counts: dict
    states: int
    seed: int
    dps: int
    floor: float
    rounds: int
    mp_seconds: float                       # extended-precision reference, per state, all functions
    rows: list[Row] = field(default_factory=list)
    below_floor: list[str] = field(default_factory=list)   # "function.output" with |ref| < floor somewhere
    details: list[str] = field(default_factory=list)       # full reasons behind "n/a" cells

    def as_dict(self) -> dict:
        return asdict(self)


#: most states and reference digits of one report (each state is an O(n^3) solve at dps digits)
MAX_STATES = 2000
MAX_DPS = 1000


def check_request(states: int, dps: int, functions, floor: float = FLOOR) -> list[str]:
    """Typed errors for a request the report cannot honour; returns the function list."""
    from ..codegen.catalogue import FUNCTIONS

    if isinstance(states, bool) or not isinstance(states, int) or not 1 <= states <= MAX_STATES:
        raise AccuracyError(f"--states must be an integer from 1 to {MAX_STATES}, got {states!r}")
    if not floor > 0 or floor == float("inf"):
        raise AccuracyError(f"--floor must be a positive finite number, got {floor!r}")
    check_dps(dps)
    if dps > MAX_DPS:
        raise AccuracyError(f"--dps must be at most {MAX_DPS} (the reference's cost grows with its digits), got {dps}")
    names = list(functions) if functions else [f for f in FUNCTIONS if f in REFERENCE_FUNCTIONS]
    for name in names:
        if name not in FUNCTIONS or name not in REFERENCE_FUNCTIONS:
            raise AccuracyError(f"unknown function {name!r}; choose from "
                                f"{', '.join(f for f in FUNCTIONS if f in REFERENCE_FUNCTIONS)}")
    return names


def _load_modules(model, names):
    """``{backend: module or 'n/a: reason'}`` for the generated NumPy and C code."""
    from ..codegen.generate import trace_all
    from ..codegen.runtime import load_generated

    lowered = trace_all(model, names)
    out = {}
    for target in TARGETS:
        try:
            out[target] = load_generated(model, target, names, lowered=lowered)
        except Exception as exc:  # noqa: BLE001 - e.g. no C compiler: the column says why
            out[target] = f"n/a: {target} build failed ({type(exc).__name__}: {str(exc).splitlines()[0][:80]})"
    return out


def _errors(reference: list[dict], outputs: list, field, floor: float) -> tuple[float, float]:
    per_state = [max((relative_error(got, want, field, floor) for got, want in zip(outs, ref.values())), default=0.0)
                 for outs, ref in zip(outputs, reference)]
    return max(per_state), statistics.median(per_state)


def accuracy_report(spec: str, *, states: int = 20, seed: int = 0, dps: int = 50, functions=None,
                    lambdify_timeout: float = DEFAULT_TIMEOUT, floor: float = FLOOR,
                    rounds: int = ROUNDS) -> AccuracyReport:
    """Measure every requested function on every backend (see the module docstring)."""
    from ..io.loading import load
    from ..codegen.reference import reference_states
    from ..model import derive

    names = check_request(states, dps, functions, floor)
    spec = os.path.abspath(spec) if os.path.exists(spec) else spec
    model = derive(load(spec))
    field_ = make_mp_field(model, dps)
    sample = reference_states(model, states, seed=seed)
    start = time.perf_counter()
    mp_states = [MpState(model, s, field_) for s in sample]
    reference = {name: [st.outputs(name) for st in mp_states] for name in names}
    mp_seconds = (time.perf_counter() - start) / states
    report = AccuracyReport(spec, model.scene.name, model.counts.as_dict(), states, seed, dps, floor, rounds, mp_seconds)
    for name in names:
        for key in reference[name][0]:
            sizes = [float(max((abs(v) for v in ref[key].flat), default=0)) for ref in reference[name]]
            if min(sizes) < floor:
                report.below_floor.append(f"{name}.{key} ({min(sizes):.1e}..{max(sizes):.1e})")
    modules = _load_modules(model, names)
    lam = run_lambdify(spec, names, sample, timeout=lambdify_timeout, rounds=rounds)
    reasons: dict[str, list[str]] = {}
    for name in names:
        for backend in BACKENDS:
            row = Row(name, backend)
            if backend in TARGETS and isinstance(modules[backend], str):
                row.note = modules[backend]
            elif backend == "lambdify":
                result = lam[name]
                if result["status"] != "ok":
                    row.note = result["status"]
                    if result.get("detail"):
                        reasons.setdefault(result["detail"], []).append(name)
                else:
                    row.max_error, row.median_error = _errors(reference[name], result["outputs"], field_, floor)
                    row.seconds = result["seconds"]
            else:
                impl = (dense_float_backend(model, name) if backend == "dense float"
                        else generated_backend(backend, modules[backend], name))
                outputs, row.seconds = run_backend(impl, sample, rounds)
                row.max_error, row.median_error = _errors(reference[name], outputs, field_, floor)
            report.rows.append(row)
    report.details = [f"lambdify ({'every function' if fns == names else ', '.join(fns)}): {why}"
                      for why, fns in reasons.items()]
    return report


# ---------------------------------------------------------------- rendering
def fmt_error(value) -> str:
    return "" if value is None else "0" if value == 0 else f"{value:.1e}"


def fmt_time(seconds) -> str:
    if seconds is None:
        return ""
    us = seconds * 1e6
    return f"{us:.3g} us" if us < 1000 else f"{us / 1000:.3g} ms" if us < 1e6 else f"{seconds:.3g} s"


def header_lines(r: AccuracyReport) -> list[str]:
    counts = ", ".join(f"{k}={v}" for k, v in r.counts.items() if k in ("n", "m", "nc"))
    return [f"symgen accuracy: scene {r.scene} ({counts}), {r.states} random loop-closed state(s), seed {r.seed}",
            f"reference: dense model (32) in mpmath at {r.dps} digits, float inputs taken exactly "
            f"({fmt_time(r.mp_seconds)} per state for all functions)",
            f"error: normwise relative |got - ref|_inf / max(|ref|_inf, {r.floor:g}) against the unrounded reference, "
            "largest over the outputs; max and median over the states",
            f"time: per call, median of {r.rounds} timed rounds of one call per state (time.perf_counter); "
            "numpy = generated NumPy module, c = generated C via ctypes, lambdify = sympy.lambdify of the "
            "dense symbolic model, dense float = Model.evaluate in float64"]


def footer_lines(r: AccuracyReport) -> list[str]:
    out = []
    if r.below_floor:
        out.append(f"outputs with |ref|_inf < {r.floor:g} at some state, where the figure is an absolute error "
                   "(range of |ref|_inf over the states): " + ", ".join(r.below_floor))
    out += r.details
    return out


def format_text(r: AccuracyReport) -> str:
    """The printed table; a backend that was not measured shows its reason across the columns."""
    cols = ("function", "backend", "max rel. error", "median rel. error", "time/call")
    body = [(row.function, row.backend, fmt_error(row.max_error), fmt_error(row.median_error), fmt_time(row.seconds),
             row.note) for row in r.rows]
    widths = [max([len(c)] + [len(b[i]) for b in body]) for i, c in enumerate(cols)]

    def line(cells):
        return "  ".join(c.ljust(w) if i < 2 else c.rjust(w) for i, (c, w) in enumerate(zip(cells, widths))).rstrip()

    rows = [line(b[:2]) + "  " + b[5] if b[5] else line(b[:5]) for b in body]
    notes = footer_lines(r)
    return "\n".join(header_lines(r) + ["", line(cols), line(["-" * w for w in widths])] + rows
                     + ([""] + notes if notes else [])) + "\n"


def markdown(r: AccuracyReport) -> str:
    lines = [f"# Accuracy of the generated functions: `{r.scene}`", ""] + [f"* {h}" for h in header_lines(r)] + [
        "", "| function | backend | max rel. error | median rel. error | time per call |", "|---|---|---|---|---|"]
    for row in r.rows:
        err = fmt_error(row.max_error) or row.note
        lines.append(f"| `{row.function}` | {row.backend} | {err} | {fmt_error(row.median_error)} | "
                     f"{fmt_time(row.seconds)} |")
    notes = footer_lines(r)
    return "\n".join(lines + ([""] + [f"* {n}" for n in notes] if notes else [])) + "\n"


def write_csv(r: AccuracyReport, path) -> None:
    with open(path, "w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(["scene", "function", "backend", "max_rel_error", "median_rel_error", "seconds_per_call",
                         "note", "states", "seed", "dps", "floor"])
        for row in r.rows:
            writer.writerow([r.scene, row.function, row.backend, _num(row.max_error), _num(row.median_error),
                             _num(row.seconds), row.note, r.states, r.seed, r.dps, r.floor])


def _num(value) -> str:
    return "" if value is None else repr(float(value))
