"""Constraint rows that vanish identically or depend on the others on the constraint manifold.

Files written for other tools state loop closures generously: MJCF's ``connect`` always removes
three translations, even where it closes a planar loop and the translation normal to the plane is
already impossible (its row of ``T``, eq. 6, is zero everywhere); a ``weld`` closing a planar
loop has three such rows. :func:`drop_vanishing_rows` finds them and removes them, with a note
naming each one, so that ``T`` has full row rank as eq. (6) requires.

Procedure: at the reference configuration rows are kept greedily, in scene order, while they
raise the rank of ``T`` (tolerance :data:`symgen.steps.structure.RANK_TOL`); a dropped row is
checked at :data:`CHECK_STATES` random loop-closed states of the reduced scene (seeded): its
position residual must stay zero and its row must stay in the span of the kept rows. A row that
passes is dependent on the manifold, not just at ``q0``; one that fails means ``q0`` is a
singular configuration, and the error says so.
"""
from __future__ import annotations

import numpy as np

from .errors import ConstraintError
from .scene.declaration import Constraint, Scene
from .steps.structure import RANK_TOL

#: random loop-closed states at which a dropped row is checked
CHECK_STATES = 5
#: a dropped row's position residual and its distance to the kept rows' span must stay below this
MANIFOLD_TOL = 1e-9


def _rank(a: np.ndarray, scale: float) -> int:
    if a.size == 0:
        return 0
    s = np.linalg.svd(a, compute_uv=False)
    return int(np.sum(s > RANK_TOL * scale))


def _rows_at(scene: Scene, config=None):
    """``(T, residual)`` of all constraint rows (float) at ``config`` (default ``q0``)."""
    from .math.fields import make_field
    from .kinematics import constraint_matrix, tree_kinematics
    from .model import reference_configuration
    from .tree import build_tree

    tree = build_tree(scene)
    config = reference_configuration(scene) if config is None else config
    kin = tree_kinematics(tree, make_field("float", tree.parameters), config)
    t = constraint_matrix(kin, scene.constraints.values()).v.astype(float)
    from .closure import kinematics_residual

    return t, kinematics_residual(kin, scene.constraints.values(), config)


def _labels(scene: Scene) -> list[tuple[str, str]]:
    return [(con.name, c) for con in scene.constraints.values() for c in con.components]


def _keep_rows(t: np.ndarray) -> list[int]:
    scale = max(float(np.max(np.abs(t))), 1e-300) if t.size else 1.0
    kept: list[int] = []
    for i in range(t.shape[0]):
        if _rank(t[kept + [i]], scale) > len(kept):
            kept.append(i)
    return kept


def _reduced(scene: Scene, labels, kept) -> Scene:
    import copy

    out = copy.deepcopy(scene)
    keep = {labels[i] for i in kept}
    out.constraints = {}
    for con in scene.constraints.values():
        comps = tuple(c for c in con.components if (con.name, c) in keep)
        if comps:
            out.constraints[con.name] = (con if comps == con.components else
                                         Constraint(con.name, "custom", con.frame_a, con.frame_b, comps))
    return out


def _check_on_manifold(reduced: Scene, full: Scene, kept, dropped, labels) -> None:
    from .closure import random_consistent_states
    from .model import derive

    if reduced.motion is None:          # the states only need the partition: any m joint rates do
        import copy

        reduced = copy.deepcopy(reduced)
        m = sum(j.dof for j in reduced.joints.values()) - len(kept)
        reduced.set_motion(joints=[j.name for j in reduced.joints.values() if j.dof == 1][:m])
    model = derive(reduced, check_reference=False)
    for config, _ in random_consistent_states(model, CHECK_STATES, seed=0, spread=0.2):
        t, res = _rows_at(full, config)
        q, _ = np.linalg.qr(t[kept].T)
        for i in dropped:
            off_span = np.linalg.norm(t[i] - q @ (q.T @ t[i]))
            if abs(res[i]) > MANIFOLD_TOL or off_span > MANIFOLD_TOL * max(1.0, np.linalg.norm(t[i])):
                name, comp = labels[i]
                raise ConstraintError(f"constraint {name!r}", f"component {comp} depends on the other constraint "
                                      "rows at the reference configuration only: q0 is a singular configuration "
                                      "of the loop; choose another q0")


def drop_vanishing_rows(scene: Scene) -> Scene:
    """``scene`` without its constraint rows that vanish identically or depend on the others on the
    constraint manifold (see the module docstring); the scene itself if there are none. Each
    dropped row is named in ``Scene.notes`` of the result."""
    if not scene.constraints:
        return scene
    t, _ = _rows_at(scene)
    labels = _labels(scene)
    kept = _keep_rows(t)
    dropped = [i for i in range(len(labels)) if i not in kept]
    if not dropped:
        return scene
    reduced = _reduced(scene, labels, kept)
    _check_on_manifold(reduced, scene, kept, dropped, labels)
    for i in dropped:
        name, comp = labels[i]
        why = "vanishes identically" if not np.any(np.abs(t[i]) > RANK_TOL * max(1.0, float(np.max(np.abs(t))))) \
            else "depends on the other rows on the constraint manifold"
        reduced.notes.append(f"constraint {name!r}: dropped component {comp} (its row of T, eq. 6, {why})")
    return reduced
