"""Loop-closure forces and the motion of every joint against the independent KKT reference.

``Model.loop_forces`` must equal the Lagrange multipliers ``lam`` of
``M qdd + h = tau + K^T lam, K qdd + kbias = 0`` in ``tests/reference/tree_dynamics.py`` (the
wrench on the body of frame A, at A's origin, in A's axes), and ``Model.joint_accelerations`` its
``qdd`` of all joints, at 10 random loop-closed states of every constrained built-in. Where model
(32) has ``eta_f`` the documented relation ``eta_f = -T_c^-T T_a1^T lam`` must hold.
"""
import dataclasses

import numpy as np
import pytest

from symgen.io.builtin import get_scene
from symgen.closure import random_consistent_states
from symgen.errors import StateError
from symgen.model import derive
from tests.reference import tree_dynamics as ref

STATES = 10
REL_TOL = 1e-9
PASSIVE_LOOPS = ["four_bar", "five_bar", "stewart"]
CONSTRAINED = PASSIVE_LOOPS + ["arm_on_plane", "multi_arm:h=2"]


def _rel(a, b) -> float:
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.linalg.norm(a - b) / max(1.0, np.linalg.norm(b)))


def four_bar_two_motors():
    """The four-bar with its coupler joint driven too: ``n_c = 3 > n_p = 2``, ``T_c = 1``."""
    scene = get_scene("four_bar")
    scene.joints["j2"] = dataclasses.replace(scene.joints["j2"], actuated=True)
    scene.constraint_forces = "joint"
    return scene


def _cases(model, seed):
    """``(config, V_m, tau, eta_m, tau_all, qd_all)`` at loop-closed states."""
    rng = np.random.default_rng(seed)
    cf = model.scene.contact_forces
    out = []
    for cfg, v_m in random_consistent_states(model, STATES, seed=seed, spread=0.2):
        tau = rng.uniform(-2, 2, model.counts.n)
        eta_m = rng.uniform(-1, 1, len(cf.components)) if cf else None
        tau_all = np.zeros(model.tree.n_coords)
        tau_all[list(model.partition.independent)] = tau
        out.append((cfg, v_m, tau, eta_m, tau_all, model.joint_rates(cfg, v_m)))
    return out


@pytest.fixture(scope="module", params=CONSTRAINED)
def scene_model(request):
    scene = get_scene(request.param)
    return request.param, scene, derive(scene)


def test_loop_forces_equal_the_kkt_multipliers(scene_model):
    spec, scene, model = scene_model
    for cfg, v_m, tau, eta_m, tau_all, qd_all in _cases(model, 7):
        _, lam = ref.kkt(scene, cfg, qd_all, tau_all, eta_m)
        assert _rel(model.loop_forces(cfg, v_m, tau, eta_m), lam) < REL_TOL, spec


def test_all_joint_accelerations_equal_the_kkt_accelerations(scene_model):
    spec, scene, model = scene_model
    for cfg, v_m, tau, eta_m, tau_all, qd_all in _cases(model, 8):
        qdd, _ = ref.kkt(scene, cfg, qd_all, tau_all, eta_m)
        assert _rel(model.joint_accelerations(cfg, v_m, tau, eta_m), qdd) < REL_TOL, spec


def test_all_joint_rates_satisfy_the_constraints_and_give_V_m(scene_model):
    """``T qd_all = 0`` (eq. 6, the reference's rows) and ``V_m`` is recovered (eq. 17)."""
    spec, scene, model = scene_model
    for cfg, v_m, _, _, _, qd_all in _cases(model, 9)[:3]:
        k, _ = ref.constraint_rows(scene, cfg, qd_all)
        assert np.linalg.norm(k @ qd_all) < 1e-10, spec
        assert _rel(ref.task_velocity(scene, cfg, qd_all), v_m) < REL_TOL, spec


def test_operational_eta_f_is_minus_the_loop_forces():
    """``T_c = T_a1`` with ``n_p = 0``: ``J_f = T`` and ``eta_f = -lam``."""
    model = derive(get_scene("arm_on_plane"))
    for cfg, v_m, tau, eta_m, *_ in _cases(model, 3)[:4]:
        _, eta_f = model.forward_dynamics(cfg, v_m, tau, eta_m)
        assert _rel(eta_f, -model.loop_forces(cfg, v_m, tau, eta_m)) < REL_TOL


