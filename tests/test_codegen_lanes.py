"""Lanes across states in the generated C (``symgen.codegen.targets.c_lanes``): the ``_batch``
entry points compiled for AVX2/AVX-512 equal the scalar generated code, state by state, and each
lane's status (singular, non-finite) is its own.

Each scene's C source is compiled twice with the strict flags, once for this processor
(``-march=native``: the lanes) and once with ``-DSYMGEN_NO_LANES`` (the scalar loop over the
single-state function), and both libraries run the same states through ``_batch_status``.
"""
from __future__ import annotations

import ctypes
import functools
import pathlib
import shutil
import subprocess

import numpy as np
import pytest

from symgen.codegen.generate import generate, trace_all
from symgen.codegen.reference import reference_states
from symgen.io.builtin import get_scene
from symgen.model import derive

from .codegen_util import SCENES, relative_error

CC = shutil.which("cc") or "cc"
STRICT = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic", "-O1", "-fPIC", "-shared"]
#: lanes against the scalar generated code, normwise relative per state
TOL = 1e-13
#: states per batch: two full groups of 4 (one of 8) and a partial one
STATES = 11
SINGULAR, NONFINITE = 1, 2


@functools.lru_cache(maxsize=1)
def lane_width() -> int:
    """States per lane group that ``cc -march=native`` compiles here (1: no lanes)."""
    out = subprocess.run([CC, "-march=native", "-dM", "-E", "-x", "c", "/dev/null"], capture_output=True,
                         text=True).stdout
    return 8 if "__AVX512F__" in out else 4 if "__AVX2__" in out else 1


pytestmark = pytest.mark.skipif(lane_width() == 1, reason="the compiler targets no AVX2 here: no lanes to test")


class Library:
    """One compiled generated source: ``_batch_status`` and ``_batch`` of every function."""

    def __init__(self, path: pathlib.Path, module: str, lowered):
        self.lib = ctypes.CDLL(str(path))
        self.module = module
        self.functions = {low.function.name: low for low in lowered}

    def sizes(self, name):
        low = self.functions[name]
        return ([(a.name, a.size) for a in low.function.inputs],
                [(arg.name, tuple(arg.shape)) for arg, _ in low.outputs])

    def batch_status(self, name, inputs: dict):
        """``(return value, outputs, status, cond)`` of ``_batch_status`` over the batch ``inputs``."""
        ins, outs = self.sizes(name)
        arrays = [np.ascontiguousarray(inputs[n], dtype=float) for n, _ in ins]
        count = len(arrays[0])
        results = [np.full((count,) + shape, -7.0) for _, shape in outs]
        status = np.full(count, -1, dtype=np.intc)
        cond = np.full(count, -1.0)
        fn = getattr(self.lib, f"symgen_{self.module}_{name}_batch_status")
        fn.restype = ctypes.c_int
        ret = fn(ctypes.c_int(count), *[a.ctypes.data_as(ctypes.c_void_p) for a in arrays + results],
                 status.ctypes.data_as(ctypes.c_void_p), cond.ctypes.data_as(ctypes.c_void_p))
        return ret, results, status, cond

    def batch(self, name, inputs: dict):
        """The return value of ``_batch`` and its ``*cond``."""
        ins, outs = self.sizes(name)
        arrays = [np.ascontiguousarray(inputs[n], dtype=float) for n, _ in ins]
        count = len(arrays[0])
        results = [np.empty((count,) + shape) for _, shape in outs]
        cond = np.zeros(1)
        fn = getattr(self.lib, f"symgen_{self.module}_{name}_batch")
        return fn(ctypes.c_int(count), *[a.ctypes.data_as(ctypes.c_void_p) for a in arrays + results],
                  cond.ctypes.data_as(ctypes.c_void_p)), float(cond[0])


def compile_pair(spec: str, out: pathlib.Path):
    """``(lanes, scalar, model)``: the scene's default functions compiled both ways."""
    model = derive(get_scene(spec))
    lowered = trace_all(model)
    gen = generate(model, "c", lowered=lowered)
    for name, text in gen.files.items():
        (out / name).write_text(text)
    libs = []
    for tag, flags in (("lanes", ["-march=native"]), ("scalar", ["-march=native", "-DSYMGEN_NO_LANES"])):
        path = out / f"{gen.module}_{tag}.so"
        subprocess.run([CC, *STRICT, *flags, "-o", str(path), str(out / f"{gen.module}.c"), "-lm"], check=True,
                       capture_output=True, text=True)
        libs.append(Library(path, gen.module, lowered))
    return libs[0], libs[1], model


_STATES: dict = {}


