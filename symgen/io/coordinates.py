"""symgen's coordinate order, and one-call maps to and from Pinocchio's ``q``/``v`` and MuJoCo's
``qpos``/``qvel``.

symgen's order. A scene's coordinates are its moving joints in declaration order (the file's
order for URDF and MJCF), ``Model.all_coordinate_names()``:

* a revolute joint: its angle (radians); a prismatic joint: its displacement. For a URDF joint
  this is the URDF joint value; for an MJCF hinge or slide it is MuJoCo's ``qpos`` itself (the
  reference ``ref`` included, so ``q0 = ref``);
* a spherical (ball) joint: a rotation matrix (the child frame's axes in the parent's joint
  frame) as its position, and three rates ``name.wx, name.wy, name.wz``: its angular velocity in
  the child frame.

The independent rates a model is evaluated with (``Model.coordinate_names()``, eq. 14) are a
subset of these names, in the order of the paper's partition (actuated joints first); pick them by
name: ``[rates[n] for n in model.coordinate_names()]``.

The other tools' forms, per joint:

============================  =========================  ======================  ===================
joint                         Pinocchio ``q``            MuJoCo ``qpos``         symgen position
============================  =========================  ======================  ===================
revolute with limits          angle (1)                  angle (1)               angle
continuous (URDF)             ``cos, sin`` (2)           --                      ``atan2(sin, cos)``
prismatic / slide             displacement (1)           displacement (1)        displacement
ball / spherical              quaternion ``x y z w``     quaternion ``w x y z``  rotation matrix
============================  =========================  ======================  ===================

Rates: one per 1-DOF joint in all three; a ball joint's three are its angular velocity in the
child frame in all three (Pinocchio's ``LOCAL`` convention, MuJoCo's ``qvel``). Quaternions are
normalised before use; ``q`` and ``-q`` give the same rotation. Joints are matched by name (a URDF
scene's names are mapped back through its :class:`~symgen.io.urdf.UrdfSource`, prefixes included);
a joint locked in symgen (``lock=``) is written at its locked value into the other tool's vector.
A free joint (a floating base, :mod:`symgen.scene.free_joint`) is one slot: its position ``x y
z`` and quaternion (``w x y z`` in MuJoCo's ``qpos``, exactly symgen's; ``x y z w`` in Pinocchio's
``q``) and its six rates: MuJoCo's ``qvel`` are symgen's (``pd`` in world axes, ``w`` in the
body's); Pinocchio's ``v`` has ``R^T pd`` (body axes), mapped here with the base's rotation ``R``.

>>> import mujoco
>>> from symgen.io.mjcf import parse_mjcf_text, scene_from_mjcf_model
>>> text = ('<mujoco><worldbody><body name="b"><joint name="q" ref="30"/><geom size="0.1"/></body>'
...         '</worldbody></mujoco>')
>>> scene = scene_from_mjcf_model(parse_mjcf_text(text))
>>> cmap = CoordinateMap.mujoco(scene, mujoco.MjModel.from_xml_string(text))
>>> config, rates = cmap.to_symgen(qpos=[0.5], qvel=[2.0])
>>> config.positions, rates
({'q': 0.5}, {'q': 2.0})
>>> [x.tolist() for x in cmap.from_symgen(config, rates)]
[[0.5], [2.0]]

With Pinocchio: ``CoordinateMap.pinocchio(scene, pin_model)``, then ``to_symgen(q, v)`` and
``from_symgen(config, rates)`` in the same way.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import SceneError
from ..math.configuration import Configuration, quaternion_rotation
from ..scene.declaration import Scene
from ..scene.free_joint import FreeJoint
from .mjcf.records import element_name

#: the forms a joint's position takes in another tool's vector
ANGLE, COS_SIN, QUAT_WXYZ, QUAT_XYZW = "value", "cos_sin", "quat_wxyz", "quat_xyzw"
#: a free joint: MuJoCo's (``x y z w x y z``, linear rate in world axes), Pinocchio's free flyer
#: (``x y z x y z w``, linear rate in body axes)
FREE_WXYZ, FREE_XYZW = "free_wxyz", "free_xyzw"
#: MuJoCo's joint types (mjtJoint)
MJ_FREE, MJ_BALL, MJ_SLIDE, MJ_HINGE = 0, 1, 2, 3


class CoordinateError(SceneError):
    """A robot model of another tool does not match the scene joint for joint (named)."""


@dataclass(frozen=True)
class Slot:
    """One symgen joint in another tool's vectors: its position form and first indices."""

    joint: str          # symgen joint name
    form: str           # ANGLE | COS_SIN | QUAT_WXYZ | QUAT_XYZW
    q: int              # first index in q / qpos
    v: int              # first index in v / qvel (-1 for a joint locked in symgen)


