"""Mass properties of mesh geoms, computed from their files as MuJoCo computes them.

Files. A ``<mesh file>`` of ``<asset>`` is found as MuJoCo finds it: an absolute path as given,
else under ``<compiler meshdir>`` (or ``assetdir`` when no ``meshdir`` is given; either relative to
the main MJCF file's directory unless absolute), ``strippath="true"`` keeping only the file's
name. A mesh without ``name`` is named after its file (without directory and extension). Binary
and ASCII STL are read (MuJoCo's limit of 200000 triangles; MuJoCo 4.0 itself refuses ASCII STL,
whose triangles symgen reads by the same rules); a missing, unreadable or malformed
file, another format (OBJ, MSH) or a mesh given by ``vertex``/``builtin`` is an
:class:`~symgen.io.mjcf.values.MjcfError` naming the mesh, its file and the geom that needs it --
only when a geom takes mass from it (a mesh used for looks or collisions only is not read).
``scale`` multiplies each vertex coordinate; ``refpos``, ``refquat`` and ``maxhullvert`` are read
only at their neutral values.

Mass properties, by ``<mesh inertia>`` (MuJoCo 4.0's default is ``legacy``; checked against the
compiled ``body_mass``, ``body_ipos``, ``body_inertia`` of a non-convex prism for every mode). With
the triangles' areas ``A_i``, unit normals ``n_i`` (right-handed order) and centroids ``c_i``, and
``f`` the area-weighted centroid of the surface:

* ``exact``: the solid the (consistently oriented, closed) surface bounds. Volume ``V = sum V_i``
  with the signed pyramid volumes ``V_i = A_i n_i . (c_i - f) / 3`` (divergence theorem), centre of
  mass ``sum V_i (3 c_i / 4 + f / 4) / V``; a surface with an edge run twice the same way is refused
  (inconsistent orientation), as MuJoCo refuses it;
* ``convex`` (MuJoCo's recommended setting): the same integrals over the convex hull of the
  vertices (``scipy.spatial.ConvexHull``, i.e. qhull as in MuJoCo);
* ``legacy``: the pyramids of the mesh's own triangles with ``|V_i|`` -- equal to ``exact`` when the
  solid is star-shaped about ``f`` (a convex mesh), an over-count otherwise, as MuJoCo computes it;
* ``shell``: mass spread over the surface: measure ``S = sum A_i``, centre ``f``.

The second moments about the centre of mass ``C`` sum, per pyramid with apex ``C`` and base
vertices ``d, e, g`` (relative to ``C``), ``V_i / 20 (d d^T + e e^T + g g^T + s s^T)`` with ``s = d +
e + g`` (a triangle of area ``A_i``: ``A_i / 12`` of the same); the volume (area) is summed again
over these pyramids (``|.|`` for ``legacy``) and is the one the mass uses. The inertia per unit
density is ``tr(P) 1 - P``. A measure below MuJoCo's ``mjMINVAL``, a nonpositive principal moment
or principal moments breaking ``A + B >= C`` (MuJoCo's tolerances) are refused as MuJoCo refuses
them.

The geom's mass is its ``mass``, else ``density`` times the measure; its centre and inertia are
those of the mesh placed by the geom's ``pos`` and orientation (MuJoCo re-centres the mesh at its
centre of mass and turns it to its principal axes, then composes the geom's pose: the same solid).

Precision: computed in double precision from the file's single-precision vertices, each result then
stored as the exact rational of its shortest decimal form (as a decimal in the file would be): a
relative error of about 1e-15 times the number of triangles, not exact arithmetic.
"""
from __future__ import annotations

import os
import struct
from dataclasses import dataclass

import numpy as np
import sympy as sp

from .values import Attrs, MjcfError, Values, describe

#: MuJoCo's default density of a geom (kg/m^3, water), for primitive and mesh geoms alike
DENSITY = "1000"

