"""Derivatives with spherical and free joints (:mod:`symgen.codegen.tangent`): ``d/dq`` along the
child-frame turn ``R exp(hat(d))``, one column per velocity coordinate.

* solo12 (free-flyer root) against Pinocchio's ``computeRNEADerivatives`` and
  ``computeABADerivatives`` through the Jacobian of the coordinate map
  (:mod:`tests.floating_derivative_map`, derived there);
* a chain with a ball wrist against Pinocchio's ``JointModelSpherical`` (same coordinates);
* against 50-digit central differences of the dense model along ``q (+) d`` (Rodrigues in ``mp``):
  the ball-wrist chain, Stewart's platform along its loop closure, solo12 standing on its feet;
* planted errors (the turn's sign, a term of the map left out) are caught; what is still refused.
"""
from __future__ import annotations

import pathlib

import numpy as np
import pytest

import symgen
from symgen.codegen.aba import motion_coordinates
from symgen.codegen.catalogue import build_function
from symgen.codegen.generate import trace_all
from symgen.codegen.reference import reference_outputs, reference_states
from symgen.codegen.runtime import call_by_name, load_generated
from symgen.codegen.trace import position_vector
from symgen.errors import CodegenError, StateError
from symgen.math.configuration import as_configuration
from symgen.math.fields import MpField

from .codegen_util import relative_error

pin = pytest.importorskip("pinocchio", reason="pin (Pinocchio) is not installed (extra 'oracle')")
legged = pytest.importorskip("symgen.io.urdf.legged")

from . import floating_derivative_map as fmap  # noqa: E402

WRIST = str(pathlib.Path(__file__).parent / "data" / "derivatives" / "spherical_wrist.yaml")
FUNCTIONS = ["inverse_dynamics_derivatives", "forward_dynamics_derivatives"]
PINOCCHIO_TOL = 1e-10
FD_TOL = 1e-9


@pytest.fixture(scope="module")
def solo12():
    from symgen.io.coordinates import CoordinateMap
    from symgen.io.urdf.examples import example_path

    model = symgen.derive(legged.solo12())
    module = load_generated(model, "numpy", lowered=trace_all(model, FUNCTIONS))
    pmodel = pin.buildModelFromUrdf(str(example_path("solo12")), pin.JointModelFreeFlyer())
    return model, module, pmodel, CoordinateMap.pinocchio(model.scene, pmodel)


def _solo_states(model, count, seed=4):
    """Random solo12 states: base anywhere, joints within +-1, rates, accelerations, forces
    (none on the base), as label -> value."""
    rng = np.random.default_rng(seed)
    labels = [c.label for c in model.tree.coordinates]
    base = next(iter(model.scene.free_joints.values()))
    for _ in range(count):
        positions = {}
        for j in model.scene.joints.values():
            if j.kind.position_is_rotation:
                x = rng.normal(size=4)
                positions[j.name] = x / np.linalg.norm(x)
            elif j.dof:
                positions[j.name] = rng.uniform(-1, 1)
        config = as_configuration(positions, model.scene)
        qd, qdd, tau = (dict(zip(labels, rng.normal(size=len(labels)))) for _ in range(3))
        tau.update({lab: 0.0 for lab in base.velocity_labels})
        yield config, np.asarray(config.positions[base.rotation], float), qd, qdd, tau


def _solo_worst(solo12, count=3, drop=None):
    """Worst relative difference of the generated Jacobians from Pinocchio's, mapped
    (``drop``: a term of the map left out, to show the check depends on it)."""
    model, module, pmodel, cmap = solo12
    labels = [c.label for c in model.tree.coordinates]
    indep = [labels[i] for i in model.partition.independent]
    motion = [labels[i] for i in motion_coordinates(model)]
    p_all, p_ind, p_mot = (cmap.velocity_indices(x) for x in (labels, indep, motion))
    worst = 0.0
    for config, rot, qd, qdd, tau in _solo_states(model, count):
        q_p, _ = cmap.from_symgen(config)
        vec = {}
        for name, values in (("qd", qd), ("qdd", qdd), ("tau", tau)):
            vec[name] = np.zeros(pmodel.nv)
            vec[name][p_all] = [values[lab] for lab in labels]
        s = {"q": position_vector(model, config), "qd": np.array([qd[lab] for lab in indep]),
             "qdd": np.array([qdd[lab] for lab in indep]), "V_m": np.array([qd[lab] for lab in motion]),
             "tau": np.array([tau[lab] for lab in indep])}
        rnea = fmap.rnea_derivatives(pin, pmodel, q_p, rot, vec["qd"], vec["qdd"], drop=drop)
        found = call_by_name(module, "inverse_dynamics_derivatives", s)
        assert s["q"].shape == (pmodel.nq,) and found[0].shape == (pmodel.nv, pmodel.nv)   # 19 entries, 18 columns
        for got, want in zip(found, rnea):
            worst = max(worst, relative_error(got, want[np.ix_(p_ind, p_ind)]))
        aba = fmap.aba_derivatives(pin, pmodel, q_p, rot, vec["qd"], vec["tau"], drop=drop)
        # d/dq columns in scene order (the tangent layout), d/dV_m in motion order, d/dtau independent
        for got, want, cols in zip(call_by_name(module, "forward_dynamics_derivatives", s), aba,
                                   (p_all, p_mot, p_ind)):
            worst = max(worst, relative_error(got, want[np.ix_(p_mot, cols)]))
    return worst


