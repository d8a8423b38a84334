"""A joint's ``springdamper="timeconst dampratio"``: its stiffness and damping, as MuJoCo sets them.

MuJoCo (``mjCModel::AutoSpringDamper``) replaces the joint's ``stiffness`` and ``damping`` by

    k = I / (timeconst^2 dampratio^2),    b = 2 I / timeconst,

with ``I = 1 / dof_invweight0``, the inverse of the joint's diagonal entry of the inverse mass
matrix ``M(qpos0)^-1`` (armature included) of the whole model at its reference configuration.
Only hinge and slide joints are read (a ball or free joint's averaged weight is not). Both numbers
must be positive (MuJoCo's rule); ``0 0`` leaves the joint's own values.

``M(qpos0)`` is built here in floating point from the records of :mod:`symgen.io.mjcf.records`
(``M = sum_b m_b J_v^T J_v + J_w^T I_b J_w`` over the bodies, each column the motion one joint
rate gives every body it carries, at the drawn pose); the two numbers are then stored as exact
decimals of those floats (a relative error of about 1e-15 times the condition of ``M``), as the
mesh inertias are (:mod:`symgen.io.mjcf.meshes`).
"""
from __future__ import annotations

import numpy as np

from ...scene.joint_kinds import joint_kind
from .meshes import exact
from .records import WORLD

def _columns(bodies: list) -> tuple[list, list, dict]:
    """``(dofs, columns, poses)``: every DOF as ``(joint, index)`` and, per DOF, ``{body: (v, w)}`` -- the
    velocity of each carried body's centre of mass and its angular velocity per unit rate, in the
    world frame at the drawn pose (MuJoCo's qvel: a free joint's linear part in the world, its
    angular part and a ball's in the body frame)."""
    pose = {WORLD: (np.eye(3), np.zeros(3))}
    for b in bodies:
        rot, pos = pose[b.parent]
        pose[b.name] = (rot @ np.array(b.rot, dtype=float), pos + rot @ np.array(b.pos, dtype=float).ravel())
    children: dict = {}
    for b in bodies:
        children.setdefault(b.parent, []).append(b.name)
    inertial = {b.name: b.inertial for b in bodies}

    def carried(name: str) -> list:
        out = [name]
        for n in out:
            out += children.get(n, [])
        return out

    def com(name: str) -> np.ndarray:
        rot, pos = pose[name]
        b = inertial[name]
        return pos + (rot @ np.array(b.pos, dtype=float).ravel() if b is not None else 0)

    dofs, columns = [], []
    for b in bodies:
        rot, pos = pose[b.name]
        for j in b.joints:
            anchor = pos + rot @ np.array(j.pos, dtype=float).ravel()
            axis = rot @ np.array(j.axis, dtype=float).ravel()
            axis = axis / np.linalg.norm(axis)
            kind = None if j.kind == "free" else joint_kind(j.kind)   # MJCF's free joint is no scene kind
            if kind is not None and kind.is_one_dof:                # a slide moves along, a hinge about, the axis
                motions = [(axis, np.zeros(3))] if kind.translates else [(np.zeros(3), axis)]
            elif kind is not None:                                  # a ball: the body's three axes
                motions = [(np.zeros(3), rot[:, k]) for k in range(3)]
            else:                                                   # free: at the body frame
                anchor = pos
                motions = [(np.eye(3)[k], np.zeros(3)) for k in range(3)] + [(np.zeros(3), rot[:, k])
                                                                             for k in range(3)]
            for k, (lin, ang) in enumerate(motions):
                dofs.append((j, k))
                columns.append({n: (lin + np.cross(ang, com(n) - anchor), ang) for n in carried(b.name)})
    return dofs, columns, pose


def mass_matrix_at_reference(bodies: list) -> tuple[list, np.ndarray]:
    """``(dofs, M)``: MuJoCo's joint-space inertia at ``qpos0`` (armature on the diagonal), floats."""
    dofs, columns, pose = _columns(bodies)
    n = len(dofs)
    m = np.diag([float(j.armature) for j, _ in dofs])
    for b in bodies:
        if b.inertial is None:
            continue
        jv, jw = np.zeros((3, n)), np.zeros((3, n))
        for i, column in enumerate(columns):
            if b.name in column:
                jv[:, i], jw[:, i] = column[b.name]
        rot = pose[b.name][0]
        world = rot @ np.array(b.inertial.inertia, dtype=float) @ rot.T
        m += float(b.inertial.mass) * jv.T @ jv + jw.T @ world @ jw
    return dofs, m


def apply_springdampers(bodies: list, springs: bool, dampers: bool) -> None:
    """Set ``stiffness`` and ``damping`` of every joint with a ``springdamper`` (module docstring);
    ``springs``/``dampers``: the flags that keep them."""
    wanted = [j for b in bodies for j in b.joints if j.springdamper is not None]
    if not wanted:
        return
    dofs, m = mass_matrix_at_reference(bodies)
    inverse = np.linalg.inv(m)
    index = {id(j): i for i, (j, k) in enumerate(dofs) if k == 0}
    for j in wanted:
        timeconst, dampratio = (float(v) for v in j.springdamper)
        weight = 1.0 / max(1e-15, inverse[index[id(j)], index[id(j)]])       # MuJoCo's mjMINVAL
        if springs:
            j.stiffness = exact(weight / max(1e-15, timeconst**2 * dampratio**2))
        if dampers:
            j.damping = exact(2 * weight / max(1e-15, timeconst))