def test_joint_choice_eta_f_is_minus_T_a1_transpose_lam_and_lam_is_the_kkt_multiplier():
    scene = four_bar_two_motors()
    model = derive(scene)
    assert (model.counts.nc, model.counts.np) == (3, 2)
    for cfg, v_m, tau, _, tau_all, qd_all in _cases(model, 4):
        qdd_ref, lam_ref = ref.kkt(scene, cfg, qd_all, tau_all)
        lam = model.loop_forces(cfg, v_m, tau)
        assert _rel(lam, lam_ref) < REL_TOL
        assert _rel(model.joint_accelerations(cfg, v_m, tau), qdd_ref) < REL_TOL
        _, eta_f = model.forward_dynamics(cfg, v_m, tau)
        k, _ = ref.constraint_rows(scene, cfg, qd_all)
        t_a1 = k[:, list(model.partition.a1)]
        assert _rel(eta_f, -t_a1.T @ lam_ref) < REL_TOL


@pytest.mark.parametrize("spec", PASSIVE_LOOPS + ["arm_on_plane"])
def test_inverse_dynamics_gives_the_same_loop_forces(spec):
    """From ``dV_m`` (and ``eta_f``): ``tau`` by inverse dynamics, then the same ``lam``."""
    model = derive(get_scene(spec))
    for cfg, v_m, tau, eta_m, *_ in _cases(model, 5)[:3]:
        dv, eta_f = model.forward_dynamics(cfg, v_m, tau, eta_m)
        forward = model.loop_forces(cfg, v_m, tau, eta_m)
        inverse = model.loop_forces(cfg, v_m, eta_m=eta_m, dV_m=dv, eta_f=eta_f if eta_f.size else None)
        assert _rel(inverse, forward) < REL_TOL
        assert _rel(model.joint_accelerations(cfg, v_m, dV_m=dv), model.joint_accelerations(cfg, v_m, tau, eta_m)) \
            < REL_TOL


def _cross(a, b) -> float:
    return a[0] * b[1] - a[1] * b[0]


def test_four_bar_holding_force_by_hand_statics():
    """The four-bar at rest at ``q0`` under in-plane gravity ``(0, -g, 0)``, held by its crank.

    By hand (free bodies, no symgen): the massless pin passes the ground's force ``lam = (f_x, f_y)``
    at D on to the rocker, and carries no moment (``j4`` is passive). Rocker: ``F_C + lam + m_3 g = 0``
    and moments about C; coupler: moments about B with ``-F_C``; crank: moments about A give the
    holding torque. Four linear equations in ``f_x, f_y, F_C``."""
    scene = get_scene("four_bar")
    import sympy as sp
    scene.gravity = sp.ImmutableMatrix([0, sp.Rational("-9.81"), 0])
    model = derive(scene)
    a, d, g = 0.1, 0.3, 9.81
    m1, m2, m3 = 2 * a, 2 * d, 2 * a
    b_pt = np.array([a * np.cos(np.pi / 3), a * np.sin(np.pi / 3)])
    c_pt, d_pt = b_pt + [d, 0], np.array([d, 0.0])
    w1, w2, w3 = (np.array([0, -m * g]) for m in (m1, m2, m3))
    g1, g2, g3 = b_pt / 2, (b_pt + c_pt) / 2, (c_pt + d_pt) / 2
    # unknowns x = (f_x, f_y, F_Cx, F_Cy)
    rows = np.array([[1, 0, 1, 0], [0, 1, 0, 1],
                     [-(d_pt - c_pt)[1], (d_pt - c_pt)[0], 0, 0],          # rocker, moments about C
                     [0, 0, (c_pt - b_pt)[1], -(c_pt - b_pt)[0]]])         # coupler, about B, force -F_C
    rhs = np.array([-w3[0], -w3[1], -_cross(g3 - c_pt, w3), -_cross(g2 - b_pt, w2)])
    f_x, f_y, *f_c = np.linalg.solve(rows, rhs)
    f_b = np.array(f_c) - w2                 # crank on coupler at B: -F_C + F_B + w2 = 0
    tau = _cross(b_pt, f_b) - _cross(g1, w1)  # crank about A: tau - B x F_B + G1 x w1 = 0
    lam = model.loop_forces(model.reference, np.zeros(1), dV_m=np.zeros(1))
    np.testing.assert_allclose(lam, [f_x, f_y, 0.0], atol=1e-12)
    np.testing.assert_allclose(model.inverse_dynamics(model.reference, np.zeros(1), np.zeros(1)), [tau],
                               atol=1e-12)


