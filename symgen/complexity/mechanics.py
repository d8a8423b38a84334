"""The benchmark chain ``chain:n=N`` built with ``sympy.physics.mechanics``: Kane and Lagrange.

The robot is rebuilt from its written definition (``symgen/io/builtin/chain.py``), nothing is taken
from symgen's model:

* joint i (i = 0..n-1) revolute about z of its frame for even i, y for odd i; joint 0's frame is
  the world frame, joint i > 0's frame is link i-1's frame translated by (L, 0, 0), L = 1/10;
* link i: mass (10 + i)/10, centre of mass (L/2, 0, 0) in its frame, inertia about the centre of
  mass diag(1, 2, 3) (10 + i)/1000; gravity (0, 0, -981/100) as a force on every centre of mass.

Both methods give ``M(q) qdd = forcing(q, qd)`` for the unactuated chain, so for the rnea
convention ``tau = M qdd + C qd + g`` one has ``forcing = -(C qd + g)``. Their results are
returned in plain symbols ``q_i``, ``qd_i`` (not ``q_i(t)``) so that counting operations does not
count the time functions. Cost: the expressions grow roughly like ``O(n^4)`` to ``O(n^5)`` terms,
and SymPy's time with them (see ``benchmarks/complexity``).
"""
from __future__ import annotations

import sympy as sp
from sympy.physics.mechanics import (KanesMethod, LagrangesMethod, Lagrangian, Point, ReferenceFrame,
                                     RigidBody, dynamicsymbols, inertia)

L = sp.Rational(1, 10)
G_ACC = sp.Rational(981, 100)   # gravity is (0, 0, -G_ACC)
METHODS = ("kane", "lagrange")


def link_mass(i: int) -> sp.Rational:
    return sp.Rational(10 + i, 10)


def link_inertia(i: int) -> tuple:
    scale = sp.Rational(10 + i, 1000)
    return scale, 2 * scale, 3 * scale


def plain_symbols(n: int) -> tuple[list[sp.Symbol], list[sp.Symbol]]:
    """``(q, qd)``: the plain real symbols of the returned expressions."""
    return ([sp.Symbol(f"q_{i}", real=True) for i in range(n)],
            [sp.Symbol(f"qd_{i}", real=True) for i in range(n)])


def chain_bodies(n: int, q: list) -> tuple:
    """``(world_frame, bodies, loads)`` of the n-link chain at the joint angles ``q`` (dynamicsymbols)."""
    if n < 1:
        raise ValueError(f"chain needs n >= 1, got {n}")
    world, origin = ReferenceFrame("N"), Point("O")
    origin.set_vel(world, 0)
    bodies, loads = [], []
    parent_frame, parent_origin = world, origin
    for i in range(n):
        if i == 0:
            joint_origin = origin
        else:
            joint_origin = parent_origin.locatenew(f"J{i}", L * parent_frame.x)
            joint_origin.v2pt_theory(parent_origin, world, parent_frame)
        link = ReferenceFrame(f"A{i}")
        link.orient_axis(parent_frame, parent_frame.z if i % 2 == 0 else parent_frame.y, q[i])
        com = joint_origin.locatenew(f"P{i}", (L / 2) * link.x)
        com.v2pt_theory(joint_origin, world, link)
        bodies.append(RigidBody(f"link{i}", com, link, link_mass(i), (inertia(link, *link_inertia(i)), com)))
        loads.append((com, -link_mass(i) * G_ACC * world.z))
        parent_frame, parent_origin = link, joint_origin
    return world, bodies, loads


def kane_equations(n: int) -> tuple[sp.Matrix, sp.Matrix]:
    """``(M, forcing)`` by Kane's method (``KanesMethod.kanes_equations``), generalized speeds
    ``u_i = q_i'``; ``M`` is n x n, ``forcing`` n x 1, in :func:`plain_symbols`."""
    q, u = dynamicsymbols(f"q0:{n}"), dynamicsymbols(f"u0:{n}")
    world, bodies, loads = chain_bodies(n, q)
    kane = KanesMethod(world, q_ind=q, u_ind=u, kd_eqs=[q[i].diff() - u[i] for i in range(n)])
    kane.kanes_equations(bodies, loads)
    return _plain(n, q, u, kane.mass_matrix), _plain(n, q, u, kane.forcing)


def lagrange_equations(n: int) -> tuple[sp.Matrix, sp.Matrix]:
    """``(M, forcing)`` by Lagrange's method (``LagrangesMethod.form_lagranges_equations``) on the
    kinetic energy, gravity as applied forces; in :func:`plain_symbols`."""
    q = dynamicsymbols(f"q0:{n}")
    world, bodies, loads = chain_bodies(n, q)
    method = LagrangesMethod(Lagrangian(world, *bodies), q, forcelist=loads, frame=world)
    method.form_lagranges_equations()
    qdot = [qi.diff() for qi in q]
    return _plain(n, q, qdot, method.mass_matrix), _plain(n, q, qdot, method.forcing)


EQUATIONS = {"kane": kane_equations, "lagrange": lagrange_equations}


def _plain(n: int, q: list, rates: list, expr: sp.Matrix) -> sp.Matrix:
    """Replace the dynamicsymbols ``rates[i]`` (``u_i(t)`` or ``q_i'(t)``) and ``q_i(t)`` by plain symbols."""
    q_sym, qd_sym = plain_symbols(n)
    out = expr.xreplace({rates[i]: qd_sym[i] for i in range(n)}).xreplace({q[i]: q_sym[i] for i in range(n)})
    leftover = out.atoms(sp.Derivative, sp.core.function.AppliedUndef)
    if leftover:
        raise AssertionError(f"time functions left after substitution: {sorted(map(str, leftover))[:5]}")
    return sp.Matrix(out)


def evaluate(M: sp.Matrix, forcing: sp.Matrix, q, qd) -> tuple:
    """``(M, forcing)`` as float NumPy arrays at joint angles ``q`` and rates ``qd``."""
    import numpy as np

    n = M.shape[0]
    q_sym, qd_sym = plain_symbols(n)
    values = dict(zip(q_sym, map(float, q))) | dict(zip(qd_sym, map(float, qd)))
    f = sp.lambdify([list(values)], [M, forcing], modules="numpy")
    m_val, f_val = f(list(values.values()))
    return np.asarray(m_val, float), np.asarray(f_val, float).reshape(-1)

