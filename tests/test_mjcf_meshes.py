"""Mass properties of mesh geoms (symgen.io.mjcf.meshes): against hand derivations of a box, a
tetrahedron and a non-convex prism written as STL files here, against MuJoCo's compiled
``body_mass``/``body_ipos``/``body_inertia``/``body_iquat`` of the same files for every ``<mesh
inertia>``, and against the control suite's dog (162 bone meshes). Missing or malformed files are
typed errors naming the mesh and the file."""
from __future__ import annotations

import os
import re
import struct

import numpy as np
import pytest
import sympy as sp

from symgen.io.mjcf import MjcfError, parse_mjcf, parse_mjcf_text
from symgen.math.configuration import quaternion_rotation

mujoco = pytest.importorskip("mujoco", minversion="3.3.6")

#: agreement with MuJoCo on these small meshes (double precision, relative to the largest entry)
TOL = 1e-12


def binary_stl(path, triangles) -> None:
    """A binary STL of ``triangles`` (each three vertices, outward by the right-hand rule)."""
    with open(path, "wb") as f:
        f.write(b"symgen test".ljust(80, b" ") + struct.pack("<I", len(triangles)))
        for tri in triangles:
            f.write(struct.pack("<3f", 0, 0, 0) + b"".join(struct.pack("<3f", *v) for v in tri) + b"\0\0")


def ascii_stl(path, triangles) -> None:
    lines = ["solid t"]
    for tri in triangles:
        lines += ["facet normal 0 0 0", "outer loop", *(f"vertex {x} {y} {z}" for x, y, z in tri), "endloop",
                  "endfacet"]
    path.write_text("\n".join(lines + ["endsolid t"]) + "\n")


def box_triangles(lo, hi) -> list:
    """The 12 outward triangles of the box ``[lo, hi]``."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    v = [(x, y, z) for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)]
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    return [t for a, b, c, d in quads for t in ([v[a], v[b], v[c]], [v[a], v[c], v[d]])]


TETRAHEDRON = [[(0, 0, 0), (0, 1, 0), (1, 0, 0)], [(0, 0, 0), (1, 0, 0), (0, 0, 1)],
               [(0, 0, 0), (0, 0, 1), (0, 1, 0)], [(1, 0, 0), (0, 1, 0), (0, 0, 1)]]


def l_prism() -> list:
    """A non-convex prism of height 1 over the L ``(0,0) (3,0) (3,1) (1,1) (1,2) (0,2)`` (area 4)."""
    p = [(0, 0), (3, 0), (3, 1), (1, 1), (1, 2), (0, 2)]
    out = []
    for a, b, c in ((0, 1, 2), (0, 2, 3), (0, 3, 4), (0, 4, 5)):
        out += [[(*p[a], 0), (*p[c], 0), (*p[b], 0)], [(*p[a], 1), (*p[b], 1), (*p[c], 1)]]
    for i in range(6):
        q, r = p[i], p[(i + 1) % 6]
        out += [[(*q, 0), (*r, 0), (*r, 1)], [(*q, 0), (*r, 1), (*q, 1)]]
    return out


def model(tmp_path, mesh: str, geom: str, compiler: str = '<compiler meshdir="meshes"/>') -> str:
    path = tmp_path / "robot.xml"
    path.write_text(f"""<mujoco model="m">
  {compiler}
  <asset>{mesh}</asset>
  <worldbody>
    <body name="b" pos="0.3 0 0">
      <joint name="q" axis="0 1 0"/>
      {geom}
    </body>
  </worldbody>
