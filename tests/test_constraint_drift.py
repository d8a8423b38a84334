"""The constraints' drift ``dT/dt qd_all`` (eq. 6 differentiated, the right-hand side of eq. 11's
``dP/dt qd``) by the outward recursion of :mod:`symgen.dynamics.twists`, which the code generator
traces instead of the jets of ``T``: against 50-digit central differences of ``T(q) qd_all`` along
``q(t) = q + t qd_all`` (revolute scenes: the arm pressing on a plane, two arms welded to one
object), in the exact field against the jets of ``T`` on the Stewart platform (spherical joints),
and planted errors caught. ``qd_all`` need not satisfy the constraints: the identity holds for any
rates. Then the welds' rows of :mod:`symgen.codegen.loop_rows` (linear rows in world axes) and
their drift, exactly against the model's rows with the linear rows turned into world axes."""
from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

import symgen
import symgen.dynamics.twists as twists
from symgen.dynamics.transforms import configuration_transforms
from symgen.kinematics import constants, constraint_matrix, tree_kinematics
from symgen.math.configuration import Configuration, CosSin, rational_rotation
from symgen.math.fields import ExactField, MpField

#: central differences with step 10^-STEP at 50 digits: error O(10^-2 STEP)
STEP = 15
FD_TOL = 1e-20


def _drift(model, fld, config, qd_all):
    tree = model.tree
    transforms = configuration_transforms(tree, constants(tree, fld), fld, config)
    x = twists.body_twists(tree, transforms, qd_all)
    beta = twists.body_drifts(tree, transforms, qd_all, x)
    kin = tree_kinematics(tree, fld, config)
    return np.array(twists.constraint_drift(kin, model.scene.constraints.values(), x, beta), dtype=object)


def _t_times(model, fld, positions, qd_all):
    kin = tree_kinematics(model.tree, fld, Configuration(positions))
    return constraint_matrix(kin, model.scene.constraints.values()).v @ np.array(qd_all, dtype=object)


def _revolute_state(model, fld, seed):
    rng = np.random.default_rng(seed)
    positions, qd_all = {}, [None] * model.tree.n_coords
    for joint in model.tree.joints:
        if not joint.kind.dof:
            continue
        assert joint.kind.dof == 1, "a scene of revolute and prismatic joints"
        positions[joint.name] = fld.const(Fraction(str(round(rng.uniform(-1, 1), 6))))
        qd_all[joint.coords[0]] = fld.const(Fraction(str(round(rng.uniform(-2, 2), 6))))
    return positions, qd_all


def _differenced(spec):
    """``(model, field, positions, qd_all, want)``: a 50-digit state of scene ``spec`` and the
    central difference of ``T(q) qd_all`` along ``q + t qd_all``."""
    model = symgen.derive(symgen.load(spec))
    fld = MpField(model.tree.parameters)
    positions, qd_all = _revolute_state(model, fld, seed=3)
    h = fld.const(10) ** -STEP
    ends = [_t_times(model, fld, {n: positions[n] + s * h * qd_all[model.tree.coordinate_of(n)]
                                  for n in positions}, qd_all) for s in (1, -1)]
    return model, fld, positions, qd_all, (ends[0] - ends[1]) / (2 * h)


@pytest.mark.parametrize("spec", ["arm_on_plane", "multi_arm:h=2"])
def test_drift_is_a_50_digit_difference_of_the_constraint_rows_times_the_rates(spec):
    model, fld, positions, qd_all, want = _differenced(spec)
    got = _drift(model, fld, Configuration(positions), qd_all)
    assert max(abs(x) for x in want) > 1e-2                     # the rows move
    assert max(abs(x) for x in got - want) < FD_TOL


def test_drift_without_the_relative_rotation_term_is_caught(monkeypatch):
    """Planted error: ``(^A X_B) x X_A`` left out (right only for rates that keep a weld, the
    generator's ``qd_all``); the two arms' grasp frames both move, at rates that do not keep the
    weld, so the differences see it."""
    model, fld, positions, qd_all, want = _differenced("multi_arm:h=2")
    tree, config = model.tree, Configuration(positions)
    transforms = configuration_transforms(tree, constants(tree, fld), fld, config)
    x = twists.body_twists(tree, transforms, qd_all)
    beta = twists.body_drifts(tree, transforms, qd_all, x)
    monkeypatch.setattr(twists, "cross_motion", lambda a, b: (0,) * 6)
    got = twists.constraint_drift(tree_kinematics(tree, fld, config), model.scene.constraints.values(), x, beta)
    assert max(abs(g - w) for g, w in zip(got, want)) > 1e-3


