"""Straight-line fits, local slopes and growth exponents of op counts against size.

* :func:`linear` -- least squares ``total = a N + b`` (``a``: ops per DOF, or per arm), reusing
  :func:`symgen.codegen.linearity.fit_line`;
* :func:`local_slopes` -- ``(y1 - y0) / (x1 - x0)`` between consecutive sizes;
* :func:`slope_constancy` -- the largest relative deviation of the local slopes from the fitted
  slope: the issue's check "the slope of inverse_dynamics is constant within 5 % over
  N = 8...64" is ``slope_constancy(...).max_deviation <= 0.05``. A quadratic count fails it;
* :func:`growth_exponent` -- ``p`` of ``total ~ c N^p`` (least squares on ``log total``
  against ``log N``): about 1 for a linear formulation, 4 for Lagrange-Euler.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..codegen.linearity import Fit, fit_line

#: the issue's tolerance on the constancy of the slope of inverse_dynamics
SLOPE_TOLERANCE = 0.05
#: the sizes of that check
SLOPE_CHECK_SIZES = (8, 12, 16, 24, 32, 48, 64)


@dataclass
class SlopeCheck:
    fit: Fit
    local: list            # [(x0, x1, slope)]
    max_deviation: float   # max |local - fit.slope| / fit.slope

    @property
    def passed(self) -> bool:
        return self.max_deviation <= SLOPE_TOLERANCE

    def describe(self, what: str = "total", unit: str = "N") -> str:
        locals_ = ", ".join(f"{x0}-{x1}: {s:.2f}" for x0, x1, s in self.local)
        return (f"local slopes of {what} ({locals_}); fitted slope {self.fit.slope:.2f} per {unit}; "
                f"largest deviation {100 * self.max_deviation:.2f} % "
                f"(limit {100 * SLOPE_TOLERANCE:.0f} %): {'PASS' if self.passed else 'FAIL'}")


def linear(xs, ys) -> Fit | None:
    """Least-squares line through at least two points, else None."""
    return fit_line(xs, ys) if len(xs) >= 2 else None


def local_slopes(xs, ys) -> list[tuple]:
    """``[(x0, x1, (y1 - y0) / (x1 - x0))]`` for consecutive points (xs ascending, distinct)."""
    pts = sorted(zip(xs, ys))
    if any(b[0] == a[0] for a, b in zip(pts, pts[1:])):
        raise ValueError("sizes must be distinct")
    return [(x0, x1, (y1 - y0) / (x1 - x0)) for (x0, y0), (x1, y1) in zip(pts, pts[1:])]


def slope_constancy(xs, ys) -> SlopeCheck:
    """How far the local slopes stray from the least-squares slope (relative)."""
    if len(xs) < 3:
        raise ValueError("need at least three sizes to judge a slope")
    fit = fit_line(xs, ys)
    local = local_slopes(xs, ys)
    dev = max(abs(s - fit.slope) for _, _, s in local) / abs(fit.slope)
    return SlopeCheck(fit, local, dev)


def growth_exponent(xs, ys) -> float | None:
    """``p`` in ``y ~ c x^p`` by least squares on logs (points with y > 0), None if < 2 points."""
    pts = [(math.log(x), math.log(y)) for x, y in zip(xs, ys) if y > 0 and x > 0]
    if len(pts) < 2:
        return None
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx if sxx else None
