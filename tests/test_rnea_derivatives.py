"""The closed-form partials of the tree's joint forces (symgen.dynamics.rnea_derivatives) and the
``analytic`` route of ``inverse_dynamics_derivatives`` traced from them: against 50-digit central
differences of the dense model, against Pinocchio's ``computeRNEADerivatives``, a planted error
caught, and the route kept where it is the cheapest."""
from __future__ import annotations

import pathlib

import numpy as np
import pytest

import symgen
from symgen.codegen import dynamics_derivatives
from symgen.codegen.emit import lower
from symgen.codegen.functions import traced_cost
from symgen.codegen.catalogue import build_function
from symgen.codegen.generate import operation_counts, trace_all
from symgen.codegen.reference import reference_states
from symgen.codegen.runtime import call_by_name, load_generated
from symgen.dynamics import _setup, rnea_derivatives as rd
from symgen.dynamics.rnea import rnea
from symgen.math.configuration import Configuration
from symgen.math.fields import MpField

from .codegen_util import relative_error
from .test_codegen_derivatives import BRANCHED, FD_TOL, FRICTION, PINOCCHIO_TOL, _central_differences

SPHERICAL = str(pathlib.Path(BRANCHED).parent / "spherical_wrist.yaml")


def _analytic_module(model, target: str):
    """The generated module of the analytic route alone (whatever route the generator would keep)."""
    return load_generated(model, target, lowered=[lower(dynamics_derivatives._traced_analytic(model))])


def _breadth_first(tmp_path) -> str:
    """The branched tree with its joints declared breadth first: the coordinates below the left
    shoulder (itself and the left elbow) are not contiguous, the right shoulder between them."""
    lines = pathlib.Path(BRANCHED).read_text(encoding="utf-8").splitlines()
    joints = {line.split(":")[0].strip(): line for line in lines if line.startswith("  ") and "parent:" in line}
    order = ["waist", "left_shoulder", "right_shoulder", "left_elbow", "right_slide"]
    body = [line for line in lines if line not in joints.values()]
    at = body.index("joints:") + 1
    path = tmp_path / "branched_tree_breadth_first.yaml"
    path.write_text("\n".join(body[:at] + [joints[j] for j in order] + body[at:]) + "\n", encoding="utf-8")
    return str(path)


@pytest.mark.parametrize("looped", [False, True], ids=["dot-products", "library-products"])
@pytest.mark.parametrize("spec", ["chain:n=3", BRANCHED, "breadth-first", FRICTION, "general_chain:n=7"])
@pytest.mark.parametrize("target", ["numpy", "c"])
def test_analytic_route_equals_50_digit_central_differences(spec, target, looped, monkeypatch, tmp_path):
    """Revolute and prismatic joints, a branched tree (also declared breadth first, so a subtree's
    coordinates are not contiguous), viscous and Coulomb friction, general geometry; ``M`` against
    the dense model's. The ancestor-pair entries as straight-line dot products and as the library
    products (:func:`~symgen.codegen.dynamics_derivatives.looped_entries`)."""
    monkeypatch.setattr(dynamics_derivatives, "LOOPED_PAIRS", 0 if looped else 10**9)
    model = symgen.derive(symgen.load(_breadth_first(tmp_path) if spec == "breadth-first" else spec))
    ops = lower(dynamics_derivatives._traced_analytic(model)).ops
    assert len(ops["products"]) == (5 if looped else 0)
    module = _analytic_module(model, target)
    for s in reference_states(model, 2, seed=31):
        dq, dqd, mass = call_by_name(module, "inverse_dynamics_derivatives", s)
        want_q, want_qd = _central_differences(model, s)
        assert relative_error(dq, want_q) < FD_TOL, spec
        assert relative_error(dqd, want_qd) < FD_TOL, spec
        assert relative_error(mass, model.evaluate(s["config"], qd=s["qd"]).M_q) < FD_TOL, spec


