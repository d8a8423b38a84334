"""Generated code whatever the user wrote: free text is inert in every target, module names never
shadow the standard library, non-finite numbers are never written as literals, and a non-finite
result is reported (C status, NumPy and ctypes exceptions naming the function and the output)."""
from __future__ import annotations

import ctypes
import shutil
import subprocess
import sys

import numpy as np
import pytest

from symgen.codegen.generate import comment_text, generate, module_name, trace_all
from symgen.codegen.reference import position_vector
from symgen.codegen.targets import c as c_target
from symgen.errors import CodegenError
from symgen.model import derive
from symgen.scene import Scene

from .codegen_util import STRICT, build, import_file

#: the flags the generated C must pass (as the fuzz test and the issue state them)
needs_cc = pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler")


def pendulum(name: str = "pendulum", description: str = "", gravity=None) -> Scene:
    scene = Scene(name, description)
    scene.add_body("link", 1, com=[0.5, 0, 0], inertia=[0.01, 0.1, 0.1])
    scene.add_joint("hinge", "revolute", "world", "link", axis="y", actuated=True)
    scene.set_motion(joints=["hinge"])
    return scene


def write(model, folder, functions=("inverse_dynamics", "forward_dynamics")):
    lowered = trace_all(model, list(functions))
    gens = {}
    for target in ("numpy", "c"):
        gens[target] = generate(model, target, lowered=lowered)
        (folder / target).mkdir(parents=True, exist_ok=True)
        for name, text in gens[target].files.items():
            (folder / target / name).write_text(text, encoding="utf-8")
    return gens