@dataclass(frozen=True)
class CoordinateMap:
    """How one scene's coordinates sit in another tool's ``q``/``v`` (see the module docstring)."""

    tool: str
    nq: int
    nv: int
    slots: tuple
    locked: tuple = ()          # (q index, form, value) of joints locked in symgen
    neutral: tuple = ()         # the other tool's q where nothing is set

    # ------------------------------------------------------------------ constructors
    @classmethod
    def pinocchio(cls, scene: Scene, model) -> "CoordinateMap":
        """The map to a Pinocchio ``model`` (``pinocchio.Model``) of the same robot."""
        names = _urdf_names(scene)
        locked = _urdf_locks(scene)
        slots, fixed = [], []
        for jid in range(1, model.njoints):
            pin_name, joint = model.names[jid], model.joints[jid]
            nq, nv, kind = joint.nq, joint.nv, joint.shortname()
            form = {(1, 1): ANGLE, (2, 1): COS_SIN, (4, 3): QUAT_XYZW}.get((nq, nv))
            if "FreeFlyer" in kind and model.parents[jid] == 0:
                slots.append(Slot(_free_root(scene, f"Pinocchio joint {pin_name!r}"), FREE_XYZW, joint.idx_q,
                                  joint.idx_v))
                continue
            if form is None or "FreeFlyer" in kind or "Planar" in kind:
                raise CoordinateError(f"Pinocchio joint {pin_name!r}", f"{kind} (nq={nq}, nv={nv}) has no symgen "
                                      "counterpart (a free flyer only at the root)")
            if pin_name in locked:
                fixed.append((joint.idx_q, form, locked[pin_name]))
                continue
            sym = names.get(pin_name, pin_name)
            _check_joint(scene, sym, form, f"Pinocchio joint {pin_name!r}")
            slots.append(Slot(sym, form, joint.idx_q, joint.idx_v))
        neutral = tuple(float(x) for x in _pin_neutral(model))
        return cls._checked("Pinocchio", scene, model.nq, model.nv, slots, fixed, neutral)

    @classmethod
    def mujoco(cls, scene: Scene, model) -> "CoordinateMap":
        """The map to a MuJoCo ``model`` (``mujoco.MjModel``) of the same MJCF file."""
        slots = []
        for jid in range(model.njnt):
            name, kind = model.joint(jid).name, int(model.jnt_type[jid])
            if kind == MJ_FREE:
                body = model.body(int(model.jnt_bodyid[jid])).name
                free = [f.name for f in scene.free_joints.values() if f.child == element_name(body)]
                if not free:
                    raise CoordinateError(f"MuJoCo joint {name!r}", f"is a free joint of body {body!r}, which has "
                                                                     "none in the scene")
                slots.append(Slot(free[0], FREE_WXYZ, int(model.jnt_qposadr[jid]), int(model.jnt_dofadr[jid])))
                continue
            form = QUAT_WXYZ if kind == MJ_BALL else ANGLE
            _check_joint(scene, name, form, f"MuJoCo joint {name!r}")
            slots.append(Slot(name, form, int(model.jnt_qposadr[jid]), int(model.jnt_dofadr[jid])))
        return cls._checked("MuJoCo", scene, model.nq, model.nv, slots, [],
                            tuple(float(x) for x in model.qpos0))

    @classmethod
    def _checked(cls, tool, scene, nq, nv, slots, locked, neutral) -> "CoordinateMap":
        covered = {j for s in slots for j in (scene.free_joints[s.joint].joints if s.form in FREE else (s.joint,))}
        missing = [j.name for j in scene.joints.values() if j.dof and j.name not in covered]
        if missing:
            raise CoordinateError(f"joint {missing[0]!r}", f"is not in {tool}'s model "
                                                            f"({len(missing)} scene joint(s) missing)")
        order = {name: i for i, name in enumerate(scene.joints)}

        def first(slot):
            return order[scene.free_joints[slot.joint].joints[0] if slot.form in FREE else slot.joint]

        return cls(tool, nq, nv, tuple(sorted(slots, key=first)), tuple(locked), neutral)

    # ------------------------------------------------------------------ maps
    def rate_names(self) -> list[str]:
        """symgen's rate names in scene order (``Model.all_coordinate_names()``)."""
        return [n for s in self.slots for n in _rate_names(s)]

    def to_symgen(self, q=None, v=None, *, qpos=None, qvel=None) -> tuple[Configuration, dict]:
        """``(Configuration, {rate name: value})`` of the other tool's ``q`` (and ``v``); MuJoCo's
        names ``qpos``/``qvel`` may be used instead."""
        q, v = (qpos if q is None else q), (qvel if v is None else v)
        if q is None:
            raise CoordinateError(f"{self.tool} q", "is missing: give q (or qpos)")
        q = np.asarray(q, dtype=float).ravel()
        if q.size != self.nq:
            raise CoordinateError(f"{self.tool} q", f"has {q.size} entries; the model has nq = {self.nq}")
        positions: dict = {}
        for s in self.slots:
            if s.form in FREE:
                positions.update(_free_positions(s, q))
            elif s.form == ANGLE:
                positions[s.joint] = float(q[s.q])
            elif s.form == COS_SIN:
                positions[s.joint] = float(np.arctan2(q[s.q + 1], q[s.q]))
            else:
                quat = q[s.q:s.q + 4]
                wxyz = quat if s.form == QUAT_WXYZ else np.array([quat[3], quat[0], quat[1], quat[2]])
                positions[s.joint] = quaternion_rotation(wxyz)
        rates: dict = {}
        if v is not None:
            v = np.asarray(v, dtype=float).ravel()
            if v.size != self.nv:
                raise CoordinateError(f"{self.tool} v", f"has {v.size} entries; the model has nv = {self.nv}")
            for s in self.slots:
                values = v[s.v:s.v + len(_rate_names(s))].copy()
                if s.form == FREE_XYZW:       # Pinocchio's linear rate is in the body's axes
                    values[:3] = positions[FreeJoint(s.joint, "", "").rotation] @ values[:3]
                rates.update({n: float(x) for n, x in zip(_rate_names(s), values)})
        return Configuration(positions), rates

    def from_symgen(self, config, rates: dict | None = None) -> tuple[np.ndarray, np.ndarray]:
        """The other tool's ``(q, v)`` of a symgen configuration and rates (missing rates are 0)."""
        positions = config.positions if isinstance(config, Configuration) else dict(config)
        q, v = np.array(self.neutral, dtype=float), np.zeros(self.nv)
        for index, form, value in self.locked:
            _write(q, index, form, value)
        for s in self.slots:
            values = np.array([float((rates or {}).get(n, 0.0)) for n in _rate_names(s)])
            if s.form in FREE:
                free = FreeJoint(s.joint, "", "")
                rot = np.array(positions[free.rotation], dtype=float)
                q[s.q:s.q + 3] = [float(positions[j]) for j in free.translations]
                _write(q, s.q + 3, QUAT_WXYZ if s.form == FREE_WXYZ else QUAT_XYZW, rot)
                if s.form == FREE_XYZW:
                    values[:3] = rot.T @ values[:3]
            else:
                _write(q, s.q, s.form, positions[s.joint])
            v[s.v:s.v + len(values)] = values
        return q, v

    def velocity_indices(self, names) -> np.ndarray:
        """The other tool's ``v`` index of each symgen rate name (``j`` or ``j.wx``)."""
        where = {n: s.v + k for s in self.slots for k, n in enumerate(_rate_names(s))}
        return np.array([where[n] for n in names], dtype=int)