def test_solo12_derivatives_equal_pinocchio_free_flyer_through_the_coordinate_map(solo12):
    assert _solo_worst(solo12) < PINOCCHIO_TOL


def test_the_free_flyer_check_catches_a_missing_term_of_the_map(solo12):
    assert _solo_worst(solo12, count=1, drop="force_turn") > 1e-3       # the map's d(B^T)/dq term
    assert _solo_worst(solo12, count=1, drop="velocity_turn") > 1e-3    # the map's dv_p/dq term


def _wrist_worst(module, model, states=3):
    """Worst relative difference of the ball-wrist chain's Jacobians from Pinocchio's."""
    from symgen.oracle.pinocchio_tree import tree_robot

    robot = tree_robot(model)
    idx = np.ix_(robot.v_of_coord, robot.v_of_coord)
    assert model.partition.independent == tuple(range(6)) and list(motion_coordinates(model)) == list(range(6))
    worst = 0.0
    for s in reference_states(model, states, seed=3):
        q = robot.q_vector(s["config"])
        data = robot.model.createData()
        d_q, d_v, _ = pin.computeRNEADerivatives(robot.model, data, q, robot.v_vector(s["qd"]), robot.v_vector(s["qdd"]))
        mass = np.triu(data.M) + np.triu(data.M, 1).T
        for got, want in zip(call_by_name(module, "inverse_dynamics_derivatives", s), (d_q, d_v, mass)):
            worst = max(worst, relative_error(got, np.asarray(want)[idx]))
        data = robot.model.createData()
        want = pin.computeABADerivatives(robot.model, data, q, robot.v_vector(s["V_m"]), robot.v_vector(s["tau"]))
        minv = np.triu(want[2]) + np.triu(want[2], 1).T
        for got, w in zip(call_by_name(module, "forward_dynamics_derivatives", s), (want[0], want[1], minv)):
            worst = max(worst, relative_error(got, np.asarray(w)[idx]))
    return worst


@pytest.mark.parametrize("target", ["numpy", "c"])
def test_a_ball_wrist_chain_equals_pinocchio_spherical_joint(target):
    model = symgen.derive(symgen.load(WRIST))
    assert _wrist_worst(load_generated(model, target, FUNCTIONS), model) < PINOCCHIO_TOL


def test_the_check_catches_the_turn_taken_the_wrong_way(monkeypatch):
    """Seeded ``R exp(-hat d)``: the rotation columns change sign, Pinocchio's check fails."""
    from symgen.codegen import tangent

    model = symgen.derive(symgen.load(WRIST))
    right = tangent._cross_unit
    monkeypatch.setattr(tangent, "_cross_unit", lambda k, j: [-c for c in right(k, j)])
    assert _wrist_worst(load_generated(model, "numpy", lowered=trace_all(model, FUNCTIONS)), model, states=1) > 1e-3


def _fd_worst(spec_or_model, function, states=1, seed=2):
    """Worst relative difference of the generated NumPy Jacobians from 50-digit central
    differences along ``q (+) d`` (:func:`symgen.codegen.reference.reference_outputs`)."""
    model = symgen.derive(symgen.load(spec_or_model)) if isinstance(spec_or_model, str) else spec_or_model
    module = load_generated(model, "numpy", lowered=trace_all(model, [function]))
    names = [a.name for a, _ in build_function(model, function).outputs]
    fld = MpField(model.tree.parameters, dps=50)
    worst = 0.0
    for s in reference_states(model, states, seed=seed):
        ref = reference_outputs(model, function, s, field=fld)
        for name, got in zip(names, call_by_name(module, function, s)):
            worst = max(worst, relative_error(got, fld.to_float(ref[name]).astype(float)))
    return worst


@pytest.mark.parametrize("function", FUNCTIONS)
def test_a_ball_wrist_chain_equals_50_digit_differences_along_the_turn(function):
    assert _fd_worst(WRIST, function) < FD_TOL


@pytest.mark.slow
def test_stewart_inverse_dynamics_derivatives_equal_50_digit_differences_along_the_closure():
    """Six passive ball joints among the dependent coordinates: ``(d tau / d q_all) P`` with the
    spherical columns along the turn, against differences with the loops re-closed (a minute)."""
    assert _fd_worst("stewart", "inverse_dynamics_derivatives") < FD_TOL


@pytest.mark.extended
def test_solo12_standing_forward_derivatives_equal_50_digit_differences_along_the_turn():
    """Feet on the ground (``eta_f``, ``n > m``): three minutes (50 s to trace, two to difference),
    so ``extended`` (not run by CI): ``pytest -m extended``."""
    assert _fd_worst("solo12_standing", "forward_dynamics_derivatives") < FD_TOL


# ------------------------------------------------------------------ what is still refused
def test_state_derivative_jacobian_and_centroidal_derivatives_refuse_a_spherical_joint_by_name():
    model = symgen.derive(symgen.load(WRIST))
    for name in ("state_derivative_jacobian", "centroidal_momentum_derivatives"):
        with pytest.raises(CodegenError, match="joint 'wrist'.*spherical.*unit-quaternion"):
            build_function(model, name)
    with pytest.raises(StateError, match="joint 'wrist'.*spherical"):
        model.state_derivative_jacobian(model.reference, [0] * 6, [0] * 6)