def compile_strict(folder, module):
    exe = folder / "test_program"
    result = subprocess.run(["cc", *STRICT, "-o", str(exe), str(folder / f"test_{module}.c"),
                             str(folder / f"{module}.c"), "-lm"], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    return exe


# ---------------------------------------------------------------------------- free text
HOSTILE = ["ends in a backslash \\", "trigraph ??/ continues", "bidi \u202e override \u2066", "nul \x00 byte",
           "lone \ud800 surrogate", "line\u2028separator", "*/ closes /* opens", '""" triple quotes \'\'\'',
           "é ünïcödé λ letters stay"]


@pytest.mark.parametrize("text", HOSTILE)
def test_comment_text_is_one_inert_line(text):
    out = comment_text(text)
    assert "\n" not in out and "\\" not in out and "??" not in out and not out.endswith("?")
    assert all(ch.isprintable() for ch in out)
    out.encode("utf-8")        # no lone surrogate left


def test_comment_text_keeps_letters_of_any_script():
    assert comment_text("é ünïcödé λ") == "é ünïcödé λ"


@needs_cc
def test_hostile_descriptions_give_files_that_compile_strictly_and_import(tmp_path):
    model = derive(pendulum(description=" | ".join(HOSTILE)))
    gens = write(model, tmp_path)
    exe = compile_strict(tmp_path / "c", gens["c"].module)
    assert subprocess.run([str(exe)], capture_output=True).returncode == 0
    module = import_file(tmp_path / "numpy" / "pendulum.py", "hostile_pendulum")
    assert np.isfinite(module.inverse_dynamics([0.1], [0.2], [0.3])).all()
    import_file(tmp_path / "c" / "pendulum_ctypes.py", "hostile_pendulum_ctypes")


# ---------------------------------------------------------------------------- module names
@pytest.mark.parametrize("name, module", [("math", "math_model"), ("numpy", "numpy_model"), ("ctypes", "ctypes_model"),
                                          ("Random", "Random_model"), ("stdio", "stdio_model"), ("lambda", "lambda_model"),
                                          ("symgen", "symgen_model"), ("four_bar", "four_bar")])
def test_module_names_never_shadow_what_the_files_import(name, module):
    assert module_name(name) == module


def test_every_standard_library_module_name_is_renamed():
    assert all(module_name(m) == m + "_model" for m in sys.stdlib_module_names if m.isidentifier())


def test_a_scene_named_math_writes_math_model_and_the_standard_library_still_imports(tmp_path):
    gens = write(derive(pendulum("math")), tmp_path)
    assert "math_model.py" in gens["numpy"].files and "math_model.h" in gens["c"].files
    assert not any(name.startswith("math.") for g in gens.values() for name in g.files)
    script = "import math, numpy; import math_model; assert math.pi > 3; print(math_model.inverse_dynamics([0.1], [0], [0]))"
    result = subprocess.run([sys.executable, "-c", script], cwd=tmp_path / "numpy", capture_output=True, text=True)
    assert result.returncode == 0, result.stderr


# ---------------------------------------------------------------------------- literals
def test_a_non_finite_number_has_no_c_literal():
    for value in (np.inf, -np.inf, np.nan):
        with pytest.raises(CodegenError):
            c_target._literal(value)


@needs_cc
def test_a_reference_that_overflows_makes_the_test_program_expect_the_status(tmp_path, monkeypatch):
    """The test program never holds ``inf``/``nan``: where the dense reference overflowed, it
    checks that the function reports SYMGEN_NONFINITE instead."""
    real = c_target.expected_outputs

    def overflowing(reference, function):
        out = real(reference, function)
        return {k: np.full_like(np.asarray(v, dtype=float), np.inf) for k, v in out.items()}

    monkeypatch.setattr(c_target, "expected_outputs", overflowing)
    gens = write(derive(pendulum()), tmp_path)
    test = gens["c"].files["test_pendulum.c"]
    assert not any(tok in test.split() for tok in ("inf", "nan", "inf,", "nan,", "-inf"))
    assert test.count("SYMGEN_NONFINITE expected") == 2
    compile_strict(tmp_path / "c", "pendulum")


# ---------------------------------------------------------------------------- run time
@pytest.fixture(scope="module")
def four_bar(tmp_path_factory):
    return build("four_bar", tmp_path_factory.mktemp("four_bar_nonfinite"), ["forward_dynamics", "mass_matrix"])


def q0(model):
    return position_vector(model, model.reference)


@pytest.mark.parametrize("target", [1, 2])
def test_an_overflowing_forward_dynamics_raises_naming_function_and_output(four_bar, target):
    model, module = four_bar[0], four_bar[target]
    with np.errstate(all="ignore"), pytest.raises(module.NonFiniteOutputError) as info:
        module.forward_dynamics(q0(model), [1e155], [1.0])
    assert info.value.function == "forward_dynamics" and info.value.output == "dV_m"
    assert "forward_dynamics" in str(info.value) and "dV_m" in str(info.value) and info.value.state is None


@pytest.mark.parametrize("target", [1, 2])
def test_an_overflowing_state_in_a_batch_is_named(four_bar, target):
    model, module = four_bar[0], four_bar[target]
    v = np.array([[0.5], [0.5], [1e155]])
    with np.errstate(all="ignore"), pytest.raises(module.NonFiniteOutputError) as info:
        module.forward_dynamics(np.tile(q0(model), (3, 1)), v, np.ones((3, 1)))
    assert info.value.state == 2 and "state 2 of the batch" in str(info.value)


@pytest.mark.parametrize("target", [1, 2])
def test_an_empty_batch_names_the_argument(four_bar, target):
    module = four_bar[target]
    with pytest.raises(ValueError, match=r"q is an empty batch \(shape \(0, 4\)\)"):
        module.forward_dynamics(np.zeros((0, 4)), np.zeros((0, 1)), np.zeros((0, 1)))
    with pytest.raises(ValueError, match="V_m is an empty batch"):
        module.forward_dynamics(np.zeros((2, 4)), np.zeros((2, 0, 1)), np.zeros((2, 1)))


def _call_forward_dynamics(lib, q, v, tau, batch: int = 0):
    """The four-bar's raw C ``forward_dynamics`` (or its ``_batch`` entry on ``batch`` states) on
    ``q, V_m, tau``: its return status and ``dV_m``."""
    arrays = [np.ascontiguousarray(x, dtype=float) for x in (q, v, tau)]
    arrays += [np.empty(np.shape(arrays[1])), np.empty(1)]
    pointers = [a.ctypes.data_as(ctypes.POINTER(ctypes.c_double)) for a in arrays]
    if batch:
        return lib.symgen_four_bar_forward_dynamics_batch(batch, *pointers), arrays[3]
    return lib.symgen_four_bar_forward_dynamics(*pointers), arrays[3]


@needs_cc
def test_the_raw_c_function_returns_the_nonfinite_status(four_bar):
    model, lib = four_bar[0], four_bar[2]._library()
    header = (four_bar[3]["c"].files["four_bar.h"])
    assert "#define SYMGEN_NONFINITE 2" in header
    assert _call_forward_dynamics(lib, q0(model), [0.5], [1.0])[0] == 0
    with np.errstate(all="ignore"):
        assert _call_forward_dynamics(lib, q0(model), [1e155], [1.0])[0] == 2       # overflow
        assert _call_forward_dynamics(lib, q0(model), [np.nan], [1.0])[0] == 2      # a NaN argument reaches the output
        assert _call_forward_dynamics(lib, q0(model), [0.5], [np.inf])[0] == 2


@needs_cc
@pytest.mark.parametrize("compiler", ["cc", "clang"])
def test_the_nonfinite_status_survives_fast_math(four_bar, compiler, tmp_path):
    """Built with ``-O2 -ffast-math -march=native`` (which lets a compiler take every double as
    finite and fold ``x - x`` to 0), the output checks still read the bits and return the status:
    the single-state function and the ``_batch`` entry (lanes where the machine has AVX2), whose
    third state overflows."""
    if shutil.which(compiler) is None:
        pytest.skip(f"{compiler} not found")
    model, files = four_bar[0], four_bar[3]["c"].files
    for name, text in files.items():
        (tmp_path / name).write_text(text, encoding="utf-8")
    library, obj = tmp_path / "four_bar_fast.so", tmp_path / "four_bar_fast.o"
    subprocess.run([compiler, "-O2", "-ffast-math", "-march=native", "-std=c99", "-fPIC", "-c",
                    str(tmp_path / "four_bar.c"), "-o", str(obj)], check=True, capture_output=True)
    # linked without -ffast-math: with it the library would bring crtfastmath.o, whose start-up code
    # sets flush-to-zero for the whole test process
    subprocess.run([compiler, "-shared", str(obj), "-o", str(library), "-lm"], check=True, capture_output=True)
    lib = ctypes.CDLL(str(library))
    assert _call_forward_dynamics(lib, q0(model), [0.5], [1.0])[0] == 0
    assert _call_forward_dynamics(lib, q0(model), [1e155], [1.0])[0] == 2        # overflow
    assert _call_forward_dynamics(lib, q0(model), [0.5], [np.inf])[0] == 2
    rates = [[0.5], [0.25], [1e155], [0.75]]
    assert _call_forward_dynamics(lib, np.tile(q0(model), (4, 1)), rates, np.ones((4, 1)), batch=4)[0] == 3
