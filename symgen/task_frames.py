"""Checks of the task coordinates ``V_m`` at the reference configuration: the gamma-weighted
frames of Section 3.3 must coincide, and a singular ``[J_m; J_f]`` (eq. 18) is traced to the motion
entry that makes it so (:func:`singular_task_hint`).

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


def dependent_motion_entry(a: np.ndarray, m: int, max_condition: float) -> int | None:
    """The first row ``i < m`` of ``A = [J_m; J_f]`` (eq. 18, floats) whose motion entry depends on
    ``J_f`` and the motion entries before it: ``[J_m[:i+1]; J_f]`` has condition number above
    ``max_condition``; ``None`` if no single row is to blame (e.g. ``J_f`` alone is rank deficient)."""
    a = np.asarray(a, dtype=float)
    j_f = a[m:]
    for i in range(m):
        rows = np.vstack([a[: i + 1], j_f])
        s = np.linalg.svd(rows, compute_uv=False)
        if not s[-1] or s[0] / s[-1] > max_condition:
            return i
    return None


def singular_task_hint(motion, a: np.ndarray, max_condition: float) -> str:
    """The hint of the :class:`~symgen.errors.SingularConfigurationError` raised for a singular
    ``[J_m; J_f]`` at ``q0``: the motion entry (frame component or joint rate, by
    :meth:`~symgen.scene.elements.Motion.labels`) whose row depends on the constraint rows and the
    entries before it, and every entry of ``V_m`` in order."""
    labels = motion.labels()
    i = dependent_motion_entry(a, len(labels), max_condition)
    where = (f"motion entry {labels[i]!r} (row {i + 1} of V_m) depends on J_f and the entries before it; "
             if i is not None else "")
    return (f"{where}V_m = {labels}: choose another q0 or other motion coordinates "
            "(frame components or joint rates)")
