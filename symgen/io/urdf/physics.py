"""What the physics allows of a URDF's mass properties, and what the reader says about the rest.

URDF files exported from CAD or written by hand often hold inertias that no rigid body has, dummy
links, or a base meant to float. Each link's ``<inertial>`` is judged where the link ends up
(:mod:`symgen.io.urdf.build` knows which links are welded to the world):

* A link **welded to the world** (the root link, and every link fixed to it) carries no dynamics
  on a fixed base: whatever its inertial says is noted in ``scene.notes`` and left out.
* A rotational inertia that is **not positive semi-definite** or breaks the **triangle
  inequality** (:func:`symgen.scene.checks.inertia_violation`, measured as a share of its largest
  principal moment) is handled by the reader option ``inertia``:

  - ``"warn"`` (default): a violation of at most :data:`~symgen.scene.checks.INERTIA_TOLERANCE`
    (1e-6, the rounding of inertias written to six digits) is kept as written, with an
    :class:`InertiaWarning` and a note naming the link and the size; a larger one is an
    :class:`~symgen.io.urdf.parse.UrdfError` naming the link.
  - ``"repair"``: every violation is replaced by the nearest physically consistent inertia
    (:func:`~symgen.io.urdf.inertia.repaired_inertia`, exact), with a warning and a note giving the
    size of the violation and of the change.
  - ``"strict"``: every violation, and every inertia on a zero-mass link, is an error (also on links
    welded to the world).

* Rotational inertia **entries below** :data:`TINY_INERTIA` (1e-15 kg m^2, a microgram at a
  millimetre: CAD export noise such as iCub's 1.4e-20) are rounded to zero first, with a note,
  so that noise cannot make an inertia fail the checks below.
* A link of **zero mass with a non-zero inertia** keeps its rotational inertia, as Pinocchio does
  (a mass-less rotor merged into its body), with a warning and a note (``"strict"``: an error).
* A **root link that looks like a free body** -- it carries mass and at least two moving joints
  leave it (legged robots, humanoids, mobile bases; Solo12, Go2, A1, Laikago, Talos) -- is loaded
  welded to the world, with a :class:`FixedBaseWarning` and a note that say so and point to
  ``floating=True`` for a floating base.
"""
from __future__ import annotations

import warnings

import sympy as sp

from ... import errors
from ...scene.checks import INERTIA_TOLERANCE, describe_violation, inertia_violation
from ...scene.declaration import WORLD
from .inertia import MassProperties, repaired_inertia
from .parse import UrdfError, UrdfRobot

#: rotational inertia entries (kg m^2) smaller than this in magnitude are rounded to zero (noted)
TINY_INERTIA = sp.Rational(1, 10**15)

#: values of the reader option ``inertia``
INERTIA_MODES = ("warn", "repair", "strict")


class UrdfWarning(UserWarning):
    """symgen loaded a URDF but changed or left out something it says; also in ``scene.notes``."""


class InertiaWarning(UrdfWarning, errors.InertiaWarning):
    """A link's inertia is not one of a rigid body (kept or repaired), or a zero-mass link has one."""


class MasslessJointWarning(UrdfWarning):
    """A moving joint (with the joints that mimic it) moves no mass: it is locked like a fixed joint."""


class FixedBaseWarning(UrdfWarning, errors.FixedBaseWarning):
    """The root link looks like a free body, and symgen loads it welded to the world."""


def check_inertia_mode(mode) -> str:
    if mode not in INERTIA_MODES:
        raise UrdfError("option inertia", f"must be one of {', '.join(map(repr, INERTIA_MODES))}, got {mode!r}")
    return mode


def _refuse(robot: UrdfRobot, name: str, message: str, hint: str) -> UrdfError:
    link = robot.links[name]
    return robot.error(f"link {name!r}", f"{message}; {hint}", link.inertia_line or link.line)