</mujoco>""")
    return str(path)


def ours(path, body="b"):
    b = next(b for b in parse_mjcf(path).bodies if b.name == body)
    return float(b.inertial.mass), np.array(b.inertial.pos, float).ravel(), np.array(b.inertial.inertia, float)


def theirs(path, body="b"):
    m = mujoco.MjModel.from_xml_path(path)
    i = m.body(body).id
    rot = quaternion_rotation(m.body_iquat[i])
    return m.body_mass[i], m.body_ipos[i].copy(), rot @ np.diag(m.body_inertia[i]) @ rot.T


def assert_close(a, b, tol=TOL):
    for x, y in zip(a, b):
        x, y = np.asarray(x, float), np.asarray(y, float)
        assert np.max(np.abs(x - y)) <= tol * max(np.max(np.abs(y)), 1.0), (x, y)


@pytest.fixture()
def meshes(tmp_path):
    folder = tmp_path / "meshes"
    folder.mkdir()
    binary_stl(folder / "box.stl", box_triangles((0, 0, 0), (0.5, 0.25, 0.125)))   # exact in single precision
    ascii_stl(folder / "tet.stl", TETRAHEDRON)
    binary_stl(folder / "tet_binary.stl", TETRAHEDRON)
    binary_stl(folder / "l.stl", l_prism())
    return folder


def box_by_hand(sizes, density, pos, rot):
    """A solid box of full sizes ``sizes`` whose corner is at the mesh origin, placed by (pos, rot)."""
    a, b, c = sizes
    m = density * a * b * c
    centre = pos + rot * sp.Matrix([a, b, c]) / 2
    inertia = rot * sp.diag(m * (b**2 + c**2), m * (a**2 + c**2), m * (a**2 + b**2)) / 12 * rot.T
    return m, centre, inertia


def test_a_scaled_box_mesh_turned_and_moved_by_its_geom_equals_the_hand_derivation_and_mujoco(tmp_path, meshes):
    path = model(tmp_path, '<mesh name="box" file="box.stl" scale="0.5 2 3"/>',
                 '<geom type="mesh" mesh="box" density="700" pos="0.1 0.2 0.3" quat="0 0 0 1"/>')
    rot = sp.diag(-1, -1, 1)                                   # quat 0 0 0 1: half a turn about z
    m, centre, inertia = box_by_hand([sp.Rational(1, 4), sp.Rational(1, 2), sp.Rational(3, 8)], 700,
                                     sp.Matrix([0.1, 0.2, 0.3]), rot)
    hand = (float(m), np.array(centre, float).ravel(), np.array(inertia, float))
    assert_close(ours(path), hand)
    assert_close(theirs(path), hand)


@pytest.mark.parametrize("file", ["tet.stl", "tet_binary.stl"])
def test_a_tetrahedron_from_ascii_or_binary_stl_equals_the_hand_derivation(tmp_path, meshes, file):
    """The corner tetrahedron of legs a: V = a^3/6, centre a/4 (1, 1, 1), about it Ixx = 3 m a^2/40
    and Ixy = m a^2/80 (second moments V/20 (sum v v^T + s s^T) over its vertices)."""
    path = model(tmp_path, f'<mesh name="t" file="{file}" scale="2 2 2"/>', '<geom type="mesh" mesh="t" mass="3"/>')
    a, m = 2.0, 3.0
    inertia = m * a**2 * (3 / 40 * np.eye(3) + (np.ones((3, 3)) - np.eye(3)) / 80)
    assert_close(ours(path), (m, np.full(3, a / 4), inertia))


def test_mujoco_reads_the_binary_tetrahedron_the_same(tmp_path, meshes):
    """(MuJoCo 4.0 refuses the ASCII file: "perhaps this is an ASCII file?")"""
    path = model(tmp_path, '<mesh name="t" file="tet_binary.stl" scale="2 2 2"/>',
                 '<geom type="mesh" mesh="t" mass="3"/>')
    assert_close(ours(path), theirs(path))


def exact_l_prism(density):
    """The L prism as two boxes (3 x 1 and 1 x 1, height 1), exact."""
    parts = [box_by_hand([3, 1, 1], density, sp.zeros(3, 1), sp.eye(3)),
             box_by_hand([1, 1, 1], density, sp.Matrix([0, 1, 0]), sp.eye(3))]
    mass = sum(p[0] for p in parts)
    com = sum((p[0] * p[1] for p in parts), sp.zeros(3, 1)) / mass
    inertia = sum((p[2] + p[0] * ((p[1] - com).dot(p[1] - com) * sp.eye(3) - (p[1] - com) * (p[1] - com).T)
                   for p in parts), sp.zeros(3, 3))
    return float(mass), np.array(com, float).ravel(), np.array(inertia, float)


@pytest.mark.parametrize("mode", ["", ' inertia="legacy"', ' inertia="convex"', ' inertia="exact"',
                                  ' inertia="shell"'])
@pytest.mark.parametrize("scale", ["1 1 1", "-1 0.5 2"])          # the second mirrors the mesh
def test_every_mesh_inertia_mode_of_a_non_convex_prism_equals_mujoco(tmp_path, meshes, mode, scale):
    path = model(tmp_path, f'<mesh name="l" file="l.stl" scale="{scale}"{mode}/>',
                 '<geom type="mesh" mesh="l" density="2" euler="0 0 30"/>')
    assert_close(ours(path), theirs(path))


def test_exact_mesh_inertia_equals_the_hand_derivation_and_legacy_does_not(tmp_path, meshes):
    """``exact`` is the solid; MuJoCo's default ``legacy`` (|pyramids| from the surface centroid)
    over-counts a non-convex one -- a check that compares the two would fail (planted mismatch)."""
    exact = model(tmp_path, '<mesh name="l" file="l.stl" inertia="exact"/>', '<geom type="mesh" mesh="l" density="2"/>')
    assert_close(ours(exact), exact_l_prism(2))
    legacy = model(tmp_path, '<mesh name="l" file="l.stl"/>', '<geom type="mesh" mesh="l" density="2"/>')
    assert ours(legacy)[0] > 1.04 * exact_l_prism(2)[0]


def test_a_mesh_body_loads_and_its_mass_matrix_equals_mujocos(tmp_path, meshes):
    from symgen.io.coordinates import CoordinateMap
    from symgen.io.mjcf import scene_from_mjcf
    from symgen.model import derive

    path = model(tmp_path, '<mesh name="l" file="l.stl"/>', '<geom type="mesh" mesh="l" density="2" pos="0 0 -1"/>')
    scene = scene_from_mjcf(path)
    m = mujoco.MjModel.from_xml_path(path)
    d = mujoco.MjData(m)
    d.qpos[:] = [0.7]
    mujoco.mj_forward(m, d)
    dense = np.zeros((1, 1))
    mujoco.mj_fullM(m, dense, d.qM) if hasattr(d, "qM") else mujoco.mj_fullM(m, d, dense)
    config, _ = CoordinateMap.mujoco(scene, m).to_symgen(d.qpos, d.qvel)
    got = derive(scene).evaluate(config, qd=[0.0])
    assert abs(float(got.M_q[0, 0]) - dense[0, 0]) <= TOL * dense[0, 0]
    assert abs(float(np.ravel(got.G_q)[0]) - d.qfrc_bias[0]) <= TOL * max(abs(d.qfrc_bias[0]), 1)


# ------------------------------------------------------------------ the control suite's dog
@pytest.fixture(scope="module")
def dog():
    """The dog's file and what symgen reads of it."""
    import importlib.metadata

    path = str(importlib.metadata.distribution("dm-control").locate_file("dm_control/suite/dog.xml"))
    return path, parse_mjcf(path)