#: ``<mesh inertia>`` keywords and MuJoCo 4.0's default (mjtMeshInertia: mjMESH_INERTIA_LEGACY)
MESH_INERTIA = ("legacy", "convex", "exact", "shell")
DEFAULT_MESH_INERTIA = "legacy"
#: MuJoCo's mjMINVAL, and its bound on the triangles of an STL file
MJMINVAL = 1e-15
MAX_STL_FACES = 200000
#: MuJoCo's tolerances of the triangle inequality of a mesh's principal moments
INEQUALITY_RTOL, INEQUALITY_ATOL = 1e-6, 1e-9
BINARY_HEADER, BINARY_RECORD = 84, 50


@dataclass(frozen=True)
class MeshAsset:
    """One ``<mesh>`` of ``<asset>``: where its file is and how it is read."""

    name: str
    path: str | None          # None: the mesh is not given by a file
    scale: tuple
    inertia: str
    attrs: Attrs


@dataclass(frozen=True)
class MeshMass:
    """A mesh's mass properties per unit density, in the mesh's own frame (floats)."""

    measure: float            # volume, or area for a shell
    com: np.ndarray           # (3,)
    inertia: np.ndarray       # (3, 3) about com


class MeshLibrary:
    """The meshes of an MJCF file's ``<asset>`` sections, read on first use (see the module docstring)."""

    def __init__(self, root, values: Values, defaults, compiler: Attrs, directory: str | None):
        """Index every named ``<mesh>``; ``directory``: the main file's (None when read from text)."""
        self.values, self.directory = values, directory
        self.meshes: dict = {}
        self._mass: dict = {}
        strip = values.boolean(compiler, "strippath", False)
        folder = compiler.get("meshdir", compiler.get("assetdir", ""))
        for section in root.findall("asset"):
            for el in section.findall("mesh"):
                attrs = defaults.attrs(el)
                file = attrs.get("file")
                name = el.get("name") or (os.path.splitext(os.path.basename(file))[0] if file else None)
                if name is None:
                    values.fail(el, "needs a name or a file")
                if name in self.meshes:
                    values.fail(el, f"mesh name {name!r} is declared twice")
                path = None
                if file is not None:
                    file = os.path.basename(file) if strip else file
                    path = file if os.path.isabs(file) else os.path.join(folder, file)
                    if not os.path.isabs(path) and directory is not None:
                        path = os.path.join(directory, path)
                scale = tuple(float(s) for s in values.numbers(attrs, "scale", 3, "1 1 1", scale=False))
                kind = values.keyword(attrs, "inertia", MESH_INERTIA, DEFAULT_MESH_INERTIA)
                self.meshes[name] = MeshAsset(name, path, scale, kind, attrs)

    def mass(self, name: str, geom) -> MeshMass:
        """The mass properties of mesh ``name`` per unit density (``geom``: the geom needing them, named
        in errors)."""
        from .schema import check_neutral

        mesh = self.meshes.get(name)
        if mesh is None:
            self.values.fail(geom, f"mesh {name!r} is not declared in <asset>")
        if name not in self._mass:
            el = mesh.attrs.el
            check_neutral(self.values, "mesh", mesh.attrs)
            given = [a for a in ("vertex", "builtin") if a in mesh.attrs]
            if mesh.path is None or given:
                self.values.fail(el, f"gives its mass to {describe(geom)} (line {geom.sourceline}), but only meshes "
                                     f"from STL files are read{' (not ' + given[0] + '=)' if given else ''}: give "
                                     "the body an <inertial>")
            if not os.path.isabs(mesh.path):
                self.values.fail(el, f"file {mesh.path!r} is relative and the MJCF was read from text: read it "
                                     "from its file (parse_mjcf), or give an absolute path")
            triangles = read_stl(mesh.path, lambda why: self.values.fail(el, f"file {mesh.path!r}: {why}"))
            triangles = triangles * np.asarray(mesh.scale)
            if np.prod(mesh.scale) < 0:      # a mirror: MuJoCo reorders each triangle to keep it outward
                triangles = triangles[:, [0, 2, 1]]
            self._mass[name] = mesh_mass(triangles, mesh.inertia,
                                         lambda why: self.values.fail(el, f"file {mesh.path!r}: {why}"))
        return self._mass[name]


