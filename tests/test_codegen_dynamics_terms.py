"""The combined entry point ``dynamics_terms``: M, C [V_m; 0] and G of (32) in one pass equal the
dense model, and cost no more than the three separate functions (kinematics computed once)."""
import pytest

from symgen.codegen.reference import reference_outputs, reference_states

from .codegen_util import build, call, relative_error

TOL = 1e-12
SCENES = ["chain:n=6", "arm_on_plane", "four_bar", "multi_arm:h=2"]
SEPARATE = ["mass_matrix", "coriolis_times_v", "gravity"]


@pytest.mark.parametrize("spec", SCENES)
def test_dynamics_terms_equal_the_dense_model_and_cost_less_than_three_calls(spec, tmp_path):
    model, py, c, gens = build(spec, tmp_path, SEPARATE + ["dynamics_terms"])
    for state in reference_states(model, 3, seed=5):
        want = reference_outputs(model, "dynamics_terms", state)
        for module in (py, c):
            got = call(module, "dynamics_terms", state)
            for out, name in zip(got, ("M", "c", "G")):
                assert relative_error(out, want[name]) < TOL
    ops = gens["numpy"].ops

    def cost(name):
        return ops[name]["total"] + ops[name]["solve_flops"] + ops[name]["trig"]

    assert cost("dynamics_terms") <= sum(cost(name) for name in SEPARATE)
