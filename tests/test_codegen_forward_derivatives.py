"""The generated ``forward_dynamics_derivatives`` and ``state_derivative_jacobian`` (NumPy and C)
against 50-digit central differences of the dense model (:mod:`symgen.dynamics_jacobians`), at ten
random loop-closed states per scene; along the loop closure through ``P`` of eq. (10); against
Pinocchio's ``computeABADerivatives``; the route choice and the refusals."""
from __future__ import annotations

import dataclasses
import os
import pathlib

import numpy as np
import pytest
import sympy as sp

import symgen
from symgen.closure import refine_closure
from symgen.codegen.catalogue import ON_REQUEST, build_function
from symgen.codegen.generate import trace_all
from symgen.codegen.reference import reference_states
from symgen.codegen.runtime import call_by_name, load_generated
from symgen.dynamics_jacobians import derivatives
from symgen.errors import CodegenError, StateError
from symgen.math.configuration import Configuration
from symgen.math.fields import MpField
from symgen.model_solves import solve_forward

from .codegen_util import relative_error
from .urdf_util import needs_examples

FUNCTIONS = ["forward_dynamics_derivatives", "state_derivative_jacobian"]
#: generated Jacobians against 50-digit central differences / against Pinocchio
FD_TOL = 1e-9
PINOCCHIO_TOL = 1e-9
#: states per scene in the suite (the 10-state runs of the issue: ``SYMGEN_FD_STATES=10``)
STATES = int(os.environ.get("SYMGEN_FD_STATES", "3"))
FAST = ["chain:n=6", "four_bar", "five_bar"]
#: 2 (nq + m) + 1 dense evaluations at 50 digits per state: a minute (arm_on_plane) to six
#: (multi_arm:h=2, marked ``extended``: ``pytest -m extended``) per state
SLOW = ["arm_on_plane", pytest.param("multi_arm:h=2", marks=pytest.mark.extended)]
SLOW_STATES = int(os.environ.get("SYMGEN_FD_STATES", "1"))


def _modules(spec):
    model = symgen.derive(symgen.load(spec))
    lowered = trace_all(model, FUNCTIONS)
    return model, {t: load_generated(model, t, lowered=lowered) for t in ("numpy", "c")}


def _reference(model, s):
    """The 50-digit Jacobians at state ``s`` (float inputs taken exactly), rounded to float, for
    both functions from one set of differences."""
    fld = MpField(model.tree.parameters, dps=50)
    both = derivatives(model, s["q"], s["V_m"], s["tau"], s["eta_m"], fld, forward=True, state=True)
    return {k: fld.to_float(v) for k, v in both.items()}


def _check_scene(spec, states=STATES):
    model, modules = _modules(spec)
    names = {name: [a.name for a, _ in build_function(model, name).outputs] for name in FUNCTIONS}
    worst = 0.0
    for s in reference_states(model, states, seed=17):
        want = _reference(model, s)
        for target, module in modules.items():
            for name in FUNCTIONS:
                for out, got in zip(names[name], call_by_name(module, name, s), strict=True):
                    err = relative_error(got, want[out])
                    assert err < FD_TOL, f"{spec} {target} {name}.{out}: {err:.3g}"
                    worst = max(worst, err)
    return worst


@pytest.mark.parametrize("spec", FAST)
def test_generated_jacobians_equal_50_digit_central_differences(spec):
    assert _check_scene(spec) < FD_TOL


@needs_examples
@pytest.mark.slow
@pytest.mark.parametrize("spec", ["ur5", "panda"])
def test_generated_jacobians_of_real_arms_equal_50_digit_central_differences(spec):
    assert _check_scene(spec, min(STATES, 2)) < FD_TOL


@pytest.mark.slow
@pytest.mark.parametrize("spec", SLOW)
def test_generated_jacobians_of_heavy_scenes_equal_50_digit_central_differences(spec):
    assert _check_scene(spec, SLOW_STATES) < FD_TOL


