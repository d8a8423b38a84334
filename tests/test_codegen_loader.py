"""``load_generated``: one call renders, writes, imports; a second call reuses the same folder."""
import numpy as np

from symgen.io.builtin import get_scene
from symgen.codegen.reference import reference_outputs, reference_states
from symgen.codegen.runtime import cache_root, load_generated
from symgen.model import derive


def test_loaded_numpy_and_c_modules_match_the_dense_model():
    model = derive(get_scene("four_bar"))
    state = reference_states(model, 1, seed=3)[0]
    want = reference_outputs(model, "forward_dynamics", state)["dV_m"]
    for target in ("numpy", "c"):
        module = load_generated(model, target, ["forward_dynamics"])
        got = module.forward_dynamics(state["q"], state["V_m"], state["tau"])
        np.testing.assert_allclose(got, want, rtol=1e-12)


def test_second_load_reuses_the_cached_folder():
    model = derive(get_scene("chain:n=2"))
    first = load_generated(model, "numpy", ["gravity"])
    folders = sorted((cache_root() / "modules").iterdir())
    second = load_generated(model, "numpy", ["gravity"])
    assert second is first
    assert sorted((cache_root() / "modules").iterdir()) == folders
