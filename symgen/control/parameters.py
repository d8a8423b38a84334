"""The constant parameter vector ``P_r`` of eq. (35) and its adaptation data of eq. (38).

Per rigid body alpha (eq. 21), the 10 standard inertial parameters, in which ``Y_alpha P_alpha``
is linear (:mod:`symgen.control.regressor`), all in the body's own frame::

    P_alpha = [m, hx, hy, hz, Ixx, Iyy, Izz, Ixy, Ixz, Iyz]
    h   = m r                      first moment of mass (r: centre of mass)
    I_o = I_c - m r^ r^            rotational inertia about the FRAME ORIGIN (I_c: about the com)

so that ``M_alpha = [[m 1, -h^], [h^, I_o]]``. Per 1-DOF joint (eq. 22) ``[I*, b, c]`` (rotor
inertia, viscous, Coulomb); per spherical joint (eq. 23) ``[b, c]`` (no inertia).

A parameter is named after its owner: ``m_link3``, ``hx_link3``, ``Ixx_link3``, ``Ir_elbow``,
``b_elbow``, ``c_elbow``. A :class:`ParameterSet` lists them with their values, which are
uncertain (adapted by eq. 38, with bounds ``P- <= P+`` and update gain ``rho > 0``) and which are
known constants.

The conversions :func:`body_parameters` and :func:`body_inertial` are exact in every field
(floats, Fractions, SymPy expressions, mpmath numbers): only ``+ - *`` and one division by ``m``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
import sympy as sp

from ..scene.joint_kinds import joint_kind
from ..math.spatial import hat
from ..errors import SceneError
from .errors import ControlInputError, ParameterBoundsError, UnknownParameterError, UpdateGainError

#: parameter quantities of a rigid body, in the order of ``P_alpha``
BODY_QUANTITIES = ("m", "hx", "hy", "hz", "Ixx", "Iyy", "Izz", "Ixy", "Ixz", "Iyz")
#: of a 1-DOF (revolute or prismatic) joint, eq. (22): rotor inertia I*, viscous b, Coulomb c
ONE_DOF_QUANTITIES = ("Ir", "b", "c")
#: of a spherical joint, eq. (23): viscous b, Coulomb c (its mass is in the links)
SPHERICAL_QUANTITIES = ("b", "c")
#: index pairs of the six inertia entries ``xx, yy, zz, xy, xz, yz``
INERTIA_ENTRIES = ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))


# ------------------------------------------------------------------ rigid-body conversions
def body_parameters(m, r, inertia, field) -> np.ndarray:
    """``P_alpha`` (10) of eq. (35) from symgen's ``(m, r, I_c)``: ``h = m r``, ``I_o = I_c - m r^ r^``."""
    r = np.asarray(r, dtype=field.dtype)
    rh = hat(r, field)
    origin = np.asarray(inertia, dtype=field.dtype) - m * (rh @ rh)
    out = [m, *(m * r[i] for i in range(3)), *(origin[i, j] for i, j in INERTIA_ENTRIES)]
    return np.array(out, dtype=field.dtype)


def origin_inertia(p_alpha, field) -> np.ndarray:
    """The 3x3 symmetric ``I_o`` (about the frame origin) from ``P_alpha``."""
    xx, yy, zz, xy, xz, yz = p_alpha[4:10]
    return np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]], dtype=field.dtype)


def body_inertial(p_alpha, field, owner: str = "body"):
    """``(m, r, I_c)`` from ``P_alpha``: ``r = h/m``, ``I_c = I_o + h^ h^ / m`` (inverse of
    :func:`body_parameters`). A zero mass has no centre of mass: :class:`ParameterBoundsError`."""
    m = p_alpha[0]
    if m == 0:
        raise ParameterBoundsError(f"m_{owner}", "a zero mass has no centre of mass")
    h = np.asarray(p_alpha[1:4], dtype=field.dtype)
    hh = hat(h, field)
    return m, h / m, origin_inertia(p_alpha, field) + (hh @ hh) / m


def body_mass_matrix(p_alpha, field) -> np.ndarray:
    """``M_alpha = [[m 1, -h^], [h^, I_o]]`` of eq. (21), linear in ``P_alpha``."""
    hh = hat(np.asarray(p_alpha[1:4], dtype=field.dtype), field)
    top = np.hstack([p_alpha[0] * field.eye(3), -hh])
    return np.vstack([top, np.hstack([hh, origin_inertia(p_alpha, field)])])


def parameter_names(owner: str, quantities) -> tuple[str, ...]:
    """``("m_link3", "hx_link3", ...)``: each quantity named after its owner."""
    return tuple(f"{q}_{owner}" for q in quantities)


