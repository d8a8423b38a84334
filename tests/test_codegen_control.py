"""Generated ``control`` (eq. 34) and ``adaptation`` (eq. 38) against the dense controller of
:mod:`symgen.control.law` (``O(n_S p)`` matrices ``T_S``, ``Y_r``, no recursion, no tracing), op
counts linear in the DOF and the arms, folding of the known parameters, and typed errors."""
from __future__ import annotations

import json

import numpy as np
import pytest

import symgen
from symgen.closure import random_consistent_states
from symgen.codegen.generate import generate, resolve_functions, trace_all
from symgen.codegen.linearity import family_counts, fit_line
from symgen.codegen.reference import position_vector
from symgen.codegen.runtime import load_generated
from symgen.control.recursive import BodyMotion, body_signal
from symgen.control.contact import ContactLaw
from symgen.control.errors import ControlInputError, GainMatrixError, UnknownParameterError
from symgen.control.law import control as dense_control
from symgen.control.law import default_parameters
from symgen.control.regressor import Y_alpha
from symgen.errors import CodegenError

from .codegen_util import relative_error

#: generated against dense, normwise relative (floor 1e-2)
TOL = 1e-12
STATES = 3
FAST = ["chain:n=6", "four_bar", "five_bar", "arm_on_plane"]
SLOW = ["multi_arm:h=2", "stewart"]
#: viscous and Coulomb coefficients of arm_on_plane's contact law (the known ones fold)
CONTACT = (0.7, 0.2)

_models: dict = {}


def model_of(spec):
    if spec not in _models:
        _models[spec] = symgen.derive(symgen.load(spec))
    return _models[spec]


def contact_of(model):
    return ContactLaw.for_scene(model.scene, *CONTACT) if model.scene.contact_forces is not None else None


def some_uncertain(model) -> list[str]:
    """Every third parameter, starting with the second: joints', bodies' and contact ones mixed."""
    return list(default_parameters(model, contact_of(model)).names[1::3])


def dense(model, params, uncertain, config, s, gain=1.0):
    """The dense law at one state: ``(tau, s)`` with ``P_hat`` scattered into ``P``'s order."""
    p = np.asarray(params.values, dtype=float).copy()
    for name, value in zip(uncertain, s["P_hat"]):
        p[params.index(name)] = value
    n, m = model.counts.n, model.counts.m
    data = model.evaluate(config, V_m=s["V_m"])
    out = dense_control(model, data, params, p, s["V_mr"], s["dV_mr"], eta_fr=s["eta_fr"] if n > m else None,
                        gain=gain, contact=contact_of(model))
    return out.tau, np.array([out.s[params.index(name)] for name in uncertain])


def states(model, uncertain, seed, *, at_rest=False):
    """Loop-closed states with random required velocities, constraint forces and estimates."""
    rng = np.random.default_rng(seed)
    n, m = model.counts.n, model.counts.m
    params = default_parameters(model, contact_of(model))
    true = np.array([float(params.values[params.index(u)]) for u in uncertain])
    for config, v_m in random_consistent_states(model, STATES, seed=seed):
        v_m = np.zeros(m) if at_rest else np.asarray(v_m, float)
        yield config, dict(q=position_vector(model, config), V_m=v_m, V_mr=v_m + rng.uniform(-1, 1, m),
                           dV_mr=rng.uniform(-1, 1, m), eta_fr=rng.uniform(-1, 1, n - m),
                           P_hat=true * (1 + 0.5 * rng.uniform(-1, 1, true.size)) + 0.1 * rng.uniform(-1, 1, true.size))


