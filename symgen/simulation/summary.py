"""Which integrator and backend reaches a given final-state error fastest: read back from the
CSV of work-precision reports (:mod:`symgen.simulation.report`), never interpolated.

For a threshold ``e``, :func:`fastest_to` picks, among the runs whose *measured* error is at most
``e`` (status ``ok``), the one of least wall time; ties go to fewer right-hand-side calls. No run
below ``e``: the threshold is *not reached*. A threshold below the study's noise floor (ten times
the reference's own difference, :class:`~symgen.simulation.study.Study`) cannot be resolved by the
reference, so it is reported as *below the noise floor* whatever the runs measured.

>>> rows = [dict(backend="c", method="rk4", kind="step", setting="0.01", error="2e-7",
...              wall_time="0.5", rhs_calls="800", status="ok"),
...         dict(backend="c", method="DOP853", kind="tol", setting="1e-08", error="4e-9",
...              wall_time="0.1", rhs_calls="266", status="ok")]
>>> fastest_to(read_rows(rows), 1e-6).run.method
'DOP853'
>>> fastest_to(read_rows(rows), 1e-12).verdict
'not reached'
"""
from __future__ import annotations

import csv
import json
import pathlib
from dataclasses import dataclass

import numpy as np

from .errors import SimulationInputError

#: the error thresholds of the summary table
THRESHOLDS = (1e-6, 1e-9, 1e-12)
REACHED, NOT_REACHED, BELOW_FLOOR = "reached", "not reached", "below the noise floor"


@dataclass(frozen=True)
class Run:
    """One row of a work-precision CSV, typed."""

    backend: str
    method: str
    kind: str
    setting: float
    error: float
    wall_time: float
    rhs_calls: int
    status: str

    @property
    def label(self) -> str:
        return f"{self.method} ({self.backend}), {self.kind} {self.setting:g}"


@dataclass(frozen=True)
class Fastest:
    """The answer for one threshold: ``run`` is ``None`` unless ``verdict`` is ``reached``."""

    threshold: float
    verdict: str
    run: Run | None = None


def read_rows(rows) -> list[Run]:
    """Typed :class:`Run` objects from CSV dictionaries (columns of ``report.COLUMNS``)."""
    out = []
    for i, r in enumerate(rows):
        try:
            out.append(Run(r["backend"], r["method"], r["kind"], float(r["setting"]),
                           float(r["error"]) if r["error"] not in ("", "nan") else float("nan"),
                           float(r["wall_time"]) if r["wall_time"] not in ("", "nan") else float("nan"),
                           int(r["rhs_calls"]), r["status"]))
        except (KeyError, ValueError) as exc:
            raise SimulationInputError(f"work-precision row {i + 1} is malformed: {exc}") from None
    return out


def read_csv(path) -> list[Run]:
    """The runs of one ``work_precision.csv``."""
    with open(path, newline="", encoding="utf-8") as fh:
        return read_rows(csv.DictReader(fh))


def read_study_meta(path) -> dict:
    """The study's metadata (``work_precision.json``: t_end, reference difference, noise floor)."""
    return json.loads(pathlib.Path(path).read_text(encoding="utf-8"))


def fastest_to(runs: list[Run], threshold: float, noise_floor: float = 0.0) -> Fastest:
    """The cheapest run (wall time, then RHS calls) whose measured error is ``<= threshold``."""
    if threshold < noise_floor:
        return Fastest(threshold, BELOW_FLOOR)
    ok = [r for r in runs if r.status == "ok" and np.isfinite(r.error) and r.error <= threshold]
    if not ok:
        return Fastest(threshold, NOT_REACHED)
    return Fastest(threshold, REACHED, min(ok, key=lambda r: (r.wall_time, r.rhs_calls)))
