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

:func:`as_configuration` takes a state as users hold it -- a :class:`Configuration`, a mapping
joint name -> position, or a flat array of positions in scene order (the generated code's ``q``:
one number per 1-DOF joint, a quaternion ``(w, x, y, z)`` per spherical joint) -- and refuses
anything else with a :class:`~symgen.errors.StateError` naming the argument.
"""
from __future__ import annotations

import numbers

from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any, Protocol, TypeAlias

import numpy as np
import numpy.typing as npt
import sympy as sp

from ..errors import StateError
from .scalar import Scalar


@dataclass(frozen=True)
class CosSin:
    """A revolute joint position given by its cosine and sine (exact or symbolic). ``angle`` is
    the angle itself where it is known (a float or 50-digit position converted into a field, a
    traced ``q`` entry): a joint spring ``k (q - q_spring)`` needs it, the rotation does not."""

    c: Scalar
    s: Scalar
    angle: Scalar | None = field(default=None, compare=False, repr=False)

    @staticmethod
    def from_half_tangent(t: Fraction | int | str | sp.Expr) -> "CosSin":
        """Rational point on the unit circle: ``cos = (1-t^2)/(1+t^2)``, ``sin = 2t/(1+t^2)``."""
        u: Scalar = Fraction(t) if not hasattr(t, "free_symbols") else t
        return CosSin((1 - u * u) / (1 + u * u), 2 * u / (1 + u * u))


def rational_rotation(w: Fraction | int | str, x: Fraction | int | str, y: Fraction | int | str,
                      z: Fraction | int | str) -> list[list[Fraction]]:
    """An exact rotation matrix with rational entries from a quaternion with rational components."""
    w, x, y, z = (Fraction(v) for v in (w, x, y, z))
    n = w * w + x * x + y * y + z * z
    return [
        [(w * w + x * x - y * y - z * z) / n, 2 * (x * y - w * z) / n, 2 * (x * z + w * y) / n],
        [2 * (x * y + w * z) / n, (w * w - x * x + y * y - z * z) / n, 2 * (y * z - w * x) / n],
        [2 * (x * z - w * y) / n, 2 * (y * z + w * x) / n, (w * w - x * x - y * y + z * z) / n],
    ]


#: a joint's position: an angle or a displacement (an element of a field), a :class:`CosSin` pair,
#: or a 3x3 rotation (a NumPy array, or nested lists of exact numbers or SymPy expressions)
Position: TypeAlias = "Scalar | CosSin | np.ndarray"


class _DeclaredKind(Protocol):
    @property
    def dof(self) -> int: ...

    @property
    def position_is_rotation(self) -> bool: ...


class DeclaredJoint(Protocol):
    """A joint as a state is checked against it: its name and its kind's coordinates."""

    @property
    def name(self) -> str: ...

    @property
    def kind(self) -> _DeclaredKind: ...


class JointDeclarations(Protocol):
    """What :func:`as_configuration` reads of a scene (a :class:`symgen.scene.declaration.Scene`
    is one, a layer up): its name and its joints by name."""

    @property
    def name(self) -> str: ...

    @property
    def joints(self) -> Mapping[str, DeclaredJoint]: ...


@dataclass
class Configuration:
    """Positions of all non-fixed joints, by joint name."""

    positions: dict[str, Position]

    def __getitem__(self, name: str) -> Position:
        return self.positions[name]

    def as_float(self) -> "Configuration":
        out: dict[str, Position] = {}
        for k, v in self.positions.items():
            if isinstance(v, CosSin):
                out[k] = float(np.arctan2(float(v.s), float(v.c)))
            elif np.ndim(v) == 2:
                out[k] = np.array(v, dtype=float)
            else:
                out[k] = float(v)
        return Configuration(out)


#: a state as users hold it (:func:`as_configuration`): a :class:`Configuration`, a mapping joint
#: name -> position, or a flat array of positions in scene order
ConfigurationLike: TypeAlias = "Configuration | Mapping[str, Any] | np.ndarray | Sequence[float]"


def _moving_joints(scene: JointDeclarations) -> list[DeclaredJoint]:
    return [j for j in scene.joints.values() if j.kind.dof]


def quaternion_rotation(q: npt.ArrayLike) -> np.ndarray:
    """The rotation matrix of a quaternion ``(w, x, y, z)`` (normalised first)."""
    w, x, y, z = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def flat_layout(scene: JointDeclarations) -> str:
    """How a flat position array of ``scene`` is laid out (for error messages)."""
    return ", ".join(f"{j.name} (w, x, y, z)" if j.kind.position_is_rotation else j.name for j in _moving_joints(scene))


