"""Scenes as other tools write them: float rotation matrices (snapped to exact rotations), full
3x3 inertias, ``point`` / ``planar_point`` loop closures, and an open loop at ``q0`` reported as
such -- each checked against its exact equivalent."""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import sympy as sp

from symgen.io.builtin import get_scene
from symgen.io.builtin.closed_chains import FOUR_BAR_A, FOUR_BAR_D, _add_link
from symgen.errors import ConstraintError, SceneError
from symgen.model import derive
from symgen.math.rotations_snap import ORTHONORMAL_TOL, snap_rotation
from symgen.scene import WORLD, Scene
from symgen.io.scene_yaml import scene_from_dict

C30, S30 = float(np.cos(np.pi / 6)), float(np.sin(np.pi / 6))
FLOAT_30_X = [[1.0, 0.0, 0.0], [0.0, C30, -S30], [0.0, S30, C30]]


def _arm(rotation=None, rpy=None, inertia=(sp.Rational(1, 100), sp.Rational(2, 100), sp.Rational(25, 1000),
                                           sp.Rational(1, 1000), 0, sp.Rational(-1, 1000))):
    scene = Scene(name="arm")
    scene.add_body("a", 1, com=(sp.Rational(1, 10), 0, 0), inertia=[sp.Rational(1, 100)] * 3)
    scene.add_body("b", 2, com=(sp.Rational(1, 5), sp.Rational(1, 20), 0), inertia=inertia)
    scene.add_joint("q1", "revolute", WORLD, "a", axis="z", actuated=True)
    scene.add_joint("q2", "revolute", "a", "b", xyz=(sp.Rational(3, 10), 0, 0), rpy=rpy, rotation=rotation,
                    axis="y", actuated=True)
    scene.set_motion(joints=["q1", "q2"])
    return scene


def _joint_space(scene):
    from symgen.math.configuration import Configuration, CosSin

    model = derive(scene)
    config = Configuration({"q1": CosSin(sp.Rational(3, 5), sp.Rational(4, 5)),
                            "q2": CosSin(sp.Rational(5, 13), sp.Rational(12, 13))})
    d = model.evaluate(config, qd=[sp.Rational(7, 10), sp.Rational(-2, 5)], field="symbolic")
    return d.M_q, d.C_q, d.G_q


def test_float_30_degree_rotation_snaps_to_the_exact_rotation():
    snapped = snap_rotation("x", FLOAT_30_X)
    assert snapped == sp.ImmutableMatrix([[1, 0, 0], [0, sp.sqrt(3) / 2, -sp.Rational(1, 2)],
                                          [0, sp.Rational(1, 2), sp.sqrt(3) / 2]])


def test_float_rotation_gives_the_same_dynamics_as_the_exact_one_exactly():
    exact = _joint_space(_arm(rpy=("pi/6", 0, 0)))
    snapped = _joint_space(_arm(rotation=FLOAT_30_X))
    for a, b in zip(exact, snapped):
        assert all(sp.simplify(v) == 0 for v in sp.Matrix(a) - sp.Matrix(b))


def test_any_float_rotation_is_snapped_within_the_tolerance_to_an_exact_rotation():
    from scipy.spatial.transform import Rotation

    r = Rotation.from_euler("xyz", [0.3, -0.7, 1.1]).as_matrix()
    snapped = snap_rotation("x", r.tolist())
    assert sp.simplify(snapped.T * snapped) == sp.eye(3)
    assert np.max(np.abs(np.array(snapped, dtype=float) - r)) < 1e-11


def test_not_a_rotation_is_refused():
    bad = [row[:] for row in FLOAT_30_X]
    bad[0][0] = 1.0 + 10 * ORTHONORMAL_TOL
    with pytest.raises(SceneError, match="not a rotation matrix within"):
        _arm(rotation=bad)
    with pytest.raises(SceneError, match="not a rotation matrix"):
        _arm(rotation=[[1.0, 0, 0], [0, 1.0, 0], [0, 0, -1.0]])


def test_full_3x3_inertia_equals_the_six_entry_form():
    full = [[sp.Rational(1, 100), sp.Rational(1, 1000), 0], [sp.Rational(1, 1000), sp.Rational(2, 100),
                                                             sp.Rational(-1, 1000)],
            [0, sp.Rational(-1, 1000), sp.Rational(25, 1000)]]
    assert _arm(rpy=(0, 0, 0), inertia=full).bodies["b"].inertia == _arm(rpy=(0, 0, 0)).bodies["b"].inertia
    full[0][1] = sp.Rational(2, 1000)
    with pytest.raises(SceneError, match="not symmetric"):
        _arm(inertia=full)


def test_yaml_takes_float_rotations_and_3x3_inertias():
    data = {"name": "y", "bodies": {"a": {"mass": 1, "com": [0.1, 0, 0],
                                          "inertia": [[0.01, 0, 0], [0, 0.02, 0], [0, 0, 0.03]]}},
            "joints": {"q": {"type": "revolute", "parent": "world", "child": "a", "rotation": FLOAT_30_X,
                             "axis": "z", "actuated": True}},
            "motion": {"joints": ["q"]}}
    scene = scene_from_dict(data)
    assert scene.joints["q"].origin.rotation[1, 1] == sp.sqrt(3) / 2
    assert scene.bodies["a"].inertia == sp.diag(sp.Rational(1, 100), sp.Rational(2, 100), sp.Rational(3, 100))


