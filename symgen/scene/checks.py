"""The checks a scene runs on what it is given: exact numbers within the input limits, full 3x3
inertias, physically possible mass properties, and a joint tree rooted at the world."""
from __future__ import annotations

import warnings

import numpy as np
import sympy as sp

from ..errors import InertiaWarning, SceneError, TopologyError
from .input_limits import magnitude_problem, number_text_problem
from ..math.numbers import parse_exact
from .elements import Body


def inertia_entries(scene, element: str, inertia):
    """``[ixx, iyy, izz, ixy, ixz, iyz]`` of a full 3x3 inertia matrix (checked symmetric, exactly);
    other forms unchanged."""
    rows = list(inertia) if isinstance(inertia, (list, tuple)) else None
    if not rows or len(rows) != 3 or not all(isinstance(r, (list, tuple)) for r in rows):
        return inertia
    if any(len(r) != 3 for r in rows):
        raise SceneError(element, "a full inertia must be a 3x3 matrix")
    i = [[scene._num(element, v, "inertia") for v in r] for r in rows]
    for a, b in ((0, 1), (0, 2), (1, 2)):
        if sp.simplify(i[a][b] - i[b][a]) != 0:
            raise SceneError(element, f"the 3x3 inertia is not symmetric: entry ({a + 1},{b + 1}) = {i[a][b]} "
                                      f"but ({b + 1},{a + 1}) = {i[b][a]}")
    return [i[0][0], i[1][1], i[2][2], i[0][1], i[0][2], i[1][2]]


def bounded_number(element: str, what: str, value, symbols=None, magnitude: bool = True) -> sp.Expr:
    """``parse_exact(value)`` within the limits of :mod:`symgen.scene.input_limits` (the text is judged
    before it is parsed, the exact value after, unless ``magnitude`` is false)."""
    problem = number_text_problem(value) if isinstance(value, str) else None
    if problem is None:
        try:
            out = parse_exact(value, symbols)
        except ValueError as exc:
            raise SceneError(element, f"{what}: {exc}") from None
        problem = magnitude_problem(out) if magnitude else None
        if problem is None:
            return out
    raise SceneError(element, f"{what}: {problem}")


#: a violation of positive semi-definiteness or of the triangle inequality smaller than this share of
#: the largest principal moment is rounding (CAD exports write inertias to about six digits): the
#: scene accepts it with an :class:`~symgen.errors.InertiaWarning`
INERTIA_TOLERANCE = 1e-6
#: below this share of the largest principal moment a violation is the eigenvalue solver's noise
INERTIA_NOISE = 1e-12


def inertia_violation(inertia) -> tuple[str, float, np.ndarray] | None:
    """``(what, size, principal moments)`` when the 3x3 rotational inertia is not one of a rigid
    body, else None. With the principal moments ``a <= b <= c``, sizes are relative to the largest
    magnitude ``s``: ``-a / s`` for a negative moment (not positive semi-definite) and
    ``(c - a - b) / s`` when the triangle inequality ``a + b >= c`` is broken; ``size`` is the larger,
    ``what`` names both when both are broken. Sizes up to :data:`INERTIA_NOISE` are not violations."""
    eig = np.linalg.eigvalsh(np.array(inertia, dtype=float))
    scale = max(1e-300, float(np.max(np.abs(eig))))
    a, b, c = eig
    found = [(what, size) for what, size in (("is not positive semi-definite", -a / scale),
                                             ("violates the triangle inequality", (c - a - b) / scale))
             if size > INERTIA_NOISE]
    if not found:
        return None
    return " and ".join(w for w, _ in found), float(max(s for _, s in found)), eig


def describe_violation(violation) -> str:
    """``"violates the triangle inequality ... by 3.2e-07 of its largest principal moment (moments ...)"``."""
    what, size, eig = violation
    return (f"{what} by {size:.3g} of its largest principal moment (principal moments "
            f"{', '.join(f'{v:.6g}' for v in eig)}; no rigid body has such an inertia)")


def check_mass_properties(element: str, body: Body, params: dict) -> None:
    """Mass >= 0; inertia symmetric, positive semi-definite and obeying the triangle inequality
    within :data:`INERTIA_TOLERANCE`; zero when the mass is."""
    try:
        m = float(body.mass.xreplace(params))
        inertia = [[float(v.xreplace(params)) for v in body.inertia.row(i)] for i in range(3)]
    except TypeError:
        raise SceneError(element, "mass and inertia need numeric values (declare parameter values)") from None
    if m < 0:
        raise SceneError(element, f"mass {m:g} is negative")
    violation = inertia_violation(inertia)
    if violation is not None and violation[1] > INERTIA_TOLERANCE:
        raise SceneError(element, f"rotational inertia {describe_violation(violation)}")
    if violation is not None:
        warnings.warn(InertiaWarning(f"{element}: rotational inertia {describe_violation(violation)}; accepted as "
                                     f"rounding (up to {INERTIA_TOLERANCE:g})"), stacklevel=4)
    if m == 0 and any(v != 0 for row in inertia for v in row):
        raise SceneError(element, "a massless body must have zero inertia")


def check_topology(scene) -> None:
    parents: dict[str, list[str]] = {}
    for j in scene.joints.values():
        parents.setdefault(j.child, []).append(j.name)
    for body, joints in parents.items():
        if len(joints) > 1:
            raise TopologyError(
                f"body {body!r}",
                f"is the child of joints {', '.join(map(repr, joints))}: a kinematic loop with no "
                "closure. Cut the loop: give one of these joints a new massless child body and tie "
                "that body to this one with a constraint (weld, planar_weld or ball)")
    for name in scene.bodies:
        if name not in parents:
            raise TopologyError(f"body {name!r}", "is not attached to anything by a joint")
    order = scene.tree_order()
    if len(order) != len(scene.joints):
        stuck = [j.name for j in scene.joints.values() if j not in order]
        raise TopologyError(f"joint {stuck[0]!r}",
                            f"joints {stuck} form a cycle not connected to the world")
