"""URDF robots as symgen scenes, and the constraint overlay that puts them in contact or in a loop.

* :func:`scene_from_urdf` -- one URDF file to a :class:`~symgen.scene.Scene` (fixed base, every
  moving joint actuated, ``V_m = qd``); :func:`add_urdf` adds a robot to an existing scene (with a
  name prefix and a base placement, so one file can be used several times).
* :mod:`symgen.io.urdf.physics` -- what is accepted of imperfect inertias, dummy links and free-looking
  bases (option ``inertia="warn" | "repair" | "strict"``), said by :class:`UrdfWarning` and ``scene.notes``.
* :func:`read_urdf` -- the parsed file (:class:`UrdfRobot`), exact numbers and line numbers.
* :mod:`symgen.io.urdf.overlay` -- "this frame slides on a plane" (:func:`add_contact`), "these
  frames hold one object" (:func:`add_hold`), "close a loop between these frames"
  (:func:`add_closure`), placed at the reference configuration.
* :mod:`symgen.io.urdf.examples` -- real robots from the ``example-robot-data`` package (UR5, Panda)
  and the paper's scenes built on them.

Reading URDF needs the extra ``urdf`` (yourdfpy, lxml); nothing is imported until used.
"""
from .build import NoMovingJointError, UrdfSource, add_urdf, scene_from_urdf, scene_name
from .overlay import add_closure, add_contact, add_hold
from .parse import JointLimits, UrdfError, UrdfRobot, read_urdf
from .physics import FixedBaseWarning, InertiaWarning, UrdfWarning

__all__ = ["FixedBaseWarning", "InertiaWarning", "JointLimits", "NoMovingJointError", "UrdfError", "UrdfRobot",
           "UrdfSource", "UrdfWarning", "add_closure", "add_contact", "add_hold", "add_urdf", "read_urdf",
           "scene_from_urdf", "scene_name"]
