"""Every built-in scene rebuilt in Pinocchio from symgen's spanning tree (symgen.oracle.pinocchio_tree):
the tree's inverse dynamics and mass matrix against Pinocchio's rnea and crba, and the constrained
forward dynamics of model (32) against a KKT solve from Pinocchio's crba, nonLinearEffects and frame
Jacobians and, for welds and balls, against Pinocchio's constraintDynamics."""
import numpy as np
import pytest

pytest.importorskip("pinocchio", reason="pin (Pinocchio) is not installed (extra 'oracle')")

from symgen.io.builtin import get_scene  # noqa: E402
from symgen.model import derive  # noqa: E402
from symgen.oracle.pinocchio_check import TOL_CONSTRAINED, TOL_JOINT_SPACE, compare_constrained, constrained_states  # noqa: E402
from symgen.oracle.pinocchio_constrained import (compare_constraint_dynamics, compare_tree,  # noqa: E402
                                                 pinocchio_tree_dynamics, random_tree_states)
from symgen.oracle.pinocchio_model import OracleError  # noqa: E402
from symgen.oracle.pinocchio_tree import constraint_models, maps_to_pinocchio, tree_robot  # noqa: E402

CONSTRAINED = ["four_bar", "five_bar", "stewart", "arm_on_plane", "multi_arm:h=2"]
SCENES = [*CONSTRAINED, "chain:n=6", "general_chain:n=7"]
TREE_STATES = 10
LOOP_STATES = 5


@pytest.fixture(scope="module")
def models():
    cache = {}

    def get(spec):
        if spec not in cache:
            cache[spec] = derive(get_scene(spec))
        return cache[spec]
    return get


def _failed(diffs):
    return [(d.quantity, d.worst, d.tolerance) for d in diffs if not d.passed]


@pytest.mark.parametrize("spec", SCENES)
def test_tree_rnea_and_crba_equal_symgen_tree_dynamics(models, spec):
    model = models(spec)
    robot = tree_robot(model)
    assert robot.model.nv == model.tree.n_coords
    diffs = compare_tree(model, robot, random_tree_states(model, TREE_STATES, seed=3))
    assert len(diffs) == 2 and all(d.tolerance == TOL_JOINT_SPACE for d in diffs)
    assert not _failed(diffs)


@pytest.mark.parametrize("spec", CONSTRAINED)
def test_forward_dynamics_equals_pinocchio_kkt(models, spec):
    model = models(spec)
    diffs = compare_constrained(model, tree_robot(model), constrained_states(model, LOOP_STATES, seed=4))
    names = {d.quantity for d in diffs}
    assert "motion rates dV_m (32)" in names and "loop-closure forces lam (Model.loop_forces)" in names
    assert not _failed(diffs)


@pytest.mark.parametrize("spec", ["multi_arm:h=2", "stewart"])
def test_forward_dynamics_equals_constraint_dynamics(models, spec):
    model = models(spec)
    assert maps_to_pinocchio(model.scene)
    robot = tree_robot(model, drop_massless_spherical_leaves=True)
    diffs = compare_constraint_dynamics(model, robot, constrained_states(model, LOOP_STATES, seed=5))
    assert diffs[0].quantity == "motion rates dV_m (32)" and all(d.tolerance == TOL_CONSTRAINED for d in diffs)
    assert len(diffs) == (2 if model.counts.np == 0 else 1)      # eta_f exists when n_p < n_c
    assert not _failed(diffs)


def test_stewart_sockets_become_balls():
    """Each leg's weld on a massless socket behind a spherical joint is a ball at the joint's centre."""
    model = derive(get_scene("stewart"))
    robot = tree_robot(model, drop_massless_spherical_leaves=True)
    assert robot.model.nv == model.tree.n_coords - 15
    assert [str(c.type).split(".")[-1] for c in constraint_models(robot)] == ["CONTACT_3D"] * 5


def test_spherical_quaternion_is_stored_xyzw(models):
    model = models("stewart")
    robot = tree_robot(model)
    state = random_tree_states(model, 1, seed=1)[0]
    rot = np.asarray(state["config"].positions["s1"], float)
    joint = robot.model.joints[robot.joints["s1"]]
    x, y, z, w = robot.q_vector(state["config"])[joint.idx_q:joint.idx_q + 4]
    # R = I + 2w[v]x + 2[v]x^2 with v = (x, y, z): the (2, 1) entry is 2(yz + wx)
    assert rot[2, 1] == pytest.approx(2 * (y * z + w * x), abs=1e-12)


def test_a_changed_mass_is_detected(models):
    model = models("multi_arm:h=2")
    robot = tree_robot(model)
    jid = robot.joints["a2_j3"]
    inertia = robot.model.inertias[jid]
    inertia.mass *= 1.01
    robot.model.inertias[jid] = inertia
    diffs = compare_tree(model, robot, random_tree_states(model, 3, seed=2))
    assert all(not d.passed for d in diffs)


def test_coordinates_follow_symgen_order(models):
    """Pinocchio adds joints depth first; the map back to symgen's declaration order is a permutation."""
    model = models("five_bar")
    robot = tree_robot(model)
    assert sorted(robot.v_of_coord) == list(range(robot.model.nv))
    state = random_tree_states(model, 1, seed=7)[0]
    ref = pinocchio_tree_dynamics(robot, state["config"], state["qd"], state["qdd"])
    assert ref["M"].shape == (5, 5) and np.allclose(ref["M"], ref["M"].T)


@pytest.mark.parametrize("spec", ["four_bar", "arm_on_plane"])
def test_planar_constraints_have_no_pinocchio_type(models, spec):
    model = models(spec)
    assert not maps_to_pinocchio(model.scene)
    name = next(iter(model.scene.constraints))
    with pytest.raises(OracleError, match=repr(name)):
        constraint_models(tree_robot(model))


def test_check_scene_runs_every_comparison_that_applies(models):
    from symgen.oracle.pinocchio_constrained import check_scene

    diffs = check_scene(models("multi_arm:h=2"), states=3)
    against = {d.against.split(" (")[0] for d in diffs}
    assert {"rnea + friction + springs", "crba", "constraintDynamics"} <= against
    assert not _failed(diffs)
