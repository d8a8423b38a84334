"""Cassie, Agility Robotics' biped, from the SDF file of ``example-robot-data``
(``cassie_description/robots/cassie_v2.sdf``) with its four closed leg linkages.

The file has 23 links, 22 revolute joints and 4 ``ball`` joints. Each ``ball`` joint closes a loop
(:mod:`symgen.io.sdf.build`), two per leg:

* ``<side>-pitch-rod-joint``: the achilles rod, hinged at the heel spring, meets the hip-pitch link
  (loop knee - shin - tarsus - heel spring - achilles rod, 3 rows of ``T``);
* ``<side>-plantar-foot-joint``: the plantar rod, driven by the foot crank, meets the foot (a planar
  four-bar tarsus - crank - rod - foot, whose out-of-plane row vanishes and is dropped: 2 rows).

So ``n_c = 4 x 3 - 2 = 10``. With the free base (6) and 22 joint rates, ``n = 28`` rates and
``m = 18`` motion DOF: the base's six, Cassie's ten motors (hip roll, yaw and pitch, knee and foot
of each leg: the joints ``*-op``, the only actuated ones) and the knee-shin spring of each leg.
The other ten joint rates (shin-tarsus, tarsus heel spring, achilles-spring, foot crank and
crank-rod of each leg) are passive and dependent: ``n_p = 10``, eliminated by eq. (10).

The file writes pi/2 as ``1.5708``; with ``snap=1e-5`` those angles are exact multiples of pi/2,
which makes the foot four-bars exactly planar, as drawn. The two ``ball`` joints of the achilles
rods carry ``<damping>0.01</damping>``, which a constraint cannot carry: it is left out with a
note, and so is the file's simulator ``<plugin>``. The springs (knee-shin 1500 N m/rad, heel
1250 N m/rad, at reference 0) and joint damping are read. The reference configuration is the
file's drawn pose (every joint at 0, the pelvis at 1.01 m), where the loops close.

=================  ==============================================================
``cassie``         on a free base, no contact: ``V_m`` = base twist, 10 motors, 2 springs
``cassie_fixed``   the pelvis welded to the world where drawn: ``m = 12``
=================  ==============================================================
"""
from __future__ import annotations

from ...scene.declaration import Scene
from ..urdf.examples import example_path
from .build import FLOATING_BASE, scene_from_sdf
from .parse import read_sdf

SIDES = ("left", "right")
#: Cassie's ten motors
MOTORS = tuple(f"{s}-{j}-op" for s in SIDES for j in ("roll", "yaw", "pitch", "knee", "foot"))
#: the joint rate of each leg that is neither a motor nor eliminated: the knee-shin spring
SPRINGS = tuple(f"{s}-knee-shin-joint" for s in SIDES)
SNAP = 1e-5


def _cassie(name: str, floating: bool, description: str) -> Scene:
    model = read_sdf(example_path("cassie"))
    scene = scene_from_sdf(model, name=name, floating=floating, actuated=MOTORS, closure_dynamics="note",
                           snap=SNAP, validate=False)
    scene.description = description
    base = [f"{FLOATING_BASE}_{a}" for a in ("x", "y", "z", "rot")] if floating else []
    scene.set_motion(joints=base + [j.replace("-", "_") for j in MOTORS + SPRINGS])
    scene.validate()
    return scene


def cassie() -> Scene:
    """Cassie on a free base with its four loop closures: ``n = 28``, ``n_c = 10``, ``m = 18``."""
    return _cassie("cassie", True, "Cassie biped on a free base, four leg loops closed (SDF): m = 18, n_c = 10")


def cassie_fixed() -> Scene:
    """Cassie with the pelvis welded where drawn: ``n = 22``, ``n_c = 10``, ``m = 12``."""
    return _cassie("cassie_fixed", False, "Cassie biped, pelvis fixed, four leg loops closed (SDF): m = 12, n_c = 10")