def joint_quantities(kind) -> tuple[str, ...]:
    """The parameter quantities of a joint kind (or its name): eq. (22) for 1-DOF joints, eq. (23)
    for spherical ones, none for fixed joints."""
    dof = joint_kind(kind).dof
    return ONE_DOF_QUANTITIES if dof == 1 else SPHERICAL_QUANTITIES if dof == 3 else ()


# ------------------------------------------------------------------------------- records
@dataclass(frozen=True)
class Parameter:
    """One entry ``P_k`` of ``P_r``: its owner, quantity and value.

    ``value`` is the true value of a known parameter or the initial estimate of an uncertain one.
    An uncertain parameter (``rho`` given) has bounds ``lower <= value <= upper`` (``-inf``/``inf``
    allowed) and update gain ``rho > 0`` (eq. 38); a known one has none.
    """

    owner: str
    quantity: str
    value: object
    lower: object = None
    upper: object = None
    rho: object = None

    @property
    def name(self) -> str:
        return f"{self.quantity}_{self.owner}"

    @property
    def uncertain(self) -> bool:
        return self.rho is not None


def _real(value, name: str, what: str, finite: bool = True) -> float:
    """``float(value)`` for the checks, or a :class:`ParameterBoundsError` naming the parameter."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ParameterBoundsError(name, f"{what} {value!r} is not a real number") from None
    if math.isnan(x) or (finite and math.isinf(x)):
        raise ParameterBoundsError(name, f"{what} {value!r} is not finite")
    return x


#: quantities that must not be negative, as the scene requires (mass, rotor inertia, viscous and
#: Coulomb friction; the contact law's ``b_<component>``, ``c_<component>`` too)
NONNEGATIVE = {"m": "mass", "Ir": "rotor inertia", "b": "viscous coefficient", "c": "Coulomb coefficient"}


def _nonnegative(quantity: str) -> str | None:
    """What a non-negative quantity is called, or None for quantities of either sign."""
    if quantity in NONNEGATIVE:
        return NONNEGATIVE[quantity]
    if quantity.startswith(("b_", "c_")):
        return NONNEGATIVE[quantity[0]] + f" of contact component {quantity[2:]!r}"
    return None


def _validate_known(p: Parameter) -> None:
    """A known value: a finite real number (unless it is symbolic), not negative where the physics says so."""
    if p.lower is not None or p.upper is not None:
        raise ParameterBoundsError(p.name, "a known parameter has no bounds; give rho to adapt it")
    if getattr(p.value, "free_symbols", None):
        return
    value = _real(p.value, p.name, "value")
    kind = _nonnegative(p.quantity)
    if kind is not None and value < 0:
        raise ParameterBoundsError(p.name, f"negative {kind} {p.value}")


def validate_parameter(p: Parameter) -> None:
    """Raise the typed error of the first problem of ``p`` (see :mod:`symgen.control.errors`)."""
    name = p.name
    if not p.uncertain:
        _validate_known(p)
        return
    try:
        rho = float(p.rho)
    except (TypeError, ValueError):
        raise UpdateGainError(name, f"update gain rho = {p.rho!r} is not a number") from None
    if not (math.isfinite(rho) and rho > 0):
        raise UpdateGainError(name, f"update gain rho = {p.rho!r} must be finite and > 0")
    lo = _real(p.lower, name, "lower bound", finite=False)
    _real(p.upper, name, "upper bound", finite=False)
    _real(p.value, name, "estimate")
    if p.lower > p.upper:
        raise ParameterBoundsError(name, f"lower bound {p.lower} > upper bound {p.upper}")
    if not p.lower <= p.value <= p.upper:
        raise ParameterBoundsError(name, f"initial estimate {p.value} outside [{p.lower}, {p.upper}]")
    kind = _nonnegative(p.quantity)
    if kind is not None and lo < 0:
        raise ParameterBoundsError(name, f"lower bound {p.lower} allows a negative {kind}; use >= 0")


def _array(values) -> np.ndarray:
    """A float array when every entry is a Python/NumPy float or int, else an object array."""
    if all(isinstance(v, (float, int, np.floating, np.integer)) and not isinstance(v, bool)
           for v in values):
        return np.array(values, dtype=float)
    return np.array(values, dtype=object)


class ParameterSet:
    """The parameters ``P_k`` of ``P_r`` (eq. 35) in order, with the adaptation data of eq. (38).

    Arrays over ``k`` (:attr:`values`, :attr:`lower`, :attr:`upper`, :attr:`rho`,
    :attr:`uncertain`) feed :mod:`symgen.control.adaptation`; a known parameter has
    ``lower = upper = value`` and ``rho = 0`` there, so it never moves.
    """

    def __init__(self, parameters):
        self.parameters = tuple(parameters)
        seen = set()
        for p in self.parameters:
            if p.name in seen:
                raise ParameterBoundsError(p.name, "appears twice in the parameter set")
            seen.add(p.name)
            validate_parameter(p)
        self._index = {p.name: k for k, p in enumerate(self.parameters)}

    def __len__(self) -> int:
        return len(self.parameters)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.parameters)

    def index(self, name: str) -> int:
        """Position ``k`` of a parameter in ``P_r``; :class:`UnknownParameterError` if absent."""
        try:
            return self._index[name]
        except KeyError:
            raise UnknownParameterError(name, "no such parameter; known: "
                                        + ", ".join(self.names[:12])
                                        + (", ..." if len(self) > 12 else "")) from None

    def owner_indices(self, owner: str) -> list[int]:
        """Positions of one owner's parameters, in order (a body's 10, a joint's 3 or 2)."""
        return [k for k, p in enumerate(self.parameters) if p.owner == owner]

    @property
    def values(self) -> np.ndarray:
        return _array([p.value for p in self.parameters])

    @property
    def uncertain(self) -> np.ndarray:
        return np.array([p.uncertain for p in self.parameters], dtype=bool)

    @property
    def lower(self) -> np.ndarray:
        return _array([p.lower if p.uncertain else p.value for p in self.parameters])

    @property
    def upper(self) -> np.ndarray:
        return _array([p.upper if p.uncertain else p.value for p in self.parameters])

    @property
    def rho(self) -> np.ndarray:
        return _array([p.rho if p.uncertain else 0 for p in self.parameters])

    def symbols(self) -> np.ndarray:
        """SymPy symbols named after the parameters (masses positive, the rest real)."""
        return np.array([sp.Symbol(p.name, positive=True) if p.quantity == "m"
                         else sp.Symbol(p.name, real=True) for p in self.parameters], dtype=object)

    def with_uncertainty(self, spec) -> "ParameterSet":
        """A copy in which ``spec = {name: (lower, upper, rho)}`` are uncertain (validated)."""
        out = list(self.parameters)
        for name, (lower, upper, rho) in spec.items():
            k = self.index(name)
            out[k] = replace(out[k], lower=lower, upper=upper, rho=rho)
        return ParameterSet(out)

    def with_values(self, values) -> "ParameterSet":
        """A copy with new values (estimates) in order; validated against the bounds."""
        if len(values) != len(self):
            raise ControlInputError(f"{len(values)} parameter values given, the set has {len(self)}")
        return ParameterSet(replace(p, value=v) for p, v in zip(self.parameters, values))


