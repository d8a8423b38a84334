"""``stewart`` -- a Stewart-Gough platform in free motion (the paper's footnotes 4 and 5).

Six U-P-S legs join a fixed base hexagon to a moving platform hexagon. Leg ``k`` (k = 1..6):

* a passive universal joint at base point ``B_k`` made of two revolute joints, ``u{k}a``
  (world -> ``cross{k}``, about x) and ``u{k}b`` (``cross{k}`` -> ``cyl{k}``, about y);
* an actuated prismatic joint ``p{k}`` (``cyl{k}`` -> ``rod{k}``) along the leg (z of the cylinder);
  its position is the leg length, the rod's frame sits at the spherical joint's centre;
* a passive spherical joint ``s{k}`` at platform point ``A_k``. The spanning tree keeps leg 1
  whole: ``s1`` joins ``rod1`` to ``platform``. Legs 2..6 are cut at their spherical joints:
  ``s{k}`` joins ``rod{k}`` to a massless ``socket{k}`` carrying the frame ``socket{k}_f``, which
  is welded to the platform frame ``att{k}`` (constraint ``leg{k}``, 6 equations each).

The platform's body frame is at ``A_1`` (the centre of ``s1``) with the platform's axes; frame
``P`` sits at the platform's centre and gives the motion coordinates (all six twist components).
All loop constraints fall on passive joints (footnote 5): ``n_c = n_p = n_1u + 3 n_3u = 30``,
``T_u`` is square and invertible away from singular poses, so ``n = m = 6`` and ``eta_f`` is
empty. Counts: ``n_1a = 6``, ``n_1u = 12``, ``n_3u = 6``, ``m = 6``, ``n_c = n_p = 30``, ``n = 6``.

Geometry (m, kg): base points on a circle of radius 0.5 at 120 j +- 10 degrees, platform points
on a circle of radius 0.3 at 60 + 120 j +- 10 degrees (both rounded to the millimetre, so exact);
crosses 0.05, cylinders 1.0 and rods 0.5 (0.4 m long each), platform 5 (disc, radius 0.3).
Reference pose: platform centre at (0.01, -0.02, 0.6), orientation the quaternion
(1, 0.03, -0.02, 0.05) (about 7 degrees off the symmetric home pose); the universal-joint angles,
leg lengths and spherical-joint rotations come from inverse kinematics in 50-digit arithmetic.
"""
from __future__ import annotations

from fractions import Fraction

import mpmath

from ...math.numbers import DPS, mp, mp_matrix, to_exact
from ...scene.declaration import WORLD, Scene
from ...math.spatial import box_inertia, cylinder_inertia, exact_quat, mp_matrix_to_quat

#: universal-joint centres B_k in the world (z = 0)
BASE_POINTS = (("0.492", "-0.087"), ("0.492", "0.087"), ("-0.171", "0.47"),
               ("-0.321", "0.383"), ("-0.321", "-0.383"), ("-0.171", "-0.47"))
#: spherical-joint centres a_k in the platform's centred frame (z = 0)
PLATFORM_POINTS = (("0.193", "-0.23"), ("0.193", "0.23"), ("0.103", "0.282"),
                   ("-0.295", "0.052"), ("-0.295", "-0.052"), ("0.103", "-0.282"))
PLATFORM_XYZ = ("0.01", "-0.02", "0.6")
PLATFORM_QUAT = (1, "0.03", "-0.02", "0.05")

CROSS = dict(mass="0.05", size="0.03")
CYLINDER = dict(mass="1.0", length="0.4", radius="0.03")
ROD = dict(mass="0.5", length="0.4", radius="0.015")
PLATFORM = dict(mass=5, radius="0.3", thickness="0.02")


def _point(xy) -> list[Fraction]:
    return [Fraction(xy[0]), Fraction(xy[1]), Fraction(0)]


