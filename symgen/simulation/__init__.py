"""Forward simulation of model (32) from the generated code.

Public API (everything a caller needs; see each module for details):

* :func:`simulate(model, t_end, method, *, step, rtol, atol, backend, stabilization, gain, tau,
  eta_m, x0, energy, record_every, max_rhs_calls, t_eval, jacobian) <symgen.simulation.integrators.simulate>`
  -> :class:`Trajectory` -- methods ``rk4``, ``semi_implicit_euler`` (fixed step) and ``RK45``,
  ``DOP853``, ``Radau``, ``BDF`` (SciPy ``solve_ivp``; the last two with the generated Jacobian
  on request, :mod:`symgen.simulation.jacobian`);
* :class:`StateLayout` -- the state ``x = [q; V_m]``: ``initial_state(config, V_m)``,
  ``configuration(q)``, ``positions(config)``, quaternion kinematics;
* :class:`Dynamics` -- the right-hand side ``f(t, x)`` (counted), ``energy(x)``;
* :class:`Stabilizer` -- constraint residuals, projection and Baumgarte correction;
* :class:`SpringTorque`, :class:`SineTorque`, :func:`named_torque` -- ready-made torques;
* :func:`builtin_model` (cached ``derive(load(spec))``), :func:`scene_variant` (friction, gravity);
* :func:`work_precision` / :func:`write_report` -- the error-against-run-time study;
* :class:`LagrangeDAE` / :func:`dae_simulate` -- the independent index-1 DAE reference;
* errors: :class:`SimulationError`, :class:`SimulationInputError`, :class:`StiffnessError`,
  :class:`ConstraintViolationError` (all :class:`symgen.errors.SymgenError`).

>>> import symgen
>>> from symgen.simulation import StateLayout, simulate
>>> model = symgen.derive(symgen.load("four_bar"))
>>> x0 = StateLayout(model).initial_state(V_m=[0.5])
>>> traj = simulate(model, 0.1, "rk4", step=0.01, x0=x0)
>>> traj.max_drift < 1e-12
True
"""
import importlib

#: public name -> defining module (imported on first use, so ``symgen --help`` stays fast)
_EXPORTS = {
    "LagrangeDAE": "dae", "dae_simulate": "dae",
    "BACKENDS": "dynamics", "Dynamics": "dynamics", "load_backend": "dynamics",
    "ConstraintViolationError": "errors", "SimulationError": "errors", "SimulationInputError": "errors",
    "StiffnessError": "errors",
    "SineTorque": "forcing", "SpringTorque": "forcing", "named_torque": "forcing",
    "METHODS": "integrators", "simulate": "integrators",
    "builtin_model": "scenes", "scene_variant": "scenes",
    "Stabilizer": "stabilize", "StateLayout": "state", "Trajectory": "trajectory",
    "work_precision": "workprecision", "write_report": "workprecision",
}
__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name in _EXPORTS:
        value = getattr(importlib.import_module(f".{_EXPORTS[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(list(globals()) + list(_EXPORTS))