def test_giving_both_tau_and_dV_m_is_a_typed_error():
    model = derive(get_scene("four_bar"))
    with pytest.raises(StateError):
        model.loop_forces(model.reference, np.zeros(1), np.zeros(1), dV_m=np.zeros(1))
    with pytest.raises(StateError):
        model.joint_accelerations(model.reference, np.zeros(1))


def test_labels_follow_the_constraints_and_the_scene_order():
    model = derive(get_scene("four_bar"))
    assert model.constraint_force_names() == ["closure.fx", "closure.fy", "closure.mz"]
    assert model.all_coordinate_names() == ["j1", "j2", "j3", "j4"]
    stewart = derive(get_scene("stewart"))
    names = stewart.all_coordinate_names()
    spherical = [j.name for j in stewart.scene.joints.values() if j.type == "spherical"]
    assert spherical
    for joint in spherical:
        k = names.index(f"{joint}.wx")
        assert names[k:k + 3] == [f"{joint}.wx", f"{joint}.wy", f"{joint}.wz"]
    assert len(names) == stewart.tree.n_coords


def test_simulate_reports_the_loop_forces_of_the_final_state(capsys):
    """``symgen simulate --json`` gives ``lam`` at the final state under the run's torque (here the
    default spring about ``q0``), equal to the KKT multipliers there."""
    import json

    from symgen.cli import main
    from symgen.simulation.forcing import named_torque
    from symgen.simulation.state import StateLayout

    assert main(["simulate", "four_bar", "--t-end", "0.2", "--backend", "numpy", "--json"]) == 0
    run = json.loads(capsys.readouterr().out)[0]
    scene = get_scene("four_bar")
    model = derive(scene)
    layout = StateLayout(model)
    x = np.array(list(run["final_state"].values()))
    q, v_m = layout.split(x)
    cfg = layout.configuration(q)
    tau = named_torque(model, "spring")(run["t_end"], q, v_m)
    tau_all = np.zeros(model.tree.n_coords)
    tau_all[list(model.partition.independent)] = tau
    _, lam = ref.kkt(scene, cfg, model.joint_rates(cfg, v_m), tau_all)
    final = run["loop_forces"]["final"]
    assert list(final) == model.constraint_force_names()
    assert _rel(list(final.values()), lam) < 1e-6      # the printed state is rounded to 12 digits
    assert all(run["loop_forces"]["peak"][k] >= abs(v) for k, v in final.items())


@pytest.mark.parametrize("spec", ["four_bar", "arm_on_plane", "multi_arm:h=2"])
def test_the_50_digit_reference_reads_the_motion_from_its_one_evaluation(spec, monkeypatch):
    """The generated code's 50-digit reference (``symgen.codegen.reference.ReferenceState``, what
    the C test program's expected values come from) gives the joint rates, joint accelerations and
    loop forces of ``Model.motion`` at the same state and field, from the one evaluation of model
    (32) its forward dynamics already made: the same numbers, and no second evaluation."""
    from symgen.codegen.reference import ReferenceState, pinned_state
    from symgen.math.fields import MpField

    model = derive(get_scene(spec))
    state = pinned_state(model, seed=3)
    fld = MpField(model.tree.parameters)
    reference = ReferenceState(model, state, fld)
    want = model.motion(reference.config, state["V_m"], state["tau"], state.get("eta_m"), field=fld)
    calls = []
    evaluate = type(model).evaluate
    monkeypatch.setattr(type(model), "evaluate", lambda self, *a, **k: calls.append(1) or evaluate(self, *a, **k))
    got = {**reference.outputs("forward_dynamics"), **reference.outputs("joint_accelerations"),
           **reference.outputs("loop_forces")}
    assert len(calls) == 1
    for name, value in (("dV_m", want.dV_m), ("qd_all", want.qd_all), ("qdd_all", want.qdd_all), ("lam", want.lam)):
        assert len(got[name]) == len(value) > 0, name
        assert all(g == w for g, w in zip(got[name], value)), name
