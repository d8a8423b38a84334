"""Exact rotations of URDF origins (symgen.io.urdf.rotations): URDF's rpy convention, exact multiples
of pi/2, and rational rotations within 1e-19 of any other angle."""
from fractions import Fraction

import numpy as np
import pytest
import sympy as sp
from scipy.spatial.transform import Rotation

from symgen.io.urdf.rotations import (axis_argument, axis_rotation, quaternion_argument, rotation_from_rpy,
                                   snapped_angle)

HALF_PI_DOUBLE = Fraction("1.5707963267948966")   # what a double holds for pi/2
HALF_PI_UR5 = Fraction("1.57079632679")          # the UR5 file's pi/2, 4.9e-12 short


def test_roll_of_half_pi_is_the_exact_rotation_about_x():
    assert rotation_from_rpy((HALF_PI_DOUBLE, 0, 0)) == sp.Matrix([[1, 0, 0], [0, 0, -1], [0, 1, 0]])


def test_rpy_is_yaw_after_pitch_after_roll_about_fixed_axes():
    # rpy (pi/2, 0, pi/2): Rz(pi/2) Rx(pi/2) maps x -> y, y -> z, z -> x
    r = rotation_from_rpy((HALF_PI_DOUBLE, 0, HALF_PI_DOUBLE))
    assert r == sp.Matrix([[0, 0, 1], [1, 0, 0], [0, 1, 0]])


def test_a_rounded_half_pi_is_kept_unless_a_larger_snap_is_asked_for():
    assert snapped_angle(HALF_PI_UR5) is None
    assert snapped_angle(HALF_PI_UR5, snap=1e-9) == sp.pi / 2
    assert snapped_angle(Fraction("-3.141592653589793")) == -sp.pi


@pytest.mark.parametrize("rpy", [(0.1, 0.2, 0.3), (0.3, 0.2, -0.1), (HALF_PI_UR5, 0, 0), (0, -0.7, 0.25)])
def test_other_angles_give_an_orthonormal_rational_matrix_at_the_file_rotation(rpy):
    r = rotation_from_rpy(tuple(Fraction(str(a)) for a in rpy))
    assert all(v.is_Rational for v in r)
    assert r.T * r == sp.eye(3) and r.det() == 1            # exactly
    expected = Rotation.from_euler("xyz", [float(a) for a in rpy]).as_matrix()   # extrinsic x, y, z = URDF
    assert np.max(np.abs(np.array(r, dtype=float) - expected)) < 1e-15


def test_a_locked_revolute_joint_turns_about_its_axis():
    assert axis_rotation((0, 0, 1), sp.pi / 2) == sp.Matrix([[0, -1, 0], [1, 0, 0], [0, 0, 1]])
    r = axis_rotation((1, 1, 0), Fraction(3, 10))
    expected = Rotation.from_rotvec(0.3 * np.array([1, 1, 0]) / np.sqrt(2)).as_matrix()
    assert r.T * r == sp.eye(3) and np.max(np.abs(np.array(r, dtype=float) - expected)) < 1e-15


def test_coordinate_axes_are_passed_by_name_and_others_as_exact_vectors():
    assert axis_argument((0, 0, 1)) == "z" and axis_argument((0, Fraction(-1), 0)) == "-y"
    assert axis_argument((Fraction(3, 5), 0, Fraction(4, 5))) == [sp.Rational(3, 5), 0, sp.Rational(4, 5)]


def test_the_scene_quaternion_rebuilds_the_rotation_exactly():
    r = rotation_from_rpy((Fraction(1, 10), Fraction(1, 5), Fraction(3, 10)))
    q = quaternion_argument(r)
    w, x, y, z = (sp.Integer(v) for v in q)
    n2 = w * w + x * x + y * y + z * z
    rebuilt = sp.Matrix([[w*w + x*x - y*y - z*z, 2*(x*y - w*z), 2*(x*z + w*y)],
                         [2*(x*y + w*z), w*w - x*x + y*y - z*z, 2*(y*z - w*x)],
                         [2*(x*z - w*y), 2*(y*z + w*x), w*w - x*x - y*y + z*z]]) / n2
    assert rebuilt == r
    assert quaternion_argument(sp.eye(3)) is None