def judged_inertials(robot: UrdfRobot, owner: dict, mode: str) -> tuple[dict, list]:
    """``({link: MassProperties to use}, [(warning class or None, note)])`` for every link with an
    ``<inertial>`` (see the module docstring); raises :class:`UrdfError` for the first refused link."""
    out, findings = {}, []
    for name, link in robot.links.items():
        props = link.inertial
        if props is None:
            continue
        props = _without_tiny_entries(name, props, findings)
        violation = inertia_violation(props.inertia)
        rotor = props.mass == 0 and any(v != 0 for v in props.inertia)
        if mode == "strict" and (violation or rotor):
            what = describe_violation(violation) if violation else "is not zero on a link of zero mass"
            raise _refuse(robot, name, f"rotational inertia {what}",
                          "inertia='warn' accepts rounding, inertia='repair' makes it physically consistent")
        if owner[name] == WORLD:
            if violation or rotor:
                findings.append((None, f"link {name!r} is welded to the world, so its mass properties do not "
                                       f"enter the dynamics; its rotational inertia "
                                       f"{describe_violation(violation) if violation else 'is not zero at zero mass'}"
                                       ": left out"))
            continue
        if violation is not None:
            props = _judged_violation(robot, name, props, violation, mode, findings)
        if rotor:
            findings.append((InertiaWarning, f"link {name!r} has zero mass and a non-zero rotational inertia: kept "
                                             "as a mass-less rotor merged into its body, as Pinocchio does"))
        out[name] = props
    return out, findings


def rounded_inertia(inertia: sp.ImmutableMatrix) -> sp.ImmutableMatrix:
    """``inertia`` with its entries below :data:`TINY_INERTIA` in magnitude set to zero."""
    return sp.ImmutableMatrix(inertia.applyfunc(lambda v: 0 if abs(v) < TINY_INERTIA else v))


def _without_tiny_entries(name: str, props: MassProperties, findings: list) -> MassProperties:
    """``props`` with its inertia entries below :data:`TINY_INERTIA` in magnitude set to zero (a note
    names the link and the largest entry rounded)."""
    tiny = [v for v in props.inertia if v != 0 and abs(v) < TINY_INERTIA]
    if not tiny:
        return props
    rounded = rounded_inertia(props.inertia)
    findings.append((None, f"link {name!r}: {len(tiny)} rotational inertia entries below {float(TINY_INERTIA):g} "
                           f"kg m^2 (largest {max(abs(float(v)) for v in tiny):.3g}) rounded to zero"))
    return MassProperties(props.mass, props.com, rounded)


def _judged_violation(robot, name, props: MassProperties, violation, mode: str, findings: list) -> MassProperties:
    size = violation[1]
    if mode == "repair":
        fixed = repaired_inertia(props.inertia)
        change = max(abs(float(v)) for v in sp.Matrix(fixed) - sp.Matrix(props.inertia))
        findings.append((InertiaWarning, f"link {name!r}: rotational inertia {describe_violation(violation)}; "
                                         f"repaired to the nearest physically consistent inertia (largest entry "
                                         f"change {change:.3g})"))
        return MassProperties(props.mass, props.com, fixed)
    if size > INERTIA_TOLERANCE:
        raise _refuse(robot, name, f"rotational inertia {describe_violation(violation)}, more than the "
                                   f"{INERTIA_TOLERANCE:g} accepted as rounding",
                      "inertia='repair' replaces it by the nearest physically consistent inertia")
    findings.append((InertiaWarning, f"link {name!r}: rotational inertia {describe_violation(violation)} "
                                     f"(within the {INERTIA_TOLERANCE:g} accepted as rounding): kept as written"))
    return props


def free_base_finding(robot: UrdfRobot, owner: dict, moving: list) -> tuple | None:
    """A :class:`FixedBaseWarning` finding when the root link looks like a free body, else None."""
    welded = [n for n, body in owner.items() if body == WORLD]
    mass = sum((robot.links[n].inertial.mass for n in welded if robot.links[n].inertial is not None), sp.Integer(0))
    branches = [j.name for j, parent, *_ in moving if parent == WORLD]
    if mass == 0 or len(branches) < 2:
        return None
    return (FixedBaseWarning, f"root link {robot.root!r} carries {float(mass):.6g} kg and {len(branches)} moving "
                              f"joints leave it ({', '.join(branches[:4])}{', ...' if len(branches) > 4 else ''}): it "
                              "looks like a free body, and it is loaded welded to the world (a fixed base); pass "
                              "floating=True for a floating base")


def report(scene, findings: list, prefix: str = "") -> None:
    """Each finding into ``scene.notes``, and those with a warning class as a Python warning."""
    for category, text in findings:
        note = f"URDF {prefix}: {text}" if prefix else f"URDF: {text}"
        scene.notes.append(note)
        if category is not None:
            warnings.warn(category(note), stacklevel=4)