def test_the_check_catches_a_planted_error():
    """The same comparison with the generated code of a chain whose third link is 1 % heavier
    than the reference's fails by far more than the tolerance."""
    scene = symgen.load("chain:n=6")
    model = symgen.derive(scene)
    name = list(scene.bodies)[2]
    scene.bodies[name] = dataclasses.replace(scene.bodies[name], mass=scene.bodies[name].mass * sp.Rational(101, 100))
    wrong = load_generated(symgen.derive(scene), "numpy", ["forward_dynamics_derivatives"])
    s = reference_states(model, 1, seed=17)[0]
    got = call_by_name(wrong, "forward_dynamics_derivatives", s)[0]
    assert relative_error(got, _reference(model, s)["ddV_m_dq"]) > 1e3 * FD_TOL


@pytest.mark.parametrize("spec", ["four_bar", "five_bar"])
def test_times_p_it_is_the_derivative_along_the_loop_closure(spec):
    """``ddV_m_dq P`` (``P`` the rates of every joint per independent rate, eq. 10) equals 50-digit
    differences in which the independent coordinate moves and the loop is re-closed."""
    model = symgen.derive(symgen.load(spec))
    module = load_generated(model, "numpy", ["forward_dynamics_derivatives", "joint_rates"])
    fld = MpField(model.tree.parameters, dps=50)
    h = fld.const(10) ** -20
    for s in reference_states(model, 3, seed=4):
        d_q = call_by_name(module, "forward_dynamics_derivatives", s)[0]
        p = np.array([call_by_name(module, "joint_rates", {**s, "V_m": e})[0] for e in np.eye(model.counts.m)]).T
        names = [j.name for j in model.tree.joints if j.coords]
        base = refine_closure(model, {n: fld.const(v) for n, v in zip(names, s["q"])}, fld)
        cols = []
        for coord in model.partition.independent:
            joint = model.tree.coordinates[coord].joint
            ends = [refine_closure(model, {**base, joint: base[joint] + k * h}, fld) for k in (1, -1)]
            dv = [solve_forward(model.evaluate(Configuration(e), V_m=s["V_m"], field=fld), s["tau"])[0] for e in ends]
            cols.append(fld.to_float((dv[0] - dv[1]) / (2 * h)))
        # motion on the independent joints: V_m are the independent rates, so P = d qd_all / d V_m
        assert relative_error(d_q @ p, np.array(cols).T) < FD_TOL


# ------------------------------------------------------------------ Pinocchio
def _pinocchio_worst(model, robot, module, states=10, seed=5):
    """Worst relative difference of ``ddV_m_dq``, ``ddV_m_dV_m``, ``ddV_m_dtau`` against
    Pinocchio's ``computeABADerivatives`` with ``u = tau - b v`` (Pinocchio leaves viscous friction
    out, so ``d/dv`` gains ``-Minv b``); motion on joints, so ``V_m`` are the joint rates."""
    pin = robot.pin
    idx = robot.v_of_coord
    rng = np.random.default_rng(seed)
    worst = 0.0
    for s in reference_states(model, states, seed=seed):
        v, u = np.zeros(robot.model.nv), np.zeros(robot.model.nv)
        v[idx] = s["V_m"]
        u[idx] = s["tau"] = rng.uniform(-1, 1, model.counts.n)
        u -= robot.damping * v
        data = robot.model.createData()
        d_q, d_v, minv = (np.asarray(x).copy() for x in
                          pin.computeABADerivatives(robot.model, data, robot.q_vector(s["config"]), v, u))
        d_v -= minv * robot.damping[None, :]
        got = call_by_name(module, "forward_dynamics_derivatives", s)
        for g, w in zip(got, (d_q, d_v, minv)):
            worst = max(worst, relative_error(g, w[np.ix_(idx, idx)]))
    return worst


@pytest.mark.parametrize("spec", ["chain:n=6"] + [pytest.param(r, marks=needs_examples) for r in ("ur5", "panda")])
def test_generated_jacobians_equal_pinocchio_aba_derivatives(spec):
    pytest.importorskip("pinocchio", reason="pin (Pinocchio) is not installed (extra 'oracle')")
    from symgen.oracle.pinocchio_tree import tree_robot

    model = symgen.derive(symgen.load(spec))
    assert model.scene.motion.joints == tuple(c.joint for c in model.tree.coordinates)
    module = load_generated(model, "c", ["forward_dynamics_derivatives"])
    assert _pinocchio_worst(model, tree_robot(model), module) < PINOCCHIO_TOL


