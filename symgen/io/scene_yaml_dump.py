"""Writing a :class:`~symgen.scene.Scene` as YAML text (the format of :mod:`symgen.io.scene_yaml`).

Each value is written in a form that reads back to the identical SymPy object: plain decimals when
the float text is exact (``0.1``), ``"p/q"`` otherwise, ``"k*pi/q"`` for rational multiples of
pi, and parameter names for symbols. A rotation with rational entries is written as an integer
quaternion ``quat: [w, x, y, z]`` (unnormalised; ``exact_quat`` divides by its squared norm); any
other rotation as ``rpy`` angles recovered from the matrix and checked to rebuild the identical
matrix. A value with no exact form raises a :class:`~symgen.errors.SceneError` naming its owner
rather than being written approximately.

The output is deterministic: sections and elements in declaration order, one element per line.
"""
from __future__ import annotations

import math
import os
import tempfile
from fractions import Fraction
from pathlib import Path

import sympy as sp
import yaml

from ..errors import SceneError
from ..scene.declaration import Scene
from ..math.spatial import AXIS_NAMES, exact_quat, exact_rpy

__all__ = ["dump_scene", "save_scene", "rational_quat"]


class _Flow(dict):
    """A mapping written on one line (``{a: 1, b: 2}``)."""


class _Dumper(yaml.SafeDumper):
    """Block style for sections, flow style for elements and lists."""


_Dumper.add_representer(_Flow, lambda d, v: d.represent_mapping("tag:yaml.org,2002:map", v, flow_style=True))
_Dumper.add_representer(list, lambda d, v: d.represent_sequence("tag:yaml.org,2002:seq", v, flow_style=True))


def _value(x, element: str):
    """The YAML form of an exact value that reads back to the identical SymPy object."""
    x = sp.sympify(x)
    if x.is_Symbol:
        return x.name
    if x.is_Integer:
        return int(x)
    if x.is_Rational:
        as_float = float(x)
        return as_float if sp.Rational(repr(as_float)) == x else f"{x.p}/{x.q}"
    c = x / sp.pi
    if c.is_Rational:
        head = {1: "pi", -1: "-pi"}.get(c.p, f"{c.p}*pi")
        return head if c.q == 1 else f"{head}/{c.q}"
    raise SceneError(element, f"value {x} cannot be written exactly in a scene file")


def _values(xs, element: str) -> list:
    return [_value(v, element) for v in xs]