def test_core_partials_in_50_digits_equal_central_differences_of_the_recursion():
    """The core function itself on the 50-digit field, against differences of
    :func:`~symgen.dynamics.rnea.rnea` (step 1e-20) on the general chain."""
    model = symgen.derive(symgen.load("general_chain:n=7"))
    tree, n = model.tree, model.tree.n_coords
    fld = MpField(tree.parameters, dps=50)
    rng = np.random.default_rng(4)
    q, qd, qdd = (rng.uniform(-1, 1, n) for _ in range(3))
    h = fld.const(10) ** -20

    def tau(angles, rates, accels):
        consts, transforms = _setup(tree, fld, Configuration(dict(zip(_names(model), angles))))
        return np.array(rnea(tree, consts, transforms, list(rates), list(accels), gravity=True), dtype=object)

    consts, transforms = _setup(tree, fld, Configuration(dict(zip(_names(model), [fld.const(v) for v in q]))))
    got = rd.rnea_derivatives(tree, consts, transforms, [fld.const(v) for v in qd], [fld.const(v) for v in qdd],
                              gravity=True)
    qm, qdm, qddm = ([fld.const(v) for v in x] for x in (q, qd, qdd))
    for i in range(n):
        e = [h if k == i else 0 for k in range(n)]
        plus, minus = ([a + s * b for a, b in zip(qm, e)] for s in (1, -1))
        want_q = (tau(plus, qdm, qddm) - tau(minus, qdm, qddm)) / (2 * h)
        want_qd = (tau(qm, [a + b for a, b in zip(qdm, e)], qddm) - tau(qm, [a - b for a, b in zip(qdm, e)], qddm)) / (2 * h)
        col_q = fld.to_float(np.array([got.dtau_dq[r][i] for r in range(n)], dtype=object))
        col_qd = fld.to_float(np.array([got.dtau_dqd[r][i] for r in range(n)], dtype=object))
        assert relative_error(col_q, fld.to_float(want_q)) < 1e-14
        assert relative_error(col_qd, fld.to_float(want_qd)) < 1e-14


def _names(model) -> list[str]:
    return [j.name for j in model.scene.joints.values() if j.kind.dof]


def test_a_dropped_term_is_caught(monkeypatch):
    """Planted error: the momentum's terms of the variation ``B`` left out (its ``l`` and the
    ``hat(h_n)`` of its ``Q``). The 50-digit check above fails by orders of magnitude more than its
    tolerance."""
    model = symgen.derive(symgen.load("general_chain:n=7"))
    s = reference_states(model, 1, seed=31)[0]
    want_q, want_qd = _central_differences(model, s)

    original = rd.variation

    def dropped(body, v, momentum):
        return original(body, v, (0,) * 6)

    monkeypatch.setattr(rd, "variation", dropped)
    dq, dqd, _ = call_by_name(_analytic_module(model, "numpy"), "inverse_dynamics_derivatives", s)
    assert relative_error(dq, want_q) > 1e3 * FD_TOL
    assert relative_error(dqd, want_qd) > 1e3 * FD_TOL


@pytest.mark.parametrize("spec", [BRANCHED, "general_chain:n=7"])
def test_analytic_route_equals_pinocchio_rnea_derivatives(spec):
    pytest.importorskip("pinocchio", reason="pin (Pinocchio) is not installed (extra 'oracle')")
    from symgen.oracle.pinocchio_tree import tree_robot

    model = symgen.derive(symgen.load(spec))
    robot = tree_robot(model)
    module = _analytic_module(model, "c")
    idx = np.ix_(robot.v_of_coord, robot.v_of_coord)
    for s in reference_states(model, 3, seed=8):
        data = robot.model.createData()
        want = robot.pin.computeRNEADerivatives(robot.model, data, robot.q_vector(s["config"]),
                                                robot.v_vector(s["qd"]), robot.v_vector(s["qdd"]))
        want = [np.asarray(w)[idx] for w in want[:2]] + [(np.triu(data.M) + np.triu(data.M, 1).T)[idx]]
        for got, w, name in zip(call_by_name(module, "inverse_dynamics_derivatives", s), want,
                                ("dtau_dq", "dtau_dqd", "M")):
            assert relative_error(got, w) < PINOCCHIO_TOL, f"{spec}: {name}"


def test_the_cheapest_route_is_kept_and_every_cost_recorded():
    """On the general chain the closed form is the cheapest, on chain:n=6 (axes and offsets that
    fold) the reverse sweep; ``method_costs`` lists all three."""
    for spec, want in (("general_chain:n=7", "analytic"), ("chain:n=6", "reverse")):
        model = symgen.derive(symgen.load(spec))
        ops = operation_counts(model, ["inverse_dynamics_derivatives"])["inverse_dynamics_derivatives"]
        assert ops["method"] == want, spec
        assert set(ops["method_costs"]) == set(dynamics_derivatives.ROUTES), spec
        assert ops["method_costs"][want] == min(ops["method_costs"].values())