def test_pinocchio_check_fails_for_a_heavier_link():
    pytest.importorskip("pinocchio", reason="pin (Pinocchio) is not installed (extra 'oracle')")
    from symgen.oracle.pinocchio_tree import tree_robot

    scene = symgen.load("chain:n=6")
    name = list(scene.bodies)[3]
    scene.bodies[name] = dataclasses.replace(scene.bodies[name], mass=scene.bodies[name].mass * sp.Rational(101, 100))
    model = symgen.derive(symgen.load("chain:n=6"))
    module = load_generated(symgen.derive(scene), "numpy", ["forward_dynamics_derivatives"])
    assert _pinocchio_worst(model, tree_robot(model), module, states=2) > 1e-5


# ------------------------------------------------------------------ routes, catalogue, refusals
#: a four-bar with every joint driven (operational eta_f, friction, a spring, contact forces), where
#: the null-space primal applies with eta_f
DRIVEN = str(pathlib.Path(__file__).parent / "data" / "null_space" / "driven_four_bar.yaml")


@pytest.mark.parametrize("spec", ["chain:n=3", "four_bar", "five_bar", DRIVEN, "arm_on_plane"])
def test_every_route_gives_the_same_jacobians(spec):
    from symgen.codegen.forward_derivatives import applicable_routes

    model = symgen.derive(symgen.load(spec))
    s = reference_states(model, 1, seed=2)[0]
    results = {}
    for route in applicable_routes(model):
        module = load_generated(model, "numpy", lowered=trace_all(model, ["forward_dynamics_derivatives"],
                                                                  {"method": route}))
        results[route] = call_by_name(module, "forward_dynamics_derivatives", s)
    first = next(iter(results.values()))
    for route, got in results.items():
        for a, b in zip(got, first, strict=True):
            assert relative_error(a, b) < 1e-12, route


@pytest.mark.parametrize("spec", ["arm_on_plane", "multi_arm:h=1", "multi_arm:h=2"])
def test_the_task_rows_by_recursion_equal_the_rows_times_the_rates(spec):
    """``Tracer.task_motion``: ``A qd`` and ``A qdd + dA/dt qd`` by the recursion of the body twists
    and accelerations equal the task matrix's entries times the rates, and its drift
    (``task_bias_of_rates``, the other path); the joint forces of the constraints' wrenches
    (``Tracer.constraint_wrenches``, in the recursion's body frames) equal ``A^T [0; eta_f]`` by
    the entries -- at the sample states of the graph, arbitrary rates and constraint forces."""
    from symgen.codegen.builder import Builder

    b = Builder(symgen.derive(symgen.load(spec)))
    g, t = b.g, b.t
    qd_all, qdd_all = g.input("rates", t.tree.n_coords), g.input("accelerations", t.tree.n_coords)
    a = t.task_matrix()
    order = [t.part.column(c) for c in range(t.tree.n_coords)]       # A's columns in qd order
    qd = [qd_all[order.index(k)] for k in range(t.n)]
    qdd = [qdd_all[order.index(k)] for k in range(t.n)]
    want_v = list(a @ np.array(qd, dtype=object))
    want_a = [x + y for x, y in zip(a @ np.array(qdd, dtype=object),
                                    t.task_bias_of_rates(qd_all, [0] * t.tree.n_coords))]
    eta_f = g.input("eta_f", t.n - t.m)
    zero = [0] * t.tree.n_coords
    want_f = list(a.T @ np.array([0] * t.m + eta_f, dtype=object)) if eta_f else []
    got_f = t.joint_forces(zero, zero, gravity=False, wrenches=t.constraint_wrenches(eta_f)) if eta_f else []
    got = g.sample_values(t.task_motion(qd_all) + t.task_motion(qd_all, qdd_all) + got_f)
    want = g.sample_values(want_v + want_a + want_f)
    assert np.max(np.abs(got - want)) < 1e-12 * max(1.0, np.max(np.abs(want)))
    assert np.max(np.abs(want)) > 1e-3


