"""The integration state ``x = [q; V_m]`` and the position kinematics (Remark 2.4).

``q`` is the generated code's position vector (:func:`symgen.codegen.trace.position_layout`):
one angle or displacement per 1-DOF joint and a unit quaternion ``(w, x, y, z)`` per spherical
joint, in scene order -- *all* joints, the dependent ones of closed chains included. ``V_m`` are
the motion coordinates of eq. (17); the velocity of every joint follows from them,
``qd_all = P [J_m; J_f]^-1 [V_m; 0]`` (eqs. 10, 18), so the velocity constraints ``J_f qd = 0``
hold by construction and only the positions can drift off the constraint manifold.

A spherical joint's rates are its angular velocity ``w`` in the child frame (``dR/dt = R w^``),
and its quaternion moves by ``dq/dt = 1/2 q (x) (0, w)`` (Hamilton product).

>>> import symgen
>>> model = symgen.derive(symgen.load("four_bar"))
>>> layout = StateLayout(model)
>>> layout.nq, layout.m, layout.size
(4, 1, 5)
"""
from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..codegen.reference import position_vector
from ..codegen.trace import position_layout
from ..math.spatial import quaternion_matrix
from ..scene.joint_kinds import joint_kind
from ..errors import StateError
from ..math.configuration import Configuration, as_configuration
from .errors import SimulationInputError