FREE = (FREE_WXYZ, FREE_XYZW)


def _rate_names(slot: Slot) -> list[str]:
    if slot.form in FREE:
        return list(FreeJoint(slot.joint, "", "").velocity_labels)
    return [f"{slot.joint}.{c}" for c in ("wx", "wy", "wz")] if slot.form in (QUAT_WXYZ, QUAT_XYZW) else [slot.joint]


def _write(q: np.ndarray, index: int, form: str, value) -> None:
    """One joint's position into ``q`` in ``form``."""
    if form == ANGLE:
        q[index] = float(value)
    elif form == COS_SIN:
        q[index:index + 2] = np.cos(float(value)), np.sin(float(value))
    else:
        w, x, y, z = _matrix_quaternion(np.array(value, dtype=float))
        q[index:index + 4] = (w, x, y, z) if form == QUAT_WXYZ else (x, y, z, w)


def _matrix_quaternion(r: np.ndarray) -> tuple:
    """The unit quaternion ``(w, x, y, z)``, ``w >= 0``, of a rotation matrix."""
    t = np.trace(r)
    if t > 0:
        s = 2.0 * np.sqrt(1.0 + t)
        return 0.25 * s, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s
    i = int(np.argmax(np.diag(r)))
    j, k = (i + 1) % 3, (i + 2) % 3
    s = 2.0 * np.sqrt(1.0 + r[i, i] - r[j, j] - r[k, k])
    out = [0.0, 0.0, 0.0, 0.0]
    out[0] = (r[k, j] - r[j, k]) / s
    out[1 + i], out[1 + j], out[1 + k] = 0.25 * s, (r[j, i] + r[i, j]) / s, (r[k, i] + r[i, k]) / s
    return tuple(-x for x in out) if out[0] < 0 else tuple(out)


