"""simulate(): energy conservation, convergence orders, constraint drift with and without
stabilization, both backends, and typed errors for bad input, stiffness and singularities."""
from __future__ import annotations

import numpy as np
import pytest

from symgen.errors import SingularConfigurationError, SymgenError
from symgen.model import derive
from symgen.simulation import (ConstraintViolationError, SimulationError, SimulationInputError, StateLayout,
                               StiffnessError, builtin_model, scene_variant, simulate)
from symgen.simulation.forcing import SineTorque, SpringTorque

#: the issue's bound on the relative energy drift of a conservative run (DOP853, rtol = atol = 1e-12, 5 s)
ENERGY_TOL = 1e-8
#: loop-closure drift with stabilization
DRIFT_TOL = 1e-9
#: numpy and C backends run the same operations up to rounding
BACKEND_TOL = 1e-12


def _alternating(layout, speed):
    return layout.initial_state(V_m=speed * (-1.0) ** np.arange(layout.m))


@pytest.mark.parametrize("spec, speed", [("chain:n=6", 0.5), ("four_bar", 0.3)])
def test_conservative_run_keeps_energy(spec, speed):
    """No friction (set to zero explicitly), no torque, no contact force, gravity on."""
    model = derive(scene_variant(builtin_model(spec).scene, viscous=0, coulomb=0))
    x0 = _alternating(StateLayout(model), speed)
    traj = simulate(model, 5.0, "DOP853", rtol=1e-12, atol=1e-12, backend="c", x0=x0)
    assert traj.conservative
    assert traj.energy_drift < ENERGY_TOL
    assert np.ptp(traj.potential) > 0.1 * np.max(traj.kinetic) or spec == "four_bar"  # energy really moves
    assert traj.max_drift < DRIFT_TOL


def test_spring_torque_is_conservative_and_its_energy_is_kept():
    model = builtin_model("five_bar")
    traj = simulate(model, 2.0, "DOP853", rtol=1e-12, atol=1e-12, backend="c",
                    tau=SpringTorque(model), x0=_alternating(StateLayout(model), 0.5))
    assert traj.conservative and traj.energy_drift < ENERGY_TOL
    assert np.ptp(traj.kinetic) > 0.5 * np.max(traj.kinetic)       # kinetic <-> spring exchange


def test_friction_or_sine_torque_is_not_conservative():
    arm = builtin_model("arm_on_plane")
    assert simulate(arm, 0.01, "rk4", step=0.005).energy_drift is None
    chain = builtin_model("chain:n=3")
    assert simulate(chain, 0.01, "rk4", step=0.005, tau=SineTorque(chain)).energy_drift is None


def test_convergence_orders_of_the_fixed_step_methods():
    """RK4 error falls 16x per halved step, semi-implicit Euler 2x (within 25 %)."""
    model = builtin_model("chain:n=3")
    x0 = _alternating(StateLayout(model), 1.0)
    ref = simulate(model, 0.5, "DOP853", rtol=1e-13, atol=1e-13, x0=x0, backend="c").final_state
    for method, steps, order in (("rk4", (0.02, 0.01), 4), ("semi_implicit_euler", (0.002, 0.001), 1)):
        err = [np.max(np.abs(simulate(model, 0.5, method, step=h, x0=x0, backend="c").final_state - ref))
               for h in steps]
        assert err[0] / err[1] == pytest.approx(2 ** order, rel=0.25), method


@pytest.mark.parametrize("spec", ["four_bar", "arm_on_plane", "chain:n=6"])
def test_numpy_and_c_backends_give_the_same_trajectory(spec):
    model = builtin_model(spec)
    x0 = _alternating(StateLayout(model), 0.2)
    runs = [simulate(model, 0.2, "rk4", step=0.01, x0=x0, backend=b, tau=SineTorque(model)) for b in ("numpy", "c")]
    assert np.max(np.abs(runs[0].states - runs[1].states)) < BACKEND_TOL


# ---------------------------------------------------------------------------- constraint drift
def _drift(spec, method, stabilization, **kw):
    model = builtin_model(spec)
    x0 = _alternating(StateLayout(model), 0.5)
    return simulate(model, kw.pop("t_end"), method, x0=x0, tau=SpringTorque(model), stabilization=stabilization,
                    energy=False, **kw)


