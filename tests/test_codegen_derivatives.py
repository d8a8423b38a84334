"""Forward-mode differentiation of the traced graph (symgen.codegen.derivatives) and the generated
``inverse_dynamics_derivatives``: the rules on hand-checked graphs, the generated NumPy and C
Jacobians against 50-digit central differences of the dense model (along the loop closure on the
four-bar) and against Pinocchio's analytic RNEA derivatives."""
from __future__ import annotations

import math
import pathlib

import numpy as np
import pytest
import sympy as sp

import symgen
from symgen.closure import refine_closure
from symgen.codegen.catalogue import ON_REQUEST, build_function
from symgen.codegen.derivatives import differentiate
from symgen.codegen.reverse import ReverseUnsupported, differentiate_reverse
from symgen.codegen.generate import operation_counts, trace_all
from symgen.codegen.graph import Graph
from symgen.codegen.reference import reference_outputs, reference_states
from symgen.codegen.runtime import call_by_name, load_generated
from symgen.errors import CodegenError
from symgen.math.configuration import Configuration
from symgen.math.fields import MpField

from .codegen_util import relative_error

BRANCHED = str(pathlib.Path(__file__).parent / "data" / "derivatives" / "branched_tree.yaml")
FRICTION = str(pathlib.Path(__file__).parent / "data" / "aba" / "prismatic_friction.yaml")
#: generated Jacobians against 50-digit central differences / against Pinocchio
FD_TOL = 1e-9
PINOCCHIO_TOL = 1e-10
X, Y = 0.3, 0.7


def _values(g: Graph, nodes, x=X, y=Y) -> np.ndarray:
    g.samples = {"v": np.array([[x, y]])}
    return g.sample_values(list(np.asarray(nodes, dtype=object).flat))[0]


def _xy():
    g = Graph()
    x, y = g.input("v", 2)
    return g, x, y


# ------------------------------------------------------------------ the rules
def test_sin_times_y_gives_cos_times_y_and_sin():
    g, x, y = _xy()
    jac = differentiate(g, [g.func("sin", x) * y], [x, y])
    assert jac[0, 0] is g.mul(g.func("cos", x), y)          # d/dx (sin x y) = cos x y, one node
    assert jac[0, 1] is g.func("sin", x)                     # d/dy = sin x, the existing node


@pytest.mark.parametrize("build, want", [
    (lambda g, x, y: x / y, (1 / Y, -X / Y**2)),
    (lambda g, x, y: g.func("cos", x * y), (-Y * math.sin(X * Y), -X * math.sin(X * Y))),
    (lambda g, x, y: g.func("sqrt", x * y), (Y / (2 * math.sqrt(X * Y)), X / (2 * math.sqrt(X * Y)))),
    (lambda g, x, y: -(x - 3 * y), (-1.0, 3.0)),
    (lambda g, x, y: g.func("sign", x - y) * y, (0.0, -1.0)),       # sign(x - y) = -1 here
])
@pytest.mark.parametrize("sweep", [differentiate, differentiate_reverse], ids=["forward", "reverse"])
def test_scalar_rules_at_a_point(build, want, sweep):
    g, x, y = _xy()
    jac = sweep(g, [build(g, x, y)], [x, y])
    np.testing.assert_allclose(_values(g, jac), want, rtol=1e-15, atol=1e-15)


def test_an_input_not_chosen_and_a_constant_have_structural_zero_derivatives():
    g, x, y = _xy()
    jac = differentiate(g, [y * y, g.const(2)], [x])
    assert all(v.is_const and v.value == 0 for v in jac.flat)


def test_solve_derivative_reuses_the_factor_and_equals_sympy():
    """``X = A^-1 b`` with ``A = [[x, y], [1, x^2]]``, ``b = [y, 2]``: ``dX`` by one more solve with
    the same factor; the expected values from SymPy's symbolic inverse, differentiated."""
    g, x, y = _xy()
    sol = g.solve(np.array([[x, y], [1, x * x]], dtype=object), np.array([y, 2], dtype=object))
    jac = differentiate(g, sol, [x, y])
    assert sum(type(s).__name__ == "Factor" for s in g.statements) == 1
    sx, sy = sp.symbols("x y")
    exact = sp.Matrix([[sx, sy], [1, sx**2]]).LUsolve(sp.Matrix([sy, 2]))
    want = [float(exact[i].diff(v).subs({sx: X, sy: Y})) for i in range(2) for v in (sx, sy)]
    np.testing.assert_allclose(_values(g, jac), want, rtol=1e-13)