def read_stl(path: str, fail) -> np.ndarray:
    """The triangles ``(n, 3, 3)`` of a binary or ASCII STL file (``fail(reason)`` raises)."""
    try:
        with open(path, "rb") as handle:
            data = handle.read()
    except FileNotFoundError:
        fail("not found")
    except (OSError, ValueError) as exc:
        fail(f"cannot be read ({exc})")
    if not path.lower().endswith(".stl"):
        fail("is not an STL file: only STL meshes are read for mass (OBJ and MSH are not)")
    if len(data) >= BINARY_HEADER:
        count = struct.unpack_from("<I", data, 80)[0]
        if len(data) == BINARY_HEADER + BINARY_RECORD * count:
            if not 1 <= count <= MAX_STL_FACES:
                fail(f"has {count} triangles; MuJoCo reads 1 to {MAX_STL_FACES}")
            records = np.frombuffer(data, dtype=np.dtype([("normal", "<f4", 3), ("v", "<f4", (3, 3)),
                                                          ("attr", "<u2")]), count=count, offset=BINARY_HEADER)
            out = records["v"].astype(np.float64)
            if not np.all(np.isfinite(out)):
                fail("has a vertex that is not a finite number")
            return out
    return _ascii_stl(data, fail)


def _ascii_stl(data: bytes, fail) -> np.ndarray:
    """The triangles of an ASCII STL (``solid ... facet normal ... outer loop vertex x y z ...``)."""
    try:
        words = data.decode("ascii").split()
    except UnicodeDecodeError:
        fail("is neither a binary STL (its size does not match its triangle count) nor ASCII text")
    if not words or words[0] != "solid":
        fail("is neither a binary STL (its size does not match its triangle count) nor an ASCII STL "
             "(it does not start with 'solid')")
    vertices = []
    for i, word in enumerate(words):
        if word == "vertex":
            try:
                vertices.append([float(w) for w in words[i + 1:i + 4]])
            except ValueError:
                fail(f"ASCII STL: 'vertex {' '.join(words[i + 1:i + 4])[:60]}' is not three numbers")
            if len(vertices[-1]) != 3:
                fail("ASCII STL: a vertex needs three numbers")
    if not vertices or len(vertices) % 3:
        fail(f"ASCII STL: {len(vertices)} vertices do not make triangles (a multiple of 3, at least 3)")
    if len(vertices) // 3 > MAX_STL_FACES:
        fail(f"has {len(vertices) // 3} triangles; MuJoCo reads at most {MAX_STL_FACES}")
    out = np.array(vertices, dtype=np.float64).reshape(-1, 3, 3)
    if not np.all(np.isfinite(out)):
        fail("has a vertex that is not a finite number")
    return out


def _faces(tri: np.ndarray) -> tuple:
    """``(areas, unit normals, centroids)`` of triangles; below mjMINVAL a face has no area (MuJoCo)."""
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    length = np.linalg.norm(cross, axis=1)
    keep = length >= MJMINVAL
    normal = np.zeros_like(cross)
    normal[keep] = cross[keep] / length[keep, None]
    return np.where(keep, length / 2, 0.0), normal, tri.mean(axis=1)


def _hull(tri: np.ndarray, fail) -> np.ndarray:
    """The convex hull's triangles of the vertices of ``tri``, each ordered outward."""
    from scipy.spatial import ConvexHull, QhullError

    points = np.unique(tri.reshape(-1, 3), axis=0)
    try:
        hull = ConvexHull(points)
    except (QhullError, ValueError) as exc:
        fail(f"its convex hull cannot be built (a flat or degenerate mesh: {str(exc).splitlines()[0][:80]})")
    faces = points[hull.simplices]
    outward = np.einsum("ij,ij->i", np.cross(faces[:, 1] - faces[:, 0], faces[:, 2] - faces[:, 0]),
                        hull.equations[:, :3]) >= 0
    return np.where(outward[:, None, None], faces, faces[:, [0, 2, 1]])


