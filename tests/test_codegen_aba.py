"""Generated forward dynamics by the articulated-body algorithm (symgen.codegen.aba): equal to the
dense model (32) and to Pinocchio's ``aba``; the route chosen by measured operation counts."""
from __future__ import annotations

import json
import pathlib

import numpy as np
import pytest
import yaml

import symgen
from symgen.io.builtin import get_scene
from symgen.codegen.aba import SingularArticulatedInertia
from symgen.codegen.catalogue import build_function
from symgen.codegen.generate import generate, trace_all
from symgen.codegen.reference import position_vector, reference_outputs, reference_states
from symgen.codegen.runtime import call_by_name, load_generated
from symgen.errors import CodegenError
from symgen.model import derive
from symgen.io.scene_yaml import dump_scene, scene_from_dict

from .codegen_util import relative_error
from .urdf_util import needs_examples

TOL = 1e-12
#: Pinocchio's aba against the generated code: both are floating-point recursions
TOL_PINOCCHIO = 1e-10
DATA = pathlib.Path(__file__).parent / "data" / "aba"
FORWARD = ["forward_dynamics", "state_derivative", "joint_accelerations"]
#: trees with a ball joint (root and leaf), prismatic and fixed joints, a massless carrier, viscous
#: and Coulomb friction, rotor inertia, contact forces, motion on a frame
TREES = ["spherical_arm", "ball_pendulum", "prismatic_friction", "frame_motion"]


def _model(spec):
    if spec in TREES:
        return derive(symgen.load(str(DATA / f"{spec}.yaml")))
    return derive(symgen.load(spec))


def _modules(model):
    """NumPy and C modules of the three forward functions, traced by the recursion."""
    lowered = trace_all(model, FORWARD, {"method": "articulated-body"})
    assert all(low.function.metadata["method"] == "articulated-body" for low in lowered)
    return {target: load_generated(model, target, lowered=lowered) for target in ("numpy", "c")}


def _assert_matches_dense_model(spec, states=4):
    model = _model(spec)
    for target, module in _modules(model).items():
        for s in reference_states(model, states, seed=7):
            for function in FORWARD:
                want = reference_outputs(model, function, s)
                for got, (name, value) in zip(call_by_name(module, function, s), want.items(), strict=True):
                    assert relative_error(got, value) < TOL, f"{spec} {target} {function}: {name}"


@pytest.mark.parametrize("n", range(1, 13))
def test_chain_recursion_equals_dense_model(n):
    _assert_matches_dense_model(f"chain:n={n}")


@pytest.mark.parametrize("spec", TREES)
def test_tree_scenes_recursion_equals_dense_model(spec):
    _assert_matches_dense_model(spec)


@needs_examples
def test_ur5_recursion_equals_dense_model():
    _assert_matches_dense_model("ur5")


# ------------------------------------------------------------------ Pinocchio's aba
def _pinocchio_aba_check(model, robot, states=10, seed=3):
    """Worst relative difference of ``dV_m`` and ``qdd_all`` (generated, NumPy and C) against
    Pinocchio's ``aba`` with ``tau - b qd - c sign(qd)`` (Pinocchio leaves friction out)."""
    from symgen.oracle.pinocchio_check import open_chain_states

    pin = robot.pin
    data = robot.model.createData()
    all_idx = robot.v_index([c.label for c in model.tree.coordinates])
    tau_idx = robot.v_index(model.coordinate_names())
    motion_idx = robot.v_index(model.scene.motion.joints)
    rng = np.random.default_rng(seed)
    worst = {}
    for target, module in _modules(model).items():
        for s in open_chain_states(model, states, seed):
            v_m, tau = rng.uniform(-1, 1, model.counts.m), rng.uniform(-1, 1, model.counts.n)
            inputs = dict(q=position_vector(model, s["config"]), V_m=v_m, tau=tau, eta_m=np.zeros(0))
            dv = np.asarray(call_by_name(module, "forward_dynamics", inputs)[0])
            qd_all, qdd_all = (np.asarray(x) for x in call_by_name(module, "joint_accelerations", inputs))
            v, u = np.zeros(robot.model.nv), np.zeros(robot.model.nv)
            v[all_idx] = qd_all
            u[tau_idx] = tau
            u -= robot.damping * v + robot.coulomb * np.sign(v)
            want = pin.aba(robot.model, data, robot.q_vector(s["config"]), v, u).copy()
            assert np.allclose(v[motion_idx], v_m, rtol=0, atol=1e-14)      # V_m are the joint rates
            worst[target] = max(worst.get(target, 0.0), relative_error(dv, want[motion_idx], 1e-300),
                                relative_error(qdd_all, want[all_idx], 1e-300))
    return worst


@needs_examples
@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_generated_recursion_equals_pinocchio_aba(name):
    pytest.importorskip("pinocchio", reason="pin (Pinocchio) is not installed (extra 'oracle')")
    from symgen.oracle import pinocchio_robot

    model = _model(name)
    worst = _pinocchio_aba_check(model, pinocchio_robot(model.scene))
    assert set(worst) == {"numpy", "c"}
    assert max(worst.values()) < TOL_PINOCCHIO, worst


