"""Subsystem dynamics of the extended subsystem space S: eqs. (21)-(24).

A rigid body in its own frame alpha, with ``X = [v; w]`` (DESIGN.md section 3)::

    M_a = [[m 1,   -m r^],
           [m r^,  I_o]]             I_o = I_c - m r^ r^        constant, symmetric
    C_a = [[m w^,  -m w^ r^],
           [m r^ w^, I_o w^ + w^ I_o]]                          skew-symmetric for every w
    G_a = M_a [R_aW g_up; 0]                                     g_up = -gravity

so that ``M_a dX/dt + C_a X + G_a = F`` (eq. 21) and ``C_a X = X x* (M_a X)``.

``C_a`` is linear in the body's ten inertial parameters ``(m, m r, I_o)``, as virtual
decomposition control needs (the regressor of eq. 35, :mod:`symgen.control.regressor`). DESIGN.md
section 3 writes the lower-right block as ``-m r^ w^ r^ + I_c w^ + w^ I_c``; the two differ by
``m (r^ r^ w^ + w^ r^ r^ - r^ w^ r^)``, which maps ``w`` to zero (Jacobi identity) and is not
linear in the parameters. Both are skew and give the same ``C_a X`` for the body's own velocity
``X = [v; w]``, so model (32)'s ``C [V_m; 0]`` and Remark 2.7 are unchanged; only ``C`` applied
to other velocities (the required ``X_r`` of Section 4) differs.

A 1-DOF joint contributes ``I* qdd + xi`` (eq. 22) with friction ``xi = b qd + c sign(qd)``; a
spherical joint only its friction moment ``xi = b w + c w/|w|`` (eq. 23); both friction laws are
:meth:`symgen.scene.joint_kinds.JointKind.friction`. Massless bodies are
left out of S (their blocks would be zero).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .dynamics.rnea import joint_springs
from .math.spatial import hat


def rigid_body_mass(m, r, inertia, field) -> np.ndarray:
    """``M_alpha`` of eq. (21): spatial inertia about the frame origin, [v; w] ordering."""
    rh = hat(r, field)
    top = np.hstack([m * field.eye(3), -m * rh])
    bottom = np.hstack([m * rh, inertia - m * rh @ rh])
    return np.vstack([top, bottom])


def rigid_body_coriolis(m, r, inertia, w, field) -> np.ndarray:
    """``C_alpha(w)`` of eq. (21): skew-symmetric, linear in ``(m, m r, I_o)``, with
    ``C_alpha X = X x* (M_alpha X)`` for ``X = [v; w]`` (module docstring)."""
    rh, wh = hat(r, field), hat(w, field)
    origin = inertia - m * rh @ rh
    top = np.hstack([m * wh, -m * wh @ rh])
    bottom = np.hstack([m * rh @ wh, origin @ wh + wh @ origin])
    return np.vstack([top, bottom])


def rigid_body_gravity(mass_matrix, r_body_world, gravity, field) -> np.ndarray:
    """``G_alpha = M_alpha [R_alphaW (-g); 0]`` (gravity on the left-hand side of eq. 21)."""
    up = r_body_world @ (-gravity)
    return mass_matrix @ np.concatenate([up, field.zeros((3,))])


@dataclass
class SubsystemSpace:
    """Layout of S: joint coordinate rows first (all N_all of them), then 6 rows per massive body."""

    bodies: tuple[int, ...]          # tree body indices in S, in order
    n_coords: int

    @property
    def size(self) -> int:
        return self.n_coords + 6 * len(self.bodies)

    def body_rows(self, k: int) -> slice:
        start = self.n_coords + 6 * k
        return slice(start, start + 6)


def subsystem_space(tree) -> SubsystemSpace:
    return SubsystemSpace(tuple(b.index for b in tree.bodies if not b.massless), tree.n_coords)


def assemble_mass(space: SubsystemSpace, tree, const, field) -> np.ndarray:
    """Block-diagonal ``M_S = diag(I*_j, 0_3 (spherical), M_alpha)`` of eq. (24); constant."""
    out = field.zeros((space.size, space.size))
    for k, joint in enumerate(tree.joints):
        if joint.kind.is_one_dof:
            out[joint.coords[0], joint.coords[0]] = const.rotor[k]
    for k, b in enumerate(space.bodies):
        rows = space.body_rows(k)
        out[rows, rows] = rigid_body_mass(const.mass[b], const.com[b], const.inertia[b], field)
    return out


def assemble_coriolis(space: SubsystemSpace, const, velocity, field) -> np.ndarray:
    """Block-diagonal ``C_S = diag(0, 0, C_alpha(w_alpha))`` of eq. (24) at S velocity ``velocity``."""
    out = field.zeros((space.size, space.size))
    for k, b in enumerate(space.bodies):
        rows = space.body_rows(k)
        w = velocity[rows][3:]
        out[rows, rows] = rigid_body_coriolis(const.mass[b], const.com[b], const.inertia[b], w, field)
    return out


def assemble_gravity(space: SubsystemSpace, tree, const, kin_rot, velocity, mass_s, field,
                     gravity: bool = True, positions: dict | None = None) -> np.ndarray:
    """``G_S = [xi_1j; xi_3i; G_alpha]`` of eq. (24): joint friction and joint springs
    ``k (q - q_spring)`` (at ``positions``), then body gravity."""
    out = field.zeros((space.size,))
    for k, joint in enumerate(tree.joints):
        if joint.coords and (const.viscous[k] != 0 or const.coulomb[k] != 0):
            idx = list(joint.coords)
            out[idx] = joint.kind.friction(velocity[idx], field, const.viscous[k], const.coulomb[k])
    for coord, term in joint_springs(tree, const, positions or {}).items():
        out[coord] = out[coord] + term
    if gravity:
        for k, b in enumerate(space.bodies):
            rows = space.body_rows(k)
            out[rows] = rigid_body_gravity(mass_s[rows, rows], kin_rot[b].v.T, const.gravity, field)
    return out
