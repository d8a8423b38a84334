"""The Jacobian ``d f / d x`` of the simulation's right-hand side for SciPy's implicit integrators
(Radau, BDF), from the generated ``state_derivative_jacobian`` instead of SciPy's finite
differences (``simulate(..., jacobian="generated")``).

For ``x = [q; V_m]`` and ``f(t, x) = state_derivative(q, V_m, tau(t, q, V_m)[, eta_m(t, q, V_m)])``
(+ the Baumgarte correction), by the chain rule::

    df/dx = dxdot/dx + dxdot/dtau dtau/dx + dxdot/deta_m deta_m/dx + d(correction)/dx

* ``dxdot/dx``, ``dxdot/dtau``: one call of the generated ``state_derivative_jacobian``
  (analytic, :mod:`symgen.codegen.forward_derivatives`);
* ``dxdot/deta_m``: exact differences of the generated ``forward_dynamics``, which is linear in
  ``eta_m`` (one call per component);
* ``dtau/dx``, ``deta_m/dx``: the force function's own ``jacobian(t, q, V_m) -> (d/dq, d/dV_m)``
  when it has one, else central differences of it (``2 (nq + m)`` calls of the user's function,
  no generated code);
* Baumgarte's ``-k W^-1 r(q)`` on the dependent rates: ``-k W^-1 dr/dq``, exact on the constraint
  manifold (``r = 0``; off it the term ``d(W^-1)/dq r`` is left out, of the order of the drift).

A spherical joint's quaternion ``p`` has four columns, the entries of ``x`` (what SciPy
integrates): ``f`` reads ``p / |p|``, so every column block of ``p`` is multiplied by
``(1 - n n^T) / |p|`` (``n = p / |p|``, the derivative of the normalisation) -- the generated
Jacobian, taken at unit length, already has no radial part. The Baumgarte correction with
spherical joints is refused (its Jacobian is formed for 1-DOF joints only).
"""
from __future__ import annotations

import numpy as np

#: relative step of the central differences of a force function without ``jacobian``
FORCE_STEP = 1e-6

_MODULES: dict[tuple[int, str], tuple[object, object]] = {}


def jacobian_backend(model, backend: str):
    """The generated ``state_derivative_jacobian`` and ``forward_dynamics`` of ``model`` (cached)."""
    from ..codegen.runtime import load_generated

    key = (id(model), backend)
    if key not in _MODULES or _MODULES[key][0] is not model:
        _MODULES[key] = (model, load_generated(model, backend, ["state_derivative_jacobian", "forward_dynamics"]))
    return _MODULES[key][1]


def force_jacobian(force, t, q, v_m) -> np.ndarray:
    """``d force / d[q; V_m]`` of a :class:`~symgen.simulation.forcing.CheckedForce`: zero for no
    force, the function's ``jacobian`` if it has one, else central differences."""
    q, v_m = np.asarray(q, dtype=float), np.asarray(v_m, dtype=float)
    if force.is_zero:
        return np.zeros((force.size, q.size + v_m.size))
    own = getattr(force.fn, "jacobian", None)
    if own is not None:
        d_q, d_v = own(t, q, v_m)
        return np.concatenate([np.asarray(d_q, dtype=float), np.asarray(d_v, dtype=float)], axis=1)
    x = np.concatenate([q, v_m])
    cols = []
    for k in range(x.size):
        h = FORCE_STEP * max(1.0, abs(x[k]))
        ends = []
        for s in (h, -h):
            y = x.copy()
            y[k] += s
            ends.append(force(t, y[:q.size], y[q.size:]))
        cols.append((ends[0] - ends[1]) / (2 * h))
    return np.array(cols).T.reshape(force.size, x.size)


class StateJacobian:
    """``jac(t, x)`` for ``solve_ivp`` from a :class:`~symgen.simulation.dynamics.Dynamics`;
    ``calls`` counts the evaluations."""

    def __init__(self, dyn):
        if dyn.baumgarte and dyn.layout.spherical:
            from .errors import SimulationInputError

            raise SimulationInputError(f"joint {dyn.layout.spherical[0][0]!r} (spherical): jacobian='generated' with "
                                       "the Baumgarte correction handles 1-DOF joints only; use "
                                       "jacobian='finite-difference' or another stabilization")
        self.dyn = dyn
        self.module = jacobian_backend(dyn.model, dyn.backend)
        self.calls = 0

    def __call__(self, t, x) -> np.ndarray:
        self.calls += 1
        dyn, layout = self.dyn, self.dyn.layout
        raw, v_m = layout.split(np.asarray(x, dtype=float))
        q = layout.normalized(raw)
        tau = dyn.tau(t, q, v_m)
        eta = (dyn.eta_m(t, q, v_m),) if dyn.n_eta else ()
        d_x, d_tau = dyn._guard(t, self.module.state_derivative_jacobian, q, v_m, tau, *eta)
        jac = np.array(d_x, dtype=float) + np.asarray(d_tau) @ force_jacobian(dyn.tau, t, q, v_m)
        if dyn.n_eta:
            jac[layout.nq:] += self._contact_columns(t, q, v_m, tau, eta[0]) @ force_jacobian(dyn.eta_m, t, q, v_m)
        if dyn.baumgarte:
            jac[:layout.nq] += self._baumgarte(q)
        for _, off, _ in layout.spherical:          # f reads p / |p|
            unit = q[off:off + 4]
            jac[:, off:off + 4] = jac[:, off:off + 4] @ (np.eye(4) - np.outer(unit, unit)) / np.linalg.norm(raw[off:off + 4])
        return jac

    def _contact_columns(self, t, q, v_m, tau, eta) -> np.ndarray:
        """``d dV_m / d eta_m``: ``forward_dynamics`` is linear in ``eta_m``."""
        call = self.module.forward_dynamics

        def accel(e):
            out = self.dyn._guard(t, call, q, v_m, tau, e)
            return np.asarray(out[0] if isinstance(out, tuple) else out)

        base = accel(np.zeros_like(eta))
        return np.array([accel(e) - base for e in np.eye(eta.size)]).T

    def _baumgarte(self, q) -> np.ndarray:
        """Rows of ``q``: ``-k W^-1 dr/dq`` on the dependent coordinates (``W = dr/dq_dep``)."""
        stab, layout = self.dyn.stabilizer, self.dyn.layout
        out = np.zeros((layout.nq, layout.nq + layout.m))
        coords = list(range(layout.n_all))
        _, d_r = stab.poses.residual_and_jacobian(q, coords)
        step = -stab.gain * np.linalg.solve(d_r[:, stab.dependent], d_r)
        for row, c in zip(step, stab.dependent):
            for k, value in zip(coords, row):
                out[layout.q_of_coord[c], layout.q_of_coord[k]] += value
        return out
