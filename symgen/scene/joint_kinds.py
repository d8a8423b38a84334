"""Joint kinds as types: what a revolute, prismatic, spherical or fixed joint contributes.

Every question the derivation asks of a joint's type is answered here, by one singleton per
kind (:data:`REVOLUTE`, :data:`PRISMATIC`, :data:`SPHERICAL`, :data:`FIXED`); code elsewhere asks
``joint.kind`` and never compares the type's name with a string. :func:`joint_kind` maps the
scene-file spelling to the kind.

Conventions (DESIGN.md section 2): a joint frame's motion is expressed in the child frame, with
twists ``X = [v; w]``. A 1-DOF joint moves along or about the z axis of its internal joint frame
(:mod:`symgen.tree`), so its motion subspace is ``Z = e3`` (prismatic) or ``Z = e6`` (revolute);
a spherical joint's is ``Z = [0; 1_3]`` (relative angular velocity in the child frame); a fixed
joint has none. Positions, per kind (:mod:`symgen.math.configuration`): an angle (or its ``CosSin`` pair), a
displacement, a 3x3 rotation matrix ``R_joint_child``, nothing. The generated code's position
vector ``q`` holds an angle, a displacement, a unit quaternion ``w, x, y, z`` or nothing
(:attr:`JointKind.position_size` entries).

Fields are used through the :class:`~symgen.math.fields.Field` protocol only (``const``, ``array``,
``zeros``, ``eye``, ``cos_sin``, ``sign``, ``norm``), so each method runs in every field.
"""
from __future__ import annotations

from abc import ABC, abstractmethod
from fractions import Fraction
from typing import Any

import numpy as np
import sympy as sp

from ..errors import StateError, SymgenError
from ..math.jet import Jet
from ..math.spatial import matrix_to_quat
from ..math.configuration import CosSin, rational_rotation


class UnknownJointKindError(SymgenError):
    """A joint type name that is none of :data:`JOINT_KIND_NAMES`."""

    def __init__(self, name):
        self.name = name
        super().__init__(f"unknown joint type {name!r}; use one of {', '.join(JOINT_KIND_NAMES)}")


def _is_expr(v) -> bool:
    """A SymPy expression (kept as it is) rather than a number to convert into the field."""
    return hasattr(v, "free_symbols")


def _entry(v, field):
    return v if _is_expr(v) else field.const(v)


class JointKind(ABC):
    """One kind of joint. Subclasses set the class attributes and implement :meth:`motion`."""

    #: the scene-file spelling (``type:`` in a scene file, the ``type`` argument of ``add_joint``)
    name: str = "abstract"
    #: velocity coordinates (entries of ``qd_all``)
    dof: int = 0
    #: entries in the generated code's position vector ``q``
    position_size: int = 0
    #: the relative angular velocity ``Z_w qd`` can be non-zero
    rotates: bool = False
    #: the relative linear velocity ``Z_v qd`` can be non-zero
    translates: bool = False
    #: the position is one angle (``CosSin`` in the exact, symbolic and trace fields)
    position_is_angle: bool = False
    #: the position is a rotation matrix (a unit quaternion in ``q``)
    position_is_rotation: bool = False
    #: ``Z`` (6 x dof) as nested tuples of 0/1, rows ``vx vy vz wx wy wz``
    subspace: tuple = ((),) * 6

    def __repr__(self) -> str:
        return f"<joint kind {self.name}>"

    def __reduce__(self):
        return (joint_kind, (self.name,))     # singletons survive copy and pickle

    @property
    def is_one_dof(self) -> bool:
        return self.dof == 1

    @property
    def moves(self) -> bool:
        """The joint has velocity coordinates (every kind but fixed)."""
        return self.dof > 0

    # ---------------------------------------------------------------- motion subspace
    def motion_subspace(self, field) -> np.ndarray:
        """``Z`` (6 x dof) in ``field``: the child's twist relative to the parent is ``Z qd_j``."""
        return field.array([list(row) for row in self.subspace]) if self.dof else field.zeros((6, 0))

    def angular(self, values) -> tuple:
        """``Z_w values`` as a 3-tuple with literal zeros (for the tuple recursion of
        :mod:`symgen.dynamics.rnea`); ``values`` has ``dof`` entries."""
        return (0, 0, 0)

    def linear(self, values) -> tuple:
        """``Z_v values`` as a 3-tuple with literal zeros."""
        return (0, 0, 0)

    def transmitted(self, force, moment) -> list:
        """``Z^T [force; moment]``: the joint-coordinate components of a wrench on the child."""
        return []

    # ---------------------------------------------------------------- positions
    def position(self, joint_name: str, positions: dict):
        """The position of joint ``joint_name`` in a configuration's ``positions``, checked;
        ``None`` for a fixed joint. Raises :class:`StateError` if it is missing or malformed."""
        if not self.moves:
            return None
        value = positions.get(joint_name)
        if value is None:
            raise StateError(f"joint {joint_name!r}: the configuration has no position for it")
        return value

    @abstractmethod
    def motion(self, value, rates, field) -> tuple[Jet, Jet]:
        """Rotation ``R_joint_child`` and translation ``p_joint_child`` of the child w.r.t. the
        joint frame, as jets, at position ``value`` moving with ``rates`` (``dof`` entries)."""

    def position_derivative(self, value, rates):
        """Time derivative of a position (same structure as ``value``) at joint rates ``rates``."""
        return None

    def field_position(self, value: Any, field: Any) -> Any:
        """A float or exact position converted into ``field`` (angles become ``CosSin``)."""
        return None

    def symbolic_position(self, joint_name: str):
        """Symbols for the position, named after the joint (``None`` for a fixed joint)."""
        return None

    def reference_position(self, q0, value_of):
        """The float position of reference ``q0`` (``value_of`` evaluates a scalar scene
        expression with the scene's parameters); ``None`` for a fixed joint."""
        return None

    def rational_position_near(self, reference, rationalize, noise):
        """An exact rational position near the float ``reference``: ``rationalize(x)`` is a
        rational close to ``x``, ``noise(scale)`` a random rational in ``[-scale, scale]``."""
        return None

    # ---------------------------------------------------------------- friction
    def friction(self, rates, field, viscous, coulomb) -> np.ndarray:
        """``xi`` of eqs. (22)-(23): ``b qd + c sign(qd)`` (1-DOF), ``b w + c w/|w|`` (spherical)."""
        out = np.array([viscous * v for v in rates], dtype=field.dtype)
        if coulomb != 0:
            dry = self._coulomb(rates, field, coulomb)
            if dry is not None:
                out = out + dry
        return out

    def _coulomb(self, rates, field, coulomb):
        return None

    # ---------------------------------------------------------------- spring
    def coordinate(self, joint_name: str, value, field):
        """A 1-DOF joint's coordinate ``q`` (angle or displacement) at position ``value``, in
        ``field``: what a joint spring ``k (q - q_spring)`` acts on. Only 1-DOF kinds have one."""
        raise StateError(f"joint {joint_name!r}: a {self.name} joint has no scalar coordinate for a spring")