def _free_positions(slot: Slot, q: np.ndarray) -> dict:
    """The positions of a free joint's parts from the other tool's ``q``."""
    free = FreeJoint(slot.joint, "", "")
    quat = q[slot.q + 3:slot.q + 7]
    wxyz = quat if slot.form == FREE_WXYZ else np.array([quat[3], quat[0], quat[1], quat[2]])
    out = {j: float(q[slot.q + k]) for k, j in enumerate(free.translations)}
    out[free.rotation] = quaternion_rotation(wxyz)
    return out


def _free_root(scene: Scene, element: str) -> str:
    """The scene's free joint at the root, for another tool's root free flyer."""
    roots = [f.name for f in scene.free_joints.values() if f.parent == "world"]
    if len(roots) != 1:
        raise CoordinateError(element, f"is a free flyer at the root; the scene has {len(roots)} free joints "
                                       "on the world (load the robot with floating=True)")
    return roots[0]


def _check_joint(scene: Scene, name: str, form: str, element: str) -> None:
    joint = scene.joints.get(name)
    if joint is None or not joint.dof:
        raise CoordinateError(element, f"has no moving joint {name!r} in scene {scene.name!r}")
    if (joint.dof == 3) != (form in (QUAT_WXYZ, QUAT_XYZW)):
        raise CoordinateError(element, f"has {joint.dof} DOF in symgen but a {form} position")


def _urdf_names(scene: Scene) -> dict:
    """``{URDF joint name: scene joint name}`` over every URDF source of the scene."""
    from .urdf.build import UrdfSource

    return {k: v for src in scene.sources if isinstance(src, UrdfSource) for k, v in src.joints.items()}


def _urdf_locks(scene: Scene) -> dict:
    from .urdf.build import UrdfSource

    return {k: v for src in scene.sources if isinstance(src, UrdfSource) for k, v in src.lock.items()}


def _pin_neutral(model) -> np.ndarray:
    """Pinocchio's neutral configuration, built from the joints (no import of pinocchio here)."""
    q = np.zeros(model.nq)
    for jid in range(1, model.njoints):
        joint = model.joints[jid]
        if joint.nq == 2:
            q[joint.idx_q] = 1.0
        elif joint.nq == 4:
            q[joint.idx_q + 3] = 1.0
    return q
