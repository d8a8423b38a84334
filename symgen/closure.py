"""Position-level loop closure: residuals, a Newton solve, and random consistent states.

For a constraint between frames A and B the residual is the pose of B relative to A in A's axes,
``[^A p_B; log(^A R_B)]``, restricted to the constraint's components. Near a closed configuration
its time derivative is ``-T qd_all`` (eq. 6), so Newton's step on the dependent coordinates
``q_u1, q_a1`` (Step 5) solves ``[T_u1, T_a1] dq = r``. Spherical joints are updated on SO(3):
``R <- R exp(dq)``.
"""
from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Protocol

import numpy as np

from .math.fields import Field, MpField, make_field
from .errors import SingularConfigurationError
from .kinematics import TreeKinematics, constraint_matrix, coupling_residual, tree_kinematics
from .math.scalar import Scalar
from .math.spatial import COMPONENTS, hat, rot_exp, rot_log
from .math.configuration import Configuration, Position
from .steps.pipeline import DerivedModel

if TYPE_CHECKING:
    from .scene.elements import Constraint
    from .steps.structure import Counts
    from .tree import Tree


class ClosureModel(DerivedModel, Protocol):
    """What the loop-closure solves read of a :class:`symgen.model.Model` (which imports this
    module, so it is named by what is used): the scene, tree and partition of the steps, the
    counts, the reference configuration and the float field."""

    @property
    def counts(self) -> Counts: ...

    @property
    def reference(self) -> Configuration: ...

    @property
    def float_field(self) -> Field: ...


def closure_residual(model: ClosureModel, config: Configuration) -> np.ndarray:
    """Stacked position residuals of all constraints (float; zero when every loop is closed)."""
    return kinematics_residual(tree_kinematics(model.tree, model.float_field, config), model.scene.constraints.values(),
                               config)


def tree_residual(tree: Tree, constraints: Iterable[Constraint], config: Configuration) -> np.ndarray:
    """:func:`closure_residual` of ``constraints`` on a tree (before a model exists)."""
    return kinematics_residual(tree_kinematics(tree, make_field("float", tree.parameters), config), constraints, config)


def kinematics_residual(kin: TreeKinematics, constraints: Iterable[Constraint], config: Configuration) -> np.ndarray:
    """The residuals ``[R_A^T (p_B - p_A); log(R_A^T R_B)]`` of ``constraints``, restricted to their
    components, from the poses of (float) kinematics ``kin`` at ``config``; a joint coupling's is
    ``offset - sum_i c_i q_i`` (:func:`symgen.kinematics.coupling_residual`)."""
    out: list[np.ndarray] = []
    positions = config.as_float().positions
    for con in constraints:
        if con.is_coupling:
            out.append(np.array([coupling_residual(kin.tree, kin.field, con, positions)], dtype=float))
            continue
        r_a, p_a = (j.v for j in kin.frame_pose(con.frame_a))
        r_b, p_b = (j.v for j in kin.frame_pose(con.frame_b))
        rel = np.concatenate([r_a.T @ (p_b - p_a), rot_log(r_a.T @ r_b)])
        out.append(rel[[COMPONENTS.index(c) for c in con.components]])
    return np.concatenate(out) if out else np.zeros(0)


def _apply_step(model: ClosureModel, config: Configuration, coords: Sequence[int], step: np.ndarray) -> Configuration:
    pos = {k: (v.copy() if isinstance(v, np.ndarray) else v) for k, v in config.as_float().positions.items()}
    spherical_steps: dict[str, np.ndarray] = {}
    for coord, delta in zip(coords, step):
        c = model.tree.coordinates[coord]
        if not c.kind.is_one_dof:            # a rotation step: R <- R exp(hat(w))
            spherical_steps.setdefault(c.joint, np.zeros(3))[c.component] += delta
        else:
            pos[c.joint] = pos[c.joint] + delta
    for joint, w in spherical_steps.items():
        pos[joint] = pos[joint] @ rot_exp(w)
    return Configuration(pos)


def solve_closure(model: ClosureModel, config: Configuration, *, tol: float = 1e-13,
                  max_iter: int = 50) -> Configuration:
    """Newton iteration on the dependent coordinates ``q_u1, q_a1`` until every residual is
    below ``tol``; raises :class:`SingularConfigurationError` if it does not converge."""
    part = model.partition
    dep = part.u1 + part.a1
    if not dep:
        return config.as_float()
    fld = model.float_field
    cfg = config.as_float()
    res = closure_residual(model, cfg)
    for _ in range(max_iter):
        if np.max(np.abs(res)) < tol:
            return cfg
        kin = tree_kinematics(model.tree, fld, cfg)
        w = constraint_matrix(kin, model.scene.constraints.values()).v[:, list(dep)]
        cond = np.linalg.cond(w)
        if not np.isfinite(cond) or cond > 1e12:
            raise SingularConfigurationError("[T_u1, T_a1] during the loop-closure solve", float(cond))
        cfg = _apply_step(model, cfg, dep, np.linalg.solve(w, res))
        res = closure_residual(model, cfg)
    if np.max(np.abs(res)) < 1e3 * tol:
        return cfg
    raise SingularConfigurationError("loop closure (Newton did not converge)", float("inf"),
                                     f"residual {np.max(np.abs(res)):.3g}")