class _OneDof(JointKind):
    dof = 1
    position_size = 1

    def _coulomb(self, rates, field, coulomb):
        return np.array([coulomb * field.sign(rates[0])], dtype=field.dtype)

    def reference_position(self, q0, value_of):
        return value_of(q0)


class Revolute(_OneDof):
    """Rotation about the joint frame's z axis: ``Z = e6``, position an angle."""

    name = "revolute"
    rotates = True
    position_is_angle = True
    subspace = ((0,), (0,), (0,), (0,), (0,), (1,))

    def angular(self, values):
        return (0, 0, values[0])

    def transmitted(self, force, moment):
        return [moment[2]]

    def motion(self, value, rates, field):
        c, s = (value.c, value.s) if isinstance(value, CosSin) else field.cos_sin(value)
        c, s = _entry(c, field), _entry(s, field)
        z = field.zero
        r = np.array([[c, -s, z], [s, c, z], [z, z, field.one]], dtype=field.dtype)
        qd = rates[0]
        dr = np.array([[-s * qd, -c * qd, z], [c * qd, -s * qd, z], [z, z, z]], dtype=field.dtype)
        zero3 = field.zeros((3,))
        return Jet(r, dr), Jet(zero3, zero3.copy())

    def position_derivative(self, value, rates):
        return CosSin(-value.s * rates[0], value.c * rates[0])

    def field_position(self, value, field):
        if isinstance(value, CosSin):
            angle = None if value.angle is None else _entry(value.angle, field)
            return CosSin(field.const(value.c), field.const(value.s), angle)
        return CosSin(*field.cos_sin(value), _entry(value, field))

    def coordinate(self, joint_name, value, field):
        if not isinstance(value, CosSin):
            return _entry(value, field)
        if value.angle is None:
            raise StateError(f"joint {joint_name!r}: its spring k (q - q_spring) needs the joint angle, and "
                             "a cosine-sine position (the exact and symbolic fields) has none: evaluate a "
                             "scene with joint springs in the float or 50-digit field")
        return _entry(value.angle, field)

    def symbolic_position(self, joint_name):
        """``c_<j>, s_<j>``, and the angle ``q_<j>`` for a joint spring (the one term that needs it)."""
        return CosSin(sp.Symbol(f"c_{joint_name}", real=True), sp.Symbol(f"s_{joint_name}", real=True),
                      sp.Symbol(f"q_{joint_name}", real=True))

    def rational_position_near(self, reference, rationalize, noise):
        """A rational point of the unit circle; its angle ``2 atan(t)`` (for a joint spring) is the
        rational nearest it with a denominator below 1e9, within 1e-18 of it."""
        point = CosSin.from_half_tangent(rationalize(np.tan(reference / 2)) + noise(Fraction(1, 4)))
        t = point.s / (1 + point.c)
        angle = Fraction(2 * float(np.arctan(float(t)))).limit_denominator(10**9)
        return CosSin(point.c, point.s, angle)


