"""``four_bar`` and ``five_bar`` -- planar closed chains (the paper's footnote 4 and Section 2).

Both mechanisms move in the world x-y plane with every revolute axis along z. Each kinematic loop
is cut at one joint: the cut joint's child is a massless body ``pin`` carrying ``pin_frame``, and
a ``planar_weld`` constraint (``vx, vy, wz`` in ``pin_frame``) ties it to the frame where the loop
closes. All loop constraints fall on passive joints: ``n_p = n_c = 3`` (eq. 7), so ``T_u1 = T_u``,
the passive rates follow from eq. (10) and there are no constraint forces (``n = m``).

``four_bar``: a parallelogram four-bar. Ground pivots A = (0, 0, 0) and D = (d, 0, 0), crank and
rocker of length a, coupler of length d (d = 0.3 m, a = 0.1 m). ``j1`` (world -> crank, actuated),
``j2`` (crank -> coupler), ``j3`` (coupler -> rocker), ``j4`` (rocker -> pin) passive; the world
frame ``ground_pin`` sits at D. Reference configuration: crank at 60 degrees, exact:
``q0 = (pi/3, -pi/3, -2 pi/3, 2 pi/3)`` (coupler horizontal, rocker parallel to the crank, the
pin frame back at D with the world orientation). Counts: ``n_1a = 1``, ``n_1u = 3``, ``m = 1``,
``n_c = n_p = 3``, ``n = 1``.

``five_bar``: a planar five-bar (2-DOF parallel manipulator). Base pivots A = (0, 0, 0) and
B = (d, 0, 0), d = 0.2 m; proximal links (0.15 m) driven by ``j1`` at A and ``j2`` at B; distal
links (0.2 m) on passive elbows ``j3``, ``j4``; passive ``j5`` at the end of distal link 1 carries
the massless ``pin``; the frame ``tip2`` sits at the end of distal link 2. Reference configuration:
the tip at C = (0.09, 0.23), elbows out (the "+ -" working mode: elbow 1 left of A->C, elbow 2
right of B->C), found by intersecting circles in 50-digit arithmetic; ``q5`` turns ``pin`` to
the orientation of distal link 2, so ``tip2`` is the plain end point of that link. Counts:
``n_1a = 2``, ``n_1u = 3``, ``m = 2``, ``n_c = n_p = 3``, ``n = 2``.
"""
from __future__ import annotations

from fractions import Fraction

import mpmath

from ...math.numbers import DPS, to_exact
from ...scene.declaration import WORLD, Scene
from ...math.spatial import bar_inertia

LINK_WIDTH = Fraction(2, 100)
#: mass per metre of the planar links (kg/m)
LINEAR_DENSITY = Fraction(2)


def _add_link(scene: Scene, name: str, length) -> None:
    """A slender planar link along its frame's x axis, from the joint at its origin."""
    length = Fraction(length)
    mass = LINEAR_DENSITY * length
    scene.add_body(name, mass, com=(length / 2, 0, 0), inertia=bar_inertia(mass, length, LINK_WIDTH))


# ---------------------------------------------------------------------------------- four-bar
FOUR_BAR_D = Fraction("0.3")
FOUR_BAR_A = Fraction("0.1")


def four_bar() -> Scene:
    """A planar parallelogram four-bar driven at the crank (one loop cut at the rocker's pivot)."""
    d, a = FOUR_BAR_D, FOUR_BAR_A
    scene = Scene(name="four_bar",
                  description="planar parallelogram four-bar, crank driven: m = 1, n_c = n_p = 3")
    _add_link(scene, "crank", a)
    _add_link(scene, "coupler", d)
    _add_link(scene, "rocker", a)      # from the coupler's end down to the ground pivot D
    scene.add_body("pin", 0)
    scene.add_joint("j1", "revolute", WORLD, "crank", axis="z", actuated=True, q0="pi/3")
    scene.add_joint("j2", "revolute", "crank", "coupler", xyz=(a, 0, 0), axis="z", q0="-pi/3")
    scene.add_joint("j3", "revolute", "coupler", "rocker", xyz=(d, 0, 0), axis="z", q0="-2*pi/3")
    scene.add_joint("j4", "revolute", "rocker", "pin", xyz=(a, 0, 0), axis="z", q0="2*pi/3")
    scene.add_frame("pin_frame", "pin")
    scene.add_frame("ground_pin", WORLD, xyz=(d, 0, 0))
    scene.add_constraint("closure", "planar_weld", "pin_frame", "ground_pin", normal="z")
    scene.set_motion(joints=["j1"])
    return scene


