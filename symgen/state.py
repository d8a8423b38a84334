"""Configurations and velocities of all joints of a scene.

A :class:`Configuration` maps every joint name to its position:

* revolute: an angle (float), or :class:`CosSin` -- the exact pair ``(cos q, sin q)`` used by the
  exact and symbolic fields (rational points come from the tangent half-angle, DESIGN.md s.5);
* prismatic: a displacement along the axis;
* spherical: a 3x3 rotation matrix ``R_joint_child`` (NumPy array, or nested lists of exact
  numbers / SymPy expressions);
* fixed joints have no entry.

Joint *coordinates* are ordered by the scene's joint declaration order; a spherical joint has
three velocity coordinates, the relative angular velocity in its child frame (DESIGN.md s.2).
"""
from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import numpy as np


@dataclass(frozen=True)
class CosSin:
    """A revolute joint position given by its cosine and sine (exact or symbolic)."""

    c: object
    s: object

    @staticmethod
    def from_half_tangent(t) -> "CosSin":
        """Rational point on the unit circle: ``cos = (1-t^2)/(1+t^2)``, ``sin = 2t/(1+t^2)``."""
        t = Fraction(t) if not hasattr(t, "free_symbols") else t
        return CosSin((1 - t * t) / (1 + t * t), 2 * t / (1 + t * t))


def rational_rotation(w, x, y, z) -> list[list[Fraction]]:
    """An exact rotation matrix with rational entries from a quaternion with rational components."""
    w, x, y, z = (Fraction(v) for v in (w, x, y, z))
    n = w * w + x * x + y * y + z * z
    return [
        [(w * w + x * x - y * y - z * z) / n, 2 * (x * y - w * z) / n, 2 * (x * z + w * y) / n],
        [2 * (x * y + w * z) / n, (w * w - x * x + y * y - z * z) / n, 2 * (y * z - w * x) / n],
        [2 * (x * z - w * y) / n, 2 * (y * z + w * x) / n, (w * w - x * x - y * y + z * z) / n],
    ]


@dataclass
class Configuration:
    """Positions of all non-fixed joints, by joint name."""

    positions: dict

    def __getitem__(self, name):
        return self.positions[name]

    def as_float(self) -> "Configuration":
        out = {}
        for k, v in self.positions.items():
            if isinstance(v, CosSin):
                out[k] = float(np.arctan2(float(v.s), float(v.c)))
            elif np.ndim(v) == 2:
                out[k] = np.array(v, dtype=float)
            else:
                out[k] = float(v)
        return Configuration(out)
