"""Closed families of the built-in loops that run into a singular configuration, exact to 50 digits.

Each :class:`Family` gives, for a parameter ``t > 0``, the positions of every joint of a built-in
scene at a configuration where every loop is closed to the field's precision, and that configuration
approaches a singular one as ``t -> 0`` (the smallest singular value of the singular matrix falls
like ``t``):

============  ==================================================================================
four_bar      ``q = [t, -t, t - pi, pi - t]``: the parallelogram goes flat, ``W = [T_u1, T_a1]``
              (eq. 9) singular (a dead point of the loop)
five_bar      both distal links at angle ``t`` from the line through the elbows: straight at
              ``t = 0``, where the three passive joints are collinear and ``W`` (eq. 9) is singular
stewart       the platform turned about its vertical axis by ``phi* + t``; at ``phi*`` (a root of
              the determinant of the six legs' Pluecker lines, found in 50 digits) the platform
              moves with its legs locked, ``W`` (eq. 9) singular
multi_arm     arm 1's wrist ``a1_j5 = -t``: its joint axes 4 and 6 align at ``t = 0``, so arm 1's
              tool Jacobian and ``[J_m; J_f]`` (eq. 18) are singular while ``W`` stays well
              conditioned; arm 2 follows by the 50-digit closure (:func:`~symgen.closure.refine_closure`)
============  ==================================================================================

The first three are written in closed form from the scene's geometry (no symgen kinematics in the
construction), the last re-closed by Newton's method at 50 digits with ``W`` well conditioned.
:func:`float_positions` rounds a family's state to the generated code's ``q``: the input a float
caller can give, off the constraint manifold by that rounding.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import mpmath
import numpy as np

from ..closure import refine_closure, solve_closure
from ..errors import SymgenError
from ..math.configuration import Configuration
from ..math.fields import MpField
from ..model import Model

#: a joint's position in the mp field: a number, or a 3 x 3 object array (spherical joint)
MpPositions = dict[str, object]


@dataclass(frozen=True)
class Family:
    """A closed family ``t -> positions`` of built-in ``scene`` approaching a singular configuration."""

    scene: str
    singular: str                       # the matrix that goes singular, as the solves name it
    description: str
    positions: Callable[[Model, MpField, object], MpPositions]
    V_m: tuple[float, ...]
    tau: tuple[float, ...]


def _mp(field: MpField, value) -> object:
    """A scene constant (SymPy number) in ``field``, exactly when rational."""
    if getattr(value, "is_Rational", False):
        return field.ctx.mpf(value.p) / value.q
    return field.ctx.mpf(str(value.evalf(field.dps + 10)))


# ------------------------------------------------------------------ four-bar
def _four_bar(model: Model, field: MpField, t) -> MpPositions:
    pi = field.ctx.pi
    return {"j1": t, "j2": -t, "j3": t - pi, "j4": pi - t}


# ------------------------------------------------------------------ five-bar
def _five_bar(model: Model, field: MpField, t) -> MpPositions:
    """Crank 1 at its reference angle; elbow 2 on its circle at distance ``2 l cos t`` from elbow 1
    (the branch nearer its reference angle); the pin on the side of the reference assembly."""
    mp, scene = field.ctx, model.scene
    joints = scene.joints
    a1 = mp.mpf(float(joints["j1"].q0))                 # any crank angle from which the fold is reachable
    base2 = [_mp(field, x) for x in joints["j2"].origin.translation[:2]]
    l1 = _mp(field, joints["j3"].origin.translation[0])  # proximal length
    l2 = _mp(field, joints["j5"].origin.translation[0])  # distal length
    e1 = [l1 * mp.cos(a1), l1 * mp.sin(a1)]
    d = 2 * l2 * mp.cos(t)
    r = mp.hypot(e1[0] - base2[0], e1[1] - base2[1])
    towards = mp.atan2(e1[1] - base2[1], e1[0] - base2[0])
    spread = mp.acos((r * r + l1 * l1 - d * d) / (2 * r * l1))
    ref2 = float(joints["j2"].q0)
    a2 = min((towards + spread, towards - spread), key=lambda a: abs(float(a) - ref2))
    e2 = [base2[0] + l1 * mp.cos(a2), base2[1] + l1 * mp.sin(a2)]
    ux, uy = (e2[0] - e1[0]) / d, (e2[1] - e1[1]) / d
    h = l2 * mp.sin(t)
    pin = [(e1[0] + e2[0]) / 2 - h * uy, (e1[1] + e2[1]) / 2 + h * ux]
    th1 = mp.atan2(pin[1] - e1[1], pin[0] - e1[0])
    th2 = mp.atan2(pin[1] - e2[1], pin[0] - e2[0])
    j5 = th2 - th1
    j5 += 2 * mp.pi if j5 < -mp.pi else -2 * mp.pi if j5 > mp.pi else 0
    return {"j1": a1, "j2": a2, "j3": th1 - a1, "j4": th2 - a2, "j5": j5}


# ------------------------------------------------------------------ Stewart platform
def _rot(mp, axis: int, angle) -> np.ndarray:
    c, s = mp.cos(angle), mp.sin(angle)
    i, j = (axis + 1) % 3, (axis + 2) % 3
    r = np.array([[mp.mpf(0)] * 3 for _ in range(3)], dtype=object)
    r[axis, axis] = mp.mpf(1)
    r[i, i], r[i, j], r[j, i], r[j, j] = c, -s, s, c
    return r


def _stewart_geometry(model: Model, field: MpField):
    """Per leg ``i``: base point ``b_i`` (world) and attachment ``a_i`` (platform frame); the
    reference pose ``(R, p)`` of the platform frame and the platform-frame point ``P``."""
    scene, legs = model.scene, range(1, 7)
    base = [np.array([_mp(field, x) for x in scene.joints[f"u{i}a"].origin.translation], dtype=object) for i in legs]
    attach = [np.array([field.zero] * 3, dtype=object)]
    attach += [np.array([_mp(field, x) for x in scene.frames[f"att{i}"].pose.translation], dtype=object)
               for i in range(2, 7)]
    centre = np.array([_mp(field, x) for x in scene.frames["P"].pose.translation], dtype=object)
    r_ref, p_ref = model.frame_pose(model.reference, "P")
    return base, attach, centre, r_ref, p_ref


def _stewart_pose(model: Model, field: MpField, phi):
    """Platform frame pose: the reference pose of ``P`` turned by ``phi`` about the world's vertical
    through ``P`` (the reference pose taken at its float values)."""
    mp = field.ctx
    base, attach, centre, r_ref, p_ref = _stewart_geometry(model, field)
    r_p = _rot(mp, 2, phi) @ np.array([[mp.mpf(float(x)) for x in row] for row in r_ref], dtype=object)
    p_p = np.array([mp.mpf(float(x)) for x in p_ref], dtype=object)
    return base, attach, r_p, p_p - r_p @ centre


def _pluecker_det(model: Model, field: MpField, phi):
    """Determinant of the six legs' unit Pluecker lines ``[u_i; a_i x u_i]`` (rows) at yaw ``phi``:
    zero where the platform can move with the legs locked (an independent test of W's singularity)."""
    mp = field.ctx
    base, attach, r, p = _stewart_pose(model, field, phi)
    rows = []
    for b, a in zip(base, attach):
        a_w = p + r @ a
        u = a_w - b
        u = u / mp.sqrt(sum(x * x for x in u))
        rows.append(list(u) + list(np.cross(a_w, u)))
    return mp.det(mp.matrix(rows))


def stewart_singular_yaw(model: Model, field: MpField):
    """The yaw ``phi*`` nearest the reference (scanning ``(0, pi)`` in steps of 0.05) at which the
    legs' Pluecker determinant changes sign, refined to the field's precision by the secant method."""
    mp = field.ctx
    grid = [mp.mpf(k) / 20 for k in range(0, 63)]
    values = [_pluecker_det(model, field, g) for g in grid]
    for lo, hi, f_lo, f_hi in zip(grid, grid[1:], values, values[1:]):
        if f_lo * f_hi < 0:
            return mp.findroot(lambda x: _pluecker_det(model, field, x), (lo, hi), solver="anderson")
    raise SymgenError("no singular yaw of the Stewart platform in (0, pi)")


def _stewart(model: Model, field: MpField, t) -> MpPositions:
    """Closed-form inverse kinematics of each U-P-S leg at the platform pose of yaw ``phi* + t``:
    ``R_x(u_a) R_y(u_b) e_z`` along the leg, the prismatic joint its length, the spherical joint
    the remaining rotation (every socket is welded to the platform's axes)."""
    mp = field.ctx
    phi = _cached_yaw(model, field.dps)
    base, attach, r, p = _stewart_pose(model, field, mp.mpf(phi) + t)
    out: MpPositions = {}
    for i, (b, a) in enumerate(zip(base, attach), start=1):
        d = p + r @ a - b
        length = mp.sqrt(sum(x * x for x in d))
        u = d / length
        beta = mp.asin(u[0])                      # R_x(alpha) R_y(beta) e_z = (sin b, -sin a cos b, cos a cos b)
        alpha = mp.atan2(-u[1], u[2])
        out[f"u{i}a"], out[f"u{i}b"], out[f"p{i}"] = alpha, beta, length
        out[f"s{i}"] = (_rot(mp, 0, alpha) @ _rot(mp, 1, beta)).T @ r
    return out


#: per scene name and digits, what the families find once: the singular yaw, the continuation's start
_FOUND: dict[tuple[str, int], object] = {}


def _cached_yaw(model: Model, dps: int) -> str:
    key = (model.scene.name, dps)
    if key not in _FOUND:
        _FOUND[key] = mpmath.nstr(stewart_singular_yaw(model, MpField(model.tree.parameters, dps=dps)), dps + 5)
    return str(_FOUND[key])


# ------------------------------------------------------------------ two arms holding one object
def _multi_arm_start(model: Model) -> dict[str, float]:
    """A closed float configuration with arm 1's wrist at ``a1_j5 = -0.1``, reached from the
    reference by continuation (20 steps of :func:`~symgen.closure.solve_closure`)."""
    key = (model.scene.name, 0)
    if key not in _FOUND:
        cfg = model.reference.as_float()
        q5 = float(cfg.positions["a1_j5"])
        for s in np.linspace(q5, -0.1, 21)[1:]:
            cfg = solve_closure(model, Configuration(dict(cfg.positions, a1_j5=float(s))))
        _FOUND[key] = {k: float(v) for k, v in cfg.positions.items()}
    return dict(_FOUND[key])


def _multi_arm(model: Model, field: MpField, t) -> MpPositions:
    mp = field.ctx
    start = _multi_arm_start(model)
    start["a1_j5"] = float(-t)
    guess = solve_closure(model, Configuration(start)).positions   # float Newton, W well conditioned
    pos: MpPositions = {k: mp.mpf(float(v)) for k, v in guess.items()}
    pos["a1_j5"] = -t                                  # held: an independent coordinate (Step 5)
    return refine_closure(model, pos, field)


FAMILIES: dict[str, Family] = {f.scene: f for f in (
    Family("four_bar", "[T_u1, T_a1]", "q = [t, -t, t - pi, pi - t] (flat at t = 0)", _four_bar, (1.0,), (1.0,)),
    Family("five_bar", "[T_u1, T_a1]", "distal links at angle t from straight", _five_bar,
           (0.5, -0.3), (1.0, -0.5)),
    Family("stewart", "[T_u1, T_a1]", "platform yaw phi* + t (legs' Pluecker lines dependent at t = 0)",
           _stewart, (0.1, -0.05, 0.02, 0.3, -0.2, 0.1), (40.0, 35.0, 30.0, 45.0, 38.0, 33.0)),
    Family("multi_arm", "[J_m; J_f]", "arm 1's wrist a1_j5 = -t (axes 4 and 6 aligned at t = 0)", _multi_arm,
           (0.1, -0.05, 0.02, 0.3, -0.2, 0.1), tuple(np.linspace(2.0, -2.0, 12))),
)}


def exact_configuration(model: Model, family: Family, field: MpField, t: float) -> Configuration:
    """The family's closed configuration at ``t`` (taken at its exact binary value) in ``field``."""
    return Configuration(family.positions(model, field, field.ctx.mpf(t)))


def _quaternion(r: np.ndarray) -> list[float]:
    """Unit quaternion ``(w, x, y, z)`` of a rotation matrix of mp numbers (Shepperd's method), in floats."""
    m = [[r[i, j] for j in range(3)] for i in range(3)]
    tr = m[0][0] + m[1][1] + m[2][2]
    cands = [tr, m[0][0], m[1][1], m[2][2]]
    k = max(range(4), key=lambda i: cands[i])
    if k == 0:
        s = 2 * mpmath.sqrt(1 + tr)
        q = [s / 4, (m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s]
    else:
        i, j, l = k - 1, k % 3, (k + 1) % 3
        s = 2 * mpmath.sqrt(1 + m[i][i] - m[j][j] - m[l][l])
        v = [None, None, None]
        v[i], v[j], v[l] = s / 4, (m[j][i] + m[i][j]) / s, (m[l][i] + m[i][l]) / s
        q = [(m[l][j] - m[j][l]) / s] + v
    if q[0] < 0:
        q = [-x for x in q]
    return [float(x) for x in q]


def float_positions(model: Model, config: Configuration) -> np.ndarray:
    """The generated code's ``q`` (angles, displacements, unit quaternions ``w, x, y, z``) of an mp
    configuration, each entry rounded to the nearest double: what a float caller can pass."""
    out: list[float] = []
    for j in model.scene.joints.values():
        if not j.kind.dof:
            continue
        value = config.positions[j.name]
        out.extend(_quaternion(np.asarray(value, dtype=object)) if j.kind.position_is_rotation else [float(value)])
    return np.array(out)


# ------------------------------------------------------------------ one point of a sweep
U = 2.0 ** -53


@dataclass(frozen=True)
class SweepPoint:
    """What every door does at one ``t`` of a family, against the 50-digit answer there.

    ``cond_W``, ``cond_A``: 2-norm condition numbers of ``[T_u1, T_a1]`` (eq. 9) and
    ``[J_m; J_f]`` (eq. 18) at the rounded input; ``bound``: ``max(cond_W, cond_A)^2 u``, what a
    function built from the maps' time derivatives may lose (:mod:`symgen.conditioning`);
    ``answers``: per door (``dense``, ``numpy``, ``c``) the relative error (max norm) of ``dV_m``
    against the 50-digit value ``want`` on the manifold (NaN when every door refused), or the name
    of the typed error it raised."""

    t: float
    cond_W: float
    cond_A: float
    want: np.ndarray
    answers: dict[str, float | str]

    @property
    def bound(self) -> float:
        return max(self.cond_W, self.cond_A) ** 2 * U


def reference_dv(model: Model, config: Configuration, field: MpField, family: Family) -> np.ndarray:
    """``dV_m`` of model (32) at ``config`` in ``field`` (50 digits): the reference."""
    from ..model_solves import solve_forward

    mp = field.ctx
    data = model.evaluate(config, V_m=[mp.mpf(v) for v in family.V_m], field=field)
    dv, _ = solve_forward(data, [mp.mpf(v) for v in family.tau])
    return np.array([float(x) for x in dv])


def conditions(model: Model, q: np.ndarray) -> tuple[float, float]:
    """``(cond W, cond A)`` in the 2-norm at ``q``, with the float field's condition limit lifted."""
    from ..math.fields import FloatField

    maps = model.evaluate(q, field=FloatField(model.tree.parameters, max_condition=np.inf)).maps
    return tuple(float(np.linalg.cond(np.asarray(m.v, dtype=float))) if m.v.size else 1.0
                 for m in (maps.W, maps.A))  # type: ignore[return-value]


def sweep_point(model: Model, family: Family, t: float, modules: dict | None = None) -> SweepPoint:
    """Evaluate ``forward_dynamics`` of the dense model and of each generated module in ``modules``
    (target name -> module) at the family's state ``t`` rounded to doubles; compare with the
    50-digit answer at the exactly closed state."""
    from ..errors import SymgenError

    field = MpField(model.tree.parameters)
    config = exact_configuration(model, family, field, t)
    q = float_positions(model, config)
    v_m, tau = np.array(family.V_m), np.array(family.tau)
    doors: dict[str, Callable[[], np.ndarray]] = {"dense": lambda: model.forward_dynamics(q, v_m, tau)[0]}
    for target, module in (modules or {}).items():
        doors[target] = lambda module=module: np.atleast_1d(module.forward_dynamics(q, v_m, tau)[0]
                                                            if model.counts.n > model.counts.m
                                                            else module.forward_dynamics(q, v_m, tau))
    answers: dict[str, float | str] = {}
    got: dict[str, np.ndarray] = {}
    for name, call in doors.items():
        try:
            got[name] = np.asarray(call(), dtype=float)
        except (SymgenError, ArithmeticError) as exc:
            answers[name] = type(exc).__name__
    want = reference_dv(model, config, field, family) if got else np.full(model.counts.m, np.nan)
    for name, value in got.items():
        answers[name] = float(np.max(np.abs(value - want)) / np.max(np.abs(want)))
    return SweepPoint(t, *conditions(model, q), want, {name: answers[name] for name in doors})
