"""The mass matrix by the composite-rigid-body algorithm (symgen.dynamics.crba): equal to the dense
reference model (32) on trees with every joint kind, cheaper than one recursion per column, and
chosen by operation count where loop closures make ``P`` dense."""
from __future__ import annotations

import pathlib

import numpy as np
import pytest

import symgen
from symgen.codegen.builder import Builder
from symgen.codegen.reference import reference_outputs, reference_states
from symgen.codegen.runtime import call_by_name, load_generated
from symgen.model import derive

from .codegen_util import relative_error

DATA = pathlib.Path(__file__).parent / "data" / "aba"
#: a ball joint at the root and at a leaf, prismatic and fixed joints, a massless carrier, rotor
#: inertia: every branch of the composite-inertia pass and of the inward force walk
TREES = [str(DATA / f"{name}.yaml") for name in ("spherical_arm", "ball_pendulum", "prismatic_friction",
                                                 "frame_motion")]


def _model(spec):
    return derive(symgen.load(spec))


@pytest.mark.parametrize("spec", TREES + ["chain:n=7", "stewart", "multi_arm:h=2", "five_bar"])
def test_generated_mass_matrix_equals_dense_model(spec):
    model = _model(spec)
    module = load_generated(model, "numpy", ["mass_matrix"])
    for s in reference_states(model, 3, seed=11):
        (got,) = call_by_name(module, "mass_matrix", s)
        assert relative_error(got, reference_outputs(model, "mass_matrix", s)["M"]) < 1e-12, spec


@pytest.mark.parametrize("spec", TREES + ["stewart", "multi_arm:h=2", "four_bar"])
def test_both_routes_agree_at_the_sample_states(spec):
    """The composite-inertia route and the column-by-column recursion trace the same ``M_q``."""
    b = Builder(_model(spec))
    composite, columns = b.mass_by_composite_inertia(), b.mass_by_columns()
    const = b.t.field.const
    got = b.g.sample_values([const(x) for x in composite.flat])
    want = b.g.sample_values([const(x) for x in columns.flat])
    assert np.abs(got - want).max() <= 1e-12 * max(1.0, np.abs(want).max())


def test_chain_mass_matrix_is_far_cheaper_than_a_recursion_per_column():
    """On the benchmark chain the column route repeats an inward pass per joint; the composite
    inertias carry one wrench per pair (measured: 451 against 542 operations at N = 6, 1798 against
    3152 at N = 12, 11 965 against 32 500 at N = 35, the columns' recursion on grouped inertias)."""
    for n in (6, 12, 35):
        b = Builder(_model(f"chain:n={n}"))
        composite = b.operations(b.mass_by_composite_inertia())
        columns = b.operations(b.mass_by_columns())
        assert composite < (0.85 if n == 6 else 0.6 if n == 12 else 0.4) * columns, n


@pytest.mark.parametrize("spec", ["four_bar", "five_bar", "stewart", "multi_arm:h=2"])
def test_loop_closures_keep_the_cheaper_route(spec):
    b = Builder(_model(spec))
    kept = b.operations(b.mass_in_joint_space())
    assert kept == min(b.operations(b.mass_by_composite_inertia()), b.operations(b.mass_by_columns()))


def test_a_tree_with_motion_on_joints_computes_no_body_jacobian():
    """Generation time: the body Jacobians (``6 x N`` each, ``O(N^2)`` in all) are computed on first
    use, and the joint-space functions of a chain with motion on joints read none of them; a frame
    that is read costs its branch only."""
    b = Builder(_model("chain:n=8"))
    b.mass(b.t.task_matrix())
    kin = b.t.kinematics()
    assert kin.jacobian._done == {}
    kin.jacobian[3]
    assert sorted(kin.jacobian._done) == [0, 1, 2, 3]