def _states(model, seed: int) -> list:
    key = (id(model), seed)
    if key not in _STATES:
        _STATES[key] = (model, reference_states(model, STATES, seed=seed))
    return _STATES[key][1]


def batch_inputs(model, lib: Library, name: str, seed: int = 3) -> dict:
    """Loop-closed states (:func:`reference_states`), one row per state, for ``name``'s inputs."""
    states = _states(model, seed)
    ins, _ = lib.sizes(name)
    return {n: np.stack([np.asarray(s[n], dtype=float) for s in states]) for n, _ in ins}


#: the largest sources take minutes to compile twice
HEAVY = {"multi_arm:h=3", "stewart"}


@pytest.fixture(scope="module", params=[pytest.param(s, marks=pytest.mark.slow) if s in HEAVY else s
                                        for s in SCENES])
def pair(request, tmp_path_factory):
    out = tmp_path_factory.mktemp(request.param.replace(":", "_").replace("=", ""))
    return compile_pair(request.param, out)


def test_lanes_equal_the_scalar_code_on_every_function(pair):
    lanes, scalar, model = pair
    for name in lanes.functions:
        inputs = batch_inputs(model, lanes, name)
        got, want = lanes.batch_status(name, inputs), scalar.batch_status(name, inputs)
        assert got[0] == want[0] == 0, f"{name}: return values {got[0]}, {want[0]}"
        np.testing.assert_array_equal(got[2], want[2])
        for g, w in zip(got[1], want[1], strict=True):
            for i in range(STATES):
                assert relative_error(g[i], w[i]) <= TOL, f"{name}, state {i}"
        np.testing.assert_allclose(got[3], want[3], rtol=1e-9)


def test_the_lane_library_calls_the_vector_sine():
    """The lanes are really vector code: the library compiled for this processor calls glibc's
    vector sine (a scalar loop would call ``sin``), the scalar one does not."""
    if not (pathlib.Path("/lib/x86_64-linux-gnu/libmvec.so.1").exists() or
            pathlib.Path("/usr/lib/x86_64-linux-gnu/libmvec.so.1").exists()):
        pytest.skip("no glibc libmvec here")
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        lanes, scalar, _ = compile_pair("chain:n=2", pathlib.Path(tmp))
        symbols = [subprocess.run(["nm", "-D", lib._name], capture_output=True, text=True).stdout
                   for lib in (lanes.lib, scalar.lib)]
    name = "_ZGVeN8v_sin" if lane_width() == 8 else "_ZGVdN4v_sin"
    assert name in symbols[0] and name not in symbols[1]


@pytest.fixture(scope="module")
def chain(tmp_path_factory):
    return compile_pair("chain:n=6", tmp_path_factory.mktemp("chain6"))


@pytest.fixture(scope="module")
def four_bar(tmp_path_factory):
    return compile_pair("four_bar", tmp_path_factory.mktemp("four_bar"))


def _one_bad_lane(pair, name, bad_lane, spoil, expected):
    """Four states, ``spoil(inputs, lane)`` spoils one; that lane has status ``expected``, the
    other three the scalar code's outputs and status 0."""
    lanes, scalar, model = pair
    inputs = {k: v[:4].copy() for k, v in batch_inputs(model, lanes, name).items()}
    spoil(inputs, bad_lane)
    ret, outs, status, cond = lanes.batch_status(name, inputs)
    want_ret, want_outs, want_status, want_cond = scalar.batch_status(name, inputs)
    assert list(status) == [expected if i == bad_lane else 0 for i in range(4)]
    assert list(want_status) == list(status)
    assert ret == 1 + bad_lane and lanes.batch(name, inputs)[0] == 1 + bad_lane
    for i in range(4):
        if i != bad_lane:
            for g, w in zip(outs, want_outs, strict=True):
                assert relative_error(g[i], w[i]) <= TOL
                assert np.all(np.isfinite(g[i]))
    if expected == SINGULAR:
        assert cond[bad_lane] == want_cond[bad_lane] and not cond[bad_lane] <= 1e12
    return outs