def check_scene(spec, choice, seed=3):
    model = model_of(spec)
    params = default_parameters(model, contact_of(model))
    uncertain = list(params.names) if choice == "all" else some_uncertain(model)
    lowered = trace_all(model, ["control", "adaptation"], {"uncertain": uncertain, "contact": contact_of(model)})
    for target in ("numpy", "c"):
        module = load_generated(model, target, lowered=lowered)
        for config, s in states(model, uncertain, seed):
            tau, sig = dense(model, params, uncertain, config, s)
            args = [s[k] for k in ("q", "V_m", "V_mr", "dV_mr")]
            extra = ([s["eta_fr"]] if model.counts.n > model.counts.m else []) + [s["P_hat"]]
            assert relative_error(module.control(*args, *extra), tau) < TOL, (target, "control")
            assert relative_error(module.adaptation(*args), sig) < TOL, (target, "adaptation")


@pytest.mark.parametrize("choice", ["all", "some"])
@pytest.mark.parametrize("spec", FAST)
def test_generated_controller_equals_the_dense_law(spec, choice):
    check_scene(spec, choice)


@pytest.mark.slow
@pytest.mark.parametrize("choice", ["all", "some"])
@pytest.mark.parametrize("spec", SLOW)
def test_generated_controller_equals_the_dense_law_on_large_scenes(spec, choice):
    check_scene(spec, choice)


def test_spherical_friction_is_finite_at_rest():
    """``w/|w|`` of eq. (23) is 0 at ``w = 0`` in the generated code as in the dense regressor."""
    model = model_of("stewart")
    params = default_parameters(model)
    uncertain = [n for n in params.names if n.startswith(("b_", "c_"))]
    module = load_generated(model, "numpy", lowered=trace_all(model, ["control"], {"uncertain": uncertain}))
    config, s = next(states(model, uncertain, 5, at_rest=True))
    got = module.control(s["q"], s["V_m"], s["V_mr"], s["dV_mr"], s["P_hat"])
    assert np.all(np.isfinite(got))
    assert relative_error(got, dense(model, params, uncertain, config, s)[0]) < TOL


def test_gain_as_input_and_folded_gain():
    model = model_of("five_bar")
    n = model.counts.n
    params = default_parameters(model)
    uncertain = some_uncertain(model)
    rng = np.random.default_rng(1)
    k = rng.uniform(-1, 1, (n, n))
    gain = k @ k.T + n * np.eye(n)
    as_input = load_generated(model, "c", lowered=trace_all(model, ["control"], {"uncertain": uncertain,
                                                                                   "gain": "input"}))
    folded = load_generated(model, "numpy", lowered=trace_all(model, ["control"], {"uncertain": uncertain,
                                                                                     "gain": gain}))
    for config, s in states(model, uncertain, 2):
        want = dense(model, params, uncertain, config, s, gain=gain)[0]
        args = [s[k] for k in ("q", "V_m", "V_mr", "dV_mr", "P_hat")]
        assert relative_error(as_input.control(*args, gain.ravel()), want) < TOL
        assert relative_error(folded.control(*args), want) < TOL


def test_known_parameters_fold_and_P_hat_follows_the_parameter_order():
    model = model_of("chain:n=3")
    names = default_parameters(model).names
    chosen = ["m_link2", "Ir_j1", "Ixx_link1"]
    ops = generate(model, "numpy", ["control"], options={"uncertain": chosen}).files["ops.json"]
    meta = json.loads(ops)["functions"]["control"]
    assert meta["P_hat"] == sorted(chosen, key=names.index) == ["Ir_j1", "Ixx_link1", "m_link2"]
    total = (lambda u: trace_all(model, ["control"], {"uncertain": u})[0].ops["total"])
    assert total("none") < total(chosen) < total("all")
    fn = trace_all(model, ["control"], {"uncertain": "none"})[0].function
    assert [a.name for a in fn.inputs] == ["q", "V_m", "V_mr", "dV_mr"]


def test_controller_functions_are_on_request_only():
    assert "control" not in resolve_functions(None) and "adaptation" not in resolve_functions(None)
    assert resolve_functions(["adaptation", "inverse_dynamics", "control"]) == \
        ["inverse_dynamics", "control", "adaptation"]