def test_the_nested_route_equals_the_implicit_one_on_two_arms_with_a_fifth_fewer_operations():
    """``multi_arm:h=2``: the nested route (the dependent rates and accelerations differentiated
    through the recursion, rates held) gives the implicit route's Jacobians (checked against the
    50-digit differences by the extended suite and against Pinocchio by the benchmark) at three
    states, generated NumPy, with at least a fifth fewer operations (the route kept, over every
    route: ``benchmarks/derivative_ops.md``; the guide's figures test ties the two)."""
    from symgen.codegen.generate import operation_counts

    model = symgen.derive(symgen.load("multi_arm:h=2"))
    results, ops = {}, {}
    for route in ("implicit-dense-reverse", "nested-dense-reverse"):
        options = {"method": route}
        ops[route] = operation_counts(model, ["forward_dynamics_derivatives"], options)["forward_dynamics_derivatives"]
        module = load_generated(model, "numpy", lowered=trace_all(model, ["forward_dynamics_derivatives"], options))
        results[route] = [call_by_name(module, "forward_dynamics_derivatives", s)
                          for s in reference_states(model, 3, seed=5)]
    for old, new in zip(results["implicit-dense-reverse"], results["nested-dense-reverse"], strict=True):
        for a, b in zip(old, new, strict=True):
            assert relative_error(b, a) < 1e-12
    assert ops["nested-dense-reverse"]["total"] < 0.8 * ops["implicit-dense-reverse"]["total"]


def test_the_nested_routes_equal_the_implicit_one_with_spherical_joints_contact_and_springs():
    """A scene with a spherical wrist and a prismatic joint, motion on a frame and a joint, a
    two-component constraint to a tilted world frame, contact forces, a spring, friction and a
    rotor inertia: the nested routes' Jacobians (as traced, at the graph's sample positions, which
    need not close the loop: the three routes are the same function of ``q``) equal the implicit
    route's."""
    from symgen.codegen.builder import Builder
    from symgen.codegen.forward_derivatives import _jacobians, nested_applies

    scene = symgen.load(str(pathlib.Path(__file__).parent / "data" / "derivatives" / "spherical_plane_contact.yaml"))
    model = symgen.derive(scene, check_reference=False)
    assert nested_applies(model)
    values = {}
    for route in ("implicit-dense", "nested-dense", "nested-dense-reverse"):
        b = Builder(model)
        _, _, _, d_dv, d_eta, _ = _jacobians(b, route)
        values[route] = b.g.sample_values(list(np.asarray(d_dv).flat) + list(np.asarray(d_eta).flat))
    want = values["implicit-dense"]
    scale = np.max(np.abs(want), axis=1, keepdims=True)
    for route in ("nested-dense", "nested-dense-reverse"):
        assert np.max(np.abs(values[route] - want) / scale) < 1e-8, route


def test_a_held_negation_holds_its_operand():
    """The graph records ``a + (-b)`` as ``a - b``: a held (or seeded) node ``-b`` is read through
    ``b``, so the sweeps hold ``b`` too (seed it negated); an operand that is one of the columns,
    or is held and seeded at once, is refused."""
    from symgen.codegen.derivatives import differentiate
    from symgen.codegen.graph import Graph
    from symgen.codegen.reverse import differentiate_reverse

    g = Graph()
    x, y = g.input("x", 2)
    b = g.mul(x, g.func("sin", x))            # b(x)
    h = g.neg(b)                              # the held value -b
    out = g.add(y, h)                         # recorded as y - b: reads b, not h
    assert g._node(out).op == "sub"
    for sweep in (differentiate, differentiate_reverse):
        jac = sweep(g, np.array([out], dtype=object), [x, y], held=[h])
        assert g._node(jac[0, 0]).is_const and g._node(jac[0, 0]).value == 0
        seeded = sweep(g, np.array([out], dtype=object), [x, y, None], seeds={h: {2: g.const(1)}})
        assert g._node(seeded[0, 2]).value == 1 and g._node(seeded[0, 0]).value == 0
    z = g.neg(x)                              # held -x with x a column: refused, not silently kept
    with pytest.raises(CodegenError, match="a column"):
        differentiate(g, np.array([g.add(y, z)], dtype=object), [x, y], held=[z])
    with pytest.raises(CodegenError, match="held and seeded"):
        differentiate(g, np.array([out], dtype=object), [x, y, None], held=[h], seeds={b: {2: g.const(1)}})


