"""The identification rows of many samples at once: one generated NumPy function, batched.

:func:`~symgen.identification.regressor.sample_rows` evaluates the dense model once per sample (5
to 20 ms each), so a log of 100,000 samples would take 10 to 30 minutes. Here the rows are traced once per
scene and problem into a function of the code generator (:mod:`symgen.codegen`), composed from the
controller's own recursions (:mod:`symgen.control.recursive`, :mod:`symgen.codegen.vdc_trace`), and the
NumPy target evaluates it over every sample in one batched call::

    identification_rows(q, qd, qdd, tau[, eta_f][, eta_m]) -> (W, y)

With the required motion equal to the actual one (``X_r = X``), row ``i`` of ``Y`` is ``Y^T u_i``
for the unit vector ``u_i`` of space A: the adaptation signal ``s = Y^T e`` of eq. (38) at
``e = u_i`` (per body ``Y_alpha^T (T_S u_i)_alpha``, per joint ``[qdd, qd, sign qd] u_i``, per
contact component ``[v_c, sign v_c] D_m u_i``). The projected rows (``eta_f`` not measured) take
``e = Omega e_j = [J_m; J_f]^-1 [e_j; 0]`` instead, so ``Omega^T Y`` is never formed densely
either. The right-hand side is ``e^T (tau - J_f^T eta_f - D_m^T eta_m)`` with the measured forces.
The dependent rates and accelerations come from eqs. (10)-(11) as in the generated
``inverse_dynamics``.

Cost per sample: ``c`` velocity passes and ``c`` body signals per body (``c`` rows a sample), each
scalar operation a ufunc over a chunk of samples (:mod:`symgen.codegen.targets.numpy`): 1,433
operations on ``chain:n=6``, 1,159 on the UR5, 1,793 on ``arm_on_plane``; 70,000 to 100,000 samples
per second on ``chain:n=6`` and the UR5 here (the trace and import, about 0.3 s, once per process).
"""
from __future__ import annotations

import numpy as np

from ..control.parameters import BODY_QUANTITIES
from .errors import IdentificationError
from .regressor import Problem

#: name of the traced function (and of the generated module's entry point)
FUNCTION = "identification_rows"


def _contact_law(problem: Problem):
    """A stand-in for :class:`~symgen.control.recursive.ControlSpec`: ``_contact`` reads only ``contact``."""
    from types import SimpleNamespace

    return SimpleNamespace(contact=problem.contact)


def _signals(t, problem: Problem, rates, motion, d_m, v_c, e) -> list:
    """``Y^T e`` (one entry per parameter of ``problem.params``, in order) for a direction ``e`` of
    space A (``n`` nodes or numbers): the adaptation signal of eq. (38) at that ``e``."""
    from ..dynamics.algebra import dot
    from ..control.recursive import body_signal, velocity_pass
    from ..codegen.vdc_trace import RequiredRates, _joint_signals

    e_all = t.complete_rates(list(e))
    r = RequiredRates(None, None, list(e), rates[0], e_all, rates[0], rates[1])
    s = _joint_signals(t, r)
    x_e = velocity_pass(t, e_all)
    for k, body in enumerate(t.tree.bodies):
        if not body.massless and motion[k] is not None:
            s.update({f"{q}_{body.name}": v for q, v in zip(BODY_QUANTITIES, body_signal(motion[k], *x_e[k]))})
    if d_m is not None:
        frame = problem.contact.frame
        for comp, row, v in zip(problem.contact.components, d_m, v_c):
            de = dot(row, e)
            s.update({f"b_{comp}_{frame}": v * de, f"c_{comp}_{frame}": t.field.sign(v) * de})
    return [s.get(name, 0) for name in problem.params.names]


def trace_rows(problem: Problem):
    """The traced :data:`FUNCTION` of ``problem`` (module docstring), a
    :class:`~symgen.codegen.builder.Function`."""
    from ..codegen.builder import Builder, eta_m_size
    from ..dynamics.algebra import dot
    from ..control.recursive import required_motion
    from ..codegen.vdc_trace import _contact

    model = problem.model
    b = Builder(model)
    t, n, m = b.t, b.n, b.m
    qd = b.arg("qd", n, "independent joint rates (eq. 14)")
    qdd = b.arg("qdd", n, "independent joint accelerations")
    tau = b.arg("tau", n, "measured joint forces on the independent coordinates")
    eta_f = (b.arg("eta_f", n - m, "measured constraint forces (eq. 12)")
             if problem.eta_f_measured and not problem.projected and n > m else None)
    eta_m = b.arg("eta_m", eta_m_size(model), "measured contact forces (eq. 16)") if problem.eta_m_measured else None
    qd_all = t.complete_rates(qd)
    bias, _ = t.rate_bias(qd_all) if model.partition.u1 else ([0] * model.tree.n_coords, None)
    qdd_all = t.complete_accelerations(qdd, bias)
    motion = required_motion(t, qd_all, qd_all, qdd_all, tuple(t.consts.gravity))
    d_m, v_c = _contact(t, _contact_law(problem), qd)
    rhs = list(tau)
    if eta_f is not None:
        rhs = [x - y for x, y in zip(rhs, t.task_matrix().T @ np.array([0] * m + list(eta_f), dtype=object))]
    if eta_m is not None:
        rhs = [x - y for x, y in zip(rhs, b.contact_term(eta_m))]
    if problem.projected:
        unit = np.array([[int(i == j) for j in range(m)] for i in range(n)], dtype=object)
        directions = t.solve_task(t.task_matrix(), unit).T          # columns of Omega (eq. 18)
    else:
        directions = [[int(i == j) for j in range(n)] for i in range(n)]
    rows = [_signals(t, problem, (qd_all, qdd_all), motion, d_m, v_c, e) for e in directions]
    lhs = [dot(e, rhs) for e in directions]
    return b.finish(FUNCTION, "Identification rows W P = y of every sample (symgen.identification.batch).",
                    [("W", rows, "regressor rows (channels x parameters)"), ("y", lhs, "measured side (channels)")])