def test_body_signal_is_the_transposed_body_regressor():
    """``Y_alpha^T x`` without the 6 x 10 matrix, against :func:`symgen.control.regressor.Y_alpha`."""
    from symgen.math.fields import make_field

    fld = make_field("float", {})
    rng = np.random.default_rng(0)
    for _ in range(5):
        om, v_r, w_r, dv_r, dw_r, xv, xw = (tuple(rng.uniform(-1, 1, 3)) for _ in range(7))
        want = Y_alpha(om, v_r + w_r, dv_r + dw_r, np.zeros(3), fld).T @ np.array(xv + xw)
        got = body_signal(BodyMotion(om, v_r, w_r, dv_r, dw_r), xv, xw)
        assert np.max(np.abs(np.array(got, float) - want)) < 1e-14


# ------------------------------------------------------------------------- op counts
def test_control_counts_are_linear_in_dof():
    rows = family_counts("chain", None, "control")          # N = 2 ... 64 (symgen.codegen.linearity)
    totals = {n: ops["total"] for n, ops in rows}
    assert fit_line(list(totals), list(totals.values())).r2 > 0.999
    assert totals[64] / totals[32] <= 2.05


@pytest.mark.slow
def test_control_counts_are_linear_in_arms():
    """Linear in H; what the controller adds to the task-space inverse dynamics (the same solves with
    ``[J_m; J_f]``, whose constants fold differently with the arms' placement) is nearly the same
    per arm: every arm's 6 x 6 tool Jacobian is eliminated in line, in a pivot order chosen from
    that arm's sample values, so each extra right-hand side the controller solves costs a few
    operations more or less from one arm to the next (within 6 % of the median increment). The
    controller's part includes the task rows' bias by jets (its required rates mix ``qd_all`` and
    ``qd_r``), where ``task_inverse_dynamics`` takes the twist-and-drift pass: about 1,900
    operations per arm, whose arm-to-arm spread (5.7 % at h = 6) is that of both pivot orders."""
    sizes = range(1, 9)
    control = [ops for _, ops in family_counts("multi_arm", sizes, "control")]
    task = [ops for _, ops in family_counts("multi_arm", sizes, "task_inverse_dynamics")]
    assert fit_line(list(sizes), [o["total"] + o["solve_flops"] for o in control]).r2 > 0.999
    assert all(o["pivot_checks"] and not o["factorizations"] for o in control + task)
    own = np.diff(np.array([o["total"] for o in control]) - np.array([o["total"] for o in task]))[1:]
    assert own.min() > 0 and np.all(np.abs(own - np.median(own)) <= 0.06 * np.median(own))


# ------------------------------------------------------------------------- errors
def test_unknown_parameter_is_named():
    with pytest.raises(UnknownParameterError, match="m_link9"):
        trace_all(model_of("chain:n=3"), ["control"], {"uncertain": ["m_link9"]})


def test_gain_that_is_not_positive_definite_is_refused():
    with pytest.raises(GainMatrixError, match="K_A"):
        trace_all(model_of("chain:n=3"), ["control"], {"gain": np.diag([1.0, -1.0, 1.0])})


def test_adaptation_without_uncertain_parameters_is_refused():
    with pytest.raises(ControlInputError, match="uncertain"):
        trace_all(model_of("chain:n=3"), ["adaptation"], {"uncertain": "none"})


def test_unknown_generation_option_is_refused():
    with pytest.raises(CodegenError, match="uncertian"):
        trace_all(model_of("chain:n=3"), ["control"], {"uncertian": "all"})


def test_contact_law_on_a_scene_without_contact_forces_is_refused():
    law = ContactLaw("tip", ("vz",), (1.0,), (0.0,))
    with pytest.raises(ControlInputError, match="no contact forces"):
        trace_all(model_of("chain:n=3"), ["control"], {"contact": law})