def test_the_joint_space_route_takes_the_inverse_mass_matrix_as_one_triangle(monkeypatch):
    """On a tree with motion on its joints ``d dV_m / d tau = M^-1`` is symmetric: the joint-space
    route mirrors its lower triangle (each column's back substitution stops at the diagonal), so
    it costs fewer operations than the same route with the whole inverse, gives the same values,
    and the generated block is symmetric bit for bit."""
    from symgen.codegen import forward_derivatives
    from symgen.codegen.generate import operation_counts

    model = symgen.derive(symgen.load("chain:n=6"))
    s = reference_states(model, 1, seed=4)[0]
    route = {"method": "implicit-joint-space-reverse"}

    def run():
        ops = operation_counts(model, ["forward_dynamics_derivatives"], route)["forward_dynamics_derivatives"]
        module = load_generated(model, "numpy", lowered=trace_all(model, ["forward_dynamics_derivatives"], route))
        return ops["total"], call_by_name(module, "forward_dynamics_derivatives", s)

    mirrored_ops, mirrored = run()
    monkeypatch.setattr(forward_derivatives, "_mirror_inverse", lambda block: None)
    whole_ops, whole = run()
    inverse = np.asarray(mirrored[2])
    assert np.array_equal(inverse, inverse.T)
    assert mirrored_ops < whole_ops - 50
    for a, b in zip(mirrored, whole, strict=True):
        assert relative_error(a, b) < 1e-12


def test_a_route_beyond_the_straight_line_budget_gives_way_to_one_within():
    """``chain:n=32``'s counts (operations, operations + library flops): the articulated-body route
    is all straight line (242k), the joint-space one leaves its 32 x 32 ``M`` to the library LU
    (102k + 221k flops). The second is kept though it counts more; without the budget, or with
    both routes within it or both beyond, the count decides."""
    from symgen.codegen.forward_derivatives import STRAIGHT_LINE_BUDGET, cheapest

    n32 = {"implicit-articulated-body": (241994, 241994), "implicit-joint-space": (101989, 322490)}
    assert 101989 <= STRAIGHT_LINE_BUDGET < 241994
    assert cheapest(n32) == "implicit-joint-space"
    assert cheapest({r: (1000, c) for r, (_, c) in n32.items()}) == "implicit-articulated-body"
    assert cheapest({r: (10**6, c) for r, (_, c) in n32.items()}) == "implicit-articulated-body"
    assert cheapest({"implicit-dense": (5, 7), "implicit-joint-space": (5, 7)}) == "implicit-dense"   # tie: ROUTES order


def test_choose_keeps_the_route_within_the_budget(monkeypatch):
    """The route choice itself applies the rule: two real routes of ``chain:n=2``, given
    chain:n=32's counts, give the joint-space one, recorded with the costs it was chosen on."""
    from symgen.codegen import forward_derivatives
    from symgen.codegen.builder import Function

    model = symgen.derive(symgen.load("chain:n=2"))
    routes = ["implicit-articulated-body", "implicit-joint-space"]
    n32 = {"implicit-articulated-body": (241994, 0), "implicit-joint-space": (101989, 220501)}
    route_of = {}

    def trace(route):
        built = build_function(model, "forward_dynamics_derivatives", method=route)
        fn = Function(**{k: v for k, v in vars(built).items() if k in Function.__dataclass_fields__})
        route_of[id(fn)] = route
        return fn

    real = forward_derivatives.traced_counts

    def counts(fn):                      # the traces inside build_function count for real
        if id(fn) not in route_of:
            return real(fn)
        total, flops = n32[route_of[id(fn)]]
        return {"total": total, "solve_flops": flops}

    monkeypatch.setattr(forward_derivatives, "applicable_routes", lambda m: routes)
    monkeypatch.setattr(forward_derivatives, "traced_counts", counts)
    chosen = forward_derivatives.choose(model, trace)
    assert chosen.metadata == {"method": "implicit-joint-space",
                               "method_costs": {"implicit-articulated-body": 241994, "implicit-joint-space": 322490}}


