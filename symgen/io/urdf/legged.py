"""Floating-base robots of ``example-robot-data``: legged robots, a humanoid and a space robot.

Each robot's root link stands on a free joint (:mod:`symgen.scene.free_joint`); the "standing"
variants put its feet on the ground (:func:`symgen.ground_contacts.stand`), which closes the chain
through the ground: the base's six rates become dependent (``n_p = 6``), ``V_m`` is the base's
twist and ``eta_f`` the remaining ``n_c - 6`` constraint-force coordinates (``T_c = 1``).

=========================  =================================================================
``solo12``                 Solo12 quadruped, free base, 12 joints, no contact (``V_m = qd``)
``solo12_standing``        Solo12 on its four point feet (``n_c = 12``, ``m = 6``)
``anymal``                 ANYmal (B) quadruped, free base, 12 joints, no contact (``V_m = qd``)
``anymal_standing``        ANYmal on its four point feet (``n_c = 12``, ``m = 6``)
``talos``                  Talos humanoid, free base, 32 joints (grippers locked), no contact
``talos_double_support``   Talos on its two flat soles (``n_c = 12``, ``m = 24``)
``space_ur5``              a UR5 on a free-floating base in zero gravity (``V_m = qd``)
=========================  =================================================================

ANYmal's file gives its ``base`` link a placeholder ``<inertial>`` (1e-6 kg, every inertia entry 1e-6:
no rigid body has it; the file says KDL needs it, its real mass is on ``base_inertia``, welded to
``base``): :func:`anymal_robot` leaves it out of the text that symgen and the Pinocchio check both read.

Reference configurations are the robots' own ("standing" for Solo12 and ANYmal, "half_sitting" for Talos,
from their SRDF files), with the numbers written here as exact decimals.
"""
from __future__ import annotations

import xml.etree.ElementTree as ElementTree

from ...ground_contacts import stand
from ...scene.declaration import Scene
from .build import MOVING, add_urdf
from .parse import UrdfRobot, read_urdf
from .examples import UR5_JOINTS, UR5_REACH, example_path

SOLO_FEET = ("FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT")
#: Solo12's "standing" configuration (solo.srdf)
SOLO_STANDING = {"FL_HAA": "0.1", "FL_HFE": "0.8", "FL_KFE": "-1.6", "FR_HAA": "-0.1", "FR_HFE": "0.8",
                 "FR_KFE": "-1.6", "HL_HAA": "0.1", "HL_HFE": "-0.8", "HL_KFE": "1.6", "HR_HAA": "-0.1",
                 "HR_HFE": "-0.8", "HR_KFE": "1.6"}
SOLO_BASE_HEIGHT = "0.235"

ANYMAL_FEET = ("LF_FOOT", "RF_FOOT", "LH_FOOT", "RH_FOOT")
#: ANYmal's "standing" configuration (anymal_b_simple_description/srdf/anymal.srdf)
ANYMAL_STANDING = {"LF_HAA": "-0.1", "LF_HFE": "0.7", "LF_KFE": "-1", "RF_HAA": "0.1", "RF_HFE": "0.7",
                   "RF_KFE": "-1", "LH_HAA": "-0.1", "LH_HFE": "-0.7", "LH_KFE": "1", "RH_HAA": "0.1",
                   "RH_HFE": "-0.7", "RH_KFE": "1"}
ANYMAL_BASE_HEIGHT = "0.4792"
#: ANYmal's link whose placeholder <inertial> is left out (see the module docstring)
ANYMAL_PLACEHOLDER_LINK = "base"

TALOS_SOLES = ("left_sole_link", "right_sole_link")
#: Talos' "half_sitting" configuration (talos.srdf); joints not listed are at 0
TALOS_HALF_SITTING = {
    "arm_left_1_joint": "0.25847", "arm_left_2_joint": "0.173046", "arm_left_3_joint": "-0.0002",
    "arm_left_4_joint": "-0.525366", "arm_left_7_joint": "0.1",
    "arm_right_1_joint": "-0.25847", "arm_right_2_joint": "-0.173046", "arm_right_3_joint": "0.0002",
    "arm_right_4_joint": "-0.525366", "arm_right_7_joint": "0.1",
    "leg_left_3_joint": "-0.411354", "leg_left_4_joint": "0.859395", "leg_left_5_joint": "-0.448041",
    "leg_left_6_joint": "-0.001708",
    "leg_right_3_joint": "-0.411354", "leg_right_4_joint": "0.859395", "leg_right_5_joint": "-0.448041",
    "leg_right_6_joint": "-0.001708", "torso_2_joint": "0.006761"}
TALOS_BASE_HEIGHT = "1.01927"
#: the grippers' joints, held closed (their fingers mimic one joint per hand)
TALOS_GRIPPER_PREFIXES = ("gripper_left_", "gripper_right_")