def body_parameter_set(owner: str, m, r, inertia, field) -> list[Parameter]:
    """The 10 known parameters of one rigid body, named after ``owner``."""
    values = body_parameters(m, r, inertia, field)
    return [Parameter(owner, q, v) for q, v in zip(BODY_QUANTITIES, values)]


def tree_parameters(tree, field) -> ParameterSet:
    """Every parameter of ``P_r`` of a kinematic tree, all known, with the tree's values.

    Order of eq. (35): the joints in tree order (``[I*, b, c]`` per 1-DOF joint, ``[b, c]`` per
    spherical joint, nothing for fixed joints), then the massive bodies in tree order (10 each,
    in the tree's internal body frames, like :mod:`symgen.subsystems`).
    """
    return ParameterSet(Parameter(owner, q, v) for owner, q, v in parameter_values(tree, field))


def sprung_joints(tree) -> list[str]:
    """The joints of ``tree`` with a spring (non-zero stiffness): the regressor of eqs. (35)-(37)
    has no term for them."""
    return [j.name for j in tree.joints if j.stiffness != 0]


def parameter_values(tree, field):
    """``(owner, quantity, value)`` of every parameter of ``P_r`` in the order of eq. (35) (see
    :func:`tree_parameters`), the values in ``field``: no validation, so traced numbers work too.

    A joint spring ``k (q - q_spring)`` is not a term of the regressor of eqs. (35)-(37), so a tree
    with one is refused (:class:`~symgen.errors.SceneError` naming the joint) rather than
    controlled or identified as if it had none."""
    sprung = sprung_joints(tree)
    if sprung:
        raise SceneError(f"joint {sprung[0]!r}", "has a spring (stiffness): the Section 4 regressor "
                         "(eqs. 35-37) has no spring term, so the adaptive controller and identification "
                         f"do not take scenes with joint springs ({len(sprung)} sprung joint(s))")
    for j in tree.joints:
        values = {"Ir": j.rotor_inertia, "b": j.viscous, "c": j.coulomb}
        yield from ((j.name, q, field.const(values[q])) for q in joint_quantities(j.kind))
    for b in tree.bodies:
        if not b.massless:
            p = body_parameters(field.const(b.mass), field.array(list(b.com)), field.array(b.inertia.tolist()), field)
            yield from ((b.name, q, v) for q, v in zip(BODY_QUANTITIES, p))