def test_the_reverse_sweep_of_a_shared_graph_equals_sympy():
    """Two outputs sharing ``u = sin(x y)``, a quotient and a held node: the adjoints meet in
    ``u`` and in ``x``; expected values from SymPy, the held ``w`` a constant."""
    g, x, y = _xy()
    u = g.func("sin", x * y)
    w = x * x
    outs = [u * u / (y + 2), g.func("sqrt", u + 3) - x * w]
    jac = differentiate_reverse(g, outs, [x, y], held=[w])
    sx, sy = sp.symbols("x y")
    su = sp.sin(sx * sy)
    exact = [su**2 / (sy + 2), sp.sqrt(su + 3) - sx * sp.Symbol("w")]
    want = [float(e.diff(v).subs({sx: X, sy: Y, sp.Symbol("w"): X * X})) for e in exact for v in (sx, sy)]
    np.testing.assert_allclose(_values(g, jac), want, rtol=1e-14)


def test_the_reverse_sweep_refuses_a_solve_that_depends_on_the_inputs():
    g, x, y = _xy()
    sol = g.solve(np.array([[x, y], [1, x * x]], dtype=object), np.array([y, 2], dtype=object))
    with pytest.raises(ReverseUnsupported, match="library .* depends on the inputs"):
        differentiate_reverse(g, sol, [x, y])


def test_the_cheaper_sweep_is_kept_and_recorded():
    """The Panda's general frames and full inertias: the adjoint sweep costs less than the forward
    one (``benchmarks/derivative_ops.md``); a closed chain's solves keep the forward sweep."""
    fn = build_function(symgen.derive(symgen.load("chain:n=6")), "inverse_dynamics_derivatives")
    assert fn.metadata["method"] == "reverse"
    assert fn.metadata["method_costs"]["reverse"] < fn.metadata["method_costs"]["forward"]


def test_a_computed_node_is_refused_as_an_input():
    g, x, y = _xy()
    with pytest.raises(CodegenError, match=r"inputs\[1\].*not an input node"):
        differentiate(g, [x * y], [x, x * y])


# ------------------------------------------------------------------ 50-digit central differences
def _mp_tau(model, fld, pos, qd, qdd):
    d = model.evaluate(Configuration(pos), qd=qd, field=fld)
    return d.M_q @ qdd + d.C_q @ qd + d.G_q


def _central_differences(model, state):
    """``(dtau_dq, dtau_dqd)`` by central differences at 50 digits, step 1e-20; on a closed chain
    the independent coordinate moves and the passive ones are re-solved (``refine_closure``)."""
    fld = MpField(model.tree.parameters, dps=50)
    h = fld.const(10) ** -20
    qd = np.array([fld.const(v) for v in state["qd"]], dtype=object)
    qdd = np.array([fld.const(v) for v in state["qdd"]], dtype=object)
    names = [j.name for j in model.scene.joints.values() if j.kind.dof]
    base = refine_closure(model, {n: fld.const(v) for n, v in zip(names, state["q"])}, fld)
    d_q, d_qd = [], []
    for i, coord in enumerate(model.partition.independent):
        joint = model.tree.coordinates[coord].joint
        ends = [refine_closure(model, {**base, joint: base[joint] + s * h}, fld) for s in (1, -1)]
        d_q.append((_mp_tau(model, fld, ends[0], qd, qdd) - _mp_tau(model, fld, ends[1], qd, qdd)) / (2 * h))
        e = np.array([h if k == i else 0 for k in range(len(qd))], dtype=object)
        d_qd.append((_mp_tau(model, fld, base, qd + e, qdd) - _mp_tau(model, fld, base, qd - e, qdd)) / (2 * h))
    return fld.to_float(np.array(d_q, dtype=object).T), fld.to_float(np.array(d_qd, dtype=object).T)


