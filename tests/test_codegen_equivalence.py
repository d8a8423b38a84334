"""Generated NumPy, generated C and the dense model (32) agree to 1e-12 relative at random
loop-closed states, for every built-in scene and every function."""
from __future__ import annotations

import numpy as np
import pytest

from symgen.codegen import FUNCTIONS
from symgen.codegen.reference import reference_outputs, reference_states

from .codegen_util import SCENES, build, call, relative_error

TOL = 1e-12
STATES = 4


@pytest.fixture(scope="module", params=SCENES)
def scene(request, tmp_path_factory):
    out = tmp_path_factory.mktemp(request.param.replace(":", "_").replace("=", ""))
    model, py, c, _ = build(request.param, out)
    return request.param, model, py, c, reference_states(model, STATES, seed=11)


@pytest.mark.parametrize("function", FUNCTIONS)
def test_numpy_matches_dense_model(scene, function):
    _, model, py, _, states = scene
    for s in states:
        want = reference_outputs(model, function, s)
        for got, (name, value) in zip(call(py, function, s), want.items(), strict=True):
            assert relative_error(got, value) < TOL, f"{function}: {name}"


@pytest.mark.parametrize("function", FUNCTIONS)
def test_c_matches_dense_model(scene, function):
    _, model, _, c, states = scene
    for s in states:
        want = reference_outputs(model, function, s)
        for got, (name, value) in zip(call(c, function, s), want.items(), strict=True):
            assert relative_error(got, value) < TOL, f"{function}: {name}"


@pytest.mark.parametrize("function", FUNCTIONS)
def test_batched_call_equals_single_calls(scene, function):
    """A leading batch axis gives the same numbers as one call per state (NumPy and C)."""
    _, _, py, c, states = scene
    batch = {k: np.stack([s[k] for s in states]) for k in states[0] if k != "config"}
    for module in (py, c):
        together = call(module, function, batch)
        for i, s in enumerate(states):
            for joint, single in zip(together, call(module, function, s), strict=True):
                np.testing.assert_allclose(joint[i], single, rtol=1e-13, atol=1e-14)


@pytest.mark.parametrize("spec", ["four_bar", "arm_on_plane", "stewart"])
def test_on_request_state_derivative_matches_dense_model(spec):
    """``state_derivative`` (emitted only by name, for the simulation) equals ``dV_m`` of forward
    dynamics and ``qd_all`` of the joint rates of the dense model, in both targets."""
    from symgen.codegen.catalogue import ON_REQUEST
    from symgen.codegen.runtime import load_generated
    from symgen.codegen.generate import trace_all
    from symgen.io.builtin import get_scene
    from symgen.model import derive

    assert "state_derivative" in ON_REQUEST and "state_derivative" not in FUNCTIONS
    model = derive(get_scene(spec))
    lowered = trace_all(model, ["state_derivative"])
    for target in ("numpy", "c"):
        module = load_generated(model, target, lowered=lowered)
        for s in reference_states(model, 2, seed=5):
            want = reference_outputs(model, "state_derivative", s)
            for got, (name, value) in zip(call(module, "state_derivative", s), want.items(), strict=True):
                assert relative_error(got, value) < TOL, f"{spec} {target}: {name}"
