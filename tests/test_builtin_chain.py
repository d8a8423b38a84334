"""The built-in ``chain:n=N`` scene is exactly the canonical benchmark robot.

The benchmark's parameters are written out here from its definition (not imported from anywhere):

* joint i (i = 0..n-1) revolute, axis z of its own frame for even i, y for odd i;
* joint 0's frame is the world frame; joint i > 0's frame is link i-1's frame translated by
  (L, 0, 0), L = 1/10, no rotation; link i's frame is joint i's frame after the joint rotation;
* link i: mass (10 + i)/10, centre of mass (L/2, 0, 0) in the link frame, rotational inertia about
  the centre of mass diag(1, 2, 3)/100 * (1 + i/10) in the link frame;
* gravity (0, 0, -981/100); no friction, no rotor inertia; every joint actuated; no constraints.

All comparisons are exact equality of SymPy values (and the values must be exact Rationals).
"""
from __future__ import annotations

import pytest
import sympy as sp

from symgen.io.builtin import get_scene
from symgen.model import derive

R = sp.Rational
L = R(1, 10)
SIZES = [1, 5, 12]


def expected(n: int) -> dict:
    joints, bodies = {}, {}
    for i in range(n):
        scale = 1 + R(i, 10)
        bodies[f"link{i}"] = dict(
            mass=R(10 + i, 10),
            com=sp.Matrix([L / 2, 0, 0]),
            inertia=sp.diag(R(1, 100) * scale, R(2, 100) * scale, R(3, 100) * scale),
        )
        joints[f"j{i}"] = dict(
            type="revolute",
            parent="world" if i == 0 else f"link{i - 1}",
            child=f"link{i}",
            axis=sp.Matrix([0, 0, 1]) if i % 2 == 0 else sp.Matrix([0, 1, 0]),
            translation=sp.Matrix([0, 0, 0]) if i == 0 else sp.Matrix([L, 0, 0]),
            rotation=sp.eye(3),
        )
    return dict(joints=joints, bodies=bodies, gravity=sp.Matrix([0, 0, -R(981, 100)]))


def assert_exact(got, want, what: str):
    """``got`` equals ``want`` exactly and every entry is a SymPy Rational (no Float, no int)."""
    if isinstance(want, sp.MatrixBase):
        assert isinstance(got, sp.MatrixBase), f"{what}: not a SymPy matrix: {got!r}"
        assert got.shape == want.shape, f"{what}: shape {got.shape} != {want.shape}"
        values = list(got)
    else:
        values = [got]
    assert all(isinstance(v, sp.Rational) for v in values), f"{what}: not exact rationals: {got!r}"
    assert sp.Matrix(values) == sp.Matrix(list(want) if isinstance(want, sp.MatrixBase) else [want]), \
        f"{what}: {got} != {want}"


@pytest.mark.parametrize("n", SIZES)
def test_bodies(n):
    scene = get_scene(f"chain:n={n}")
    want = expected(n)["bodies"]
    assert list(scene.bodies) == list(want)
    for name, w in want.items():
        body = scene.bodies[name]
        assert_exact(body.mass, w["mass"], f"{name}.mass")
        assert_exact(body.com, w["com"], f"{name}.com")
        assert_exact(body.inertia, w["inertia"], f"{name}.inertia")


@pytest.mark.parametrize("n", SIZES)
def test_joints(n):
    scene = get_scene(f"chain:n={n}")
    want = expected(n)["joints"]
    assert list(scene.joints) == list(want)
    for name, w in want.items():
        joint = scene.joints[name]
        assert joint.type == w["type"], name
        assert joint.parent == w["parent"], name
        assert joint.child == w["child"], name
        assert_exact(joint.axis, w["axis"], f"{name}.axis")
        assert_exact(joint.origin.translation, w["translation"], f"{name}.origin.translation")
        assert_exact(joint.origin.rotation, w["rotation"], f"{name}.origin.rotation")
        for attr in ("rotor_inertia", "viscous", "coulomb"):
            assert getattr(joint, attr) == 0, f"{name}.{attr}"


@pytest.mark.parametrize("n", SIZES)
def test_gravity_and_task(n):
    """Gravity; no frames' constraints, no contact forces, every joint actuated, V_m = qd."""
    scene = get_scene(f"chain:n={n}")
    assert_exact(scene.gravity, expected(n)["gravity"], "gravity")
    assert scene.parameters == {}
    assert scene.constraints == {}
    assert scene.contact_forces is None
    assert all(j.actuated for j in scene.joints.values())
    assert scene.motion is not None and list(scene.motion.joints) == [f"j{i}" for i in range(n)]

    counts = derive(scene).counts
    assert (counts.n1a, counts.n1u, counts.n3a, counts.n3u) == (n, 0, 0, 0)
    assert (counts.m, counts.nc, counts.np, counts.n) == (n, 0, 0, n)