def test_on_request_with_the_route_recorded():
    from symgen.codegen.generate import operation_counts

    assert set(FUNCTIONS) <= set(ON_REQUEST)
    model = symgen.derive(symgen.load("chain:n=6"))
    ops = operation_counts(model, FUNCTIONS)
    for name in FUNCTIONS:
        assert ops[name]["method"] == "implicit-joint-space-reverse"   # the adjoint sweep of the explicit partials
        assert ops[name]["method_costs"]["implicit-joint-space-reverse"] == min(ops[name]["method_costs"].values())


def test_a_route_that_does_not_apply_is_refused():
    model = symgen.derive(symgen.load("four_bar"))
    with pytest.raises(CodegenError, match="route 'graph-articulated-body' does not apply"):
        build_function(model, "forward_dynamics_derivatives", method="graph-articulated-body")


def test_the_model_api_refuses_a_state_of_the_wrong_length_and_a_float_field():
    """Spherical joints are taken (in the state's quaternion entries, as the generated function
    takes them: tests/test_model_state_jacobian.py); a ``q`` without Stewart's 6 x 4 quaternion
    entries is refused with the layout before any difference is taken."""
    model = symgen.derive(symgen.load("stewart"))
    with pytest.raises(StateError, match=r"must hold \d+ real numbers.*\(w, x, y, z\)"):
        model.state_derivative_jacobian(np.zeros(model.counts.n), [0] * model.counts.m, [0] * model.counts.n)
    chain = symgen.derive(symgen.load("chain:n=2"))
    with pytest.raises(StateError, match="extended-precision"):
        chain.forward_dynamics_derivatives(chain.reference, [0, 0], [0, 0], field="float")


# ------------------------------------------------------------------ bytes and run-time checks
def test_generated_files_are_the_same_bytes_twice():
    from symgen.codegen.generate import generate

    model = symgen.derive(symgen.load("chain:n=3"))
    first, second = (generate(model, "c", FUNCTIONS).files for _ in range(2))
    assert first == second


@pytest.mark.parametrize("target", ["numpy", "c"])
def test_an_overflow_raises_the_typed_error_naming_the_function(target):
    model = symgen.derive(symgen.load("four_bar"))
    module = load_generated(model, target, FUNCTIONS)
    q = reference_states(model, 1, seed=1)[0]["q"]
    for name in FUNCTIONS:
        with np.errstate(all="ignore"), pytest.raises(module.NonFiniteOutputError, match=name):
            getattr(module, name)(q, [1e155], [1.0])


# ------------------------------------------------------------------ the model's own Jacobians
def test_the_model_api_agrees_across_precisions():
    model = symgen.derive(symgen.load("four_bar"))
    s = reference_states(model, 1, seed=6)[0]
    fine = model.forward_dynamics_derivatives(s["config"], s["V_m"], s["tau"])
    coarse = model.forward_dynamics_derivatives(s["config"], s["V_m"], s["tau"], field="mp:40")
    assert set(fine) == {"ddV_m_dq", "ddV_m_dV_m", "ddV_m_dtau"}
    for name in fine:
        assert relative_error(MpField().to_float(coarse[name]), MpField().to_float(fine[name])) < 1e-12


def test_on_a_chain_the_position_rows_of_the_state_jacobian_are_the_identity_in_v_m():
    """Motion on joints: ``dq/dt = V_m``, so ``d qdot / dq = 0`` and ``d qdot / dV_m = 1``."""
    model = symgen.derive(symgen.load("chain:n=3"))
    s = reference_states(model, 1, seed=6)[0]
    jac = model.state_derivative_jacobian(s["config"], s["V_m"], s["tau"])
    top = MpField().to_float(jac["dxdot_dx"][:3])
    np.testing.assert_allclose(top, np.hstack([np.zeros((3, 3)), np.eye(3)]), atol=1e-15)
    np.testing.assert_allclose(MpField().to_float(jac["dxdot_dtau"][:3]), np.zeros((3, 3)), atol=0)


