"""Shared pieces of the built-in scenes: mass properties, the 6R arm, reference kinematics.

* :func:`box_inertia`, :func:`bar_inertia`, :func:`cylinder_inertia` give exact (``Fraction``)
  rotational inertias about the centre of mass of simple solids, so every built-in body obeys the
  triangle inequality by construction.
* :func:`add_arm` declares one six-revolute arm (the manipulator of the paper's Sections 3.2 and
  3.3): an anthropomorphic arm with a shoulder offset and a spherical wrist.
* :func:`reference_pose`, :func:`pose_to_exact` and friends evaluate the forward kinematics of a
  (possibly partly built) scene at its reference configuration ``q0`` in 50-digit arithmetic
  (mpmath), following the frame conventions of :mod:`symgen.scene`. Built-in scenes use them to
  place frames that must coincide at ``q0`` (the loop closures and grasps) and to compute ``q0``
  by inverse kinematics. Derived numbers are rounded to the grid ``10**-20`` and handed to the
  scene as exact ``Fraction`` s, so the scenes are exact rational data, identical on every
  platform, and every closure holds at ``q0`` to about ``1e-20``.
"""
from __future__ import annotations

from fractions import Fraction

import mpmath
import sympy as sp

from ..spatial import matrix_to_quat as spatial_matrix_to_quat
from ..scene import WORLD, Scene

#: working precision of the reference kinematics (decimal digits)
DPS = 50
#: derived placements and reference positions are rounded to multiples of 10**-GRID_DIGITS
GRID_DIGITS = 20


# ----------------------------------------------------------------------------- mass properties
def _q(x) -> Fraction:
    return Fraction(str(x)) if isinstance(x, (str, float)) else Fraction(x)


def box_inertia(mass, sx, sy, sz) -> list[Fraction]:
    """Principal inertias ``[ixx, iyy, izz]`` of a solid box with edge lengths ``sx, sy, sz``."""
    m, x, y, z = (_q(v) for v in (mass, sx, sy, sz))
    return [m * (y * y + z * z) / 12, m * (x * x + z * z) / 12, m * (x * x + y * y) / 12]


def bar_inertia(mass, length, width, axis: str = "x") -> list[Fraction]:
    """A bar of square cross-section ``width`` x ``width`` and ``length`` along ``axis``."""
    sizes = {a: _q(width) for a in "xyz"}
    sizes[axis] = _q(length)
    return box_inertia(mass, sizes["x"], sizes["y"], sizes["z"])


def cylinder_inertia(mass, length, radius, axis: str = "z") -> list[Fraction]:
    """A solid cylinder of ``radius`` and ``length`` along ``axis``."""
    m, h, r = _q(mass), _q(length), _q(radius)
    axial, transverse = m * r * r / 2, m * (3 * r * r + h * h) / 12
    return [axial if a == axis else transverse for a in "xyz"]


# ------------------------------------------------------------------------------------ 6R arm
#: joint k (1..6): origin in the parent link's frame (j1's is the base placement given to
#: :func:`add_arm`) and axis (in the joint frame). The zero
#: configuration stretches the arm horizontally along x: a vertical base column (j1 about z),
#: shoulder (j2) and elbow (j3) pitch about y with a 0.12 m shoulder offset, then a spherical
#: wrist (j4 roll about x, j5 pitch about y, j6 roll about x; the three axes meet 0.35 m beyond
#: the elbow).
ARM_JOINTS = (
    ((0, 0, 0), "z"),
    ((0, "0.12", "0.3"), "y"),
    (("0.4", 0, 0), "y"),
    (("0.15", 0, 0), "x"),
    (("0.2", 0, 0), "y"),
    (("0.06", 0, 0), "x"),
)

#: link k (1..6): mass, centre of mass and the bar that gives its inertia (length, width, axis)
ARM_LINKS = (
    (4, (0, 0, "0.15"), ("0.3", "0.1", "z")),
    (3, ("0.2", 0, 0), ("0.4", "0.08", "x")),
    ("1.5", ("0.075", 0, 0), ("0.15", "0.07", "x")),
    ("1.2", ("0.1", 0, 0), ("0.2", "0.06", "x")),
    ("0.5", ("0.03", 0, 0), ("0.06", "0.05", "x")),
    ("0.2", ("0.02", 0, 0), ("0.04", "0.05", "x")),
)

#: distance from the origin of the last link's frame to the end of its flange (m)
FLANGE = Fraction("0.04")