class Prismatic(_OneDof):
    """Translation along the joint frame's z axis: ``Z = e3``, position a displacement."""

    name = "prismatic"
    translates = True
    subspace = ((0,), (0,), (1,), (0,), (0,), (0,))

    def linear(self, values):
        return (0, 0, values[0])

    def transmitted(self, force, moment):
        return [force[2]]

    def motion(self, value, rates, field):
        d = _entry(value, field)
        p = np.array([field.zero, field.zero, d], dtype=field.dtype)
        dp = np.array([field.zero, field.zero, rates[0]], dtype=field.dtype)
        return Jet.const(field.eye(3), field), Jet(p, dp)

    def position_derivative(self, value, rates):
        return rates[0]

    def field_position(self, value, field):
        return field.const(value)

    def coordinate(self, joint_name, value, field):
        return _entry(value, field)

    def symbolic_position(self, joint_name):
        return sp.Symbol(f"d_{joint_name}", real=True)

    def rational_position_near(self, reference, rationalize, noise):
        return rationalize(reference) + noise(Fraction(1, 20))


class Spherical(JointKind):
    """Free rotation: ``Z = [0; 1_3]``, position the rotation matrix ``R_joint_child``."""

    name = "spherical"
    dof = 3
    position_size = 4
    rotates = True
    position_is_rotation = True
    subspace = ((0, 0, 0), (0, 0, 0), (0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1))

    def angular(self, values):
        return tuple(values)

    def transmitted(self, force, moment):
        return list(moment)

    def position(self, joint_name, positions):
        value = super().position(joint_name, positions)
        if np.shape(value) != (3, 3):
            raise StateError(f"joint {joint_name!r}: a spherical joint's position is a 3x3 rotation matrix, "
                             f"got shape {np.shape(value)}")
        return value

    def motion(self, value, rates, field):
        r = np.array([[_entry(v, field) for v in row] for row in np.asarray(value, dtype=object)],
                     dtype=field.dtype)
        zero3 = field.zeros((3,))
        return Jet(r, r @ _hat(rates, field.zero, field.dtype)), Jet(zero3, zero3.copy())

    def position_derivative(self, value, rates):
        return np.asarray(value, dtype=object) @ _hat(rates, 0, object)

    def field_position(self, value, field):
        return np.array([[field.const(v) for v in row] for row in np.asarray(value, dtype=object)], dtype=object)

    def symbolic_position(self, joint_name):
        return [[sp.Symbol(f"R_{joint_name}_{a}{b}", real=True) for b in range(1, 4)] for a in range(1, 4)]

    def reference_position(self, q0, value_of):
        return np.array(sp.Matrix(q0).evalf().tolist(), dtype=float)

    def rational_position_near(self, reference, rationalize, noise):
        return rational_rotation(*[rationalize(v) + noise(Fraction(1, 8)) for v in matrix_to_quat(reference)])

    def _coulomb(self, rates, field, coulomb):
        norm = field.norm(rates)
        if norm == 0:
            return None
        return np.array([coulomb * v / norm for v in rates], dtype=field.dtype)


def _hat(w, zero, dtype) -> np.ndarray:
    """``hat(w)`` with ``zero`` on the diagonal."""
    return np.array([[zero, -w[2], w[1]], [w[2], zero, -w[0]], [-w[1], w[0], zero]], dtype=dtype)


class Fixed(JointKind):
    """No motion: no coordinates, no position, ``Z`` is 6 x 0."""

    name = "fixed"

    def motion(self, value, rates, field):
        zero3 = field.zeros((3,))
        return Jet.const(field.eye(3), field), Jet(zero3, zero3.copy())


REVOLUTE = Revolute()
PRISMATIC = Prismatic()
SPHERICAL = Spherical()
FIXED = Fixed()
#: every kind by its scene-file spelling, in the order the documentation lists them
JOINT_KINDS = {k.name: k for k in (REVOLUTE, PRISMATIC, SPHERICAL, FIXED)}
JOINT_KIND_NAMES = tuple(JOINT_KINDS)


def joint_kind(name) -> JointKind:
    """The kind spelled ``name`` (a :class:`JointKind` is returned as it is); raises
    :class:`UnknownJointKindError` for any other name."""
    if isinstance(name, JointKind):
        return name
    try:
        return JOINT_KINDS[name]
    except (KeyError, TypeError):
        raise UnknownJointKindError(name) from None
