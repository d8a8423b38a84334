"""A body's mass properties from its geoms, by MuJoCo's rules (``<compiler inertiafromgeom>``).

Which bodies. ``inertiafromgeom="auto"`` (MuJoCo's default) computes them for a body without
``<inertial>``; ``"true"`` for every body, its ``<inertial>`` overridden; ``"false"`` never (a body
without ``<inertial>`` is massless). Only geoms whose ``group`` (default 0) lies in
``<compiler inertiagrouprange>`` (default ``0 5``) count.

Each geom is a solid of uniform density: ``mass`` when given (MuJoCo then ignores ``density``),
else ``density`` (default 1000) times its volume. Shapes, with ``size`` as MuJoCo reads it and the
moments of inertia about the geom's centre in its own axes (``m`` its mass):

* ``sphere`` (radius r): ``V = 4/3 pi r^3``, ``I = 2/5 m r^2`` about every axis;
* ``ellipsoid`` (semi-axes a, b, c): ``V = 4/3 pi abc``, ``Ixx = m (b^2 + c^2) / 5`` and so on;
* ``box`` (half-sizes a, b, c): ``V = 8abc``, ``Ixx = m (b^2 + c^2) / 3`` and so on;
* ``cylinder`` (radius r, half-length h, length L = 2h): ``V = pi r^2 L``,
  ``Ixx = Iyy = m (3 r^2 + L^2) / 12``, ``Izz = m r^2 / 2``;
* ``capsule`` (radius r, half-length h of its cylinder, L = 2h): a cylinder of mass ``mc`` and two
  hemispheres of total mass ``ms`` (their share of the volume ``pi r^2 L + 4/3 pi r^3``):
  ``Ixx = Iyy = mc (3 r^2 + L^2) / 12 + ms (2 r^2 / 5 + L^2 / 4 + 3 L r / 8)``,
  ``Izz = mc r^2 / 2 + 2/5 ms r^2`` (each hemisphere moved from its centre of mass, 3r/8 from its
  flat face, to the capsule's centre by the parallel-axis theorem).

``fromto`` (capsule, cylinder, box, ellipsoid) puts the geom's centre halfway, its z axis along
``to - from`` and its half-length at ``|to - from| / 2``; only ``size[0]`` is read then, as the
radius of a capsule or cylinder and as *both* transverse half-sizes of a box or ellipsoid
(MuJoCo's rule, checked against its compiled masses). Such a solid is symmetric about its z axis,
so its inertia ``Ixx 1 + (Izz - Ixx) z z^T`` is exact whatever rotation takes z along the segment.
Otherwise ``pos`` and the orientation place it. The body's mass is the sum, its centre of mass the
mass-weighted mean, its inertia the sum of the geoms' inertias moved to that point
(parallel-axis theorem). Everything is exact (``pi`` and square roots stay symbols) except a geom
turned by ``euler``/``axisangle``/``xyaxes``/``zaxis``, whose rotation is snapped as every MJCF
orientation is (:mod:`symgen.io.mjcf.values`).

A ``mesh`` geom takes its mass properties from its mesh file (:mod:`symgen.io.mjcf.meshes`: as
MuJoCo computes them, in floating point, then stored as exact decimals), placed by its ``pos`` and
orientation like any other geom.

Refused, naming the geom: ``hfield``, ``plane`` and ``sdf`` geoms that would give mass (give the
body an ``<inertial>``), a primitive geom with ``mesh=...`` (MuJoCo fits the primitive to the mesh,
which is not read), ``shellinertia="true"``, a negative mass or density.
"""
from __future__ import annotations

import numpy as np
import sympy as sp

from .meshes import DENSITY, MeshLibrary, exact, mesh_geom_inertial
from .records import MjcfInertial
from .values import Attrs, Values

#: the geom shapes whose mass properties MuJoCo computes from their size
SOLIDS = ("sphere", "capsule", "cylinder", "box", "ellipsoid")
MESH = "mesh"
#: shapes that give no solid: a body taking its inertia from them needs <inertial>
NOT_SOLID = ("hfield", "plane", "sdf")
FROMTO_SHAPES = ("capsule", "cylinder", "box", "ellipsoid")
#: MuJoCo's defaults (DENSITY, shared with mesh geoms, is in :mod:`symgen.io.mjcf.meshes`)
GROUP_RANGE = "0 5"
#: how many numbers of ``size`` each shape reads (without fromto, with it)
SIZES = {"sphere": (1, 1), "capsule": (2, 1), "cylinder": (2, 1), "box": (3, 1), "ellipsoid": (3, 1)}