@pytest.mark.parametrize("count", [1, 5, 7])
def test_a_partial_group_writes_only_its_own_states(chain, count):
    """The unused lanes of a partial last group write to a scratch row, never past the ``count``
    states: rows after them keep their sentinel, the ``count`` rows are the scalar code's."""
    lanes, scalar, model = chain
    inputs = batch_inputs(model, lanes, "inverse_dynamics")
    arrays = [np.ascontiguousarray(inputs[n][:count]) for n, _ in lanes.sizes("inverse_dynamics")[0]]
    tau = np.full((count + 8, 6), -7.0)
    status = np.full(count + 8, -1, dtype=np.intc)
    cond = np.full(count + 8, -1.0)
    fn = getattr(lanes.lib, f"symgen_{lanes.module}_inverse_dynamics_batch_status")
    ret = fn(ctypes.c_int(count), *[a.ctypes.data_as(ctypes.c_void_p) for a in arrays + [tau, status, cond]])
    assert ret == 0 and not status[:count].any()
    assert np.all(tau[count:] == -7.0) and np.all(status[count:] == -1) and np.all(cond[count:] == -1.0)
    want = scalar.batch_status("inverse_dynamics", {k: v[:count] for k, v in inputs.items()})[1][0]
    for i in range(count):
        assert relative_error(tau[i], want[i]) <= TOL


@pytest.mark.parametrize("bad_lane", [0, 2, 3])
def test_a_non_finite_output_marks_its_own_lane(chain, bad_lane):
    def spoil(inputs, lane):
        inputs["qd"][lane, :] = 1e200           # qd^2 overflows in the velocity products
    _one_bad_lane(chain, "inverse_dynamics", bad_lane, spoil, NONFINITE)


@pytest.mark.parametrize("bad_lane", [1, 2])
def test_a_singular_pivot_marks_its_own_lane(four_bar, bad_lane):
    """A NaN coordinate makes the loop matrix's pivots NaN in one lane: that lane is singular
    (with an infinite estimate), the three others are computed as the scalar code computes them."""
    def spoil(inputs, lane):
        inputs["q"][lane, :] = np.nan
    _one_bad_lane(four_bar, "inverse_dynamics", bad_lane, spoil, SINGULAR)


def test_batch_reports_the_first_failing_state(chain):
    lanes, scalar, model = chain
    inputs = batch_inputs(model, lanes, "inverse_dynamics")
    inputs["qdd"][9, 0] = np.inf
    inputs["qdd"][6, 1] = np.nan
    assert lanes.batch("inverse_dynamics", inputs)[0] == scalar.batch("inverse_dynamics", inputs)[0] == 7


def test_a_function_with_a_library_lu_keeps_the_scalar_loop(tmp_path):
    """The dense route of chain:n=17's forward dynamics factors M (17 x 17) by the library LU: no
    lane kernel; its _batch entry points still compile with the lanes on and give the scalar
    function's numbers."""
    model = derive(get_scene("chain:n=17"))
    lowered = trace_all(model, ["forward_dynamics"], {"method": "dense"})
    assert lowered[0].ops["factorizations"] == [17]
    gen = generate(model, "c", lowered=lowered)
    (tmp_path / f"{gen.module}.c").write_text(gen.files[f"{gen.module}.c"])
    (tmp_path / f"{gen.module}.h").write_text(gen.files[f"{gen.module}.h"])
    assert "symgen_chain_n17_forward_dynamics_lanes" not in gen.files[f"{gen.module}.c"]
    path = tmp_path / "lu.so"
    subprocess.run([CC, *STRICT, "-march=native", "-o", str(path), str(tmp_path / f"{gen.module}.c"), "-lm"],
                   check=True, capture_output=True, text=True)
    lib = Library(path, gen.module, lowered)
    rng = np.random.default_rng(2)
    inputs = {n: rng.uniform(-1, 1, (STATES, size)) for n, size in lib.sizes("forward_dynamics")[0]}
    ret, (dv,), status, _ = lib.batch_status("forward_dynamics", inputs)
    assert ret == 0 and not status.any()
    single = getattr(lib.lib, f"symgen_{gen.module}_forward_dynamics")
    for i in range(STATES):
        out = np.empty(17)
        args = [np.ascontiguousarray(inputs[n][i]) for n, _ in lib.sizes("forward_dynamics")[0]] + [out]
        assert single(*[a.ctypes.data_as(ctypes.c_void_p) for a in args], None) == 0
        np.testing.assert_array_equal(dv[i], out)


@pytest.mark.parametrize("compiler", ["cc", "clang"])
@pytest.mark.parametrize("flags", [[], ["-march=native"], ["-mavx512f"]])
def test_the_source_compiles_with_the_strict_flags_at_every_width(four_bar, compiler, flags, tmp_path):
    """Scalar, this processor's lanes and the AVX-512F lanes (compiled, not run), with GCC and
    Clang (which warns of unused static inline functions) alike."""
    if shutil.which(compiler) is None:
        pytest.skip(f"no {compiler} here")
    source = next(pathlib.Path(four_bar[0].lib._name).parent.glob("*.c"))
    result = subprocess.run([compiler, *STRICT, *flags, "-o", str(tmp_path / "x.so"), str(source), "-lm"],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
