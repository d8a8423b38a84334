"""``chain:n=N`` -- the canonical benchmark robot, the n-link spatial chain.

An open serial chain of ``n`` revolute joints (the unconstrained special case of the paper's
Section 2: ``n_1a = m = n``, ``n_c = 0``, ``T_S = [1; T_S*]`` as in Section 3.2). Every performance
figure of symgen is taken on this family, so it must stay exactly this robot:

* joint ``j{i}`` (i = 0..n-1) is revolute, axis z in its own frame for even i, y for odd i;
* the frame of ``j0`` is the world frame; the frame of ``j{i}`` (i > 0) is the frame of link i-1
  translated by (L, 0, 0), L = 1/10, no rotation; link i's frame is joint i's frame after motion;
* link ``link{i}``: mass (10 + i)/10, centre of mass (L/2, 0, 0), inertia about the centre of mass
  diag(1, 2, 3) (10 + i)/1000 (= diag(0.01, 0.02, 0.03) (1 + i/10));
* gravity (0, 0, -981/100); every joint actuated; no friction, no rotor inertia.

The motion coordinates are the joint rates (``V_m = qd``, ``J_m = 1``).
"""
from __future__ import annotations

from fractions import Fraction

from ...scene.declaration import WORLD, Scene

L = Fraction(1, 10)


def chain(n: int = 6) -> Scene:
    """The ``n``-link spatial chain (joints ``j0..``, bodies ``link0..``)."""
    scene = Scene(name=f"chain_n{n}",
                  description=f"{n}-link spatial benchmark chain (revolute, axes alternating z/y, L = 0.1 m)")
    parent = WORLD
    for i in range(n):
        body = f"link{i}"
        scale = Fraction(10 + i, 1000)
        scene.add_body(body, Fraction(10 + i, 10), com=(L / 2, 0, 0),
                       inertia=[scale, 2 * scale, 3 * scale])
        scene.add_joint(f"j{i}", "revolute", parent, body, xyz=(0, 0, 0) if i == 0 else (L, 0, 0),
                        axis="z" if i % 2 == 0 else "y", actuated=True)
        parent = body
    scene.set_motion(joints=list(scene.joints))
    return scene