def _check_orientation(tri: np.ndarray, fail) -> None:
    """MuJoCo's rule for ``exact``: no directed edge twice (faces of area above sqrt(mjMINVAL))."""
    area, _, _ = _faces(tri)
    edges = {}
    for face in tri[area > np.sqrt(MJMINVAL)]:
        for a, b in ((0, 1), (1, 2), (2, 0)):
            key = (tuple(face[a]), tuple(face[b]))
            if key in edges:
                fail("inertia='exact' needs consistently oriented faces: the edge from "
                     f"{list(map(float, face[a]))} to {list(map(float, face[b]))} is run twice the same way")
            edges[key] = True


def mesh_mass(tri: np.ndarray, kind: str, fail) -> MeshMass:
    """The mass properties per unit density of triangles ``tri`` for ``<mesh inertia=kind>`` (module
    docstring); ``fail(reason)`` raises."""
    area, normal, centre = _faces(tri)
    if area.sum() < MJMINVAL:
        fail("its surface area is too small (MuJoCo refuses it)")
    surface_centre = (area[:, None] * centre).sum(axis=0) / area.sum()
    if kind == "exact":
        _check_orientation(tri, fail)
    solid = _hull(tri, fail) if kind == "convex" else tri
    if kind != "shell":
        area, normal, centre = _faces(solid)
    if kind == "shell":
        com = surface_centre
    else:
        pyramids = np.einsum("ij,ij->i", centre - surface_centre, normal) * area / 3
        pyramids = np.abs(pyramids) if kind == "legacy" else pyramids
        volume = pyramids.sum()
        if volume < MJMINVAL:
            fail("its volume is negative (faces oriented inward)" if volume < 0 else
                 "its volume is too small (MuJoCo refuses it; inertia='shell' spreads the mass on the surface)")
        com = (pyramids[:, None] * (0.75 * centre + 0.25 * surface_centre)).sum(axis=0) / volume
    rel = solid - com
    area, normal, centre = _faces(rel)
    weights = area if kind == "shell" else np.einsum("ij,ij->i", centre, normal) * area / 3
    weights = np.abs(weights) if kind == "legacy" else weights
    total = rel.sum(axis=1)
    second = (np.einsum("nvi,nvj->nij", rel, rel) + np.einsum("ni,nj->nij", total, total))
    p = (weights[:, None, None] * second).sum(axis=0) / (12 if kind == "shell" else 20)
    inertia = np.trace(p) * np.eye(3) - p
    moments = np.linalg.eigvalsh(inertia)
    if moments.max() <= 0:
        fail("a principal moment of inertia is not positive (MuJoCo refuses it)")
    a, b, c = moments
    if a + b < c * (1 - INEQUALITY_RTOL) - INEQUALITY_ATOL:
        fail("its principal moments of inertia violate A + B >= C (MuJoCo refuses it)")
    return MeshMass(float(weights.sum()), com, inertia)


def exact(x: float) -> sp.Rational:
    """The exact rational of a float's shortest decimal form (as if written in the file)."""
    return sp.Rational(repr(float(x)))


def mesh_geom_inertial(values: Values, attrs: Attrs, library: MeshLibrary | None):
    """``(mass, centre, inertia)`` of a mesh geom in its own frame, exact numbers from floats (see
    the module docstring); None when its mass is zero."""
    el = attrs.el
    name = attrs.get("mesh")
    if name is None:
        values.fail(attrs.origin("type"), "a mesh geom needs mesh=... (the name of an <asset><mesh>)")
    if library is None:
        values.fail(el, "mesh geoms need the file's <asset> section")
    props = library.mass(name, el)
    if "mass" in attrs:
        mass = values.scalar(attrs, "mass")
        if mass < 0:
            values.fail(attrs.origin("mass"), "mass must not be negative")
        density = float(mass) / props.measure
    else:
        density = values.scalar(attrs, "density", DENSITY)
        if density < 0:
            values.fail(attrs.origin("density"), "density must not be negative")
        mass = exact(float(density) * props.measure)
        density = float(density)
    if mass == 0:
        return None
    inertia = density * props.inertia
    inertia = (inertia + inertia.T) / 2
    return mass, sp.Matrix([exact(v) for v in props.com]), sp.Matrix(3, 3, [exact(v) for v in inertia.ravel()])