def test_the_dogs_body_masses_from_162_bone_meshes_equal_mujocos(dog):
    """Masses and centres to double precision. The inertias agree to 1e-7 only because MuJoCo's
    principal axes of each mesh stop its Jacobi iteration at an absolute off-diagonal of 1e-12
    (mjuu_eig3), coarse for bones of about 1e-9 m^5 per unit density; the mesh-level test below
    shows ours is exact in MuJoCo's own frames to that threshold."""
    path, mj = dog
    m = mujoco.MjModel.from_xml_path(path)
    assert len(mj.bodies) == m.nbody - 1
    for b in mj.bodies:
        i = m.body(b.name).id
        rot = quaternion_rotation(m.body_iquat[i])
        inertia = rot @ np.diag(m.body_inertia[i]) @ rot.T
        assert abs(float(b.inertial.mass) - m.body_mass[i]) <= 1e-13 * m.body_mass[i], b.name
        assert np.max(np.abs(np.array(b.inertial.pos, float).ravel() - m.body_ipos[i])) <= 1e-13, b.name
        assert np.max(np.abs(np.array(b.inertial.inertia, float) - inertia)) <= 1e-7 * np.max(inertia), b.name



def test_the_dogs_tail_springs_from_springdamper_equal_mujocos(dog):
    """Its caudal joints set stiffness and damping by ``springdamper`` from M(qpos0)^-1, which the
    meshes' inertias enter (symgen.io.mjcf.springdamper)."""
    path, mj = dog
    m = mujoco.MjModel.from_xml_path(path)
    tail = [j for b in mj.bodies for j in b.joints if j.springdamper is not None]
    assert len(tail) == 21
    for j in tail:
        i = m.joint(j.name).id
        assert abs(float(j.stiffness) - m.jnt_stiffness[i]) <= 1e-10 * m.jnt_stiffness[i], j.name
        assert abs(float(j.damping) - m.dof_damping[m.jnt_dofadr[i]]) <= 1e-10 * m.dof_damping[m.jnt_dofadr[i]]