def test_library_products_equal_pinocchio_on_full_groups_overlapping_tails_and_short_columns():
    """chain:n=20 (above the size where the entries go to library products): column lengths 1 to 20
    (at and above each torque's coordinate) and 19 to 0 (below it) cover the kernel's full groups of
    rows, its half groups (the last one overlapping), its row-by-row short columns and the partial groups whose rows
    must not spill into the neighbouring product's. The C module (its products written straight
    into the outputs) and the NumPy one against Pinocchio's ``computeRNEADerivatives``."""
    pytest.importorskip("pinocchio", reason="pin (Pinocchio) is not installed (extra 'oracle')")
    from symgen.oracle.pinocchio_tree import tree_robot

    model = symgen.derive(symgen.load("chain:n=20"))
    assert dynamics_derivatives.loops_entries(model.tree)
    robot = tree_robot(model)
    low = lower(dynamics_derivatives._traced_analytic(model))
    assert [p["terms"] for p in low.ops["products"]] == [9, 9, 6, 6, 6]      # B^c_j^T S_j: linear part 0
    idx = np.ix_(robot.v_of_coord, robot.v_of_coord)
    modules = [load_generated(model, target, lowered=[low]) for target in ("c", "numpy")]
    for s in reference_states(model, 3, seed=5):
        data = robot.model.createData()
        want = robot.pin.computeRNEADerivatives(robot.model, data, robot.q_vector(s["config"]),
                                                robot.v_vector(s["qd"]), robot.v_vector(s["qdd"]))
        want = [np.asarray(w)[idx] for w in want[:2]] + [(np.triu(data.M) + np.triu(data.M, 1).T)[idx]]
        for module in modules:
            for got, w, name in zip(call_by_name(module, "inverse_dynamics_derivatives", s), want,
                                    ("dtau_dq", "dtau_dqd", "M")):
                assert relative_error(got, w) < PINOCCHIO_TOL, name


def test_library_products_compile_with_the_strict_flags_and_pass_the_c_test_program(monkeypatch, tmp_path):
    """The product loop (vector extensions under GCC and clang, plain loops otherwise) with
    ``-std=c99 -Wall -Wextra -Werror -pedantic``, by each compiler there is, and the standalone test
    program (one state against the 50-digit reference) passes."""
    import shutil
    import subprocess

    from symgen.codegen.generate import generate

    from .test_codegen_hardening import STRICT

    monkeypatch.setattr(dynamics_derivatives, "LOOPED_PAIRS", 0)
    model = symgen.derive(symgen.load(_breadth_first(tmp_path)))
    gen = generate(model, "c", lowered=[lower(dynamics_derivatives._traced_analytic(model))])
    for name, text in gen.files.items():
        (tmp_path / name).write_text(text)
    assert "symgen_product(" in gen.files[f"{gen.module}.c"]
    compilers = [c for c in ("cc", "clang") if shutil.which(c)]
    assert compilers, "no C compiler"
    for cc in compilers:
        exe = tmp_path / f"test_{cc}"
        built = subprocess.run([cc, *STRICT, "-O2", "-o", str(exe), str(tmp_path / f"test_{gen.module}.c"),
                                str(tmp_path / f"{gen.module}.c"), "-lm"], capture_output=True, text=True)
        assert built.returncode == 0, built.stderr
        ran = subprocess.run([str(exe)], capture_output=True, text=True)
        assert ran.returncode == 0, ran.stdout + ran.stderr


def test_the_entries_go_to_library_products_on_long_chains_only():
    """By the count of ancestor pairs (:data:`~symgen.codegen.dynamics_derivatives.LOOPED_PAIRS`):
    chain:n=11 has 66, chain:n=12 78 (``benchmarks/closed_form_products.md``: 0.55x the dot
    products' time at 78)."""
    short, long = (symgen.derive(symgen.load(f"chain:n={n}")).tree for n in (11, 12))
    assert (dynamics_derivatives.ancestor_pairs(short), dynamics_derivatives.ancestor_pairs(long)) == (66, 78)
    assert not dynamics_derivatives.loops_entries(short)
    assert dynamics_derivatives.loops_entries(long)


def test_long_chains_cost_fewer_operations_in_closed_form():
    """The closed form's advantage grows with the chain: at N = 24 it traces fewer than 0.8 of
    the reverse sweep's operations."""
    model = symgen.derive(symgen.load("chain:n=24"))
    analytic = traced_cost(dynamics_derivatives._traced_analytic(model))
    reverse = traced_cost(dynamics_derivatives._traced(model, "reverse"))
    assert analytic < 0.8 * reverse


@pytest.mark.parametrize("spec", ["four_bar", SPHERICAL])
def test_the_closed_form_does_not_apply_to_loops_or_spherical_joints(spec):
    model = symgen.derive(symgen.load(spec))
    assert not dynamics_derivatives.analytic_applies(model)
    with pytest.raises(rd.UnsupportedJoint):
        dynamics_derivatives._traced_analytic(model)


# ------------------------------------------------------------------ forward dynamics
def _without_contact(tmp_path) -> str:
    """The friction scene without its contact forces (which the closed-form routes leave to the sweeps)."""
    text = pathlib.Path(FRICTION).read_text(encoding="utf-8")
    path = tmp_path / "prismatic_friction_free.yaml"
    path.write_text("\n".join(line for line in text.splitlines() if not line.startswith("contact_forces")),
                    encoding="utf-8")
    return str(path)


