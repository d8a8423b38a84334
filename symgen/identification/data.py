"""Measured samples for identification: the CSV format, its checks, and simulated data.

One row per sample, a header naming the columns (any order; other columns such as ``t`` are
ignored). With ``<c>`` the independent coordinates of ``qd`` (eq. 14, ``symgen info SCENE``):

=====================  =======================================================================
``q_<joint>``          position of every joint of ``qd`` (required); of a dependent joint
                       (``q_u1``, eq. 8) optional -- missing ones are found by closing the loops
``qd_<c>``, ``qdd_<c>``  rates and accelerations of the independent coordinates (required)
``tau_<c>``            joint forces on the independent coordinates (required)
``eta_f_<k>``          ``k = 0 .. n-m-1``: the constraint forces of model (32), all or none;
                       when absent they are not measured and the rows are projected (``Omega^T``)
``eta_m_<component>``  the contact forces of eq. (16) (``eta_m_vx``), all or none; when absent
                       the contact law's ``P_m`` is identified
=====================  =======================================================================

Positions in rad or m, forces in N or N m. Rows are numbered from 1 (the header excluded).
"""
from __future__ import annotations

import csv
from dataclasses import dataclass

import numpy as np

from ..control.contact import ContactLaw
from ..scene.input_limits import MAX_EXPONENT
from .errors import (DataColumnError, DataFileError, NonFiniteSampleError, OptionError, SampleRangeError,
                     TooFewSamplesError)
from .states import State, close_configuration


@dataclass(frozen=True)
class Samples:
    """Columns by name (float arrays of equal length)."""

    columns: dict

    def __len__(self) -> int:
        return len(next(iter(self.columns.values()))) if self.columns else 0

    def block(self, names) -> np.ndarray:
        return np.column_stack([self.columns[n] for n in names]) if names else np.zeros((len(self), 0))


def column_names(model) -> dict[str, list[str]]:
    """The columns a scene's data use, by group (module docstring)."""
    coords = model.coordinate_names()
    part = model.partition
    dependent = [model.tree.coordinates[c].joint for c in part.u1]
    out = {"q": [f"q_{c}" for c in coords], "q_dependent": [f"q_{j}" for j in dependent],
           "qd": [f"qd_{c}" for c in coords], "qdd": [f"qdd_{c}" for c in coords],
           "tau": [f"tau_{c}" for c in coords],
           "eta_f": [f"eta_f_{k}" for k in range(model.counts.n - model.counts.m)],
           "eta_m": [f"eta_m_{c}" for c in (model.scene.contact_forces.components if model.scene.contact_forces
                                             else ())]}
    return out


#: prefixes of the columns a scene's data use; other columns (``t``, notes) are ignored unread
DATA_PREFIXES = ("q_", "qd_", "qdd_", "tau_", "eta_f_", "eta_m_")
#: data rows a file may hold (a 100,000-row log is ordinary; the stacked regressor has its own
#: limit, :data:`symgen.identification.batch.MAX_ENTRIES`)
MAX_SAMPLES = 2_000_000
#: rows converted to numbers at a time (the text of only this many rows is held at once)
READ_CHUNK = 20_000
#: a sample's magnitude above this is refused (rad, m, N, N m; the scene readers' limit,
#: :data:`symgen.scene.input_limits.MAX_EXPONENT`): the regressor multiplies rates and accelerations
SAMPLE_LIMIT = 10.0 ** MAX_EXPONENT


def read_csv(path) -> Samples:
    """The data columns (:data:`DATA_PREFIXES`) of a CSV file as floats (UTF-8, a byte-order mark
    allowed, blank lines skipped). Typed errors name the file (:class:`DataFileError`: missing,
    not UTF-8 text, a malformed line, more than :data:`MAX_SAMPLES` rows), a duplicated column or
    a row of the wrong length, or a cell that is not a number -- its column and row
    (:class:`DataColumnError`)."""
    try:
        with open(path, newline="", encoding="utf-8-sig") as handle:
            reader = csv.reader(handle)
            try:
                return _read(reader, path)
            except csv.Error as exc:
                raise DataFileError(path, f"line {reader.line_num}: {exc}") from None
    except UnicodeDecodeError as exc:
        raise DataFileError(path, f"is not UTF-8 text (byte 0x{exc.object[exc.start]:02x}); save it as UTF-8") \
            from None
    except OSError as exc:
        raise DataFileError(path, f"cannot be read: {exc.strerror or exc}") from None