def random_positions(model: ClosureModel, rng: np.random.Generator) -> Configuration:
    """Random positions of every moving joint, loops left open: angles uniform in ``[-pi, pi]``,
    displacements within the scene's joint limits (else ``[-0.5, 0.5]`` m), rotations
    ``exp(w^)`` with ``w`` uniform in ``[-2, 2]^3``."""
    limits = model.scene.joint_limits
    pos: dict[str, Position] = {}
    for j in model.scene.joints.values():
        if j.kind.position_is_rotation:
            pos[j.name] = rot_exp(rng.uniform(-2.0, 2.0, 3))
        elif j.kind.position_is_angle:
            pos[j.name] = rng.uniform(-np.pi, np.pi)
        elif j.kind.translates:
            lim = limits.get(j.name)
            lo, hi = (float(lim.lower), float(lim.upper)) if lim and lim.lower is not None else (-0.5, 0.5)
            pos[j.name] = rng.uniform(lo, hi)
    return Configuration(pos)


def random_consistent_states(model: ClosureModel, count: int, *, seed: int = 0, spread: float = 0.3,
                             speed: float = 1.0, max_tries: int = 20) -> list[tuple[Configuration, np.ndarray]]:
    """``count`` random states ``(config, V_m)`` with closed loops, near the reference.

    The independent coordinates are perturbed uniformly by up to ``spread`` (rad or m; spherical
    joints by a random rotation of that angle), the dependent ones solved by :func:`solve_closure`;
    ``V_m`` is uniform in ``[-speed, speed]``, so ``qd = Omega V_m`` satisfies ``J_f qd = 0``.
    """
    rng = np.random.default_rng(seed)
    part, out = model.partition, []
    indep = part.a2 + part.u2
    tries = 0
    while len(out) < count:
        tries += 1
        if tries > max_tries * count:
            raise SingularConfigurationError("random consistent states", float("inf"),
                                             "loop closure failed too often; reduce the spread")
        cfg = _apply_step(model, model.reference, indep, rng.uniform(-spread, spread, len(indep)))
        try:
            cfg = solve_closure(model, cfg)
        except SingularConfigurationError:
            continue
        out.append((cfg, rng.uniform(-speed, speed, model.counts.m)))
    return out


# ------------------------------------------------------------------ extended precision
def field_rot_exp(w: Sequence[Scalar], fld: Field) -> np.ndarray:
    """``exp(hat(w))`` (Rodrigues) in ``fld``, which must answer ``sqrt`` and ``cos_sin``."""
    theta2 = sum(x * x for x in w)
    eye = fld.eye(3)
    if theta2 == 0:
        return eye
    theta = fld.sqrt(theta2)
    c, s = fld.cos_sin(theta)
    k = hat(np.array([x / theta for x in w], dtype=object), fld)
    return eye + s * k + (fld.one - c) * (k @ k)


def refine_closure(model: ClosureModel, positions: dict[str, Position], fld: MpField, *,
                   max_iter: int = 40) -> dict[str, Position]:
    """Newton's iteration of :func:`solve_closure` in an extended-precision field ``fld`` (``mp``).

    ``positions``: joint -> position in ``fld`` (an angle or a displacement as one number, a
    spherical joint's rotation matrix). The independent coordinates are held; the dependent ones
    (``q_u1, q_a1`` of Step 5) move until every residual is below ``10^-(dps - 8)``. The rotation
    residual is the axial vector of the skew part of ``R_A^T R_B``, which agrees with
    ``log(R_A^T R_B)`` to first order, so the iteration keeps Newton's quadratic convergence and
    the same closed configuration. From a start near a closed state the result is that state to
    about ``dps`` digits, whatever float library produced the start.
    """
    part = model.partition
    dep = list(part.u1 + part.a1)
    pos = dict(positions)
    if not dep:
        return pos
    cons = list(model.scene.constraints.values())
    tol = fld.const(10) ** -(fld.dps - 8)
    for _ in range(max_iter):
        kin = tree_kinematics(model.tree, fld, fld.configuration(Configuration(pos), model.tree))
        res = _field_residual(kin, cons, pos)
        if max(abs(r) for r in res) < tol:
            return pos
        w = constraint_matrix(kin, cons).v[:, dep]
        step = fld.solve(w, res, "[T_u1, T_a1] during the loop-closure solve")
        rot: dict[str, list] = {}
        for coord, delta in zip(dep, step):
            c = model.tree.coordinates[coord]
            if c.kind.is_one_dof:
                pos[c.joint] = pos[c.joint] + delta
            else:
                rot.setdefault(c.joint, [fld.zero] * 3)[c.component] += delta
        for joint, v in rot.items():
            pos[joint] = pos[joint] @ field_rot_exp(v, fld)
    raise SingularConfigurationError("loop closure (extended-precision Newton did not converge)", float("inf"))


def _field_residual(kin: TreeKinematics, constraints: Iterable[Constraint], positions: dict[str, Position]) -> np.ndarray:
    """:func:`kinematics_residual` in any field, the rotation part as the skew part's axial vector."""
    out: list[Scalar] = []
    for con in constraints:
        if con.is_coupling:
            out.append(coupling_residual(kin.tree, kin.field, con, positions))
            continue
        r_a, p_a = (j.v for j in kin.frame_pose(con.frame_a))
        r_b, p_b = (j.v for j in kin.frame_pose(con.frame_b))
        r = r_a.T @ r_b
        half = [(r[2, 1] - r[1, 2]) / 2, (r[0, 2] - r[2, 0]) / 2, (r[1, 0] - r[0, 1]) / 2]
        rel = list(r_a.T @ (p_b - p_a)) + half
        out.extend(rel[COMPONENTS.index(c)] for c in con.components)
    return np.array(out, dtype=object)
