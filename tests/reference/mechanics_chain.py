"""Independent exact reference for the benchmark n-link spatial chain, built with
``sympy.physics.mechanics`` (Kane's method).

Nothing here is taken from symgen's model: the robot is rebuilt from its written definition
(``chain:n=N``, the canonical benchmark) as SymPy mechanics bodies by
:func:`symgen.complexity.mechanics.chain_bodies` -- the same construction the complexity tables
count, which uses only ``sympy.physics.mechanics`` -- checked by hand for one and two links in
``tests/test_chain_vs_mechanics.py``:

* joint i (i = 0..n-1) revolute, axis z of its own frame for even i, y for odd i;
* joint 0's frame is the world frame; joint i > 0's frame is link i-1's frame translated by
  (L, 0, 0), L = 1/10, not rotated; link i's frame is joint i's frame after the rotation q_i;
* link i: mass (10 + i)/10, centre of mass (L/2, 0, 0) in the link frame, rotational inertia
  about the centre of mass diag(1, 2, 3)/100 * (1 + i/10) in the link frame;
* gravity (0, 0, -981/100).

Convention (Pinocchio's ``rnea``)::

    tau = M(q) qdd + Cqd(q, qd) + G(q)

Kane's method gives ``M(q) u' = forcing(q, u)`` for the *unactuated* chain, i.e. the sum of the
generalized active forces (gravity) and the velocity-product part of the generalized inertia
forces, so ``tau = M qdd - forcing``. With the gravity loads the split is
``G = -forcing|_{u=0}`` and ``Cqd = -forcing - G``.

Symbols: the returned expressions are in *plain* (time-independent) real SymPy symbols
``q_0 .. q_{n-1}`` (joint angles) and ``qd_0 .. qd_{n-1}`` (joint rates), see :func:`symbols`;
the dynamicsymbols used during the derivation are replaced before returning (``qdd_i`` for the
joint accelerations in :func:`inverse_dynamics_equations`). All parameters are exact
:class:`sympy.Rational`.

:func:`evaluate_exact` / :func:`inverse_dynamics_exact` evaluate at a rational point given by exact
``(cos q_i, sin q_i)`` pairs, returning exact Rationals.
"""
from __future__ import annotations

from fractions import Fraction
from functools import lru_cache

import sympy as sp
from sympy.physics.mechanics import KanesMethod, dynamicsymbols

from symgen.complexity.mechanics import chain_bodies, plain_symbols

def symbols(n: int) -> tuple[list[sp.Symbol], list[sp.Symbol]]:
    """The plain symbols ``(q, qd)`` in which :func:`chain_equations` returns its expressions."""
    return plain_symbols(n)


@lru_cache(maxsize=None)
def _kane(n: int):
    """Kane's equations of the n-link chain: ``(qs, us, fr, frstar, mass_matrix, forcing)`` in the
    dynamicsymbols ``q_i(t)``, ``u_i(t) = q_i'(t)``."""
    qs = [dynamicsymbols(f"q{i}") for i in range(n)]   # joint angles q_i(t)
    us = [dynamicsymbols(f"u{i}") for i in range(n)]   # generalized speeds u_i = q_i'

    world, bodies, loads = chain_bodies(n, qs)

    kd = [qs[i].diff() - us[i] for i in range(n)]
    kane = KanesMethod(world, q_ind=qs, u_ind=us, kd_eqs=kd)
    fr, frstar = kane.kanes_equations(bodies, loads)
    return qs, us, fr, frstar, kane.mass_matrix, kane.forcing


def _to_plain(n: int, expr: sp.Matrix) -> sp.Matrix:
    """Replace ``u_i'(t) -> qdd_i``, ``u_i(t) -> qd_i``, ``q_i(t) -> q_i`` (plain symbols)."""
    qs, us = _kane(n)[:2]
    q, qd = symbols(n)
    qdd = [sp.Symbol(f"qdd_{i}", real=True) for i in range(n)]
    repl = {us[i].diff(): qdd[i] for i in range(n)}
    repl.update({us[i]: qd[i] for i in range(n)})
    repl.update({qs[i]: q[i] for i in range(n)})
    out = expr.xreplace(repl)
    leftover = out.free_symbols - set(q) - set(qd) - set(qdd)
    if leftover or out.has(sp.Derivative):
        raise AssertionError(f"unexpected symbols left in Kane's equations: {leftover}")
    return out