def test_each_dog_mesh_has_mujocos_centre_and_principal_axes(dog):
    """Per mesh (legacy inertia, the dog's setting): our centre is MuJoCo's ``mesh_pos`` and our
    inertia is diagonal in MuJoCo's ``mesh_quat`` frame up to MuJoCo's own stopping threshold."""
    from symgen.io.mjcf.meshes import mesh_mass, read_stl

    path, _ = dog
    m = mujoco.MjModel.from_xml_path(path)
    files = dict(re.findall(r'<mesh name="([^"]+)" file="([^"]+)"', open(path).read()))
    folder = os.path.join(os.path.dirname(path), "dog_assets")
    assert m.nmesh == len(files) == 162

    def fail(why):
        raise AssertionError(why)

    for k in range(m.nmesh):
        props = mesh_mass(read_stl(os.path.join(folder, files[m.mesh(k).name]), fail), "legacy", fail)
        assert np.max(np.abs(props.com - m.mesh_pos[k])) <= 1e-12 * np.max(np.abs(m.mesh_pos[k]))
        rot = quaternion_rotation(m.mesh_quat[k])
        local = rot.T @ props.inertia @ rot
        assert np.max(np.abs(local - np.diag(np.diag(local)))) <= 5e-12     # a few times mjuu_eig3's 1e-12


# ------------------------------------------------------------------ errors: typed, naming mesh and file
def error(path) -> MjcfError:
    with pytest.raises(MjcfError) as info:
        parse_mjcf(path)
    return info.value


@pytest.mark.parametrize("write, words", [
    (None, "not found"),
    (lambda p: p.write_bytes(b"\0" * 84 + b"\1\2\3"), "neither a binary STL"),
    (lambda p: p.write_text("solid x\nfacet normal 0 0 0\nouter loop\nvertex 0 0 a\n"), "is not three numbers"),
    (lambda p: p.write_text("solid x\nvertex 0 0 0\nvertex 1 0 0\n"), "do not make triangles"),
    (lambda p: p.write_bytes(b"x" * 80 + struct.pack("<I", 0)), "has 0 triangles"),
    (lambda p: binary_stl(p, [[(0, 0, 0), (1, 0, 0), (0, 1, 0)]] * 2), "volume is too small"),
])
def test_a_missing_or_malformed_mesh_file_is_a_typed_error_naming_the_mesh_and_file(tmp_path, write, words):
    (tmp_path / "meshes").mkdir()
    if write is not None:
        write(tmp_path / "meshes" / "part.stl")
    err = error(model(tmp_path, '<mesh name="part" file="part.stl"/>', '<geom type="mesh" mesh="part"/>'))
    assert err.element == "<mesh name='part'>" and err.line == 3, str(err)
    assert "part.stl" in str(err) and words in str(err), str(err)


def test_unread_mesh_sources_and_settings_are_refused_where_they_give_mass(tmp_path, meshes):
    geom = '<geom type="mesh" mesh="p"/>'
    cases = [('<mesh name="p" file="part.obj"/>', "only STL"),
             ('<mesh name="p" vertex="0 0 0 1 0 0 0 1 0 0 0 1"/>', "only meshes from STL files"),
             ('<mesh name="p" file="box.stl" refpos="0 0 1"/>', "refpos"),
             ('<mesh name="p" file="box.stl" maxhullvert="8"/>', "maxhullvert")]
    (meshes / "part.obj").write_text("v 0 0 0\n")
    for mesh, words in cases:
        err = error(model(tmp_path, mesh, geom))
        assert err.element.startswith("<mesh") and words in str(err), str(err)
    # the same meshes are fine where they give no mass (beside an <inertial>)
    inertial = '<inertial pos="0 0 0" mass="1" diaginertia="1 1 1"/>'
    for mesh, _ in cases:
        assert parse_mjcf(model(tmp_path, mesh, geom + inertial)).bodies[0].inertial.mass == 1


def test_a_relative_mesh_file_needs_the_mjcf_files_directory(tmp_path, meshes):
    text = open(model(tmp_path, '<mesh name="box" file="box.stl"/>', '<geom type="mesh" mesh="box"/>')).read()
    with pytest.raises(MjcfError, match="relative and the MJCF was read from text"):
        parse_mjcf_text(text)
    # strippath and an absolute meshdir find it from text too
    text = text.replace('meshdir="meshes"', f'meshdir="{meshes}" strippath="true"').replace(
        'file="box.stl"', 'file="elsewhere/box.stl"')
    assert float(parse_mjcf_text(text).bodies[0].inertial.mass) == pytest.approx(1000 * 0.5 * 0.25 * 0.125, rel=1e-12)


def test_a_mesh_named_after_its_file_and_one_from_a_default_class(tmp_path, meshes):
    path = model(tmp_path, '<mesh file="box.stl" class="big"/>', '<geom type="mesh" mesh="box"/>',
                 compiler='<compiler assetdir="meshes"/><default><default class="big"><mesh scale="2 2 2"/>'
                          '</default></default>')
    assert_close(ours(path), theirs(path))
    assert ours(path)[0] == pytest.approx(8 * 1000 * 0.5 * 0.25 * 0.125, rel=1e-12)