def leg_reference(k: int) -> dict:
    """Inverse kinematics of leg ``k`` (1-based) at the reference pose: universal-joint angles
    ``a``, ``b``, leg length ``length`` and the spherical joint's quaternion ``quat`` (exact)."""
    with mpmath.workdps(DPS):
        r_p = mp_matrix(exact_quat(*(Fraction(str(v)) for v in PLATFORM_QUAT)))
        p = mpmath.matrix([mp(Fraction(v)) for v in PLATFORM_XYZ])
        a_world = p + r_p * mpmath.matrix([mp(v) for v in _point(PLATFORM_POINTS[k - 1])])
        leg = a_world - mpmath.matrix([mp(v) for v in _point(BASE_POINTS[k - 1])])
        length = mpmath.norm(leg)
        d = leg / length
        # R_cyl = Rx(a) Ry(b) and R_cyl e_z = (sin b, -sin a cos b, cos a cos b) = d
        b = mpmath.asin(d[0])
        a = mpmath.atan2(-d[1], d[2])
        ca, sa, cb, sb = mpmath.cos(a), mpmath.sin(a), mpmath.cos(b), mpmath.sin(b)
        r_cyl = mpmath.matrix([[1, 0, 0], [0, ca, -sa], [0, sa, ca]]) * \
            mpmath.matrix([[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]])
        quat = mp_matrix_to_quat(r_cyl.T * r_p)       # the rod keeps the cylinder's orientation
        return dict(a=to_exact(a), b=to_exact(b), length=to_exact(length), quat=[to_exact(v) for v in quat])


def _platform_inertia() -> list[Fraction]:
    m, r, t = PLATFORM["mass"], Fraction(PLATFORM["radius"]), Fraction(PLATFORM["thickness"])
    return cylinder_inertia(m, t, r, axis="z")


def stewart() -> Scene:
    """A 6-U-P-S Stewart platform in free motion (motion coordinates: the platform's twist)."""
    scene = Scene(name="stewart",
                  description="Stewart-Gough platform, six U-P-S legs, prismatic actuators: "
                              "m = 6, n_c = n_p = 30")
    a1 = _point(PLATFORM_POINTS[0])
    scene.add_body("platform", PLATFORM["mass"], com=[-v for v in a1], inertia=_platform_inertia())
    for k in range(1, 7):
        ref = leg_reference(k)
        scene.add_body(f"cross{k}", CROSS["mass"], inertia=box_inertia(CROSS["mass"], *[CROSS["size"]] * 3))
        scene.add_body(f"cyl{k}", CYLINDER["mass"], com=(0, 0, Fraction(CYLINDER["length"]) / 2),
                       inertia=cylinder_inertia(CYLINDER["mass"], CYLINDER["length"], CYLINDER["radius"]))
        scene.add_body(f"rod{k}", ROD["mass"], com=(0, 0, -Fraction(ROD["length"]) / 2),
                       inertia=cylinder_inertia(ROD["mass"], ROD["length"], ROD["radius"]))
        scene.add_joint(f"u{k}a", "revolute", WORLD, f"cross{k}", xyz=_point(BASE_POINTS[k - 1]), axis="x",
                        q0=ref["a"])
        scene.add_joint(f"u{k}b", "revolute", f"cross{k}", f"cyl{k}", axis="y", q0=ref["b"])
        scene.add_joint(f"p{k}", "prismatic", f"cyl{k}", f"rod{k}", axis="z", actuated=True, q0=ref["length"])
        if k == 1:
            scene.add_joint("s1", "spherical", "rod1", "platform", q0=ref["quat"])
            continue
        scene.add_body(f"socket{k}", 0)
        scene.add_joint(f"s{k}", "spherical", f"rod{k}", f"socket{k}", q0=ref["quat"])
        scene.add_frame(f"socket{k}_f", f"socket{k}")
        scene.add_frame(f"att{k}", "platform", xyz=[v - w for v, w in zip(_point(PLATFORM_POINTS[k - 1]), a1)])
        scene.add_constraint(f"leg{k}", "weld", f"socket{k}_f", f"att{k}")
    scene.add_frame("P", "platform", xyz=[-v for v in a1])
    scene.set_motion(frame="P")
    return scene
