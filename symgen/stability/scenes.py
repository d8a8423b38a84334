"""Scenes for the stability suite: the benchmark chain with extreme parameters, and a planar arm
whose task Jacobian can be driven to a singularity.

:func:`scaled_chain` keeps the benchmark chain's geometry (``symgen.io.builtin.chain``: revolute
joints, axes alternating z/y, each link a box-like body with its centre of mass at mid-link) and
changes what the suite needs to stress:

* ``length``: the link length ``L`` (the benchmark has ``L = 0.1 m``), so the lengths span 1e-3 to
  1e3 m; inertias scale with ``m L^2`` as a body of that size would;
* ``mass_ratio``: link ``i`` has mass ``mass_ratio ** (i % 2)`` times the benchmark's, so
  neighbouring links differ by that ratio (1e-6 .. 1e6);
* ``viscous``: viscous friction on every joint (one number) or joint by joint (one per joint),
  which makes the ODE stiff when the time constant ``inertia / viscous`` is small against the
  motion's time scale.

:func:`planar_arm` is a two-link planar arm whose motion coordinates are the tip's ``vx, vy``
(``J_m`` = the tip Jacobian, Step 10): ``[J_m; J_f] = J_m`` is singular when the arm is
outstretched (``q2 = 0``), with condition number growing like ``1 / |q2|``.
"""
from __future__ import annotations

from fractions import Fraction

import sympy as sp

from ..scene.declaration import WORLD, Scene

#: benchmark link length (m)
BENCHMARK_LENGTH = Fraction(1, 10)


def _exact(x) -> Fraction:
    return Fraction(x).limit_denominator(10**15) if isinstance(x, float) else Fraction(x)


def scaled_chain(n: int, *, length=BENCHMARK_LENGTH, mass_ratio=1, viscous=0, name: str | None = None) -> Scene:
    """The benchmark chain with link length ``length``, neighbour mass ratio ``mass_ratio`` and
    viscous friction ``viscous`` on every joint, or ``viscous[i]`` on joint ``j<i>`` when it is a
    sequence of ``n`` numbers (all exact). A sequence of another length is a ``ValueError``."""
    length, ratio = _exact(length), _exact(mass_ratio)
    per_joint = isinstance(viscous, (list, tuple))
    if per_joint and len(viscous) != n:
        raise ValueError(f"scaled_chain: viscous has {len(viscous)} values for {n} joints")
    frictions = [_exact(v) for v in viscous] if per_joint else [_exact(viscous)] * n
    said = ", ".join(f"{float(v):g}" for v in frictions) if per_joint else f"{float(frictions[0]):g}"
    scene = Scene(name=name or f"chain_n{n}_scaled",
                  description=f"{n}-link benchmark chain, L = {float(length):g} m, neighbour mass ratio "
                              f"{float(ratio):g}, viscous friction {said} N m s/rad")
    parent = WORLD
    for i in range(n):
        mass = Fraction(10 + i, 10) * ratio ** (i % 2)
        unit = mass * length * length
        scene.add_body(f"link{i}", mass, com=(length / 2, 0, 0), inertia=[unit, 2 * unit, 3 * unit])
        scene.add_joint(f"j{i}", "revolute", parent, f"link{i}", xyz=(0, 0, 0) if i == 0 else (length, 0, 0),
                        axis="z" if i % 2 == 0 else "y", actuated=True, viscous=frictions[i])
        parent = f"link{i}"
    scene.set_motion(joints=list(scene.joints))
    return scene


def planar_arm(*, length=Fraction(1, 2), q0=(Fraction(1, 2), Fraction(3, 2))) -> Scene:
    """A 2R planar arm (axes z, gravity along -y) whose task coordinates are the tip's
    ``vx, vy``; ``q0`` is a well-conditioned reference (elbow bent)."""
    length = _exact(length)
    scene = Scene(name="planar_arm", description="2R planar arm, task = tip velocity (vx, vy)")
    scene.gravity = sp.ImmutableMatrix([0, sp.Rational(-981, 100), 0])
    parent = WORLD
    for i in (1, 2):
        unit = length * length / 12
        scene.add_body(f"link{i}", 1, com=(length / 2, 0, 0), inertia=[unit / 100, unit, unit])
        scene.add_joint(f"j{i}", "revolute", parent, f"link{i}", xyz=(0, 0, 0) if i == 1 else (length, 0, 0),
                        axis="z", actuated=True, q0=_exact(q0[i - 1]))
        parent = f"link{i}"
    scene.add_frame("tip", "link2", xyz=(length, 0, 0))
    scene.set_motion(frame="tip", components=["vx", "vy"])
    return scene