@pytest.fixture(scope="module", params=["chain:n=3", "chain:n=6", BRANCHED, FRICTION, "four_bar"])
def generated(request):
    model = symgen.derive(symgen.load(request.param))
    lowered = trace_all(model, ["inverse_dynamics_derivatives"])
    modules = {t: load_generated(model, t, lowered=lowered) for t in ("numpy", "c")}
    return request.param, model, modules


@pytest.mark.parametrize("target", ["numpy", "c"])
def test_generated_jacobians_equal_50_digit_central_differences(generated, target):
    spec, model, modules = generated
    for s in reference_states(model, 2, seed=21):
        dq, dqd, mass = call_by_name(modules[target], "inverse_dynamics_derivatives", s)
        want_q, want_qd = _central_differences(model, s)
        assert relative_error(dq, want_q) < FD_TOL, spec
        assert relative_error(dqd, want_qd) < FD_TOL, spec
        assert relative_error(mass, model.evaluate(s["config"], qd=s["qd"]).M_q) < FD_TOL, spec


def test_generated_function_equals_its_catalogue_reference(generated):
    spec, model, modules = generated
    for s in reference_states(model, 1, seed=5):
        want = reference_outputs(model, "inverse_dynamics_derivatives", s)
        for got, (name, value) in zip(call_by_name(modules["c"], "inverse_dynamics_derivatives", s),
                                      want.items(), strict=True):
            assert relative_error(got, value) < FD_TOL, f"{spec}: {name}"


# ------------------------------------------------------------------ Pinocchio
@pytest.mark.parametrize("spec", ["chain:n=6", BRANCHED])
def test_generated_jacobians_equal_pinocchio_rnea_derivatives(spec):
    pytest.importorskip("pinocchio", reason="pin (Pinocchio) is not installed (extra 'oracle')")
    from symgen.oracle.pinocchio_tree import tree_robot

    model = symgen.derive(symgen.load(spec))
    robot = tree_robot(model)
    module = load_generated(model, "c", ["inverse_dynamics_derivatives"])
    idx = np.ix_(robot.v_of_coord, robot.v_of_coord)
    for s in reference_states(model, 3, seed=8):
        data = robot.model.createData()
        want = robot.pin.computeRNEADerivatives(robot.model, data, robot.q_vector(s["config"]),
                                                robot.v_vector(s["qd"]), robot.v_vector(s["qdd"]))
        want = [np.asarray(w)[idx] for w in want[:2]] + [np.triu(data.M) + np.triu(data.M, 1).T]
        want[2] = want[2][idx]
        for got, w, name in zip(call_by_name(module, "inverse_dynamics_derivatives", s), want,
                                ("dtau_dq", "dtau_dqd", "M")):
            assert relative_error(got, w) < PINOCCHIO_TOL, f"{spec}: {name}"


# ------------------------------------------------------------------ catalogue, counts, refusals
def test_on_request_only_with_its_operation_count():
    assert "inverse_dynamics_derivatives" in ON_REQUEST
    model = symgen.derive(symgen.load("chain:n=6"))
    ops = operation_counts(model, ["inverse_dynamics", "inverse_dynamics_derivatives"])
    assert ops["inverse_dynamics"]["total"] < ops["inverse_dynamics_derivatives"]["total"]
    assert ops["inverse_dynamics_derivatives"]["trig"] == ops["inverse_dynamics"]["trig"]   # cos, sin reused


def test_a_spherical_joint_is_taken_along_its_child_frame_turn():
    """Three columns per spherical joint (checked against Pinocchio and 50-digit differences in
    tests/test_floating_derivatives.py); the q input keeps the quaternion's four entries."""
    model = symgen.derive(symgen.load(str(pathlib.Path(BRANCHED).parent / "spherical_wrist.yaml")))
    fn = build_function(model, "inverse_dynamics_derivatives")
    shapes = {a.name: a.shape for a, _ in fn.outputs}
    assert fn.inputs[0].shape == (7,) and shapes["dtau_dq"] == (6, 6)
