"""``arm_on_plane`` -- a constrained single arm: the example of the paper's Section 3.2.

A six-revolute arm (:func:`symgen.io.builtin._arm.add_arm`, all joints actuated, with a small rotor
inertia and viscous friction on every joint so that the joint dynamics (22) are exercised) holds an
object -- a 0.1 m cube of 1 kg rigidly gripped by a fixed joint ``grip`` on ``link6`` -- whose
bottom face slides on a horizontal table.

* Frame ``O`` sits at the centre of the object's bottom face; its x and y axes lie in the contact
  plane and its z axis is the plane normal (pointing up, out of the table).
* The world frame ``plane`` coincides with ``O`` at the reference configuration.
* Constraint ``contact`` (``plane_contact``, normal z) removes ``vz, wx, wy`` of ``O`` relative to
  the table: ``n_c = 3`` with ``T_a = T_f J`` (Step 4) and ``eta_f = [f_z, m_x, m_y]`` in ``O``
  (Step 7, ``constraint_forces = "operational"``, ``J_f = T_a``).
* Motion coordinates ``V_m = [v_x, v_y, w_z]`` of ``O`` (Step 10, ``J_m = T_m J``) and dynamic
  contact (friction) forces ``eta_m`` along the same components (Step 9, ``D_m = T_m J``).

Counts: ``n_1a = 6``, ``m = 3``, ``n_c = 3``, ``n_p = 0``, ``n = 6``.

Reference configuration ``q0 = (pi/6, -pi/4, pi/2, 0, pi/4, pi/6)``: elbow bent 90 degrees, wrist
pitched so the gripper points straight down, ``q1 = q6`` so ``O`` is aligned with the world axes;
the end-effector Jacobian ``J`` (6 x 6, in ``O``) has condition number about 9.4 there.
"""
from __future__ import annotations

from ...reference_kinematics import reference_pose
from ...scene.declaration import WORLD, Scene
from ...math.spatial import box_inertia, pose_to_exact
from ._arm import add_arm

Q0 = ("pi/6", "-pi/4", "pi/2", 0, "pi/4", "pi/6")
ROTOR_INERTIA = "0.01"
VISCOUS = "0.05"
OBJECT_MASS = 1
OBJECT_SIZE = "0.1"


def arm_on_plane() -> Scene:
    """A 6R arm pressing a gripped object onto a horizontal plane (paper, Section 3.2)."""
    scene = Scene(name="arm_on_plane",
                  description="6R arm sliding a gripped object on a plane (paper Section 3.2): "
                              "m = 3, n_c = 3, friction forces eta_m")
    last = add_arm(scene, q0=Q0, rotor_inertia=ROTOR_INERTIA, viscous=VISCOUS)
    size = OBJECT_SIZE
    scene.add_body("object", OBJECT_MASS, inertia=box_inertia(OBJECT_MASS, size, size, size))
    # the cube's centre 0.05 m beyond the flange; its z axis along -x of link6 (up at q0)
    scene.add_joint("grip", "fixed", last, "object", xyz=("0.09", 0, 0), rpy=(0, "-pi/2", 0))
    scene.add_frame("O", "object", xyz=(0, 0, "-0.05"))
    scene.add_frame("plane", WORLD, **pose_to_exact(reference_pose(scene, "O")))
    scene.add_constraint("contact", "plane_contact", "O", "plane", normal="z")
    scene.set_motion(frame="O", components=["vx", "vy", "wz"])
    scene.set_contact_forces("O", ["vx", "vy", "wz"])
    scene.constraint_forces = "operational"
    return scene