def _stewart_state():
    """A rational configuration of the Stewart platform's spanning tree (loops not closed: the
    identity does not need them) and rational rates of every coordinate."""
    model = symgen.derive(symgen.load("stewart"))
    rng = np.random.default_rng(7)
    positions, qd_all = {}, [None] * model.tree.n_coords
    for joint in model.tree.joints:
        if joint.kind.dof == 3:
            positions[joint.name] = np.array(rational_rotation(*(Fraction(int(v), 16) for v in
                                                                  rng.integers(-16, 17, 4))), dtype=object)
        elif joint.kind.rotates:
            positions[joint.name] = CosSin.from_half_tangent(Fraction(int(rng.integers(-9, 10)), 10))
        else:
            positions[joint.name] = Fraction(int(rng.integers(5, 9)), 10)
        for c in joint.coords:
            qd_all[c] = Fraction(int(rng.integers(-20, 21)), 10)
    return model, positions, qd_all


def test_stewart_drift_equals_the_jets_of_t_exactly():
    model, positions, qd_all = _stewart_state()
    fld = ExactField(model.tree.parameters)
    config = Configuration(positions)
    kin = tree_kinematics(model.tree, fld, config, np.array(qd_all, dtype=object))
    want = constraint_matrix(kin, model.scene.constraints.values()).d @ np.array(qd_all, dtype=object)
    got = _drift(model, fld, config, qd_all)
    assert any(x != 0 for x in want)
    assert list(got) == list(want)


def _welded_rows_and_rates(model, positions, qd_all=None):
    """The model's ``T`` (with jets along ``qd_all``) and the code generator's weld rows
    (:mod:`symgen.codegen.loop_rows`) in the exact field, with the world rotations of frames A."""
    from symgen.codegen import loop_rows as lr

    fld = ExactField(model.tree.parameters)
    config = Configuration(positions)
    kin0 = tree_kinematics(model.tree, fld, config)
    rates = None if qd_all is None else np.array(qd_all, dtype=object)
    t_model = constraint_matrix(tree_kinematics(model.tree, fld, config, rates), model.scene.constraints.values())
    t_loop = lr.loop_rows(kin0, model.scene.constraints.values()).v
    return fld, kin0, t_model, t_loop


def _world_axes(kin, constraints, rows):
    """``diag(R_W_A, 1)`` applied to each weld's six rows of ``rows`` (the model's ``T``, A's axes):
    the linear rows in world axes, the angular ones left in A's."""
    out, i = [], 0
    for con in constraints:
        r = kin.frame_pose(con.frame_a)[0].v
        block = rows[i:i + 6]
        out.append(np.concatenate([r @ block[:3], block[3:]]))
        i += 6
    return np.concatenate(out)


def test_stewart_weld_rows_are_the_model_rows_with_linear_rows_in_world_axes_exactly():
    model, positions, _ = _stewart_state()
    _, kin0, t_model, t_loop = _welded_rows_and_rates(model, positions)
    constraints = list(model.scene.constraints.values())
    assert all(len(c.components) == 6 for c in constraints)
    assert (t_loop == _world_axes(kin0, constraints, t_model.v)).all()


def test_stewart_weld_drift_is_the_model_drift_with_linear_rows_in_world_axes_for_completed_rates():
    """``qd_all = P qd`` (eq. 10, exact) keeps the welds at any configuration, closed or not."""
    from symgen import steps
    from symgen.codegen import loop_rows as lr

    model, positions, _ = _stewart_state()
    fld = ExactField(model.tree.parameters)
    kin0 = tree_kinematics(model.tree, fld, Configuration(positions))
    part = model.partition
    cm = steps.constraint_matrix(kin0, model.scene.constraints.values(), part)
    rates = steps.rate_map(fld, steps.constraint_blocks(fld, cm, part), part)
    qd_all = list(steps.all_rates(rates, [Fraction(k + 1, 7) for k in range(model.counts.n)]))
    _, kin0, t_model, _ = _welded_rows_and_rates(model, positions, qd_all)
    want = _world_axes(kin0, model.scene.constraints.values(), t_model.d @ np.array(qd_all, dtype=object))
    transforms = configuration_transforms(model.tree, constants(model.tree, fld), fld, Configuration(positions))
    x = twists.body_twists(model.tree, transforms, qd_all)
    got = lr.loop_drift(kin0, model.scene.constraints.values(), x, twists.body_drifts(model.tree, transforms, qd_all, x))
    assert any(v != 0 for v in want)
    assert list(got) == list(want)


def test_weld_rows_with_b_taken_at_its_own_origin_are_caught(monkeypatch):
    """Planted error: frame B's Jacobian at B's origin instead of A's (the two coincide only where
    the loop is closed; the configuration here is not)."""
    from symgen.codegen import loop_rows as lr

    real = lr.frame_jacobian_world
    monkeypatch.setattr(lr, "frame_jacobian_world", lambda kin, name, point=None: real(kin, name))
    model, positions, _ = _stewart_state()
    _, kin0, t_model, t_loop = _welded_rows_and_rates(model, positions)
    assert (t_loop != _world_axes(kin0, model.scene.constraints.values(), t_model.v)).any()