def _four_bar_point(kind: str, q0=("pi/3", "-pi/3", "-2*pi/3")) -> Scene:
    """The built-in four-bar without its pin joint: the rocker's end meets the ground pivot D."""
    d, a = FOUR_BAR_D, FOUR_BAR_A
    scene = Scene(name="four_bar_point")
    for name, length in (("crank", a), ("coupler", d), ("rocker", a)):
        _add_link(scene, name, length)
    scene.add_joint("j1", "revolute", WORLD, "crank", axis="z", actuated=True, q0=q0[0])
    scene.add_joint("j2", "revolute", "crank", "coupler", xyz=(a, 0, 0), axis="z", q0=q0[1])
    scene.add_joint("j3", "revolute", "coupler", "rocker", xyz=(d, 0, 0), axis="z", q0=q0[2])
    scene.add_frame("rocker_end", "rocker", xyz=(a, 0, 0))
    scene.add_frame("ground_pin", WORLD, xyz=(d, 0, 0))
    scene.add_constraint("closure", kind, "rocker_end", "ground_pin", normal="z")
    scene.set_motion(joints=["j1"])
    return scene


def test_planar_point_loop_gives_the_dynamics_of_the_builtin_four_bar():
    ref = derive(get_scene("four_bar"))
    model = derive(_four_bar_point("planar_point"))
    assert model.scene.constraints["closure"].components == ("vx", "vy")
    for angle, v in ((np.pi / 3, 0.4), (np.pi / 3 + 0.2, -1.0)):
        from symgen.closure import solve_closure
        from symgen.math.configuration import Configuration

        cfg_ref = solve_closure(ref, Configuration({"j1": angle, "j2": -np.pi / 3, "j3": -2 * np.pi / 3,
                                                    "j4": 2 * np.pi / 3}))
        cfg = Configuration({k: cfg_ref.positions[k] for k in ("j1", "j2", "j3")})
        for tau in ([0.3], [-1.2]):
            want = ref.forward_dynamics(cfg_ref, [v], tau)[0]
            got = model.forward_dynamics(cfg, [v], tau)[0]
            np.testing.assert_allclose(got, want, rtol=1e-12)
        # same force on the rocker's end, stated in different axes: the builtin's pin frame has the
        # world's axes when the loop is closed, rocker_end the rocker's (angle j1 + j2 + j3)
        lam_ref = ref.loop_forces(cfg_ref, [v], [0.3])
        theta = sum(float(cfg.positions[k]) for k in ("j1", "j2", "j3"))
        rot = np.array([[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]])
        np.testing.assert_allclose(rot @ model.loop_forces(cfg, [v], [0.3]), lam_ref[:2], rtol=1e-10, atol=1e-13)
        assert abs(lam_ref[2]) < 1e-13       # the passive pin joint carries no moment


def test_point_closing_a_planar_loop_is_refused_or_reduced_with_a_note():
    """Three point rows in a planar loop leave no motion (eq. 5); drop_vanishing_rows (what the MJCF
    reader runs) removes the one normal to the plane and says so."""
    from symgen.vanishing_rows import drop_vanishing_rows

    with pytest.raises(ConstraintError, match="no motion is left"):
        derive(_four_bar_point("point"))
    reduced = drop_vanishing_rows(_four_bar_point("point"))
    assert reduced.constraints["closure"].components == ("vx", "vy")
    assert reduced.notes == ["constraint 'closure': dropped component vz (its row of T, eq. 6, vanishes identically)"]
    assert derive(reduced).counts.m == 1


def test_open_loop_at_q0_is_reported_before_redundancy():
    """A stretched, singular four-bar at ``q0 = 0`` does not close: say so, not 'redundant'."""
    with pytest.raises(ConstraintError, match="violated by .* at the reference configuration"):
        derive(_four_bar_point("planar_point", q0=(0, 0, 0)))


def test_weighted_frames_that_do_not_coincide_at_q0_are_refused_with_the_reason():
    """Section 3.3: the gamma-weighted frames must be one frame at q0."""
    from symgen.scene import Frame, Pose

    scene = get_scene("multi_arm:h=2")
    o2 = scene.frames["O2"]
    moved = sp.ImmutableMatrix(list(sp.Matrix(o2.pose.translation) + sp.Matrix([sp.Rational(1, 100), 0, 0])))
    scene.frames["G2"] = Frame("G2", o2.body, o2.pose)       # the weld keeps the grasp frame
    scene.constraints["grasp12"] = dataclasses.replace(scene.constraints["grasp12"], frame_b="G2")
    scene.frames["O2"] = Frame(o2.name, o2.body, Pose(o2.pose.rotation, moved))
    with pytest.raises(SceneError, match="'O1' and 'O2' must coincide at the reference configuration q0"):
        derive(scene)
