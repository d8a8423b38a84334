"""The on-request generated functions ``joint_accelerations`` and ``loop_forces`` against the dense
model, and code generation for ``constraint_forces: joint`` with ``n_c > n_p`` (``J_f = [1, T21,
T22]`` and its acceleration bias ``E2 W^-1 (dT/dt qd_all + T dP/dt qd)``)."""
from __future__ import annotations

import pytest

from symgen.io.builtin import get_scene
from symgen.codegen import FUNCTIONS
from symgen.codegen.catalogue import ON_REQUEST
from symgen.codegen.generate import trace_all
from symgen.codegen.reference import reference_states
from symgen.codegen.runtime import load_generated
from symgen.model import derive

from .codegen_util import call, relative_error
from .test_loop_forces import four_bar_two_motors

TOL = 1e-12
NEW = ["joint_accelerations", "loop_forces"]


def test_new_functions_are_on_request_only():
    assert all(name in ON_REQUEST and name not in FUNCTIONS for name in NEW)


def _dense(model, s):
    eta_m = s["eta_m"] if s["eta_m"].size else None
    return {"joint_accelerations": (model.joint_rates(s["config"], s["V_m"]),
                                    model.joint_accelerations(s["config"], s["V_m"], s["tau"], eta_m)),
            "loop_forces": (model.loop_forces(s["config"], s["V_m"], s["tau"], eta_m),)}


@pytest.mark.parametrize("spec", ["four_bar", "five_bar", "stewart", "arm_on_plane", "multi_arm:h=2"])
def test_generated_joint_accelerations_and_loop_forces_match_the_dense_model(spec):
    model = derive(get_scene(spec))
    lowered = trace_all(model, NEW)
    states = reference_states(model, 3, seed=21)
    for target in ("numpy", "c"):
        module = load_generated(model, target, lowered=lowered)
        for s in states:
            want = _dense(model, s)
            for name in NEW:
                for got, value in zip(call(module, name, s), want[name], strict=True):
                    assert relative_error(got, value) < TOL, f"{spec} {target} {name}"


def test_joint_choice_with_more_constraints_than_passive_joints_generates_and_agrees():
    """The generator no longer refuses ``constraint_forces: joint`` with ``n_c > n_p``: forward
    dynamics (``dV_m``, ``eta_f``), the accelerations of every joint and the loop forces of the
    generated code equal the dense model's (whose ``d/dt`` comes from exact jets)."""
    model = derive(four_bar_two_motors())
    assert model.counts.nc > model.counts.np > 0 and model.scene.constraint_forces == "joint"
    names = ["forward_dynamics", "task_inverse_dynamics", "mass_matrix", "coriolis_times_v"] + NEW
    lowered = trace_all(model, names)
    module = load_generated(model, "numpy", lowered=lowered)
    for s in reference_states(model, 4, seed=3):
        dv, eta_f = model.forward_dynamics(s["config"], s["V_m"], s["tau"])
        got_dv, got_eta = call(module, "forward_dynamics", s)
        assert relative_error(got_dv, dv) < TOL and relative_error(got_eta, eta_f) < TOL
        d = model.evaluate(s["config"], V_m=s["V_m"])
        assert relative_error(call(module, "coriolis_times_v", s)[0], d.C[:, :1] @ s["V_m"]) < TOL
        tau = model.inverse_dynamics(s["config"], s["V_m"], s["dV_m"], s["eta_f"])
        assert relative_error(call(module, "task_inverse_dynamics", s)[0], tau) < TOL
        for name in NEW:
            for got, value in zip(call(module, name, s), _dense(model, s)[name], strict=True):
                assert relative_error(got, value) < TOL, name


def test_joint_choice_without_passive_joints_generates_and_agrees():
    """``arm_on_plane`` with ``T_c = 1`` (``n_p = 0``, ``J_f = T_a1^-1 T``), once refused by the
    generator: ``dV_m`` and ``eta_f`` of the generated forward dynamics equal the dense model's."""
    scene = get_scene("arm_on_plane")
    scene.constraint_forces = "joint"
    model = derive(scene)
    module = load_generated(model, "numpy", lowered=trace_all(model, ["forward_dynamics", "mass_matrix"]))
    for s in reference_states(model, 3, seed=4):
        dv, eta_f = model.forward_dynamics(s["config"], s["V_m"], s["tau"], s["eta_m"])
        got_dv, got_eta = call(module, "forward_dynamics", s)
        assert relative_error(got_dv, dv) < TOL and relative_error(got_eta, eta_f) < TOL
        assert relative_error(call(module, "mass_matrix", s)[0], model.evaluate(s["config"]).M) < TOL
