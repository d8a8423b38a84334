"""Operation counts across a family of scenes and their straight-line fit ``a N + b``.

The linearity checks: ``inverse_dynamics`` on ``chain:n=N`` (N = 2..64) and ``multi_arm:h=H``
(H = 1..8) must fit a line with ``R^2 > 0.999`` and ``total(2x) / total(x) <= 2.05``; so must
``forward_dynamics`` by the articulated-body algorithm on ``chain:n=N`` (library solves included).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..io.builtin import get_scene
from ..model import derive
from .generate import operation_counts

FAMILIES = {"chain": ("n", (2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64)),
            "multi_arm": ("h", (1, 2, 3, 4, 5, 6, 7, 8))}


@dataclass
class Fit:
    slope: float
    intercept: float
    r2: float

    def __str__(self) -> str:
        return f"{self.slope:.2f} N {self.intercept:+.1f}  (R^2 = {self.r2:.6f})"


def fit_line(xs, ys) -> Fit:
    """Least-squares ``y = a x + b`` and its coefficient of determination."""
    x, y = np.asarray(xs, float), np.asarray(ys, float)
    a, b = np.polyfit(x, y, 1)
    resid = y - (a * x + b)
    total = np.sum((y - y.mean()) ** 2)
    return Fit(float(a), float(b), float(1 - np.sum(resid**2) / total) if total else 1.0)


def family_counts(family: str, sizes=None, function: str = "inverse_dynamics",
                  options=None) -> list[tuple[int, dict]]:
    """``[(size, ops)]`` of ``function`` over ``family`` (``chain`` or ``multi_arm``); ``options``
    are generation options (e.g. ``{"method": "articulated-body"}`` for forward dynamics)."""
    key, default = FAMILIES[family]
    return [(s, operation_counts(derive(get_scene(f"{family}:{key}={s}")), [function], options)[function])
            for s in (sizes or default)]