def rational_quat(r: sp.Matrix) -> list[int]:
    """Integer quaternion ``[w, x, y, z]`` (unnormalised, gcd 1) of a rational rotation matrix."""
    d = [1 + r.trace(), 1 + r[0, 0] - r[1, 1] - r[2, 2], 1 - r[0, 0] + r[1, 1] - r[2, 2],
         1 - r[0, 0] - r[1, 1] + r[2, 2]]
    a, b, c = r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]  # 4w(x, y, z)
    e, f, g = r[0, 1] + r[1, 0], r[0, 2] + r[2, 0], r[1, 2] + r[2, 1]  # 4(xy, xz, yz)
    rows = [[d[0], a, b, c], [a, d[1], e, f], [b, e, d[2], g], [c, f, g, d[3]]]  # 4 q_k q
    q = [Fraction(int(v.p), int(v.q)) for v in rows[max(range(4), key=lambda k: d[k])]]
    den = math.lcm(*(v.denominator for v in q))
    ints = [int(v * den) for v in q]
    if not any(ints):  # not a rotation; callers check the result with exact_quat
        return [1, 0, 0, 0]
    gcd = math.gcd(*ints)
    sign = -1 if next(v for v in ints if v) < 0 else 1
    return [sign * v // gcd for v in ints]


def _angle(c, s):
    """The angle with cosine ``c`` and sine ``s``, read off ``cos(x)``/``sin(x)`` when it can be."""
    if isinstance(c, sp.cos) and s in (sp.sin(c.args[0]), -sp.sin(c.args[0])):
        return c.args[0] if s == sp.sin(c.args[0]) else -c.args[0]
    return sp.atan2(s, c)


def _asin(s):
    for sign in (1, -1):
        if isinstance(sign * s, sp.sin):
            return sign * (sign * s).args[0]
    return sp.asin(s)


def _rotation_items(r: sp.Matrix, element: str) -> dict:
    """``{}`` for the identity, else ``{"quat": ...}`` or ``{"rpy": ...}`` that rebuilds ``r``."""
    r = sp.Matrix(r)
    if r == sp.eye(3):
        return {}
    if all(v.is_Rational for v in r):
        q = rational_quat(r)
        if exact_quat(*q) == r:
            return {"quat": q}
    pitch = _asin(-r[2, 0])
    cp = sp.cos(pitch)
    if cp == 0:
        rpy = [sp.Integer(0), pitch, _angle(r[1, 1], -r[0, 1])]
    else:
        rpy = [_angle(r[2, 2] / cp, r[2, 1] / cp), pitch, _angle(r[0, 0] / cp, r[1, 0] / cp)]
    try:
        if exact_rpy(*rpy) == r:
            return {"rpy": _values(rpy, element)}
    except SceneError:
        pass
    raise SceneError(element, "rotation cannot be written exactly (declare it with a rational "
                              "quaternion or rpy angles that are numbers or multiples of pi)")


def _pose_items(pose, element: str) -> dict:
    return {"xyz": _values(pose.translation, element), **_rotation_items(pose.rotation, element)}


def _axis_item(axis, element: str):
    for name, i in AXIS_NAMES.items():
        unit = sp.Matrix([int(k == i) for k in range(3)])
        if sp.Matrix(axis) == unit:
            return name
        if sp.Matrix(axis) == -unit:
            return f"-{name}"
    lead = next(v for v in axis if v != 0)
    scaled = [v / abs(lead) for v in axis]
    if sp.Matrix(scaled) / sp.sqrt(sum(v * v for v in scaled)) != sp.Matrix(axis):
        raise SceneError(element, f"axis {list(axis)} cannot be written exactly")
    return _values(scaled, element)


def _joint_item(j) -> _Flow:
    element = f"joint {j.name!r}"
    out = _Flow(type=j.type, parent=j.parent, child=j.child, **_pose_items(j.origin, element))
    if j.dof == 1:
        out["axis"] = _axis_item(j.axis, element)
    if j.kind.moves:
        out["actuated"] = bool(j.actuated)
    if j.rotor_inertia != 0:
        out["rotor_inertia"] = _value(j.rotor_inertia, element)
    friction = {k: _value(v, element) for k, v in (("viscous", j.viscous), ("coulomb", j.coulomb)) if v != 0}
    if friction:
        out["friction"] = _Flow(friction)
    for key, value in (("stiffness", j.stiffness), ("springref", j.springref)):
        if value != 0:
            out[key] = _value(value, element)
    if j.kind.position_is_rotation and sp.Matrix(j.q0) != sp.eye(3):
        if not all(v.is_Rational for v in j.q0):
            raise SceneError(element, "q0 cannot be written exactly (a spherical q0 needs rational entries)")
        out["q0"] = rational_quat(sp.Matrix(j.q0))
    elif j.kind.is_one_dof and j.q0 != 0:
        out["q0"] = _value(j.q0, element)
    return out


def _free_joint_item(scene: Scene, free) -> _Flow:
    """A free joint as it was declared (``type: free``), from the joints it stands for."""
    first = scene.joints[free.translations[0]]
    out = _Flow(type="free", parent=free.parent, child=free.child,
                **_pose_items(first.origin, f"joint {free.name!r}"))
    position = [scene.joints[j].q0 for j in free.translations]
    rotation = sp.Matrix(scene.joints[free.rotation].q0)
    if any(v != 0 for v in position) or rotation != sp.eye(3):
        element = f"joint {free.name!r}"
        if not all(v.is_Rational for v in rotation):
            raise SceneError(element, "q0 cannot be written exactly (a free joint's q0 needs a rational rotation)")
        out["q0"] = [_value(v, element) for v in position] + list(rational_quat(rotation))
    return out


def _joint_items(scene: Scene) -> dict:
    """Every joint's entry; the parts of a free joint as one ``type: free`` entry."""
    part_of = {j: free for free in scene.free_joints.values() for j in free.joints}
    out = {}
    for j in scene.joints.values():
        free = part_of.get(j.name)
        if free is None:
            out[j.name] = _joint_item(j)
        elif j.name == free.translations[0]:
            out[free.name] = _free_joint_item(scene, free)
    return out


def _motion_labels(scene: Scene, labels) -> list[str]:
    """Motion labels with a free joint's six rates, where they stand together, as its name."""
    labels = list(labels)
    for free in scene.free_joints.values():
        rates = list(free.velocity_labels)
        for k in range(len(labels) - 5):
            if labels[k:k + 6] == rates:
                labels[k:k + 6] = [free.name]
                break
    return labels


def _coupling_item(c) -> _Flow:
    """A joint coupling in the mimic form when it has one leader, else with its ``terms``."""
    element = f"constraint {c.name!r}"
    (joint, _), *others = c.terms
    out = _Flow(type=c.kind, joint=joint)
    if len(others) == 1:
        out["leader"] = others[0][0]
        if others[0][1] != -1:
            out["multiplier"] = _value(-others[0][1], element)
    else:
        out["terms"] = _Flow({j: _value(v, element) for j, v in others})
    if c.offset != 0:
        out["offset"] = _value(c.offset, element)
    return out


def _constraint_item(c) -> _Flow:
    if c.is_coupling:
        return _coupling_item(c)
    out = _Flow(type=c.kind, frames=[c.frame_a, c.frame_b])
    if c.kind == "custom":
        out["components"] = list(c.components)
    elif c.kind in ("planar_weld", "plane_contact"):
        kept = "w" if c.kind == "planar_weld" else "v"
        normal = next(comp[1] for comp in c.components if comp[0] == kept)
        if normal != "z":
            out["normal"] = normal
    return out


def _motion_item(m, scene: Scene) -> _Flow:
    if not m.frames:
        return _Flow(joints=_motion_labels(scene, m.joints))
    comps = list(m.components)
    joints = {"joints": _motion_labels(scene, m.joints)} if m.joints else {}
    if len(m.frames) == 1 and m.frames[0][1] == 1:
        return _Flow(frame=m.frames[0][0], components=comps, **joints)
    return _Flow(frames=_Flow((f, _value(g, "motion")) for f, g in m.frames), components=comps, **joints)


def dump_scene(scene: Scene) -> str:
    """The scene as YAML text; deterministic, and :func:`scene_from_dict` of its
    :func:`yaml.safe_load` rebuilds an equal :class:`Scene`.

    Raises:
        SceneError: a value (e.g. a rotation) has no exact form in the scene format.
    """
    data: dict = {"name": scene.name}
    if scene.description:
        data["description"] = scene.description
    data["gravity"] = _values(scene.gravity, "gravity")
    if scene.parameters:
        data["parameters"] = {str(s): _value(v, f"parameter {str(s)!r}")
                              for s, v in scene.parameters.items()}
    if scene.bodies:
        data["bodies"] = {}
    carriers = {b for free in scene.free_joints.values() for b in free.carriers}
    for b in scene.bodies.values():
        if b.name in carriers:
            continue
        element = f"body {b.name!r}"
        i = b.inertia
        off = [i[0, 1], i[0, 2], i[1, 2]]  # written only when not all zero
        inertia = [i[0, 0], i[1, 1], i[2, 2]] + (off if any(v != 0 for v in off) else [])
        data["bodies"][b.name] = _Flow(mass=_value(b.mass, element), com=_values(b.com, element),
                                       inertia=_values(inertia, element))
    if scene.joints:
        data["joints"] = _joint_items(scene)
    if scene.frames:
        data["frames"] = {f.name: _Flow(body=f.body, **_pose_items(f.pose, f"frame {f.name!r}"))
                          for f in scene.frames.values()}
    if scene.constraints:
        data["constraints"] = {c.name: _constraint_item(c) for c in scene.constraints.values()}
    if scene.motion is not None:
        data["motion"] = _motion_item(scene.motion, scene)
    if scene.contact_forces is not None:
        cf = scene.contact_forces
        data["contact_forces"] = _Flow(frame=cf.frame, components=list(cf.components))
    data["constraint_forces"] = scene.constraint_forces
    return yaml.dump(data, Dumper=_Dumper, sort_keys=False, default_flow_style=False,
                     allow_unicode=True, width=10_000)


def save_scene(scene: Scene, path) -> None:
    """Write :func:`dump_scene` to ``path`` atomically (a temporary file, then a rename)."""
    text = dump_scene(scene)
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as handle:
            handle.write(text)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