# ---------------------------------------------------------------------------------- five-bar
FIVE_BAR_D = Fraction("0.2")
FIVE_BAR_PROXIMAL = Fraction("0.15")
FIVE_BAR_DISTAL = Fraction("0.2")
FIVE_BAR_TIP = (Fraction("0.09"), Fraction("0.23"))


def _elbow(base, tip, proximal, distal, side: int):
    """The elbow point of a two-link chain from ``base`` to ``tip``: the intersection of the
    circles |E - base| = proximal and |E - tip| = distal on the left (``side = 1``) or the right
    (``side = -1``) of the line base -> tip."""
    bx, by = base
    tx, ty = tip
    dx, dy = tx - bx, ty - by
    dist = mpmath.sqrt(dx * dx + dy * dy)
    along = (proximal ** 2 - distal ** 2 + dist ** 2) / (2 * dist)
    across = mpmath.sqrt(proximal ** 2 - along ** 2)
    ux, uy = dx / dist, dy / dist
    return bx + along * ux - side * across * uy, by + along * uy + side * across * ux


def _wrap(angle):
    """Angle in (-pi, pi]."""
    return angle - 2 * mpmath.pi * mpmath.ceil((angle - mpmath.pi) / (2 * mpmath.pi))


def five_bar_reference() -> dict:
    """``q0`` of the five-bar joints (exact Fractions) by inverse kinematics of the tip C."""
    with mpmath.workdps(DPS):
        d, l1, l2 = (mpmath.mpf(x.numerator) / x.denominator for x in (FIVE_BAR_D, FIVE_BAR_PROXIMAL, FIVE_BAR_DISTAL))
        tip = tuple(mpmath.mpf(x.numerator) / x.denominator for x in FIVE_BAR_TIP)
        a, b = (mpmath.mpf(0), mpmath.mpf(0)), (d, mpmath.mpf(0))
        e1, e2 = _elbow(a, tip, l1, l2, side=1), _elbow(b, tip, l1, l2, side=-1)
        th1 = mpmath.atan2(e1[1] - a[1], e1[0] - a[0])
        th2 = mpmath.atan2(e2[1] - b[1], e2[0] - b[0])
        phi1 = mpmath.atan2(tip[1] - e1[1], tip[0] - e1[0])     # distal link 1, absolute
        phi2 = mpmath.atan2(tip[1] - e2[1], tip[0] - e2[0])     # distal link 2, absolute
        q = dict(j1=th1, j2=th2, j3=_wrap(phi1 - th1), j4=_wrap(phi2 - th2), j5=_wrap(phi2 - phi1))
        return {k: to_exact(v) for k, v in q.items()}


def five_bar() -> Scene:
    """A planar five-bar driven at both base joints (one loop cut at the tip)."""
    d, l1, l2 = FIVE_BAR_D, FIVE_BAR_PROXIMAL, FIVE_BAR_DISTAL
    q0 = five_bar_reference()
    scene = Scene(name="five_bar",
                  description="planar five-bar, both base joints driven: m = 2, n_c = n_p = 3")
    for name, length in (("proximal1", l1), ("proximal2", l1), ("distal1", l2), ("distal2", l2)):
        _add_link(scene, name, length)
    scene.add_body("pin", 0)
    scene.add_joint("j1", "revolute", WORLD, "proximal1", axis="z", actuated=True, q0=q0["j1"])
    scene.add_joint("j2", "revolute", WORLD, "proximal2", xyz=(d, 0, 0), axis="z", actuated=True, q0=q0["j2"])
    scene.add_joint("j3", "revolute", "proximal1", "distal1", xyz=(l1, 0, 0), axis="z", q0=q0["j3"])
    scene.add_joint("j4", "revolute", "proximal2", "distal2", xyz=(l1, 0, 0), axis="z", q0=q0["j4"])
    scene.add_joint("j5", "revolute", "distal1", "pin", xyz=(l2, 0, 0), axis="z", q0=q0["j5"])
    scene.add_frame("pin_frame", "pin")
    scene.add_frame("tip2", "distal2", xyz=(l2, 0, 0))
    scene.add_constraint("closure", "planar_weld", "pin_frame", "tip2", normal="z")
    scene.set_motion(joints=["j1", "j2"])
    return scene