@pytest.mark.parametrize("spec, t_end", [("stewart", 0.2), ("five_bar", 1.0)])
def test_drift_grows_without_stabilization(spec, t_end):
    """Coarse RK4 (h = 0.02 s): projection keeps the loops closed to 1e-13, without it the
    residual grows by orders of magnitude (five_bar: a loop that is nonlinear in the joint angles)."""
    kw = dict(step=0.02, t_end=t_end, backend="numpy" if spec == "stewart" else "c")
    stabilized = _drift(spec, "rk4", "projection", **kw)
    free = _drift(spec, "rk4", "none", **kw)
    assert stabilized.max_drift < DRIFT_TOL
    assert free.max_drift > 100 * max(stabilized.max_drift, 1e-15)
    assert free.drift[-1] > 2 * free.drift[1]                   # and it keeps growing along the run


@pytest.mark.parametrize("spec", ["four_bar", "stewart"])
def test_stabilized_drift_stays_below_bound(spec):
    t_end, backend = (0.2, "numpy") if spec == "stewart" else (2.0, "c")
    for method, kw in (("rk4", dict(step=0.02)), ("semi_implicit_euler", dict(step=0.005)),
                       ("DOP853", dict(rtol=1e-10))):
        traj = _drift(spec, method, "auto", t_end=t_end, backend=backend, **kw)
        assert traj.stabilization == ("baumgarte" if method == "DOP853" else "projection")
        assert traj.max_drift < DRIFT_TOL, (method, traj.max_drift)


def test_four_bar_closure_is_linear_so_runge_kutta_keeps_it():
    """The parallelogram's loop closure is linear in the joint angles (j2 = -j1, j3 = j1 - pi,
    j4 = pi - j1): every Runge-Kutta method preserves linear invariants, so even without
    stabilization its drift stays at round-off -- the reason five_bar shows the growth above."""
    traj = _drift("four_bar", "rk4", "none", step=0.05, t_end=2.0, backend="c")
    assert traj.max_drift < 1e-13


# ---------------------------------------------------------------------------- typed errors
@pytest.fixture(scope="module")
def four_bar():
    return builtin_model("four_bar")


@pytest.mark.parametrize("kwargs, match", [
    (dict(t_end=-1.0), "t_end must be positive"),
    (dict(t_end=float("nan")), "t_end must be positive"),
    (dict(method="euler"), "unknown method 'euler'"),
    (dict(method="rk4", step=0.0), "step must be positive"),
    (dict(method="rk4", step=-0.1), "step must be positive"),
    (dict(method="rk4"), "needs a step size"),
    (dict(method="DOP853", step=0.01), "adaptive"),
    (dict(rtol=0.0), "rtol must be positive"),
    (dict(backend="fortran"), "unknown backend"),
    (dict(stabilization="magic"), "unknown stabilization"),
    (dict(method="RK45", stabilization="projection"), "fixed-step method"),
    (dict(eta_m=lambda t, q, v: np.zeros(3)), "no contact forces"),
])
def test_bad_arguments_are_typed_errors(four_bar, kwargs, match):
    args = dict(t_end=0.1, method="DOP853")
    args.update(kwargs)
    with pytest.raises(SimulationInputError, match=match):
        simulate(four_bar, args.pop("t_end"), args.pop("method"), **args)


def test_tau_of_wrong_shape_names_the_function_and_time(four_bar):
    def my_torque(t, q, v):
        return np.zeros(3)

    with pytest.raises(SimulationInputError, match=r"tau function 'my_torque' returned shape \(3,\) at t = 0"):
        simulate(four_bar, 0.1, "rk4", step=0.01, tau=my_torque)


def test_tau_returning_nan_names_the_function_and_time(four_bar):
    def broken(t, q, v):
        return np.array([np.nan if t > 0.05 else 0.0])

    with pytest.raises(SimulationInputError, match=r"tau function 'broken' returned NaN or infinity at t = 0\.06"):
        simulate(four_bar, 0.1, "rk4", step=0.02, tau=broken)


def test_eta_m_of_wrong_shape_is_a_typed_error():
    arm = builtin_model("arm_on_plane")
    with pytest.raises(SimulationInputError, match=r"eta_m function .* shape \(2,\)"):
        simulate(arm, 0.01, "rk4", step=0.01, eta_m=lambda t, q, v: np.zeros(2))