def in_group_range(values: Values, attrs: Attrs, group_range: tuple) -> bool:
    """Whether a geom's ``group`` lies in ``inertiagrouprange``."""
    group = values.numbers(attrs, "group", 1, "0", scale=False)[0]
    return group_range[0] <= group <= group_range[1]


def _size(values: Values, attrs: Attrs, kind: str, fromto: bool) -> list:
    """The numbers of ``size`` the shape reads (MuJoCo reads the first ones; the rest may be absent)."""
    need = SIZES[kind][1 if fromto else 0]
    text = attrs.get("size")
    parts = [] if text is None else text.split()
    if len(parts) > 3 or len(parts) < need:
        values.fail(attrs.origin("size") if text is not None else attrs.el,
                    f"size={text or ''!r}: a {kind}{' given by fromto' if fromto else ''} needs {need} positive "
                    f"number{'s' if need > 1 else ''} (at most 3)")
    out = [values.number(attrs.origin("size"), "size", p) for p in parts[:need]]
    if any(v <= 0 for v in out):
        values.fail(attrs.origin("size"), f"size={text!r}: the sizes a {kind} reads must be positive")
    return out


def _principal(kind: str, mass, size: list) -> tuple:
    """``(volume, (Ixx, Iyy, Izz))`` of a solid of mass ``mass`` in its own axes (module docstring)."""
    if kind == "sphere":
        r = size[0]
        return sp.Rational(4, 3) * sp.pi * r**3, (sp.Rational(2, 5) * mass * r**2,) * 3
    if kind == "ellipsoid":
        a, b, c = size
        return (sp.Rational(4, 3) * sp.pi * a * b * c,
                (mass * (b**2 + c**2) / 5, mass * (a**2 + c**2) / 5, mass * (a**2 + b**2) / 5))
    if kind == "box":
        a, b, c = size
        return 8 * a * b * c, (mass * (b**2 + c**2) / 3, mass * (a**2 + c**2) / 3, mass * (a**2 + b**2) / 3)
    r, length = size[0], 2 * size[1]
    cylinder = sp.pi * r**2 * length
    if kind == "cylinder":
        side = mass * (3 * r**2 + length**2) / 12
        return cylinder, (side, side, mass * r**2 / 2)
    sphere = sp.Rational(4, 3) * sp.pi * r**3
    volume = cylinder + sphere
    mc, ms = mass * cylinder / volume, mass * sphere / volume
    side = mc * (3 * r**2 + length**2) / 12 + ms * (sp.Rational(2, 5) * r**2 + length**2 / 4 + 3 * length * r / 8)
    return volume, (side, side, mc * r**2 / 2 + sp.Rational(2, 5) * ms * r**2)


def _volume(kind: str, size: list):
    return _principal(kind, sp.Integer(1), size)[0]


def geom_inertial(values: Values, attrs: Attrs, pose, meshes: MeshLibrary | None = None) -> MjcfInertial | None:
    """The mass properties of one geom in its body's frame (``pose``: its enclosing frames), or
    None when it has no mass; ``meshes``: the file's meshes, for a mesh geom."""
    el = attrs.el
    kind = values.keyword(attrs, "type", SOLIDS + (MESH,) + NOT_SOLID, "sphere")
    if kind in NOT_SOLID:
        values.fail(attrs.origin("type") if "type" in attrs else el,
                    f"a {kind} geom gives its body's inertia here (inertia from geoms), which symgen does not "
                    "compute: give the body an <inertial> (with <compiler inertiafromgeom> 'auto' or 'false')")
    if values.boolean(attrs, "shellinertia", False):
        values.fail(attrs.origin("shellinertia"), "shellinertia='true' (a hollow shell) is not read: give the "
                                                  "body an <inertial> (or the mesh inertia='shell')")
    if kind == MESH:
        return _mesh_inertial(values, attrs, pose, meshes)
    if "mesh" in attrs:
        values.fail(attrs.origin("mesh"), f"a {kind} geom with mesh=... is fitted to the mesh by MuJoCo, which "
                                          "symgen does not read: give the body an <inertial>")
    fromto = values.numbers(attrs, "fromto", 6)
    if fromto is not None and kind not in FROMTO_SHAPES:
        values.fail(attrs.origin("fromto"), f"fromto is not read for a {kind} (MuJoCo takes it for "
                                            f"{', '.join(FROMTO_SHAPES)})")
    size = _size(values, attrs, kind, fromto is not None)
    if fromto is not None:
        start, end = sp.Matrix(fromto[:3]), sp.Matrix(fromto[3:])
        axis = end - start
        half = sp.sqrt(axis.dot(axis)) / 2
        if half == 0:
            values.fail(attrs.origin("fromto"), "fromto: the two points must differ")
        size = [size[0], size[0], half] if kind in ("box", "ellipsoid") else [size[0], half]
        centre, z, rot = (start + end) / 2, axis / (2 * half), None
    else:
        centre = sp.Matrix(values.numbers(attrs, "pos", 3, "0 0 0"))
        rot, z = values.rotation(attrs), None
    mass = _mass(values, attrs, kind, size)
    if mass == 0:
        return None
    _, (ixx, iyy, izz) = _principal(kind, mass, size)
    if rot is None:                      # symmetric about z: I = Ixx 1 + (Izz - Ixx) z z^T, exactly
        inertia = ixx * sp.eye(3) + (izz - ixx) * z * z.T
    else:
        inertia = rot * sp.diag(ixx, iyy, izz) * rot.T
    inertia = pose.rot * inertia * pose.rot.T
    return MjcfInertial(mass, (pose.pos + pose.rot * centre).applyfunc(sp.expand), inertia.applyfunc(sp.expand))