def add_arm(scene: Scene, prefix: str = "", *, base_xyz=(0, 0, 0), base_quat=None, q0=(0,) * 6,
            rotor_inertia=0, viscous=0) -> str:
    """Declare a 6R arm on the world: bodies ``{prefix}link1..6``, joints ``{prefix}j1..6``
    (all actuated), the first joint placed at ``base_xyz`` / ``base_quat`` (w, x, y, z).

    Returns the name of the last link."""
    parent = WORLD
    for k, ((xyz, axis), (mass, com, (length, width, bar_axis))) in enumerate(zip(ARM_JOINTS, ARM_LINKS), 1):
        link = f"{prefix}link{k}"
        scene.add_body(link, mass, com=com, inertia=bar_inertia(mass, length, width, bar_axis))
        placement = dict(xyz=base_xyz, quat=base_quat) if k == 1 else dict(xyz=xyz)
        scene.add_joint(f"{prefix}j{k}", "revolute", parent, link, axis=axis, actuated=True,
                        rotor_inertia=rotor_inertia, viscous=viscous, q0=q0[k - 1], **placement)
        parent = link
    return parent


# ------------------------------------------------------------------ reference kinematics (mpmath)
def mp(value) -> mpmath.mpf:
    """An exact scene number as a 50-digit mpmath float."""
    return mpmath.mpf(sp.Float(sp.N(sp.sympify(value), DPS + 10), DPS + 10)._mpf_)


def mp_matrix(m) -> mpmath.matrix:
    """An exact SymPy matrix (or nested list) as an mpmath matrix."""
    m = sp.Matrix(m)
    return mpmath.matrix([[mp(m[i, j]) for j in range(m.cols)] for i in range(m.rows)])


def _rodrigues(axis: mpmath.matrix, angle) -> mpmath.matrix:
    k = mpmath.matrix([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return mpmath.eye(3) + mpmath.sin(angle) * k + (1 - mpmath.cos(angle)) * (k * k)


def reference_poses(scene: Scene) -> dict:
    """World pose ``(R, p)`` (mpmath) of every body reachable from the world at ``q0``."""
    with mpmath.workdps(DPS):
        poses = {WORLD: (mpmath.eye(3), mpmath.matrix(3, 1))}
        for joint in scene.tree_order():
            r_p, p_p = poses[joint.parent]
            r_j = r_p * mp_matrix(joint.origin.rotation)
            p_j = p_p + r_p * mp_matrix(joint.origin.translation)
            axis = mp_matrix(joint.axis)
            kind = joint.kind
            if kind.position_is_angle:
                r_j = r_j * _rodrigues(axis, mp(joint.q0))
            elif kind.translates:
                p_j = p_j + r_j * (axis * mp(joint.q0))
            elif kind.position_is_rotation:
                r_j = r_j * mp_matrix(joint.q0)
            poses[joint.child] = (r_j, p_j)
        return poses


def reference_pose(scene: Scene, frame: str, poses: dict | None = None):
    """World pose ``(R, p)`` of a declared frame or body at ``q0``."""
    poses = reference_poses(scene) if poses is None else poses
    with mpmath.workdps(DPS):
        if frame in scene.frames:
            f = scene.frames[frame]
            r_b, p_b = poses[f.body]
            return r_b * mp_matrix(f.pose.rotation), p_b + r_b * mp_matrix(f.pose.translation)
        return poses[frame]


def relative_pose(pose_a, pose_b):
    """Pose of b in a's frame: ``(R_a^T R_b, R_a^T (p_b - p_a))``."""
    (r_a, p_a), (r_b, p_b) = pose_a, pose_b
    with mpmath.workdps(DPS):
        return r_a.T * r_b, r_a.T * (p_b - p_a)


def to_exact(x) -> Fraction:
    """Round a 50-digit number to the grid ``10**-GRID_DIGITS`` (an exact ``Fraction``)."""
    scale = 10 ** GRID_DIGITS
    with mpmath.workdps(DPS):
        return Fraction(int(mpmath.nint(x * scale)), scale)


def matrix_to_quat(r) -> list:
    """Unit quaternion ``(w, x, y, z)`` of an mpmath rotation matrix, at ``DPS`` digits."""
    with mpmath.workdps(DPS):
        return spatial_matrix_to_quat(r, sqrt=mpmath.sqrt)


def pose_to_exact(pose) -> dict:
    """``xyz`` and ``quat`` keyword arguments (exact Fractions) for a placement ``(R, p)``."""
    r, p = pose
    return dict(xyz=[to_exact(p[i]) for i in range(3)], quat=[to_exact(v) for v in matrix_to_quat(r)])