def as_configuration(value: object, scene: JointDeclarations, argument: str = "config") -> Configuration:
    """A :class:`Configuration` of ``scene`` from a state as users hold it.

    * a :class:`Configuration`: returned as it is;
    * a mapping joint name -> position (a spherical joint's position a 3x3 rotation matrix or a
      quaternion ``(w, x, y, z)``): every key must name a moving joint;
    * a flat array of ``sum(1 per 1-DOF joint, 4 per spherical joint)`` finite numbers in scene
      order (the generated code's ``q``).

    A joint without a position is refused here; a malformed position when the configuration is
    read (by the joint's kind, naming the joint). Raises :class:`StateError` naming ``argument``.
    """
    joints = {j.name: j for j in _moving_joints(scene)}
    if isinstance(value, (Configuration, Mapping)):
        given = value.positions if isinstance(value, Configuration) else value
        unknown = [name for name in given if name not in joints] if isinstance(value, Mapping) else []
        if unknown:
            raise StateError(f"{argument}: {unknown[0]!r} is not a moving joint of scene {scene.name!r} "
                             f"(joints: {', '.join(joints) or 'none'})")
        missing = [name for name in joints if name not in given]
        if missing:
            raise StateError(f"{argument}: joint {missing[0]!r} has no position (a state gives every moving joint: "
                             f"{', '.join(joints)})")
    if isinstance(value, Configuration):
        return value
    if isinstance(value, Mapping):
        return Configuration({name: _position(joints[name], position, argument) for name, position in value.items()})
    if isinstance(value, (str, bytes)) or not isinstance(value, (list, tuple, np.ndarray)):
        raise StateError(f"{argument} must be a Configuration, a mapping joint -> position, or a flat array of "
                         f"positions in scene order ({flat_layout(scene)}); got {type(value).__name__}")
    return _from_flat(np.asarray(value), joints.values(), argument, scene)


#: a rotation matrix given as a joint position must satisfy max|R^T R - 1| and |det R - 1| below
#: this (the scene reader's tolerance); it is then snapped to the nearest rotation
ROTATION_TOL = 1e-6


def _position(joint: DeclaredJoint, position: object, argument: str) -> Position:
    """One joint's position from a mapping, checked as the flat array's are: a finite real number
    (or a ``CosSin`` pair) for a 1-DOF joint; for a spherical joint a non-zero finite quaternion
    ``(w, x, y, z)`` (normalised) or a rotation matrix (orthonormal with determinant +1 within
    :data:`ROTATION_TOL`, then snapped to the nearest rotation). Raises :class:`StateError`."""
    where = f"{argument}: joint {joint.name!r}"
    if not joint.kind.position_is_rotation:
        if isinstance(position, CosSin):
            return position
        if isinstance(position, (bool, np.bool_)) or not isinstance(position, (numbers.Real, sp.Basic)):
            raise StateError(f"{where} needs a real number, got {type(position).__name__}")
        if isinstance(position, (float, np.floating)) and not np.isfinite(position):
            raise StateError(f"{where} is {float(position)} (not finite)")
        return position
    try:
        arr = np.asarray(position, dtype=float)
    except (TypeError, ValueError):
        raise StateError(f"{where}: a spherical joint's position is a quaternion (w, x, y, z) or a 3x3 rotation "
                         "matrix of real numbers") from None
    if arr.shape not in ((4,), (3, 3)):
        raise StateError(f"{where}: a spherical joint's position is a quaternion (w, x, y, z) or a 3x3 rotation "
                         f"matrix, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise StateError(f"{where} contains NaN or infinity")
    if arr.shape == (4,):
        if np.linalg.norm(arr) < 1e-12:
            raise StateError(f"{where} has a zero quaternion")
        return quaternion_rotation(arr)
    entries = np.asarray(position, dtype=object).ravel()
    if all(isinstance(v, (int, Fraction, sp.Basic)) and not isinstance(v, bool) for v in entries):
        return position                    # exact entries (Fractions, SymPy): the exact fields read them
    return _snapped_rotation(arr, where)


def _snapped_rotation(r: np.ndarray, where: str) -> np.ndarray:
    """The rotation nearest ``r`` (polar factor), if ``r`` is one within :data:`ROTATION_TOL`."""
    error = max(float(np.max(np.abs(r.T @ r - np.eye(3)))), abs(float(np.linalg.det(r)) - 1.0))
    if not error <= ROTATION_TOL:
        raise StateError(f"{where}: the matrix is not a rotation (max |R^T R - 1| or |det R - 1| is {error:.3g}, "
                         f"above {ROTATION_TOL:g}); give a rotation matrix or a quaternion (w, x, y, z)")
    u, _, vt = np.linalg.svd(r)
    nearest: np.ndarray = u @ vt
    return nearest


def _from_flat(array: np.ndarray, joints: Collection[DeclaredJoint], argument: str,
               scene: JointDeclarations) -> Configuration:
    size = sum(4 if j.kind.position_is_rotation else 1 for j in joints)
    if array.dtype.kind not in "biuf" or array.shape != (size,):
        raise StateError(f"{argument} as a flat array must hold {size} real numbers in scene order "
                         f"({flat_layout(scene)}); got shape {array.shape}, dtype {array.dtype}")
    array = array.astype(float)
    if not np.all(np.isfinite(array)):
        raise StateError(f"{argument} contains NaN or infinity")
    out: dict[str, Position] = {}
    offset = 0
    for j in joints:
        if j.kind.position_is_rotation:
            quat = array[offset:offset + 4]
            if np.linalg.norm(quat) < 1e-12:
                raise StateError(f"{argument}: joint {j.name!r} has a zero quaternion")
            out[j.name], offset = quaternion_rotation(quat), offset + 4
        else:
            out[j.name], offset = float(array[offset]), offset + 1
    return Configuration(out)