def _mesh_inertial(values: Values, attrs: Attrs, pose, meshes: MeshLibrary | None) -> MjcfInertial | None:
    """A mesh geom's mass properties (:mod:`symgen.io.mjcf.meshes`) placed by its pose."""
    if values.numbers(attrs, "fromto", 6) is not None:
        values.fail(attrs.origin("fromto"), "fromto is not read for a mesh")
    got = mesh_geom_inertial(values, attrs, meshes)
    if got is None:
        return None
    mass, com, inertia = got
    rot = pose.rot * values.rotation(attrs)
    centre = pose.pos + pose.rot * sp.Matrix(values.numbers(attrs, "pos", 3, "0 0 0"))
    return MjcfInertial(mass, (centre + rot * com).applyfunc(sp.expand), (rot * inertia * rot.T).applyfunc(sp.expand),
                        rounded=True)


def _mass(values: Values, attrs: Attrs, kind: str, size: list):
    """``mass`` when given, else ``density`` times the volume (exact)."""
    if "mass" in attrs:
        mass = values.scalar(attrs, "mass")
        if mass < 0:
            values.fail(attrs.origin("mass"), "mass must not be negative")
        return mass
    density = values.scalar(attrs, "density", DENSITY)
    if density < 0:
        values.fail(attrs.origin("density"), "density must not be negative")
    return density * _volume(kind, size)


def _combined_rounded(parts: list) -> MjcfInertial:
    """:func:`combined` in floating point, for parts of which one at least is rounded already (a
    mesh's): the exact sum would only carry long decimals, not exactness; stored as exact decimals."""
    masses = np.array([float(p.mass) for p in parts])
    pos = np.array([np.array(p.pos, dtype=float).ravel() for p in parts])
    mass = masses.sum()
    com = masses @ pos / mass
    inertia = np.zeros((3, 3))
    for m, x, p in zip(masses, pos, parts):
        d = x - com
        inertia += np.array(p.inertia, dtype=float) + m * (d @ d * np.eye(3) - np.outer(d, d))
    inertia = (inertia + inertia.T) / 2
    return MjcfInertial(exact(mass), sp.Matrix([exact(v) for v in com]),
                        sp.Matrix(3, 3, [exact(v) for v in inertia.ravel()]), rounded=True)


def combined(parts: list) -> MjcfInertial | None:
    """The mass properties of rigidly joined parts (mass, centre of mass, inertia about it), exact."""
    parts = [p for p in parts if p is not None]
    mass = sum((p.mass for p in parts), sp.Integer(0))
    if not parts or mass == 0:
        return None
    if any(p.rounded for p in parts):
        return _combined_rounded(parts)
    com = (sum((p.mass * p.pos for p in parts), sp.zeros(3, 1)) / mass).applyfunc(sp.cancel)
    inertia = sp.zeros(3, 3)
    for p in parts:
        d = p.pos - com
        inertia += p.inertia + p.mass * (d.dot(d) * sp.eye(3) - d * d.T)
    return MjcfInertial(sp.expand(mass), com, inertia.applyfunc(sp.cancel))
