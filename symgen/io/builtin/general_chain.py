"""``general_chain:n=N`` -- an unbranched chain of revolute joints in general geometry with general
inertia: the robot of the published operation-count tables (RBDA's ``GU(n)``; Balafoutis, Patel &
Misra 1988 count their inverse dynamics on it), where ``chain:n=N`` is a special one (parallel and
perpendicular axes, diagonal inertias, centres of mass on a link axis).

Joint ``i`` is placed on link ``i - 1`` by modified Denavit-Hartenberg parameters, so its frame is
``Rx(alpha_i) Tx(a_i) Tz(d_i)`` from the previous joint's and its motion ``Rz(q_i)``: the joint
origin has rotation ``Rx(alpha_i)`` and translation ``(a_i, -sin(alpha_i) d_i, cos(alpha_i) d_i)``.
Every parameter is an exact rational drawn from a fixed seed, joint by joint, so
``general_chain:n=N`` is the first ``N`` links of every longer one:

* ``alpha_i``: ``cos = (1 - t^2) / (1 + t^2)``, ``sin = 2 t / (1 + t^2)`` with ``|t|`` in
  ``[0.05, 0.95]`` (a rational point of the unit circle, 5.7 to 87 degrees either way: never a
  multiple of 90 degrees);
* ``a_i``, ``d_i`` of magnitude in ``[0.05, 0.3]`` m, signs drawn;
* link ``i``: mass in ``[1, 5]`` kg, centre of mass with every coordinate of magnitude in
  ``[0.01, 0.1]`` m, inertia about it ``R diag(J) R^T`` with principal moments ``J`` obeying the
  triangle inequality and ``R`` the Cayley rotation of a drawn vector (rational), drawn again until
  no product of inertia is zero;
* gravity (0, 0, -981/100); every joint actuated; no friction; motion on the joint rates.
"""
from __future__ import annotations

import random
from fractions import Fraction

import sympy as sp

from ...scene.declaration import WORLD, Scene

#: the stream every ``general_chain`` draws from (:meth:`random.Random.random` is reproducible across
#: Python versions for an integer seed)
SEED = 1988


def _draw(rng: random.Random, low: float, high: float, denominator: int = 1000) -> Fraction:
    """A rational in ``[low, high]`` with the given denominator."""
    return Fraction(round((low + (high - low) * rng.random()) * denominator), denominator)


def _signed(rng: random.Random, low: float, high: float, denominator: int = 1000) -> Fraction:
    """A rational of magnitude in ``[low, high]`` (``low > 0``: never zero) and a drawn sign."""
    magnitude = _draw(rng, low, high, denominator)
    return magnitude if rng.random() < 0.5 else -magnitude


def _cayley(v: list[Fraction]) -> sp.Matrix:
    """The rotation ``(1 - K)^-1 (1 + K)`` of the skew matrix ``K`` of ``v``: rational entries."""
    k = sp.Matrix([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    return (sp.eye(3) - k).inv() * (sp.eye(3) + k)


def _link(rng: random.Random) -> tuple[Fraction, tuple, list]:
    """Mass, centre of mass and inertia about it (physically consistent) of one link."""
    mass = _draw(rng, 1, 5, 100)
    com = tuple(_signed(rng, 0.01, 0.1) for _ in range(3))
    while True:                      # principal moments obeying the triangle inequality
        j = [_draw(rng, 0.01, 0.1, 10000) for _ in range(3)]
        if all(j[i] < j[(i + 1) % 3] + j[(i + 2) % 3] for i in range(3)):
            break
    while True:                      # a rotation leaving every product of inertia nonzero
        r = _cayley([_signed(rng, 0.05, 1, 100) for _ in range(3)])
        inertia = r * sp.diag(*j) * r.T
        if all(inertia[a, b] != 0 for a, b in ((0, 1), (0, 2), (1, 2))):
            return mass, com, inertia.tolist()


def general_chain(n: int = 7) -> Scene:
    """The ``n``-link general chain (joints ``j0..``, bodies ``link0..``; module docstring)."""
    scene = Scene(name=f"general_chain_n{n}",
                  description=f"{n}-link chain in general geometry (modified DH from seed {SEED}) with general inertia")
    rng = random.Random(SEED)
    parent = WORLD
    for i in range(n):
        t = _signed(rng, 0.05, 0.95, 100)          # a twist of 5.7 to 87 degrees, either sign
        c, s = (1 - t * t) / (1 + t * t), 2 * t / (1 + t * t)
        a, d = _signed(rng, 0.05, 0.3), _signed(rng, 0.05, 0.3)
        mass, com, inertia = _link(rng)
        body = f"link{i}"
        scene.add_body(body, mass, com=com, inertia=inertia)
        rotation = [[1, 0, 0], [0, c, -s], [0, s, c]]
        scene.add_joint(f"j{i}", "revolute", parent, body, xyz=(a, -s * d, c * d), rotation=rotation,
                        actuated=True)
        parent = body
    scene.set_motion(joints=list(scene.joints))
    return scene