#: generated modules already loaded in this process: key -> (model, module)
_LOADED: dict = {}


def _load(problem: Problem):
    """The generated module of ``problem`` (traced on first use; cached per model and problem)."""
    from ..codegen.emit import lower
    from ..codegen.runtime import load_generated

    contact = problem.contact
    key = (id(problem.model), problem.params.names, problem.eta_f_measured, problem.eta_m_measured,
           None if contact is None else (contact.frame, tuple(contact.components)))
    hit = _LOADED.get(key)
    if hit is None or hit[0] is not problem.model:
        if len(_LOADED) >= 8:
            _LOADED.clear()
        hit = _LOADED[key] = (problem.model, load_generated(problem.model, "numpy",
                                                            lowered=[lower(trace_rows(problem))]))
    return hit[1]


#: rows whose dependent positions are closed by Newton one at a time (``q_u1`` columns missing) at
#: most: each costs a few ms of dense evaluation, so a longer log must carry those columns
MAX_CLOSED_ROWS = 5_000
#: entries of the stacked regressor (samples x channels x parameters) at most: 8 bytes each, and
#: least squares holds about three copies
MAX_ENTRIES = 120_000_000


def position_matrix(model, samples) -> np.ndarray:
    """The generated code's ``q`` (one angle or displacement per joint, scene order) of every
    sample: the columns themselves when every joint has one, else the loops closed row by row by
    continuation (:func:`~symgen.identification.data.states_from_samples`), at most
    :data:`MAX_CLOSED_ROWS` rows."""
    from ..codegen.trace import position_layout, position_vector
    from .data import states_from_samples

    joints = [name for name, *_ in position_layout(model)]
    if all(f"q_{j}" in samples.columns for j in joints):
        return np.column_stack([samples.columns[f"q_{j}"] for j in joints]) if joints else np.zeros((len(samples), 0))
    if len(samples) > MAX_CLOSED_ROWS:
        missing = ", ".join(f"q_{j}" for j in joints if f"q_{j}" not in samples.columns)
        raise IdentificationError(f"{len(samples)} rows without the columns {missing}: the loops would be "
                                  f"closed row by row (a few ms each), which is allowed for at most "
                                  f"{MAX_CLOSED_ROWS} rows; add those columns (the dependent joints' positions) "
                                  "or decimate the log")
    return np.array([position_vector(model, s.config) for s in states_from_samples(model, samples)])


def sample_rows_batch(problem: Problem, samples) -> tuple[np.ndarray, np.ndarray]:
    """``(W, y)`` of every sample of a checked table (:func:`~symgen.identification.data.check_samples`):
    ``W`` samples x channels x parameters, ``y`` samples x channels."""
    from .data import column_names

    model, names = problem.model, column_names(problem.model)
    size = len(samples) * len(problem.channels) * len(problem.params)
    if size > MAX_ENTRIES:
        raise IdentificationError(f"{len(samples)} samples x {len(problem.channels)} channels x "
                                  f"{len(problem.params)} parameters = {size} regressor entries, more than the "
                                  f"{MAX_ENTRIES} allowed (about {MAX_ENTRIES * 8 // 10 ** 6} MB); decimate the "
                                  "log or split it")
    eta_f = samples.block(names["eta_f"]) if all(c in samples.columns for c in names["eta_f"]) else None
    eta_m = samples.block(names["eta_m"]) if all(c in samples.columns for c in names["eta_m"]) else None
    return batch_rows(problem, position_matrix(model, samples), samples.block(names["qd"]),
                      samples.block(names["qdd"]), samples.block(names["tau"]), eta_f, eta_m)


def batch_rows(problem: Problem, q, qd, qdd, tau, eta_f=None, eta_m=None) -> tuple[np.ndarray, np.ndarray]:
    """``(W, y)``: ``W`` (samples x channels x parameters) and ``y`` (samples x channels) at the
    rows of ``q`` (generated layout, loops closed), ``qd``, ``qdd``, ``tau`` (and the measured
    ``eta_f``, ``eta_m`` where the problem uses them)."""
    module = _load(problem)
    fn, failures = getattr(module, FUNCTION), (module.SingularSolveError, module.NonFiniteOutputError)
    args = [q, qd, qdd, tau]
    if problem.eta_f_measured and not problem.projected and problem.model.counts.n > problem.model.counts.m:
        args.append(eta_f)
    if problem.eta_m_measured:
        args.append(eta_m)
    args = [np.asarray(a, float) for a in args]
    try:
        with np.errstate(all="ignore"):                  # an overflow becomes the typed error below
            w, y = fn(*args)
    except failures as exc:
        raise IdentificationError(f"sample {_first_bad(fn, args, failures)}: {exc}") from None
    return w, y


def _first_bad(fn, args, failures) -> int:
    """The first sample (counted from 1) on which ``fn`` raises, by bisection."""
    lo, hi = 0, len(args[0])
    while hi - lo > 1:
        mid = (lo + hi) // 2
        try:
            with np.errstate(all="ignore"):
                fn(*(a[lo:mid] for a in args))
        except failures:
            hi = mid
            continue
        lo = mid
    return lo + 1