def _header(reader, path) -> list[str]:
    """The first non-blank row, stripped; a duplicated name is refused with both positions."""
    header = next((row for row in reader if row), None)
    if header is None:
        raise DataColumnError("(header)", f"{path}: empty file, expected a header row")
    header = [h.strip() for h in header]
    seen: dict[str, int] = {}
    for k, h in enumerate(header):
        if h in seen:
            raise DataColumnError(h, f"appears twice in the header (fields {seen[h] + 1} and {k + 1})")
        seen[h] = k
    return header


def _read(reader, path) -> Samples:
    """Rows after the header, converted :data:`READ_CHUNK` rows at a time."""
    header = _header(reader, path)
    used = [(k, h) for k, h in enumerate(header) if h.startswith(DATA_PREFIXES)]
    parts: dict[str, list[np.ndarray]] = {h: [] for _, h in used}
    chunk, done = [], 0
    for row in reader:
        if not row:
            continue
        if len(row) != len(header):
            raise DataColumnError("(row)", f"row {done + len(chunk) + 1} has {len(row)} fields, the header has "
                                           f"{len(header)}")
        chunk.append(row)
        if len(chunk) == READ_CHUNK:
            done = _convert(chunk, used, parts, done)
            chunk = []
            if done > MAX_SAMPLES:
                raise DataFileError(path, f"more than {MAX_SAMPLES} data rows; decimate the log or split it")
    done = _convert(chunk, used, parts, done)
    if done > MAX_SAMPLES:
        raise DataFileError(path, f"more than {MAX_SAMPLES} data rows; decimate the log or split it")
    return Samples({h: np.concatenate(parts[h]) if parts[h] else np.zeros(0) for _, h in used})


def _convert(chunk: list, used, parts: dict, done: int) -> int:
    """Append the used columns of ``chunk`` (rows ``done + 1 ..``) to ``parts``; the new row count."""
    if chunk:
        fields = list(zip(*chunk))
        for k, h in used:
            parts[h].append(_numbers(h, fields[k], done))
    return done + len(chunk)


def _numbers(column: str, cells, offset: int = 0) -> np.ndarray:
    """The cells of one column as floats (Python's ``float`` syntax); the first cell that is not a
    number is a :class:`DataColumnError` naming the column and the row (``offset`` rows before)."""
    try:
        return np.fromiter(map(float, cells), dtype=float, count=len(cells))
    except ValueError:
        for i, cell in enumerate(cells, start=offset + 1):
            try:
                float(cell)
            except ValueError:
                raise DataColumnError(column, f"row {i}: {cell[:40]!r} is not a number") from None
        raise


def write_csv(path, samples: Samples) -> None:
    with open(path, "w", newline="", encoding="utf-8") as handle:
        w = csv.writer(handle)
        names = list(samples.columns)
        w.writerow(names)
        for k in range(len(samples)):
            w.writerow([repr(float(samples.columns[n][k])) for n in names])


def _foreign_columns(model, samples: Samples, names: dict) -> None:
    """A data column (:data:`DATA_PREFIXES`) the scene does not have: the file is another robot's
    data or has a typo -- refused, naming the column and what the scene expects."""
    known = {c for group in names.values() for c in group}
    for col in samples.columns:
        if col.startswith(DATA_PREFIXES) and col not in known:
            joints = [c[2:] for c in names["q"] + names["q_dependent"]]
            raise DataColumnError(col, f"names no joint, coordinate or force of scene {model.scene.name!r} "
                                       f"(joints {', '.join(joints)}; qd: {', '.join(model.coordinate_names())}); "
                                       "is this another robot's data?")


def _check_values(samples: Samples, wanted) -> None:
    """NaN, infinity or a magnitude above :data:`SAMPLE_LIMIT` in a used column: the first one, by row."""
    for col in wanted:
        if col not in samples.columns:
            continue
        values = samples.columns[col]
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            raise NonFiniteSampleError(int(bad[0]) + 1, col, float(values[bad[0]]))
        big = np.flatnonzero(np.abs(values) > SAMPLE_LIMIT)
        if big.size:
            raise SampleRangeError(int(big[0]) + 1, col, float(values[big[0]]), SAMPLE_LIMIT)