@pytest.mark.parametrize("spec, looped", [("friction", False), (BRANCHED, False), ("general_chain:n=7", False),
                                           ("general_chain:n=7", True)])
@pytest.mark.parametrize("route", ["implicit-joint-space-analytic", "implicit-dense-analytic",
                                   "implicit-articulated-body-analytic"])
def test_forward_jacobians_by_the_closed_form_equal_50_digit_central_differences(spec, looped, route, tmp_path,
                                                                                  monkeypatch):
    """The implicit routes with the closed-form partials of ``tau_ID`` (held accelerations), whose
    mass entries are also the joint-space and dense primals' mass matrix: prismatic joints, viscous
    and Coulomb friction and rotor inertias, a branched tree, general geometry -- and its entries as
    library products (``looped``: from any number of ancestor pairs on)."""
    from .test_codegen_forward_derivatives import _reference

    if looped:
        monkeypatch.setattr(dynamics_derivatives, "LOOPED_PAIRS", 0)
    model = symgen.derive(symgen.load(_without_contact(tmp_path) if spec == "friction" else spec))
    module = load_generated(model, "c", lowered=trace_all(model, ["forward_dynamics_derivatives"], {"method": route}))
    names = [a.name for a, _ in build_function(model, "forward_dynamics_derivatives", method=route).outputs]
    for s in reference_states(model, 2, seed=17):
        want = _reference(model, s)
        for out, got in zip(names, call_by_name(module, "forward_dynamics_derivatives", s), strict=True):
            assert relative_error(got, want[out]) < FD_TOL, f"{spec} {route} {out}"


@pytest.mark.parametrize("spec", ["chain:n=6", "chain:n=12", BRANCHED])
def test_the_closed_form_routes_take_the_primal_mass_matrix_from_the_closed_form(spec):
    """On a closed-form route the primal's ``M_q`` (the one factored) is the closed form's own mass
    entries: the partials at the solution add no straight-line operation to the traced Jacobians
    (their composites are the primal's), the composite-rigid-body algorithm would add some, and the
    mass matrix factored is the closed form's entry for entry (straight-line dot products below
    ``LOOPED_PAIRS`` ancestor pairs; library products above, one statement per call)."""
    from symgen.codegen.builder import Builder
    from symgen.codegen import forward_derivatives as fd

    model = symgen.derive(symgen.load(spec))
    b = Builder(model)
    dv, eta_f, qd_all, d_dv, d_eta, _ = fd._jacobians(b, "implicit-joint-space-analytic")
    outputs = [np.asarray(d_dv).ravel(), np.asarray(dv, dtype=object)]

    def ops(*more):
        return b.g.count(b.g.live(outputs + [np.asarray(x, dtype=object).ravel() for x in more]))["total"]

    qdd_all = b.task_accelerations(b.t.task_matrix(), qd_all, dv)
    dq, dqd, mass = dynamics_derivatives.closed_form_partials(b, qd_all, qdd_all)
    assert ops(dq, dqd, mass) == ops()
    assert ops(b.mass_by_composite_inertia()) > ops()
    if not dynamics_derivatives.loops_entries(model.tree):
        assert all(x is b.g.const(y) for x, y in zip(np.asarray(b.mass_in_joint_space()).ravel(), mass.ravel()))


def test_the_closed_form_routes_apply_to_trees_with_motion_on_joints_only():
    from symgen.codegen.forward_derivatives import applicable_routes

    assert "implicit-joint-space-analytic" in applicable_routes(symgen.derive(symgen.load("chain:n=3")))
    for spec in ("four_bar", "arm_on_plane", SPHERICAL, FRICTION):       # FRICTION: contact forces
        assert not [r for r in applicable_routes(symgen.derive(symgen.load(spec))) if r.endswith("-analytic")], spec


def test_the_core_function_names_a_joint_it_does_not_cover():
    """A spherical joint (three coordinates) is refused with the typed error naming it."""
    model = symgen.derive(symgen.load(SPHERICAL))
    tree = model.tree
    fld = MpField(tree.parameters)
    consts, transforms = _setup(tree, fld, model.reference)
    spherical = next(j.name for j in tree.joints if j.kind.dof == 3)
    with pytest.raises(rd.UnsupportedJoint, match=repr(spherical)):
        rd.rnea_derivatives(tree, consts, transforms, [0] * tree.n_coords, [0] * tree.n_coords, gravity=True)
    assert issubclass(rd.UnsupportedJoint, symgen.errors.SymgenError)
