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
from pathlib import Path

import numpy as np

from ..control.contact import ContactLaw
from .errors import DataColumnError, NonFiniteSampleError
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


def read_csv(path) -> Samples:
    """Columns of a CSV file as floats; a cell that is not a number raises :class:`DataColumnError`."""
    with open(path, newline="", encoding="utf-8") as handle:
        rows = list(csv.reader(handle))
    if not rows:
        raise DataColumnError("(header)", f"{path}: empty file, expected a header row")
    header = [h.strip() for h in rows[0]]
    cols = {h: [] for h in header}
    for i, row in enumerate(rows[1:], start=1):
        if len(row) != len(header):
            raise DataColumnError("(row)", f"row {i} has {len(row)} fields, the header has {len(header)}")
        for h, cell in zip(header, row):
            try:
                cols[h].append(float(cell))
            except ValueError:
                raise DataColumnError(h, f"row {i}: {cell!r} is not a number") from None
    return Samples({h: np.array(v, float) for h, v in cols.items()})


def write_csv(path, samples: Samples) -> None:
    with open(path, "w", newline="", encoding="utf-8") as handle:
        w = csv.writer(handle)
        names = list(samples.columns)
        w.writerow(names)
        for k in range(len(samples)):
            w.writerow([repr(float(samples.columns[n][k])) for n in names])


def check_samples(model, samples: Samples, *, used=None) -> dict[str, bool]:
    """Raise the typed error of the first problem; returns which optional groups are present."""
    names = column_names(model)
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
    wanted = names["q"] + names["q_dependent"] + names["qd"] + names["qdd"] + names["tau"] \
        + (names["eta_f"] if present["eta_f"] else []) + (names["eta_m"] if present["eta_m"] else [])
    for col in wanted:
        if col not in samples.columns:
            continue
        values = samples.columns[col]
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            raise NonFiniteSampleError(int(bad[0]) + 1, col, float(values[bad[0]]))
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