@lru_cache(maxsize=None)
def chain_equations(n: int) -> tuple[sp.ImmutableMatrix, sp.ImmutableMatrix, sp.ImmutableMatrix]:
    """``(M, Cqd, G)`` of the n-link chain in the plain symbols of :func:`symbols`.

    ``M`` is n x n, ``Cqd`` and ``G`` are n x 1; ``tau = M qdd + Cqd + G``.
    """
    _, _, _, _, mass_matrix, forcing = _kane(n)
    q, qd = symbols(n)
    m_plain = _to_plain(n, mass_matrix)
    f_plain = _to_plain(n, forcing)          # M qdd = forcing  (no actuation)
    grav = -f_plain.xreplace({v: 0 for v in qd})
    cqd = -f_plain - grav
    return sp.ImmutableMatrix(m_plain), sp.ImmutableMatrix(cqd), sp.ImmutableMatrix(grav)


@lru_cache(maxsize=None)
def inverse_dynamics_equations(n: int) -> sp.ImmutableMatrix:
    """``tau(q, qd, qdd) = -(Fr + Fr*)`` straight from Kane's equations (no M / forcing split),
    in the plain symbols ``q_i``, ``qd_i``, ``qdd_i``."""
    _, _, fr, frstar, _, _ = _kane(n)
    return sp.ImmutableMatrix(-_to_plain(n, fr + frstar))


def _rational(x) -> sp.Rational:
    if isinstance(x, Fraction):
        return sp.Rational(x.numerator, x.denominator)
    if isinstance(x, float):
        raise TypeError(f"{x!r} is a float; give exact rationals (Fraction, int, sympy.Rational)")
    r = sp.sympify(x)
    if not r.is_Rational:
        raise TypeError(f"{x!r} is not an exact rational")
    return r


def _substitution(n: int, cos_sin, qd, qdd=None) -> dict:
    if len(cos_sin) != n or len(qd) != n or (qdd is not None and len(qdd) != n):
        raise ValueError(f"need {n} (cos, sin) pairs and {n} rates")
    q_syms, qd_syms = symbols(n)
    repl = {}
    for i, (c, s) in enumerate(cos_sin):
        c, s = _rational(c), _rational(s)
        if c * c + s * s != 1:
            raise ValueError(f"joint {i}: cos^2 + sin^2 = {c * c + s * s} != 1")
        repl[sp.cos(q_syms[i])] = c
        repl[sp.sin(q_syms[i])] = s
    for i, v in enumerate(qd):
        repl[qd_syms[i]] = _rational(v)
    for i, v in enumerate(qdd or ()):
        repl[sp.Symbol(f"qdd_{i}", real=True)] = _rational(v)
    return repl


def _exact(mat: sp.Matrix, repl: dict) -> sp.Matrix:
    val = mat.xreplace(repl)
    if val.free_symbols:
        # e.g. sin(2 q) or sin(q_i + q_j) would need expand_trig; the Kane output has none
        raise AssertionError(f"terms not reduced by the cos/sin substitution: {val.free_symbols}")
    return sp.Matrix(val).applyfunc(sp.Rational)


def evaluate_exact(n: int, cos_sin, qd) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """``(M, Cqd, G)`` as exact :class:`sympy.Rational` matrices at a rational point.

    ``cos_sin`` is a sequence of ``n`` pairs ``(cos q_i, sin q_i)`` of exact rationals (``int``,
    :class:`fractions.Fraction` or SymPy Rational) with ``c^2 + s^2 = 1``; ``qd`` a sequence of
    ``n`` exact rationals. ``sin(q_i)`` and ``cos(q_i)`` are replaced by these values (``xreplace``),
    so the result is exact; any trigonometric form not of this kind is an error.
    """
    repl = _substitution(n, cos_sin, qd)
    return tuple(_exact(mat, repl) for mat in chain_equations(n))


def inverse_dynamics_exact(n: int, cos_sin, qd, qdd) -> sp.Matrix:
    """``tau`` (n x 1, exact Rationals) from Kane's ``-(Fr + Fr*)`` at a rational state."""
    return _exact(inverse_dynamics_equations(n), _substitution(n, cos_sin, qd, qdd))
