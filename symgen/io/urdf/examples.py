"""Real robots as scenes: URDF files of the ``example-robot-data`` package, read where pip installed
them (never downloaded), and the paper's constrained scenes built on them.

=====================  ==========================================================================
``ur5``                UR5 (``ur_description/urdf/ur5_robot.urdf``), 6 revolute joints, open chain
``panda``              Franka Panda (``panda_description/urdf/panda.urdf``): the 7-joint arm, fingers
                       locked closed (``lock``; ``panda_finger_joint2`` mimics joint 1), hand merged
``ur5_on_plane``       Section 3.2 on the UR5: ``tool0`` slides on a horizontal plane, ``m = 3``,
                       ``V_m = (vx, vy, wz)`` of ``tool0`` with friction forces ``eta_m``
``panda_on_plane``     the same on the Panda's ``panda_hand_tcp``; 7 joints, so ``m = 4``
                       and ``V_m`` are joint rates chosen by QR at ``q0``
``multi_ur5:h=H``      Section 3.3: ``H`` UR5s (prefixes ``a1_`` ...) on a circle hold a 0.2 m cube of
                       2 kg, ``m = 6``, ``n_c = 6 (H - 1)``
=====================  ==========================================================================

The package is found through its installed file list (:mod:`importlib.metadata`); without it
every function raises :class:`~symgen.io.urdf._deps.MissingExtraError` naming the extra ``examples``.
"""
from __future__ import annotations

import importlib.metadata
from pathlib import Path

import mpmath

from ...math.numbers import DPS, to_exact
from ...reference_kinematics import reference_pose
from ...scene.declaration import Scene
from ...math.spatial import box_inertia
from ._deps import MissingExtraError
from .build import add_urdf, scene_from_urdf
from .overlay import add_contact, add_hold

DISTRIBUTION = "example-robot-data"
#: example name -> path below ``share/example-robot-data/robots``
FILES = {
    "ur5": "ur_description/urdf/ur5_robot.urdf",
    "ur10": "ur_description/urdf/ur10_robot.urdf",
    "kinova": "kinova_description/robots/kinova.urdf",
    "panda": "panda_description/urdf/panda.urdf",
    "solo12": "solo_description/robots/solo12.urdf",
    "talos": "talos_data/robots/talos_full_v2.urdf",
    "anymal": "anymal_b_simple_description/robots/anymal.urdf",
    "cassie": "cassie_description/robots/cassie_v2.sdf",      # SDF, read by symgen.io.sdf
}
PANDA_LOCK = {"panda_finger_joint1": 0, "panda_finger_joint2": 0}
UR5_JOINTS = ("shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint", "wrist_2_joint",
              "wrist_3_joint")
PANDA_JOINTS = tuple(f"panda_joint{k}" for k in range(1, 8))
#: tool0 pointing straight down (z of tool0 = -z of the world), Jacobian condition number ~8
UR5_DOWN = ("pi/6", "-pi/3", "pi/2", "-2*pi/3", "-pi/2", "pi/4")
#: tool0 horizontal, pointing away from the base (multi_ur5 grasps)
UR5_REACH = (0, "-pi/3", "pi/2", "-pi/6", "pi/2", "pi/4")
#: Panda's "ready" pose: the hand points straight down
PANDA_READY = (0, "-pi/4", 0, "-3*pi/4", 0, "pi/2", "pi/4")


def example_path(name: str) -> Path:
    """The installed URDF (or SDF) file of example ``name`` (a key of :data:`FILES`)."""
    if name not in FILES:
        raise KeyError(f"unknown example robot {name!r}; choose from {', '.join(FILES)}")
    try:
        dist = importlib.metadata.distribution(DISTRIBUTION)
    except importlib.metadata.PackageNotFoundError:
        raise MissingExtraError(f"the example robot {name!r}", DISTRIBUTION, "examples") from None
    wanted = f"share/example-robot-data/robots/{FILES[name]}"
    for file in dist.files or ():
        if str(file).endswith(wanted):
            path = Path(dist.locate_file(file))
            if path.is_file():
                return path
    raise MissingExtraError(f"the example robot {name!r} ({wanted} is not among the installed files)",
                            DISTRIBUTION, "examples")


def ur5() -> Scene:
    """The UR5 as its URDF file describes it, open chain, ``V_m = qd``."""
    return scene_from_urdf(example_path("ur5"), name="ur5")


def panda() -> Scene:
    """The Panda arm, fingers locked closed, ``V_m = qd`` (7 joints)."""
    return scene_from_urdf(example_path("panda"), name="panda", lock=PANDA_LOCK)


def ur5_on_plane() -> Scene:
    """The UR5's ``tool0`` sliding on a horizontal plane (paper Section 3.2)."""
    scene = Scene("ur5_on_plane", description="UR5 tool0 sliding on a plane (paper Section 3.2): m = 3, n_c = 3")
    add_urdf(scene, example_path("ur5"), q0=dict(zip(UR5_JOINTS, UR5_DOWN)))
    add_contact(scene, "tool0")
    scene.validate()
    return scene


def panda_on_plane() -> Scene:
    """The Panda's ``panda_hand_tcp`` sliding on a horizontal plane; ``V_m`` = 4 joint rates."""
    scene = Scene("panda_on_plane", description="Panda hand on a plane (paper Section 3.2): m = 4, n_c = 3")
    add_urdf(scene, example_path("panda"), lock=PANDA_LOCK, q0=dict(zip(PANDA_JOINTS, PANDA_READY)))
    add_contact(scene, "panda_hand_tcp", motion="joints")
    scene.validate()
    return scene


def _bases(h: int) -> list[dict]:
    """Base placements on a circle such that every arm's aim point (0.1 m beyond tool0 at q0)
    lands on the world z axis (50-digit arithmetic, rounded to 1e-20)."""
    probe = Scene("probe")
    add_urdf(probe, example_path("ur5"), q0=dict(zip(UR5_JOINTS, UR5_REACH)))
    rot, pos = reference_pose(probe, "tool0")
    with mpmath.workdps(DPS):
        aim = pos + rot[:, 2] * mpmath.mpf("0.1")
        radius, phase = mpmath.hypot(aim[0], aim[1]), mpmath.atan2(aim[1], aim[0])
        out = []
        for i in range(h):
            theta = 2 * mpmath.pi * i / h
            yaw = theta + mpmath.pi - phase
            out.append(dict(base_xyz=[to_exact(radius * mpmath.cos(theta)), to_exact(radius * mpmath.sin(theta)), 0],
                            base_quat=[to_exact(mpmath.cos(yaw / 2)), 0, 0, to_exact(mpmath.sin(yaw / 2))]))
    return out


def multi_ur5(h: int = 2) -> Scene:
    """``h`` UR5s holding one 0.2 m cube of 2 kg (paper Section 3.3)."""
    scene = Scene(f"multi_ur5_h{h}", description=f"{h} UR5s holding one object (paper Section 3.3): m = 6, "
                                                  f"n_c = {6 * (h - 1)}")
    path = example_path("ur5")
    for i, base in enumerate(_bases(h), 1):
        add_urdf(scene, path, prefix=f"a{i}_", q0={f"a{i}_{j}": v for j, v in zip(UR5_JOINTS, UR5_REACH)}, **base)
    add_hold(scene, [f"a{i}_tool0" for i in range(1, h + 1)], mass=2, inertia=box_inertia(2, "0.2", "0.2", "0.2"),
             at_xyz=[0, 0, "0.1"])
    scene.validate()
    return scene
