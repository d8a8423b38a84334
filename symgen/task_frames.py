"""The gamma-weighted task of Section 3.3 needs its frames to coincide.

``V_m = sum_i gamma_i T_m X_i`` (``J_m = H J``, ``H = [gamma_1 1, ..., gamma_h 1]``) is the twist
of *one* frame -- the held object's frame O -- only when every weighted frame ``O_i`` is that same
frame: same origin, same axes. The closure constraints (welds between the ``O_i``) then keep them
together for all time, so it suffices that they coincide at the reference configuration ``q0``.
Frames that only meet somewhere else would give a ``V_m`` that is a weighted mix of twists at
different points, whose rate is not the object's acceleration.
"""
from __future__ import annotations

import numpy as np

from .errors import SceneError

#: the weighted frames' origins (m) and axes must agree to this at q0
COINCIDE_TOL = 1e-9


def check_weighted_frames(scene, tree, config) -> None:
    """Raise :class:`SceneError` (element ``motion``) if the weighted frames of ``scene.motion`` do
    not coincide at ``config`` (the reference configuration)."""
    motion = scene.motion
    if motion is None or len(motion.frames) < 2:
        return
    from .math.fields import make_field
    from .kinematics import tree_kinematics

    kin = tree_kinematics(tree, make_field("float", tree.parameters), config)
    poses = {name: tuple(np.asarray(j.v, float) for j in kin.frame_pose(name)) for name, _ in motion.frames}
    (first, (r0, p0)), *rest = poses.items()
    for name, (r, p) in rest:
        dp, dr = float(np.max(np.abs(p - p0))), float(np.max(np.abs(r - r0)))
        if dp > COINCIDE_TOL or dr > COINCIDE_TOL:
            raise SceneError("motion", f"the gamma-weighted frames {first!r} and {name!r} must coincide at the "
                                       f"reference configuration q0 (Section 3.3: V_m = sum gamma_i X_i is the "
                                       f"twist of the held object's frame only if every weighted frame is that "
                                       f"frame); they are {dp:.3g} m apart and their axes differ by {dr:.3g}. "
                                       "Place each arm's frame at the object's frame (the welds keep them together)")