def check_samples(model, samples: Samples, *, used=None) -> dict[str, bool]:
    """Raise the typed error of the first problem; returns which optional groups are present.

    In order: a data column the scene does not have, a missing required column, a partial group
    of ``eta_f``/``eta_m`` columns, no data rows, then per used column a non-finite value or
    one beyond :data:`SAMPLE_LIMIT` (row and column named)."""
    names = column_names(model)
    _foreign_columns(model, samples, names)
    for col in names["q"] + names["qd"] + names["qdd"] + names["tau"]:
        if col not in samples.columns:
            raise DataColumnError(col, f"missing; scene {model.scene.name!r} needs q_, qd_, qdd_, tau_ columns for "
                                       f"{', '.join(model.coordinate_names())}")
    present = {}
    for group in ("eta_f", "eta_m"):
        have = [c for c in names[group] if c in samples.columns]
        if have and len(have) != len(names[group]):
            missing = next(c for c in names[group] if c not in samples.columns)
            raise DataColumnError(missing, f"missing: give all of {', '.join(names[group])} or none")
        present[group] = bool(names[group]) and bool(have)
    if len(samples) == 0:
        raise TooFewSamplesError("data rows", 0, 1, "the file holds a header only")
    wanted = names["q"] + names["q_dependent"] + names["qd"] + names["qdd"] + names["tau"] \
        + (names["eta_f"] if present["eta_f"] else []) + (names["eta_m"] if present["eta_m"] else [])
    _check_values(samples, wanted)
    return present


def states_from_samples(model, samples: Samples) -> list[State]:
    """The samples' states, dependent positions closed by continuation from the reference."""
    names = column_names(model)
    q, qd, qdd = samples.block(names["q"]), samples.block(names["qd"]), samples.block(names["qdd"])
    joints = [n[2:] for n in names["q"]]
    dep = [n for n in names["q_dependent"] if n in samples.columns]
    guess, out = model.reference, []
    for k in range(len(samples)):
        pos = dict(zip(joints, q[k]))
        pos.update({n[2:]: samples.columns[n][k] for n in dep})
        config = close_configuration(model, pos, guess)
        out.append(State(config, qd[k], qdd[k]))
        guess = config
    return out


def simulated_samples(problem, states, *, noise: float = 0.0, seed: int = 0, eta_f=None,
                      law: ContactLaw | None = None, dependent: bool = True, eta_m_columns: bool = False) -> Samples:
    """Samples at ``states`` with the joint forces of the scene's inverse dynamics (its parameters
    are the truth), contact forces of ``law`` (not written: unmeasured), constraint forces
    ``eta_f`` (a function ``k -> eta_f`` or None for zero; written as columns), and Gaussian noise
    of standard deviation ``noise`` (N or N m) added to every ``tau``. ``eta_m_columns``: write the
    contact forces too (measured). ``dependent``: write the
    dependent joints' positions too (needed when successive states are not close, e.g. random
    states, where closing the loops by continuation could land in another assembly mode)."""
    from .regressor import true_forces

    if not (isinstance(noise, (int, float, np.floating)) and 0 <= noise <= SAMPLE_LIMIT):
        raise OptionError("noise", f"{noise!r}: give a finite standard deviation >= 0 and <= {SAMPLE_LIMIT:g}")
    model = problem.model
    names = column_names(model)
    rng = np.random.default_rng(seed)
    q_names = names["q"] + (names["q_dependent"] if dependent else [])
    cols = {n: [] for n in q_names + names["qd"] + names["qdd"] + names["tau"]
            + (names["eta_f"] if eta_f is not None else []) + (names["eta_m"] if eta_m_columns else [])}
    joints = [n[2:] for n in q_names]
    for k, s in enumerate(states):
        ef = None if eta_f is None else np.asarray(eta_f(k), float)
        tau, eta_m = true_forces(problem, s, eta_f=ef, law=law)
        tau = tau + noise * rng.normal(size=tau.shape)
        pos = s.config.as_float().positions
        for j, n in zip(joints, q_names):
            cols[n].append(float(pos[j]))
        for group, values in (("qd", s.qd), ("qdd", s.qdd), ("tau", tau)):
            for n, v in zip(names[group], values):
                cols[n].append(float(v))
        if ef is not None:
            for n, v in zip(names["eta_f"], ef):
                cols[n].append(float(v))
        if eta_m_columns:
            for n, v in zip(names["eta_m"], eta_m):
                cols[n].append(float(v))
    return Samples({n: np.array(v, float) for n, v in cols.items()})