@needs_examples
def test_pinocchio_check_fails_for_a_wrong_model():
    """The comparison can fail: symgen's UR5 with a 1 % heavier forearm against the file's."""
    pytest.importorskip("pinocchio", reason="pin (Pinocchio) is not installed (extra 'oracle')")
    import dataclasses

    import sympy as sp

    from symgen.oracle import pinocchio_robot

    scene = symgen.load("ur5")
    name = "forearm_link" if "forearm_link" in scene.bodies else list(scene.bodies)[3]
    scene.bodies[name] = dataclasses.replace(scene.bodies[name], mass=scene.bodies[name].mass * sp.Rational(101, 100))
    worst = _pinocchio_aba_check(derive(scene), pinocchio_robot(symgen.load("ur5")), states=2)
    assert min(worst.values()) > 1e-5


# ------------------------------------------------------------------ the route chosen
def test_route_with_fewer_operations_is_kept_and_recorded():
    model = derive(get_scene("chain:n=16"))
    fn = build_function(model, "forward_dynamics")
    costs = fn.metadata["method_costs"]
    assert fn.metadata["method"] == "articulated-body" and costs["articulated-body"] < costs["dense"]
    text = generate(model, "numpy", ["forward_dynamics"]).files["ops.json"]
    meta = json.loads(text)["functions"]["forward_dynamics"]
    assert meta["method"] == "articulated-body"
    assert meta["total"] + meta["solve_flops"] == costs["articulated-body"]
    assert meta["factorizations"] == []


def test_chain_switches_to_the_recursion_at_fourteen_links():
    """Measured crossover on chain:n=N (README): the joint-space route, whose mass matrix comes
    from the composite-rigid-body algorithm on grouped inertias and is factored by straight-line
    LDL^T and whose bias forces come from the recursion on grouped inertias, is cheaper from N = 2
    to 13 (N = 1: all three routes tie and the dense one is kept); from N = 14 on the
    articulated-body recursion is; the kept route is always the cheapest. Sampled at both ends
    and on both sides of the crossover."""
    sizes = (1, 2, 3, 6, 12, 13, 14, 15)
    methods = {n: build_function(derive(get_scene(f"chain:n={n}")), "forward_dynamics").metadata
               for n in sizes}
    for meta in methods.values():
        costs = meta["method_costs"]
        assert costs[meta["method"]] == min(costs.values())
    assert len(set(methods[1]["method_costs"].values())) == 1 and methods[1]["method"] == "dense"
    assert all(methods[n]["method"] == "joint-space" for n in sizes if 2 <= n <= 13)
    assert all(methods[n]["method"] == "articulated-body" for n in sizes if n >= 14)


@needs_examples
@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_real_arms_take_the_cheaper_route(name):
    meta = build_function(_model(name), "forward_dynamics").metadata
    assert meta["method_costs"][meta["method"]] == min(meta["method_costs"].values())
    if name == "panda":       # 1625 against 1735: the grouped bias forces tip it
        assert meta["method"] == "joint-space"


def test_forced_dense_route_is_the_old_code():
    model = derive(get_scene("chain:n=4"))
    dense = build_function(model, "forward_dynamics", method="dense")
    assert dense.metadata == {"method": "dense", "method_costs": {"dense": dense.metadata["method_costs"]["dense"]}}
    ops = dense.graph.count(dense.graph.live([a.flat for _, a in dense.outputs]))
    assert ops["factorizations"] == [] and ops["pivot_checks"] == [4]      # M_mm by LDL^T


@pytest.mark.parametrize("spec", ["four_bar", "arm_on_plane"])
def test_scenes_with_constraints_have_no_recursion(spec):
    model = derive(get_scene(spec))
    assert "articulated-body" not in build_function(model, "forward_dynamics").metadata["method_costs"]
    with pytest.raises(CodegenError, match="articulated-body method needs a tree"):
        build_function(model, "forward_dynamics", method="articulated-body")


def test_unknown_method_is_refused():
    with pytest.raises(CodegenError, match="unknown forward-dynamics method 'crba'"):
        build_function(derive(get_scene("chain:n=2")), "forward_dynamics", method="crba")


def test_massless_leaf_falls_back_to_the_mass_matrix_routes():
    """A leaf joint whose body has no mass (and no rotor inertia): its pivot D is the constant 0,
    so the recursion is refused (naming the joint) and a route through the mass matrix is kept."""
    data = yaml.safe_load(dump_scene(get_scene("chain:n=3")))
    data["bodies"]["link2"] = {"mass": 0, "com": [0, 0, 0], "inertia": [0, 0, 0]}
    model = derive(scene_from_dict(data))
    assert "articulated-body" not in build_function(model, "forward_dynamics").metadata["method_costs"]
    with pytest.raises(SingularArticulatedInertia, match="joint 'j2'"):
        build_function(model, "forward_dynamics", method="articulated-body")


def test_coulomb_friction_on_a_ball_joint_is_refused_by_both_routes():
    data = yaml.safe_load((DATA / "ball_pendulum.yaml").read_text())
    data["joints"]["ball"]["friction"] = {"viscous": 0.02, "coulomb": 0.1}
    model = derive(scene_from_dict(data))
    for method in ("articulated-body", "dense", "auto"):
        with pytest.raises(CodegenError, match="Coulomb friction on a spherical joint"):
            build_function(model, "forward_dynamics", method=method)
