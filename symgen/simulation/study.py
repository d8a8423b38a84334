"""The result of a work-precision study (:mod:`symgen.simulation.workprecision`) and its checks.

A :class:`Study` holds one :class:`Row` per run (backend, method, step or tolerance) and the
reference's own accuracy, which sets the noise floor; :func:`series` groups the rows per backend
and method, coarse to fine, and :func:`monotonicity_violations` checks that the error falls as the
step shrinks or the tolerance tightens, down to that floor. The runner and the report writer
(:mod:`symgen.simulation.report`) both build on this module.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass, field

import numpy as np

#: the noise floor is this multiple of the reference difference (and at least FLOOR_MIN)
FLOOR_FACTOR = 10.0
FLOOR_MIN = 1e-12


@dataclass
class Row:
    """One run of the study (``setting`` is the step in s or the tolerance)."""

    backend: str
    method: str
    kind: str              # "step" or "tol"
    setting: float
    error: float
    drift: float
    energy_drift: float | None
    wall_time: float
    rhs_calls: int
    steps: int
    status: str = "ok"


@dataclass
class Study:
    """All rows of one scene plus the reference's own accuracy."""

    scene: str
    t_end: float
    rows: list[Row]
    reference_difference: float
    reference_calls: int
    conservative: bool
    stabilization: str
    description: dict = field(default_factory=dict)

    @property
    def noise_floor(self) -> float:
        return max(FLOOR_FACTOR * self.reference_difference, FLOOR_MIN)

    def as_dict(self) -> dict:
        return {"scene": self.scene, "t_end": self.t_end, "reference_difference": self.reference_difference,
                "noise_floor": self.noise_floor, "reference_calls": self.reference_calls,
                "conservative": self.conservative, "stabilization": self.stabilization,
                "description": self.description, "rows": [_finite_or_none(asdict(r)) for r in self.rows]}


def _finite_or_none(row: dict) -> dict:
    """NaN (a failed run's error) becomes ``None``, so the dictionary is valid JSON."""
    return {k: (None if isinstance(v, float) and not np.isfinite(v) else v) for k, v in row.items()}


def series(study: Study):
    """``{(backend, method): rows ordered coarse -> fine}`` (decreasing step or tolerance)."""
    out: dict[tuple[str, str], list[Row]] = {}
    for row in study.rows:
        out.setdefault((row.backend, row.method), []).append(row)
    return {k: sorted(v, key=lambda r: -r.setting) for k, v in out.items()}


def monotonicity_violations(study: Study, floor: float | None = None) -> list[str]:
    """Places where the error does *not* fall from one setting to the next finer one, while the
    finer error is above the noise floor (``study.noise_floor`` unless given). Failed runs are
    skipped. Empty list: the table is monotone."""
    floor = study.noise_floor if floor is None else floor
    bad = []
    for (backend, method), rows in series(study).items():
        ok = [r for r in rows if r.status == "ok"]
        for coarse, fine in zip(ok, ok[1:]):
            if fine.error > floor and not fine.error < coarse.error:
                bad.append(f"{backend} {method}: error {fine.error:.3g} at {fine.kind} {fine.setting:g} is not below "
                           f"{coarse.error:.3g} at {coarse.kind} {coarse.setting:g} (noise floor {floor:.3g})")
    return bad
