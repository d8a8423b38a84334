"""The six-revolute arm shared by the built-in scenes ``multi_arm`` and ``arm_on_plane``.

:func:`add_arm` declares one six-revolute arm (the manipulator of the paper's Sections 3.2 and
3.3): an anthropomorphic arm with a shoulder offset and a spherical wrist. The helpers the
built-in scenes also use live below this package: exact inertias of simple solids and 50-digit
pose helpers in :mod:`symgen.math.spatial`, 50-digit numbers rounded to the exact grid in
:mod:`symgen.math.numbers`, the forward kinematics at ``q0`` in :mod:`symgen.reference_kinematics`.
"""
from __future__ import annotations

from fractions import Fraction

from ...scene.declaration import WORLD, Scene
from ...math.spatial import bar_inertia


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
