"""Generated NumPy and C code of coupled scenes against the dense model: a coupling's row of ``T``
is a constant, so the generated code has no drift term for it (eq. 11)."""
from __future__ import annotations

import pytest

from symgen.codegen.generate import trace_all
from symgen.codegen.reference import reference_states
from symgen.codegen.runtime import load_generated
from symgen.model import derive

from .codegen_util import call, relative_error
from .test_couplings import geared_pendulums

TOL = 1e-12
NAMES = ["forward_dynamics", "joint_accelerations", "loop_forces"]


def _dense(model, s):
    dv, eta_f = model.forward_dynamics(s["config"], s["V_m"], s["tau"])
    return {"forward_dynamics": (dv, eta_f) if eta_f.size else (dv,),
            "joint_accelerations": (model.joint_rates(s["config"], s["V_m"]),
                                    model.joint_accelerations(s["config"], s["V_m"], s["tau"])),
            "loop_forces": (model.loop_forces(s["config"], s["V_m"], s["tau"]),)}


@pytest.mark.parametrize("actuated_b", [False, True], ids=["passive_follower", "both_actuated"])
def test_generated_code_of_a_coupled_scene_matches_the_dense_model(actuated_b):
    scene = geared_pendulums(actuated_b)
    if actuated_b:
        scene.constraint_forces = "joint"
    model = derive(scene)
    lowered = trace_all(model, NAMES)
    states = reference_states(model, 3, seed=4, spread=0.8)
    for target in ("numpy", "c"):
        module = load_generated(model, target, lowered=lowered)
        for s in states:
            want = _dense(model, s)
            for name, values in want.items():
                for got, value in zip(call(module, name, s), values, strict=True):
                    assert relative_error(got, value) < TOL, f"{target} {name}"
