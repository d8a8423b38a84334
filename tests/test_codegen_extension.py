"""The C target's CPython extension module (``generate(..., python_extension=True)``): the same
numbers as the ctypes binding, and typed errors for bad arguments and bad statuses, raised in C."""
from __future__ import annotations

import shutil
import subprocess
import sysconfig

import numpy as np
import pytest

from symgen.codegen.generate import generate, trace_all
from symgen.codegen.reference import reference_states
from symgen.codegen.runtime import call_by_name, load_generated
from symgen.errors import CodegenError
from symgen.io.builtin import get_scene
from symgen.model import derive

CC = shutil.which("cc") or "cc"


@pytest.fixture(scope="module", params=["chain:n=6", "four_bar"])
def pair(request):
    model = derive(get_scene(request.param))
    lowered = trace_all(model)
    return (model, load_generated(model, "c", lowered=lowered, python_extension=True),
            load_generated(model, "c", lowered=lowered))


def test_extension_equals_the_ctypes_binding_on_every_function(pair):
    model, ext, binding = pair
    names = [low for low in ("inverse_dynamics", "task_inverse_dynamics", "forward_dynamics", "mass_matrix",
                             "coriolis_times_v", "gravity", "joint_rates") if hasattr(binding, low)]
    assert len(names) >= 5
    for state in reference_states(model, 3, seed=5):
        for name in names:
            got, want = call_by_name(ext, name, state), call_by_name(binding, name, state)
            for g, w in zip(got, want, strict=True):
                assert isinstance(g, np.ndarray) and g.dtype == np.float64 and g.shape == w.shape
                np.testing.assert_array_equal(g, w)


def test_the_functions_are_compiled_ones(pair):
    """No Python wrapper sits between the caller and the C function."""
    _, ext, _ = pair
    assert type(ext.inverse_dynamics).__name__ == "builtin_function_or_method"


@pytest.fixture(scope="module")
def chain():
    return load_generated(derive(get_scene("chain:n=3")), "c", ["inverse_dynamics", "mass_matrix"],
                          python_extension=True)


def test_other_real_arguments_are_converted(chain):
    q = np.array([0.3, -0.2, 0.5])
    want = chain.inverse_dynamics(q, q, q)
    for other in (list(q), tuple(q), np.repeat(q, 2)[::2], q.astype(">f8"), memoryview(q)):
        np.testing.assert_array_equal(chain.inverse_dynamics(other, q, q), want)
    ints = np.array([1, 0, -1])
    np.testing.assert_array_equal(chain.inverse_dynamics(ints, q, q), chain.inverse_dynamics(ints * 1.0, q, q))
    assert chain.mass_matrix(q).shape == (3, 3)


@pytest.mark.parametrize("bad, error, match", [
    (np.zeros(4), ValueError, r"q must have shape \(3,\)"),
    (np.zeros((2, 3)), ValueError, r"q must have shape \(3,\)"),
    ([1.0, 2.0], ValueError, r"q must have shape \(3,\)"),
    (np.zeros(3, complex), TypeError, "q must hold real numbers, got complex"),
    ([1.0, 2j, 0.0], TypeError, "q must hold real numbers"),
    (np.array(["a", "b", "c"]), TypeError, "q must hold real numbers"),
    (["a", "b", "c"], TypeError, "q must hold real numbers"),
    (None, TypeError, "q must be an array of 3 real numbers"),
    (np.array([0.0, np.nan, 0.0]), ValueError, "q contains NaN or infinity"),
    ([0.0, float("inf"), 0.0], ValueError, "q contains NaN or infinity"),
])
def test_bad_arguments_raise_typed_errors_naming_them(chain, bad, error, match):
    with pytest.raises(error, match=match):
        chain.inverse_dynamics(bad, np.zeros(3), np.zeros(3))


def test_wrong_argument_count_is_a_type_error(chain):
    with pytest.raises(TypeError, match=r"takes 3 arguments \(q, qd, qdd\), got 2"):
        chain.inverse_dynamics(np.zeros(3), np.zeros(3))


def test_overflow_raises_non_finite_output_error(chain):
    with pytest.raises(chain.NonFiniteOutputError, match="inverse_dynamics: output tau") as info:
        chain.inverse_dynamics(np.zeros(3), np.full(3, 1e200), np.zeros(3))
    assert isinstance(info.value, ValueError) and info.value.output == "tau"


def test_singular_state_raises_singular_solve_error():
    """All four-bar angles 0: the links are collinear and [T_u1, T_a1] is singular."""
    ext = load_generated(derive(get_scene("four_bar")), "c", ["inverse_dynamics"], python_extension=True)
    with pytest.raises(ext.SingularSolveError) as info:
        ext.inverse_dynamics(np.zeros(4), [1.0], [0.0])
    assert info.value.condition > 1e12 and "inverse_dynamics" in str(info.value)
    assert np.all(np.isfinite(ext.inverse_dynamics(np.array([0.3, 2.0, 0.5, 1.0]), [1.0], [0.0])))


def test_extension_source_compiles_without_warnings(tmp_path):
    import numpy

    gen = generate(derive(get_scene("four_bar")), "c", python_extension=True)
    for name, text in gen.files.items():
        (tmp_path / name).write_text(text)
    cmd = [CC, "-std=c99", "-Wall", "-Wextra", "-Werror", "-O1", "-fPIC", "-c",
           f"-I{sysconfig.get_paths()['include']}", f"-I{numpy.get_include()}", str(tmp_path / "four_bar_ext.c"),
           "-o", str(tmp_path / "ext.o")]
    result = subprocess.run(cmd, capture_output=True, text=True)
    assert result.returncode == 0, result.stderr


def test_only_the_c_target_has_an_extension():
    with pytest.raises(CodegenError, match="no CPython extension"):
        generate(derive(get_scene("chain:n=1")), "numpy", python_extension=True)