def test_along_the_closure_they_equal_pinocchio_constraint_dynamics_derivatives():
    """The MJCF four-bar and its Pinocchio ``CONTACT_3D`` twin. Pinocchio differentiates the joint
    accelerations in ``(q, v)`` of every joint; symgen in ``(q, V_m)`` with ``v = P Omega V_m``
    (``joint_rates``). Along the manifold's tangent ``q' = P Omega e`` with ``V_m`` held, Pinocchio's
    total derivative is ``ddq_dq q' + ddq_dv v'``, ``v' = (d qd_all / dq) q'`` (the generated state
    Jacobian's position rows); in ``V_m``, ``ddq_dv P Omega``; in ``tau``, its actuated column."""
    pin = pytest.importorskip("pinocchio", reason="pin (Pinocchio) is not installed (extra 'oracle')")
    from symgen.codegen.reference import position_vector
    from symgen.oracle.pinocchio_check import constrained_states

    from .pinocchio_contact import four_bar_contact

    model, robot, (data, models, datas) = four_bar_contact(pin, pin.ReferenceFrame.LOCAL)
    module = load_generated(model, "numpy", FUNCTIONS + ["joint_rates"])
    labels = [c.label for c in model.tree.coordinates]
    motion = [labels.index(j) for j in model.scene.motion.joints]
    actuated = [labels.index(j) for j in model.coordinate_names()]
    idx, nq = robot.v_of_coord, len(labels)
    settings = pin.ProximalSettings(1e-14, 1e-10, 200)
    for state in constrained_states(model, 4, seed=3):
        s = dict(q=position_vector(model, state["config"]), V_m=np.asarray(state["V_m"], float),
                 tau=np.asarray(state["tau"], float), eta_m=np.zeros(0))
        d_q, d_v, d_t = call_by_name(module, "forward_dynamics_derivatives", s)
        rows = call_by_name(module, "state_derivative_jacobian", s)[0][:nq, :nq]
        tangent = np.array([call_by_name(module, "joint_rates", {**s, "V_m": e})[0]
                            for e in np.eye(model.counts.m)]).T
        v, tau = np.zeros(robot.model.nv), np.zeros(robot.model.nv)
        v[idx] = call_by_name(module, "joint_rates", s)[0]
        tau[robot.v_index(model.coordinate_names())] = s["tau"]
        pin.constraintDynamics(robot.model, data, robot.q_vector(state["config"]), v, tau, models, datas, settings)
        pin.computeConstraintDynamicsDerivatives(robot.model, data, models, datas, settings)
        dq, dv, dt = (np.asarray(x)[np.ix_(idx, idx)] for x in (data.ddq_dq, data.ddq_dv, data.ddq_dtau))
        assert relative_error(d_q @ tangent, dq[motion] @ tangent + dv[motion] @ rows @ tangent) < PINOCCHIO_TOL
        assert relative_error(d_v, dv[motion] @ tangent) < PINOCCHIO_TOL
        assert relative_error(d_t, dt[np.ix_(motion, actuated)]) < PINOCCHIO_TOL


def test_the_reference_s_columns_follow_the_generated_q_not_the_tree():
    """``multi_arm`` orders its spanning tree arm by arm interleaved; ``q`` is in scene order."""
    from symgen.codegen.trace import position_layout
    from symgen.dynamics_jacobians import state_layout

    model = symgen.derive(symgen.load("multi_arm:h=2"))
    assert [j.name for j in model.tree.joints if j.coords] != [name for name, *_ in position_layout(model)]
    assert state_layout(model) == [(name, off, size) for name, _, off, size in position_layout(model)]
    stewart = symgen.derive(symgen.load("stewart"))          # quaternions: the same four entries each
    assert state_layout(stewart) == [(name, off, size) for name, _, off, size in position_layout(stewart)]