def _floating(name: str, description: str, robot, *, q0: dict, base_height: str = "0", **options) -> Scene:
    """``robot`` (an example name, or a read :class:`UrdfRobot`) on a free joint, ``V_m = qd``."""
    scene = Scene(name, description=description)
    urdf = example_path(robot) if isinstance(robot, str) else robot
    src = add_urdf(scene, urdf, q0=q0, floating=True, friction=False,
                   base_xyz=[0, 0, base_height], **options)
    scene.set_motion(joints=[src.floating] + src.leading_joints)
    return scene


def solo12() -> Scene:
    """Solo12 on a free base, standing pose as reference, no contact: ``V_m = qd`` (18)."""
    scene = _floating("solo12", "Solo12 quadruped on a free base (12 joints + 6 base coordinates)", "solo12",
                      q0=SOLO_STANDING, base_height=SOLO_BASE_HEIGHT)
    scene.validate()
    return scene


def solo12_standing() -> Scene:
    """Solo12 on its four point feet: ``m = 6`` (the base's twist), ``n_c = 12``."""
    scene = _floating("solo12_standing", "Solo12 standing on four point feet: m = 6, n_c = 12", "solo12",
                      q0=SOLO_STANDING, base_height=SOLO_BASE_HEIGHT)
    stand(scene, SOLO_FEET, "point")
    scene.validate()
    return scene


def anymal_robot() -> UrdfRobot:
    """ANYmal's URDF as read, without the placeholder ``<inertial>`` of its ``base`` link (the
    robot's ``text`` is the edited file, so a Pinocchio model built from it is the same robot)."""
    root = ElementTree.fromstring(example_path("anymal").read_text())
    link = next(el for el in root.findall("link") if el.get("name") == ANYMAL_PLACEHOLDER_LINK)
    link.remove(link.find("inertial"))
    robot = read_urdf(ElementTree.tostring(root, encoding="unicode"))
    robot.notes.append(f"link {ANYMAL_PLACEHOLDER_LINK!r}: the file's placeholder <inertial> (1e-6 kg, an inertia "
                       "no rigid body has) left out; the base's mass is that of 'base_inertia'")
    return robot


def anymal() -> Scene:
    """ANYmal (B) on a free base, standing pose as reference, no contact: ``V_m = qd`` (18)."""
    scene = _floating("anymal", "ANYmal quadruped on a free base (12 joints + 6 base coordinates)", anymal_robot(),
                      q0=ANYMAL_STANDING, base_height=ANYMAL_BASE_HEIGHT)
    scene.validate()
    return scene


def anymal_standing() -> Scene:
    """ANYmal on its four point feet: ``m = 6`` (the base's twist), ``n_c = 12``."""
    scene = _floating("anymal_standing", "ANYmal standing on four point feet: m = 6, n_c = 12", anymal_robot(),
                      q0=ANYMAL_STANDING, base_height=ANYMAL_BASE_HEIGHT)
    stand(scene, ANYMAL_FEET, "point")
    scene.validate()
    return scene


def _talos() -> UrdfRobot:
    return read_urdf(example_path("talos"))


def _talos_lock(robot: UrdfRobot | None = None) -> dict:
    """The grippers' moving joints, each held at 0."""
    robot = robot or _talos()
    return {j: 0 for j, joint in robot.joints.items() if j.startswith(TALOS_GRIPPER_PREFIXES) and joint.type in MOVING}


def talos() -> Scene:
    """Talos on a free base (32 joints + 6 base coordinates, grippers locked), half-sitting."""
    robot = _talos()
    scene = _floating("talos", "Talos humanoid on a free base (32 joints, grippers locked)", robot,
                      q0=TALOS_HALF_SITTING, base_height=TALOS_BASE_HEIGHT, lock=_talos_lock(robot))
    scene.validate()
    return scene


def talos_double_support() -> Scene:
    """Talos standing on both soles (two flat contacts): ``n_c = 12``, ``m = 24``."""
    robot = _talos()
    scene = _floating("talos_double_support", "Talos on two flat feet: m = 24, n_c = 12", robot,
                      q0=TALOS_HALF_SITTING, base_height=TALOS_BASE_HEIGHT, lock=_talos_lock(robot))
    stand(scene, TALOS_SOLES, "flat")
    scene.validate()
    return scene


def space_ur5() -> Scene:
    """A UR5 on a free-floating base in zero gravity: ``V_m = qd`` (12); its momentum is conserved."""
    scene = _floating("space_ur5", "UR5 on a free-floating base, zero gravity (a space robot)", "ur5",
                      q0=dict(zip(UR5_JOINTS, UR5_REACH)))
    scene.gravity = type(scene.gravity)([0, 0, 0])
    scene.validate()
    return scene