class StateLayout:
    """Where each joint's position and rate live: ``q`` offsets and all-coordinate indices.

    Attributes: ``nq`` (length of ``q``), ``m`` (length of ``V_m``), ``n_all`` (all joint rate
    coordinates), ``scalar_q`` / ``scalar_coord`` (matching index arrays of the 1-DOF joints),
    ``spherical`` (list of ``(joint, q offset, first coordinate)``), ``joints`` (the
    ``(joint, kind, q offset, size)`` of :func:`position_layout`, with kind a
    :class:`~symgen.scene.joint_kinds.JointKind`).
    """

    def __init__(self, model):
        self.model = model
        layout = position_layout(model)
        self.nq = sum(size for *_, size in layout)
        self.m = model.counts.m
        self.n = model.counts.n
        self.n_all = model.tree.n_coords
        first = {}
        for c, coord in enumerate(model.tree.coordinates):
            first.setdefault(coord.joint, c)
        self.joints = [(name, joint_kind(kind), off, size) for name, kind, off, size in layout]
        self.scalar_q = np.array([off for _, kind, off, _ in self.joints if not kind.position_is_rotation], dtype=int)
        self.scalar_coord = np.array([first[name] for name, kind, _, _ in self.joints
                                      if not kind.position_is_rotation], dtype=int)
        self.spherical = [(name, off, first[name]) for name, kind, off, _ in self.joints if kind.position_is_rotation]
        self.q_of_coord = dict(zip(self.scalar_coord.tolist(), self.scalar_q.tolist()))

    @property
    def size(self) -> int:
        """Length of the state ``x = [q; V_m]``."""
        return self.nq + self.m

    def split(self, x) -> tuple[np.ndarray, np.ndarray]:
        """``(q, V_m)`` views of a state vector."""
        return x[: self.nq], x[self.nq:]

    def join(self, q, v_m) -> np.ndarray:
        return np.concatenate([np.asarray(q, float), np.asarray(v_m, float)])

    # ------------------------------------------------------------------ quaternions
    def normalized(self, q) -> np.ndarray:
        """``q`` with every quaternion scaled to unit length (a copy)."""
        q = np.array(q, dtype=float)
        for name, off, _ in self.spherical:
            norm = np.linalg.norm(q[off:off + 4])
            if not np.isfinite(norm) or norm < 1e-8:
                raise SimulationInputError(f"joint {name!r}: quaternion {q[off:off + 4]} cannot be normalised")
            q[off:off + 4] /= norm
        return q

    def position_rates(self, q, qd_all) -> np.ndarray:
        """``dq/dt`` from the rates of all joint coordinates (angle rates, and
        ``1/2 q (x) (0, w)`` for spherical joints with ``w`` in the child frame)."""
        out = np.zeros(self.nq)
        out[self.scalar_q] = qd_all[self.scalar_coord]
        for _, off, c in self.spherical:
            out[off:off + 4] = quaternion_rate(q[off:off + 4], qd_all[c:c + 3])
        return out

    def advance(self, q, rates, h) -> np.ndarray:
        """Move ``q`` by ``h`` at constant joint rates ``qd_all``: angles linearly, quaternions by
        the exact rotation ``q <- q (x) quaternion_exp(h w)`` (they stay unit)."""
        out = np.array(q, dtype=float)
        out[self.scalar_q] += h * rates[self.scalar_coord]
        for _, off, c in self.spherical:
            out[off:off + 4] = quaternion_multiply(out[off:off + 4], quaternion_exp(h * rates[c:c + 3]))
        return out

    # ------------------------------------------------------------------ configurations
    def configuration(self, q) -> Configuration:
        """The :class:`~symgen.math.configuration.Configuration` of a position vector (quaternions normalised)."""
        q = self.normalized(q)
        pos = {}
        for name, kind, off, _ in self.joints:
            if kind.position_is_rotation:
                pos[name] = np.array(quaternion_matrix(*q[off:off + 4]), dtype=float)
            else:
                pos[name] = float(q[off])
        return Configuration(pos)

    def positions(self, config) -> np.ndarray:
        """The position vector ``q`` of a configuration (rotation matrices to quaternions);
        ``config`` in any form :func:`~symgen.math.configuration.as_configuration` takes (a
        :class:`Configuration`, a mapping joint -> position, a flat array)."""
        return position_vector(self.model, as_configuration(config, self.model.scene, "config").as_float())

    def initial_state(self, config: Configuration | None = None, V_m=None) -> np.ndarray:
        """``x0`` from a configuration (default: the scene's reference ``q0``) and ``V_m``
        (default: zero)."""
        q = self.positions(self.model.reference if config is None else config)
        v = np.zeros(self.m) if V_m is None else np.asarray(V_m, dtype=float)
        if v.shape != (self.m,):
            raise SimulationInputError(f"V_m must have shape ({self.m},), got {v.shape}")
        return self.join(q, v)

    def state_from(self, x0=None, V_m=None) -> np.ndarray:
        """``x = [q; V_m]`` from a state as users hold it: ``None`` (the reference ``q0``), a
        :class:`~symgen.math.configuration.Configuration`, a mapping joint -> position, a flat array of the
        ``nq`` positions in scene order (each with ``V_m``, default zero), or the whole flat
        state ``[q; V_m]`` (then ``V_m`` must not be given). Anything else is a
        :class:`SimulationInputError` naming ``x0``."""
        if x0 is not None and not isinstance(x0, (Configuration, Mapping, list, tuple, np.ndarray)):
            raise SimulationInputError(f"x0 must be a Configuration, a mapping joint -> position, or a flat array "
                                       f"in scene order (q ({self.nq}) or [q; V_m] ({self.size})); got "
                                       f"{type(x0).__name__}")
        if isinstance(x0, (list, tuple, np.ndarray)) and np.shape(x0) == (self.size,) and self.size != self.nq:
            if V_m is not None:
                raise SimulationInputError("x0 = [q; V_m] already holds V_m; give V_m only with positions")
            return self.check_state(x0)
        try:
            config = None if x0 is None else as_configuration(x0, self.model.scene, "x0")
        except StateError as exc:
            raise SimulationInputError(str(exc)) from None
        try:
            return self.check_state(self.initial_state(config, V_m))
        except StateError as exc:
            raise SimulationInputError(f"x0: {exc}") from None

    def check_state(self, x, what: str = "x0") -> np.ndarray:
        """A float copy of ``x`` after checking its shape and finiteness."""
        x = np.array(x, dtype=float)
        if x.shape != (self.size,):
            raise SimulationInputError(f"{what} must have shape ({self.size},) = [q ({self.nq}); V_m ({self.m})], "
                                       f"got {x.shape}")
        if not np.all(np.isfinite(x)):
            raise SimulationInputError(f"{what} contains NaN or infinity")
        q, v = self.split(x)
        return self.join(self.normalized(q), v)

    def coordinate_labels(self) -> list[str]:
        """Names of the entries of ``q`` then ``V_m`` (``j1``, ``s1.qw``, ``V_m[0]``...)."""
        labels = []
        for name, kind, _, _ in self.joints:
            labels += [f"{name}.q{c}" for c in "wxyz"] if kind.position_is_rotation else [name]
        return labels + [f"V_m[{i}]" for i in range(self.m)]


def quaternion_multiply(a, b) -> np.ndarray:
    """Hamilton product ``a (x) b`` of quaternions ``(w, x, y, z)``."""
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return np.array([aw * bw - ax * bx - ay * by - az * bz,
                     aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx,
                     aw * bz + ax * by - ay * bx + az * bw])


def quaternion_rate(q, w) -> np.ndarray:
    """``dq/dt = 1/2 q (x) (0, w)``: ``w`` is the angular velocity in the rotated (child) frame,
    so that ``dR/dt = R w^`` for ``R = R(q)``."""
    return 0.5 * quaternion_multiply(q, (0.0, w[0], w[1], w[2]))


def quaternion_exp(v) -> np.ndarray:
    """Unit quaternion of the rotation vector ``v``: ``(cos |v|/2, sin(|v|/2) v/|v|)``."""
    angle = float(np.linalg.norm(v))
    if angle < 1e-12:
        return np.array([1.0, 0.5 * v[0], 0.5 * v[1], 0.5 * v[2]])
    s = np.sin(0.5 * angle) / angle
    return np.array([np.cos(0.5 * angle), s * v[0], s * v[1], s * v[2]])