def test_initial_state_off_the_manifold(four_bar):
    layout = StateLayout(four_bar)
    x0 = layout.initial_state(V_m=[0.3])
    x0[1] += 1e-4                                   # turn the coupler by 0.1 mrad: the loop opens
    with pytest.raises(ConstraintViolationError, match=r"constraint 'closure' is violated by 0\.0001 at the initial"):
        simulate(four_bar, 0.1, "rk4", step=0.01, x0=x0, stabilization="none")
    traj = simulate(four_bar, 0.1, "rk4", step=0.01, x0=x0)       # projected first
    assert traj.max_drift < DRIFT_TOL


def test_explicit_method_on_a_stiff_problem_suggests_radau_or_bdf():
    """Heavy viscous friction on a light chain: eigenvalues near -b / I ~ -1e4 / s."""
    model = derive(scene_variant(builtin_model("chain:n=2").scene, viscous=100))
    x0 = _alternating(StateLayout(model), 1.0)
    with pytest.raises(StiffnessError, match="method='Radau' or method='BDF'") as info:
        simulate(model, 1.0, "RK45", rtol=1e-6, x0=x0, max_rhs_calls=3000, energy=False)
    assert info.value.method == "RK45" and isinstance(info.value, SymgenError)
    implicit = simulate(model, 1.0, "Radau", rtol=1e-6, x0=x0, max_rhs_calls=3000, energy=False)
    assert implicit.rhs_calls < 3000 and np.all(np.isfinite(implicit.states))


def test_fixed_step_divergence_is_a_typed_error_not_nan():
    model = derive(scene_variant(builtin_model("chain:n=2").scene, viscous=100))
    x0 = _alternating(StateLayout(model), 1.0)
    for method in ("rk4", "semi_implicit_euler"):
        with pytest.raises(SimulationError, match=r"non-finite at t = .*take a smaller step.*Radau"):
            simulate(model, 1.0, method, step=0.05, x0=x0, energy=False)


def test_starting_at_the_dead_point_is_a_typed_error(four_bar):
    """The parallelogram folded flat (crank at 0: a change point, [T_u1, T_a1] singular): a typed
    error with the condition number and the time, never NaN."""
    from symgen.math.configuration import Configuration

    flat = Configuration({"j1": 0.0, "j2": 0.0, "j3": -np.pi, "j4": np.pi})
    x0 = StateLayout(four_bar).initial_state(flat, V_m=[1.0])
    for method, kw in (("rk4", dict(step=0.01)), ("DOP853", dict(rtol=1e-8))):
        with pytest.raises(SingularConfigurationError, match=r"singular \(condition number"):
            simulate(four_bar, 0.1, method, x0=x0, **kw)


def test_projection_that_does_not_converge_names_the_matrix_and_its_condition():
    """Newton's projection stopped early (one iteration from far off the manifold): the typed
    error names [T_u1, T_a1] with its actual (finite) condition number and the residual."""
    from symgen.simulation.stabilize import Stabilizer

    model = builtin_model("five_bar")
    stab = Stabilizer(model, max_iter=1)
    q = StateLayout(model).positions(model.reference).copy()
    q[stab.dependent[0]] += 0.3
    with pytest.raises(SingularConfigurationError, match=r"\[T_u1, T_a1\].*Newton did not converge in 1 iter") as err:
        stab.project(q)
    assert np.isfinite(err.value.condition) and err.value.condition >= 1


def test_a_fixed_step_run_needing_more_calls_than_the_budget_is_refused_before_any_step():
    """rk4 takes 4 right-hand-side calls a step: 1 s at 1e-3 s is 4000 calls, above a budget of 1000."""
    from symgen.io.loading import load
    from symgen.simulation.integrators import simulate

    model = derive(load("chain:n=1"))
    with pytest.raises(SimulationInputError, match=r"step 0.001 s over t_end 1 s needs 1e\+03 steps of rk4"):
        simulate(model, 1.0, "rk4", step=1e-3, max_rhs_calls=1000)
    assert simulate(model, 1.0, "rk4", step=1e-2, max_rhs_calls=1000).steps == 100
