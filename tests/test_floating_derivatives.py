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


@pytest.mark.slow
def test_solo12_standing_forward_derivatives_equal_50_digit_differences_along_the_turn():
    """Feet on the ground (``eta_f``, ``n > m``), the Jacobians of the null-space primal
    (``graph-null-space``, the route kept): about a minute."""
    assert _fd_worst("solo12_standing", "forward_dynamics_derivatives") < FD_TOL


# ------------------------------------------------------------------ the state Jacobian, the momentum
def _state_worst(spec_or_model, targets=("numpy",), states=1, seed=2, lowered=None):
    """Worst relative difference of the generated ``state_derivative_jacobian`` from 50-digit
    central differences of the right-hand side in the entries of ``x``, a quaternion's four moved
    off the unit sphere (:func:`symgen.dynamics_jacobians.state_jacobian`, the model API's too)."""
    model = symgen.derive(symgen.load(spec_or_model)) if isinstance(spec_or_model, str) else spec_or_model
    lowered = lowered or trace_all(model, ["state_derivative_jacobian"])
    modules = [load_generated(model, t, lowered=lowered) for t in targets]
    fld = MpField(model.tree.parameters, dps=50)
    worst = 0.0
    for s in reference_states(model, states, seed=seed):
        ref = reference_outputs(model, "state_derivative_jacobian", s, field=fld)
        for module in modules:
            got = call_by_name(module, "state_derivative_jacobian", s)
            for name, g in zip(("dxdot_dx", "dxdot_dtau"), got, strict=True):
                worst = max(worst, relative_error(g, ref[name]))
    return worst


def test_a_ball_wrist_state_jacobian_equals_50_digit_differences_in_the_quaternion_entries():
    """13 x 13: the wrist's four quaternion rows and columns, NumPy and C, two states."""
    assert _state_worst(WRIST, ("numpy", "c"), states=2) < FD_TOL


def test_the_state_check_catches_the_turn_mapped_in_the_parent_frame(monkeypatch):
    """``delta = 2 vec(dp (x) p*)`` (the parent frame's turn) instead of ``2 vec(p* (x) dp)``."""
    from symgen.codegen import forward_derivatives
    from symgen.codegen.tangent import tangent_layout
    from symgen.codegen.trace import position_layout

    right = forward_derivatives.ambient_map

    def parent(b):
        out = right(b)
        q = b.g.input("q", b.inputs[0].size)
        for (_, _, off, size), (_, col, _) in zip(position_layout(b.model), tangent_layout(b.model)):
            if size == 4:
                w, x, y, z = (2 * e for e in q[off:off + 4])
                out[col:col + 3, off:off + 4] = [[-x, w, -z, y], [-y, z, w, -x], [-z, -y, x, w]]
        return out

    monkeypatch.setattr(forward_derivatives, "ambient_map", parent)
    model = symgen.derive(symgen.load(WRIST))
    assert _state_worst(model, lowered=trace_all(model, ["state_derivative_jacobian"])) > 1e3 * FD_TOL


def test_a_radial_change_of_a_quaternion_moves_nothing():
    """The right-hand side reads ``p / |p|``: ``dxdot/dx`` times ``[0; p; 0]`` is zero in every row."""
    model = symgen.derive(symgen.load(WRIST))
    module = load_generated(model, "numpy", lowered=trace_all(model, ["state_derivative_jacobian"]))
    s = reference_states(model, 1, seed=5)[0]
    d_x = call_by_name(module, "state_derivative_jacobian", s)[0]
    radial = np.zeros(d_x.shape[1])
    radial[3:7] = s["q"][3:7]
    assert np.max(np.abs(d_x @ radial)) < 1e-13 * np.max(np.abs(d_x))
    assert np.max(np.abs(d_x[:, 3:7])) > 1e-1


@pytest.mark.slow
def test_space_ur5_state_jacobian_equals_50_digit_differences():
    """A free-floating base (prismatic x, y, z and a quaternion) under a UR5: 25 x 25 (a minute)."""
    assert _state_worst("space_ur5") < FD_TOL


@pytest.mark.extended
def test_stewart_state_jacobian_equals_50_digit_differences():
    """Six ball joints closing the loops: 48 x 48, one state; a minute to trace and two to
    difference, so ``extended`` (not run by CI): ``pytest -m extended``."""
    assert _state_worst("stewart") < FD_TOL


def _momentum_worst(spec_or_model, targets=("numpy",), states=1, lowered=None):
    """Worst relative difference of the generated ``centroidal_momentum_derivatives`` from its
    reference: ``dh_dq`` by 50-digit differences along the turn, the loops re-closed."""
    name = "centroidal_momentum_derivatives"
    model = symgen.derive(symgen.load(spec_or_model)) if isinstance(spec_or_model, str) else spec_or_model
    lowered = lowered or trace_all(model, [name])
    fn = build_function(model, name)
    worst = 0.0
    for s in reference_states(model, states, seed=6):
        want = fn.reference(s)
        for target in targets:
            got = call_by_name(load_generated(model, target, lowered=lowered), name, s)
            worst = max(worst, relative_error(got[0], want["dh_dq"]), relative_error(got[1], want["A_G"]))
    return worst


def test_ball_wrist_momentum_derivatives_equal_50_digit_differences_along_the_turn():
    assert _momentum_worst(WRIST, ("numpy", "c"), states=2) < FD_TOL


def test_the_momentum_check_catches_the_turn_taken_the_wrong_way(monkeypatch):
    from symgen.codegen import tangent

    model = symgen.derive(symgen.load(WRIST))
    right = tangent._cross_unit
    monkeypatch.setattr(tangent, "_cross_unit", lambda k, j: [-c for c in right(k, j)])
    assert _momentum_worst(model, lowered=trace_all(model, ["centroidal_momentum_derivatives"])) > 1e3 * FD_TOL


@pytest.mark.slow
def test_stewart_momentum_derivatives_equal_50_digit_differences_along_the_closure():
    assert _momentum_worst("stewart") < FD_TOL


def test_the_model_api_takes_the_ball_wrist_and_refuses_a_zero_quaternion_by_name():
    """Once refused (the state holds the quaternion), the wrist is now taken in its quaternion's
    entries (tests/test_model_state_jacobian.py checks the values); a zero quaternion is still
    refused, naming the joint, before any difference is taken."""
    model = symgen.derive(symgen.load(WRIST))
    q = position_vector(model, as_configuration(model.reference, model.scene))
    assert q.shape == (7,)
    q[3:7] = 0.0
    with pytest.raises(StateError, match="joint 'wrist'.*zero quaternion"):
        model.state_derivative_jacobian(q, [0] * 6, [0] * 6)
