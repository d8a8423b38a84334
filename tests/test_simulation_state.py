"""The simulation state: position vectors, quaternion kinematics, the fast kinematics of
:mod:`symgen.simulation.poses` against :mod:`symgen.closure`, and the generated ``joint_rates``."""
from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

import symgen
from symgen.closure import closure_residual, random_consistent_states
from symgen.simulation import Dynamics, StateLayout, Stabilizer, builtin_model, scene_variant
from symgen.simulation.errors import SimulationInputError
from symgen.simulation.poses import Poses
from symgen.simulation.state import quaternion_exp, quaternion_multiply, quaternion_rate
from symgen.codegen.trace import quaternion_matrix

#: central differences with step 1e-6 are accurate to about this
FD_TOL = 1e-8


@pytest.fixture(scope="module")
def stewart():
    return builtin_model("stewart")


@pytest.fixture(scope="module")
def arm():
    return builtin_model("arm_on_plane")


def _hat(w):
    return np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


def test_quaternion_rate_gives_child_frame_angular_velocity():
    """dR/dt = R w^ for dq/dt = 1/2 q (x) (0, w): the code's spherical-joint convention."""
    rng = np.random.default_rng(3)
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    w = rng.normal(size=3)
    eps = 1e-6
    r = lambda v: np.array(quaternion_matrix(*v)) / (v @ v)  # noqa: E731
    qd = quaternion_rate(q, w)
    r_dot = (r(q + eps * qd) - r(q - eps * qd)) / (2 * eps)
    np.testing.assert_allclose(r_dot, r(q) @ _hat(w), atol=FD_TOL)
    assert abs(q @ qd) < 1e-15          # the rate keeps the norm


def test_quaternion_exp_is_the_rotation_by_the_vector():
    v = np.array([0.3, -0.2, 0.5])
    angle = np.linalg.norm(v)
    k = _hat(v / angle)
    rodrigues = np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k
    np.testing.assert_allclose(np.array(quaternion_matrix(*quaternion_exp(v))), rodrigues, atol=1e-15)
    np.testing.assert_allclose(quaternion_multiply(quaternion_exp(v), quaternion_exp(-v)), [1, 0, 0, 0], atol=1e-16)


def test_position_vector_round_trips_through_configuration(stewart):
    layout = StateLayout(stewart)
    cfg, _ = random_consistent_states(stewart, 1, seed=4)[0]
    q = layout.positions(cfg)
    back = layout.configuration(q)
    for name, value in cfg.as_float().positions.items():
        np.testing.assert_allclose(back[name], value, atol=1e-15)
    assert layout.nq == 6 * 3 + 6 * 4 and layout.size == layout.nq + 6


def test_fast_residual_equals_closure_residual_off_the_manifold(stewart, arm):
    rng = np.random.default_rng(5)
    for model in (stewart, arm, symgen.derive(symgen.load("five_bar"))):
        layout, poses = StateLayout(model), Poses(model)
        q = layout.normalized(layout.positions(model.reference) + rng.normal(0, 0.05, layout.nq))
        np.testing.assert_allclose(poses.residual(q), closure_residual(model, layout.configuration(q)),
                                   rtol=0, atol=1e-15)


def test_residual_jacobian_matches_finite_differences(stewart):
    """Exact d r / d q (spherical coordinates as child-frame rotations) at a non-closed state."""
    layout, poses = StateLayout(stewart), Poses(stewart)
    q = layout.normalized(layout.positions(stewart.reference) + np.random.default_rng(6).normal(0, 0.05, layout.nq))
    coords = list(range(layout.n_all))
    jac = poses.residual_jacobian(q, coords)
    eps = 1e-6
    for i in coords:
        rates = np.zeros(layout.n_all)
        rates[i] = 1.0
        fd = (poses.residual(layout.advance(q, rates, eps)) - poses.residual(layout.advance(q, rates, -eps))) / (2 * eps)
        np.testing.assert_allclose(jac[:, i], fd, atol=FD_TOL, err_msg=stewart.tree.coordinates[i].label)


def test_projection_closes_the_loops(stewart):
    stab = Stabilizer(stewart)
    layout = stab.layout
    q = layout.positions(stewart.reference)
    q[layout.scalar_q] += 1e-3                 # every angle and leg length off by 1 mm / 1 mrad
    assert stab.drift(q) > 1e-4
    closed = stab.project(q)
    assert stab.drift(closed) <= 1e-13
    independent = [layout.q_of_coord[c] for c in stewart.partition.independent]
    np.testing.assert_array_equal(closed[independent], q[independent])


def test_joint_rates_keep_every_constraint_satisfied(stewart):
    """T qd_all = 0 from the generated joint_rates: the residual does not change to first order."""
    dyn = Dynamics(stewart, "numpy")
    layout = dyn.layout
    cfg, v_m = random_consistent_states(stewart, 1, seed=8)[0]
    q = layout.positions(cfg)
    rates = dyn.joint_rates(0.0, q, v_m)
    eps = 1e-6
    change = dyn.stabilizer.residual(layout.advance(q, rates, eps)) - dyn.stabilizer.residual(layout.advance(q, rates, -eps))
    assert np.max(np.abs(change)) / (2 * eps) < FD_TOL


def test_kinetic_energy_is_half_qd_mass_qd(arm):
    """1/2 V_m^T M_mm V_m (generated M) equals 1/2 qd^T M_q qd of the dense joint-space model."""
    dyn = Dynamics(arm, "numpy")
    cfg, v_m = random_consistent_states(arm, 1, seed=9)[0]
    d = arm.evaluate(cfg, V_m=v_m)
    kinetic, _ = dyn.energy(dyn.layout.initial_state(cfg, v_m))
    assert kinetic == pytest.approx(0.5 * d.qd @ d.M_q @ d.qd, rel=1e-12)


def test_scene_variant_sets_friction_and_keeps_the_original():
    scene = symgen.load("arm_on_plane")
    plain = scene_variant(scene, viscous=0)
    assert all(j.viscous == 0 for j in plain.joints.values())
    assert any(j.viscous != 0 for j in scene.joints.values())
    sticky = scene_variant(symgen.load("chain:n=2"), viscous="1/2", coulomb=0.25)
    assert {(j.viscous, j.coulomb) for j in sticky.joints.values()} == {(sp.Rational(1, 2),
                                                                          sp.Rational(1, 4))}


def test_bad_state_shapes_are_typed_errors(arm):
    layout = StateLayout(arm)
    with pytest.raises(SimulationInputError, match=r"shape \(9,\)"):
        layout.check_state(np.zeros(5))
    with pytest.raises(SimulationInputError, match="NaN"):
        layout.check_state(np.full(9, np.nan))
    with pytest.raises(SimulationInputError, match="V_m"):
        layout.initial_state(V_m=[1.0])


@pytest.mark.parametrize("module", ["symgen.simulation", "symgen.simulation.state", "symgen.simulation.scenes"])
def test_docstring_examples_run(module):
    import doctest
    import importlib

    result = doctest.testmod(importlib.import_module(module))
    assert result.attempted > 0 and result.failed == 0
