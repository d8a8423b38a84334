"""Frame poses and the loop forces as wrenches, in the axes a user wants.

:meth:`~symgen.model.Model.loop_forces` gives the multipliers ``lam`` of ``M qdd + h = tau + T^T
lam`` component by component, in the axes of each constraint's frame A (eq. 6 rows): the force or
moment about A's origin that the constraint exerts on the body of A. Here they become one 6-vector
``[f; m]`` per constraint (the components a constraint does not have are zero: it exerts nothing
along them), in A's axes, in the world's (``R_W_A [f; m]``) or in B's (``R_W_B^T R_W_A [f; m]``),
the moment still about A's origin and the wrench still the one on A's body in each. The body of
frame B receives the opposite wrench.
"""
from __future__ import annotations

import numpy as np

from .errors import StateError
from .kinematics import tree_kinematics
from .math.configuration import as_configuration
from .math.spatial import COMPONENTS

#: the axes :func:`constraint_wrenches` can express the wrenches in
AXES = ("A", "world", "B")


def _kinematics(model, config):
    fld = model.float_field
    return tree_kinematics(model.tree, fld, fld.configuration(as_configuration(config, model.scene, "config"),
                                                                 model.tree))


def _pose(kin, name: str) -> tuple[np.ndarray, np.ndarray]:
    r, p = kin.frame_pose(name)
    return np.asarray(r.v, dtype=float), np.asarray(p.v, dtype=float)


def frame_pose(model, config, name: str) -> tuple[np.ndarray, np.ndarray]:
    """``(R_W_F, p_W_F)``: the rotation and origin of the named frame ``F`` in the world at
    ``config`` (any state form of :func:`~symgen.math.configuration.as_configuration`), floats."""
    from .frame_kinematics import model_frame_pose

    return model_frame_pose(model, config, name)


def constraint_wrenches(model, config, lam, axes: str = "A") -> dict[str, np.ndarray]:
    """``{constraint: [f; m]}`` from the loop forces ``lam`` (in the order of
    :meth:`~symgen.model.Model.constraint_force_names`), on the body of frame A, moment about A's
    origin, in ``axes``: ``"A"`` (frame A's), ``"world"`` or ``"B"`` (frame B's). ``O(n)`` per
    constraint for the poses. Joint couplings are left out (their force, a generalized joint
    force, is in :meth:`~symgen.model.Model.loop_forces`)."""
    if axes not in AXES:
        raise StateError(f"axes must be one of {', '.join(AXES)}, got {axes!r}")
    lam = np.asarray(lam, dtype=float)
    kin = _kinematics(model, config) if axes != "A" else None
    out, k = {}, 0
    for con in model.scene.constraints.values():
        if con.is_coupling:              # a joint coupling exerts a joint force, no wrench of two frames
            k += con.dim
            continue
        wrench = np.zeros(6)
        for comp in con.components:
            wrench[COMPONENTS.index(comp)] = lam[k]
            k += 1
        if kin is not None:
            r, _ = _pose(kin, con.frame_a)                       # R_W_A
            if axes == "B":
                r = _pose(kin, con.frame_b)[0].T @ r            # R_B_A = R_W_B^T R_W_A
            wrench = np.concatenate([r @ wrench[:3], r @ wrench[3:]])
        out[con.name] = wrench
    return out
