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
import re
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
    """States per lane group that ``cc -march=native`` compiles here (1: no lanes): 8 with
    AVX-512F, 4 with AVX2."""
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


def compile_pair(spec: str, out: pathlib.Path, flags: tuple[str, ...] = ("-O0",)):
    """``(lanes, scalar, model)``: the scene's default functions compiled both ways, at ``-O0``
    unless ``flags`` say otherwise (what the statements compute is under test here; the optimised
    build's warnings are ``test_the_source_compiles_with_the_strict_flags_at_every_width``'s, and
    -O1 took 38 s on multi_arm:h=3 where -O0 takes 10 s)."""
    model = derive(get_scene(spec))
    lowered = trace_all(model)
    gen = generate(model, "c", lowered=lowered)
    for name, text in gen.files.items():
        (out / name).write_text(text)
    libs = []
    for tag, build in (("lanes", ["-march=native", *flags]), ("scalar", ["-march=native", *flags, "-DSYMGEN_NO_LANES"])):
        path = out / f"{gen.module}_{tag}.so"
        subprocess.run([CC, *STRICT, *build, "-o", str(path), str(out / f"{gen.module}.c"), "-lm"],
                       check=True, capture_output=True, text=True)
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
    _lanes_equal_the_scalar_code(*pair)


@pytest.mark.parametrize("defines", [("-DSYMGEN_LANES_256",), ("-DSYMGEN_VECTOR_512",)])
def test_the_other_widths_equal_the_scalar_code(tmp_path, defines):
    """The 4 lanes an AVX-512F processor takes on request (``-DSYMGEN_LANES_256``) and the 8 angles
    per vector its scalar functions take on request (``-DSYMGEN_VECTOR_512``; on a processor
    without AVX-512F, the default widths again) against the scalar loop, every function of
    ``chain:n=11`` (inputs of 11: whole tiles of 4 or 8 entries and the rest one by one)."""
    _lanes_equal_the_scalar_code(*compile_pair("chain:n=11", tmp_path, ("-O0", *defines)))


@pytest.mark.parametrize("defines, lanes, vector", [((), 8, 4), (("-DSYMGEN_LANES_256",), 4, 4),
                                                    (("-DSYMGEN_VECTOR_512",), 8, 8),
                                                    (("-DSYMGEN_NO_LANES",), 1, 4), (("-DSYMGEN_NO_VECTOR",), 1, 1)])
def test_each_define_gives_its_widths(defines, lanes, vector):
    """The widths the preprocessor picks for an AVX-512F target (``-mavx512f``; AVX2 alone gives 4
    lanes): 8 lanes and 4 angles per scalar vector by default, and what each define asks for."""
    from symgen.codegen.targets import c_lanes
    from symgen.codegen.targets.base import render

    source = render("lanes.c.jinja", uses_sign=False, **c_lanes.trig_context())
    out = subprocess.run([CC, "-mavx512f", *defines, "-dM", "-E", "-x", "c", "-"], input=source,
                         capture_output=True, text=True, check=True).stdout
    found = {m: int(re.search(rf"^#define {m} (\d+)$", out, re.M).group(1)) for m in ("SYMGEN_LANES", "SYMGEN_VECTOR")}
    assert found == {"SYMGEN_LANES": lanes, "SYMGEN_VECTOR": vector}
    avx2 = subprocess.run([CC, "-mavx2", "-dM", "-E", "-x", "c", "-"], input=source, capture_output=True,
                          text=True, check=True).stdout
    assert re.search(r"^#define SYMGEN_LANES 4$", avx2, re.M)


def test_lanes_with_fused_multiply_adds_equal_the_scalar_code(tmp_path):
    """Built as the bindings build it (``-O2 -ffp-contract=fast``), the compiler fuses multiply-adds
    in the lanes and in the scalar code, not always alike: the two still agree to ``TOL`` on every
    function of ``chain:n=11``."""
    _lanes_equal_the_scalar_code(*compile_pair("chain:n=11", tmp_path, ("-O2", "-ffp-contract=fast")))


def _lanes_equal_the_scalar_code(lanes, scalar, model):
    for name in lanes.functions:
        inputs = batch_inputs(model, lanes, name)
        got, want = lanes.batch_status(name, inputs), scalar.batch_status(name, inputs)
        assert got[0] == want[0] == 0, f"{name}: return values {got[0]}, {want[0]}"
        np.testing.assert_array_equal(got[2], want[2])
        for g, w in zip(got[1], want[1], strict=True):
            for i in range(STATES):
                assert relative_error(g[i], w[i]) <= TOL, f"{name}, state {i}"
        np.testing.assert_allclose(got[3], want[3], rtol=1e-9)


def test_the_lane_kernel_is_vector_code_with_sin_and_cos_inline():
    """The lanes are really vector code: the kernel compiled for this processor works on ymm
    registers (zmm with AVX-512F) and calls no sin or cos (the polynomials are inline; only the cold helper for far
    arguments calls the C library); the scalar library has no kernel."""
    if shutil.which("objdump") is None:
        pytest.skip("no objdump here")
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        lanes, scalar, _ = compile_pair("chain:n=2", pathlib.Path(tmp))
        listings = [subprocess.run(["objdump", "-d", "--no-show-raw-insn", lib._name], capture_output=True,
                                   text=True).stdout for lib in (lanes.lib, scalar.lib)]
    kernel = re.compile(r"<symgen_chain_n2_inverse_dynamics_lanes[^>]*>:\n(.*?)\n\n", re.S)
    body = kernel.search(listings[0]).group(1)
    assert ("%zmm" if lane_width() == 8 else "%ymm") in body
    calls = re.findall(r"call\s+\S+\s+<([^>]+)>", body)
    assert not [c for c in calls if re.match(r"(sin|cos|sincos|_ZGV)", c)], calls
    assert kernel.search(listings[1]) is None


@pytest.fixture(scope="module")
def chain(tmp_path_factory):
    return compile_pair("chain:n=6", tmp_path_factory.mktemp("chain6"))


@pytest.fixture(scope="module")
def chain11(tmp_path_factory):
    """Inputs and outputs of 11 entries: whole tiles of 4 or 8 and the rest one by one."""
    return compile_pair("chain:n=11", tmp_path_factory.mktemp("chain11"))


@pytest.fixture(scope="module")
def four_bar(tmp_path_factory):
    return compile_pair("four_bar", tmp_path_factory.mktemp("four_bar"))


def _one_bad_lane(pair, name, bad_lane, spoil, expected):
    """One group of lanes (4 or 8 states; two groups of 4 where a lane past the fourth is spoiled),
    ``spoil(inputs, lane)`` spoils one; that lane has status ``expected``, the others the scalar
    code's outputs and status 0."""
    lanes, scalar, model = pair
    width = max(lane_width(), bad_lane + 1)
    inputs = {k: v[:width].copy() for k, v in batch_inputs(model, lanes, name).items()}
    spoil(inputs, bad_lane)
    ret, outs, status, cond = lanes.batch_status(name, inputs)
    want_ret, want_outs, want_status, want_cond = scalar.batch_status(name, inputs)
    assert list(status) == [expected if i == bad_lane else 0 for i in range(width)]
    assert list(want_status) == list(status)
    assert ret == 1 + bad_lane and lanes.batch(name, inputs)[0] == 1 + bad_lane
    for i in range(width):
        if i != bad_lane:
            for g, w in zip(outs, want_outs, strict=True):
                assert relative_error(g[i], w[i]) <= TOL
                assert np.all(np.isfinite(g[i]))
    if expected == SINGULAR:
        assert cond[bad_lane] == want_cond[bad_lane] and not cond[bad_lane] <= 1e12
    return outs


@pytest.mark.parametrize("count", [1, 5, 7, 10])
def test_a_partial_group_writes_only_its_own_states(chain11, count):
    """The unused lanes of a partial last group write to a scratch row, never past the ``count``
    states: rows after them keep their sentinel, the ``count`` rows are the scalar code's (rows of
    11 entries: whole tiles read and written too)."""
    lanes, scalar, model = chain11
    inputs = batch_inputs(model, lanes, "inverse_dynamics")
    arrays = [np.ascontiguousarray(inputs[n][:count]) for n, _ in lanes.sizes("inverse_dynamics")[0]]
    tau = np.full((count + 8, 11), -7.0)
    status = np.full(count + 8, -1, dtype=np.intc)
    cond = np.full(count + 8, -1.0)
    fn = getattr(lanes.lib, f"symgen_{lanes.module}_inverse_dynamics_batch_status")
    ret = fn(ctypes.c_int(count), *[a.ctypes.data_as(ctypes.c_void_p) for a in arrays + [tau, status, cond]])
    assert ret == 0 and not status[:count].any()
    assert np.all(tau[count:] == -7.0) and np.all(status[count:] == -1) and np.all(cond[count:] == -1.0)
    want = scalar.batch_status("inverse_dynamics", {k: v[:count] for k, v in inputs.items()})[1][0]
    for i in range(count):
        assert relative_error(tau[i], want[i]) <= TOL


#: the largest batch the sanitizer driver runs: every partial group of 4 and of 8 lanes, two groups or more
ASAN_COUNTS = 20


def asan_driver(lib: Library) -> str:
    """A C program calling every function's ``_batch_status`` and ``_batch`` of ``lib``'s source on
    ``count = 1 .. ASAN_COUNTS`` states, each array on the heap with exactly its ``count`` rows (any
    read or write past them lands in AddressSanitizer's red zone). Inputs are smooth functions of
    the index, every state a valid one for an open chain."""
    lines = ["#include <math.h>", "#include <stdlib.h>", f'#include "{lib.module}.h"', "",
             "static double *filled(int n, int seed)", "{",
             "    double *p = malloc(sizeof(double) * (size_t)n);",
             "    for (int i = 0; i < n; ++i) p[i] = 0.5 * sin(0.37 * (i + 1) + seed);",
             "    return p;", "}", "", "int main(void)", "{",
             f"    for (int count = 1; count <= {ASAN_COUNTS}; ++count) {{"]
    for k, name in enumerate(sorted(lib.functions)):
        ins, outs = lib.sizes(name)
        args = [f"i{j}" for j in range(len(ins))] + [f"o{j}" for j in range(len(outs))]
        lines += ["        {"]
        lines += [f"            double *i{j} = filled(count * {size}, {k + j});" for j, (_, size) in enumerate(ins)]
        lines += [f"            double *o{j} = malloc(sizeof(double) * (size_t)count * {int(np.prod(shape))});"
                  for j, (_, shape) in enumerate(outs)]
        lines += ["            int *status = malloc(sizeof(int) * (size_t)count);",
                  "            double *conds = malloc(sizeof(double) * (size_t)count), cond;",
                  f"            symgen_{lib.module}_{name}_batch_status(count, {', '.join(args)}, status, conds);",
                  f"            symgen_{lib.module}_{name}_batch(count, {', '.join(args)}, &cond);",
                  "            free(status); free(conds);"]
        lines += [f"            free({a});" for a in args]
        lines += ["        }"]
    lines += ["    }", "    return 0;", "}", ""]
    return "\n".join(lines)


def test_the_batch_entries_touch_no_byte_past_their_states(chain11, tmp_path):
    """Built with AddressSanitizer (``-fsanitize=address``, this processor's lanes), every
    ``_batch`` and ``_batch_status`` entry of ``chain:n=11`` (rows of 11 entries: whole tiles and
    leftovers) reads and writes only its ``count`` states, for every count up to 20: a tile load or
    a partial group that read one row too many, or a scratch row written past the batch, stops the
    program with a report."""
    result = _run_asan(chain11[0], tmp_path, "detect_leaks=0")
    assert result.returncode == 0, result.stderr[-3000:]
    assert "AddressSanitizer" not in result.stderr


def _run_asan(lib: Library, tmp_path, options: str) -> subprocess.CompletedProcess:
    """:func:`asan_driver` of ``lib`` built with AddressSanitizer and run with ``ASAN_OPTIONS``
    ``options`` (skipped where the compiler cannot link it)."""
    if subprocess.run([CC, "-fsanitize=address", "-x", "c", "-", "-o", str(tmp_path / "probe")],
                      input="int main(void) { return 0; }\n", capture_output=True, text=True).returncode:
        pytest.skip(f"{CC} cannot link AddressSanitizer here")
    source = pathlib.Path(lib.lib._name).parent / f"{lib.module}.c"
    (tmp_path / "driver.c").write_text(asan_driver(lib), encoding="utf-8")
    binary = tmp_path / "driver"
    subprocess.run([CC, "-std=c99", "-O1", "-march=native", "-fsanitize=address", "-fno-omit-frame-pointer",
                    "-I", str(source.parent), str(tmp_path / "driver.c"), str(source), "-lm", "-o", str(binary)],
                   check=True, capture_output=True, text=True)
    # leak checking fails under some tracers and containers: asked for only where a test needs it
    return subprocess.run([str(binary)], capture_output=True, text=True, env={"ASAN_OPTIONS": options})


@pytest.mark.parametrize("blocks", [None, 300], ids=["whole", "cut-into-blocks"])
def test_a_kernel_beyond_the_stack_limit_keeps_its_arrays_on_the_heap(tmp_path, monkeypatch, blocks):
    """With the limit at 0 bytes every lane kernel of ``chain:n=11`` takes its arrays (outputs, their
    scratch rows, the workspace) from the block its ``_batch`` entries allocate: the kernels' stack
    frames shrink (``-fstack-usage``), the lanes still equal the scalar code, and under
    AddressSanitizer no access leaves the block and, where leak checking runs, nothing leaks.
    ``cut-into-blocks``: the functions cut into blocks of 300 statements, so that the workspace
    the blocks share is on the heap too."""
    from symgen.codegen.targets import c_lanes
    from symgen.codegen.targets import target as resolve_target

    default = derive(get_scene("chain:n=11"))
    assert not any((ctx.get("lanes") or {}).get("heap") for ctx in _lane_contexts(default))
    if blocks:
        monkeypatch.setattr(resolve_target("c"), "split_statements", blocks)
        monkeypatch.setattr(resolve_target("c"), "block_statements", blocks)
    monkeypatch.setattr(c_lanes, "LANE_STACK_LIMIT", 0)
    lanes, scalar, model = compile_pair("chain:n=11", tmp_path)
    source = (tmp_path / f"{lanes.module}.c").read_text()
    assert "#include <stdlib.h>" in source and source.count("free(block);") == 2 * len(lanes.functions)
    assert ("symgen_lanes_t *const work = heap + " in source) == bool(blocks)
    _lanes_equal_the_scalar_code(lanes, scalar, model)
    if blocks:
        result = _run_asan(lanes, tmp_path, "detect_leaks=0")
        assert result.returncode == 0 and "AddressSanitizer" not in result.stderr, result.stderr[-3000:]
        return
    frames = {}
    for tag, limit in (("heap", 0), ("stack", 64 * 1024)):
        monkeypatch.setattr(c_lanes, "LANE_STACK_LIMIT", limit)
        gen = generate(model, "c", lowered=trace_all(model, ["mass_matrix"]))
        folder = tmp_path / tag
        folder.mkdir()
        for name, text in gen.files.items():
            (folder / name).write_text(text)
        subprocess.run([CC, "-std=c99", "-O2", "-march=native", "-fstack-usage", "-c", str(folder / f"{gen.module}.c"),
                        "-o", str(folder / "m.o")], check=True, capture_output=True, text=True, cwd=folder)
        usage = (folder / "m.su").read_text()
        frames[tag] = max(int(line.split("\t")[1]) for line in usage.splitlines() if "mass_matrix_lanes" in line)
    assert frames["heap"] < frames["stack"] - 64 * 121 // 2, frames      # M's 121 vectors left the frame
    monkeypatch.setattr(c_lanes, "LANE_STACK_LIMIT", 0)
    result = _run_asan(lanes, tmp_path, "detect_leaks=1")
    if "LeakSanitizer has encountered a fatal error" in result.stderr:
        result = _run_asan(lanes, tmp_path, "detect_leaks=0")
    assert result.returncode == 0, result.stderr[-3000:]
    assert "AddressSanitizer" not in result.stderr and "LeakSanitizer" not in result.stderr


def _lane_contexts(model) -> list[dict]:
    """The C target's function contexts of ``model``'s default functions."""
    from symgen.codegen.generate import module_name
    from symgen.codegen.targets import target as resolve_target

    target = resolve_target("c")
    return [target.function_context(low, module_name(model.scene.name)) for low in trace_all(model)]


@pytest.mark.parametrize("bad_lane", [0, 2, 3, 7])
def test_a_non_finite_output_marks_its_own_lane(chain, bad_lane):
    def spoil(inputs, lane):
        inputs["qd"][lane, :] = 1e200           # qd^2 overflows in the velocity products
    _one_bad_lane(chain, "inverse_dynamics", bad_lane, spoil, NONFINITE)


@pytest.mark.parametrize("bad_lane", [1, 2, 6])
def test_a_singular_pivot_marks_its_own_lane(four_bar, bad_lane):
    """A NaN coordinate makes the loop matrix's pivots NaN in one lane: that lane is singular
    (with an infinite estimate), the others are computed as the scalar code computes them."""
    def spoil(inputs, lane):
        inputs["q"][lane, :] = np.nan
    _one_bad_lane(four_bar, "inverse_dynamics", bad_lane, spoil, SINGULAR)


def test_batch_reports_the_first_failing_state(chain):
    lanes, scalar, model = chain
    inputs = batch_inputs(model, lanes, "inverse_dynamics")
    inputs["qdd"][9, 0] = np.inf
    inputs["qdd"][6, 1] = np.nan
    assert lanes.batch("inverse_dynamics", inputs)[0] == scalar.batch("inverse_dynamics", inputs)[0] == 7


@pytest.fixture(scope="module")
def products(tmp_path_factory):
    """chain:n=14's inverse-dynamics Jacobians in closed form, its entries by library products
    (105 ancestor pairs), compiled both ways as the scenes are."""
    from symgen.codegen import dynamics_derivatives
    from symgen.codegen.emit import lower

    out = tmp_path_factory.mktemp("products")
    model = derive(get_scene("chain:n=14"))
    assert dynamics_derivatives.loops_entries(model.tree)
    lowered = [lower(dynamics_derivatives._traced_analytic(model))]
    assert len(lowered[0].ops["products"]) == 5
    gen = generate(model, "c", lowered=lowered)
    for name, text in gen.files.items():
        (out / name).write_text(text)
    assert "symgen_lanes_product(" in gen.files[f"{gen.module}.c"]
    libs = []
    for tag, build in (("lanes", ["-march=native"]), ("scalar", ["-march=native", "-DSYMGEN_NO_LANES"])):
        path = out / f"{gen.module}_{tag}.so"
        subprocess.run([CC, *STRICT, "-O0", *build, "-o", str(path), str(out / f"{gen.module}.c"), "-lm"],
                       check=True, capture_output=True, text=True)
        libs.append(Library(path, gen.module, lowered))
    return libs[0], libs[1], model


def test_banded_products_run_over_the_lanes(products):
    """A function with library products keeps its lane kernel (``symgen_lanes_product``): the lanes
    equal the scalar loop, and a state whose output overflows marks its own lane."""
    _lanes_equal_the_scalar_code(*products)

    def spoil(inputs, lane):
        inputs["qd"][lane, :] = 1e200
    _one_bad_lane(products, "inverse_dynamics_derivatives", 1, spoil, NONFINITE)


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
@pytest.mark.parametrize("flags", [[], ["-march=native"], ["-mavx2"], ["-mavx512f"], ["-mavx512f", "-DSYMGEN_LANES_256"],
                                   ["-mavx512f", "-DSYMGEN_VECTOR_512"]])
def test_the_source_compiles_with_the_strict_flags_at_every_width(four_bar, compiler, flags, tmp_path):
    """Scalar, this processor's lanes, AVX2's 4 lanes, AVX-512F processors' default (8 lanes), the
    4 lanes and the 8 angles per scalar vector they take on request (compiled, not run), with GCC and
    Clang (which warns of unused static inline functions) alike."""
    if shutil.which(compiler) is None:
        pytest.skip(f"no {compiler} here")
    source = next(pathlib.Path(four_bar[0].lib._name).parent.glob("*.c"))
    result = subprocess.run([compiler, *STRICT, *flags, "-o", str(tmp_path / "x.so"), str(source), "-lm"],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr


# ---------------------------------------------------------------------------------------------
# sin and cos in the lanes (symgen_lanes_sincos) against 50-digit sin and cos

#: largest error of the lanes' sin and cos on |x| <= 2^20, in units of 2^-53 max(|f(x)|, 2^-10)
#: (relative where the value is not small, absolute near a zero of sin or cos); 1.84 measured
TRIG_ULPS = 2.0
TRIG_DRIVER = r"""
#include <math.h>
#include <stddef.h>
#define SYMGEN_SINGULAR 1
#define SYMGEN_NONFINITE 2
{lanes}
#if SYMGEN_LANES > 1
void lanes_sincos(int n, const double *x, double *s, double *c)
{{
    for (int i = 0; i + SYMGEN_LANES <= n; i += SYMGEN_LANES) {{
        symgen_lanes_t v;
        for (int l = 0; l < SYMGEN_LANES; ++l) v[l] = x[i + l];
        const symgen_lanes_t a = symgen_lanes_sin(v), b = symgen_lanes_cos(v);
        for (int l = 0; l < SYMGEN_LANES; ++l) {{ s[i + l] = a[l]; c[i + l] = b[l]; }}
    }}
}}
#endif
{scalar}
void scalar_sincos(int n, const double *x, double *s, double *c)
{{
    for (int i = 0; i < n; ++i) {{ s[i] = symgen_sin(x[i]); c[i] = symgen_cos(x[i]); }}
}}
/* symgen_sincos_n in groups of m angles (the last group shorter), as a scalar function calls it */
void grouped_sincos(int m, int n, const double *x, double *s, double *c)
{{
    for (int i = 0; i < n; i += m) symgen_sincos_n(i + m <= n ? m : n - i, x + i, s + i, c + i);
}}
"""


def _trig_library(tmp_path, sin_coefficients=None, defines=()):
    from symgen.codegen.targets import c_lanes
    from symgen.codegen.targets.base import render

    context = c_lanes.trig_context()
    if sin_coefficients is not None:
        context["sin_first"] = repr(float(sin_coefficients[0]))
        context["sin_tail"] = c_lanes.horner(sin_coefficients[1:])
    source = tmp_path / "trig.c"
    source.write_text(TRIG_DRIVER.format(lanes=render("lanes.c.jinja", uses_sign=False, **context),
                                         scalar=render("trig.c.jinja", **context)))
    path = tmp_path / "trig.so"
    subprocess.run([CC, *STRICT, "-march=native", *defines, "-o", str(path), str(source), "-lm"], check=True,
                   capture_output=True, text=True)
    return ctypes.CDLL(str(path))


def _trig_points() -> np.ndarray:
    rng = np.random.default_rng(11)
    half_pi = np.arange(-200, 201) * (np.pi / 2)
    big = np.arange(1, 101) * 10007.0 * (np.pi / 2)       # up to 1.57e6: the last third beyond 2^20
    x = np.concatenate([rng.uniform(-np.pi / 4, np.pi / 4, 2000), rng.uniform(-8, 8, 2000),
                        rng.uniform(-2.0 ** 20, 2.0 ** 20, 1000), half_pi, np.nextafter(half_pi, np.inf), big,
                        [0.0, -0.0, 1e-300, -5e-324, 2.0 ** 20, -2.0 ** 20, np.nextafter(2.0 ** 20, np.inf),
                         1e300, np.inf, -np.inf, np.nan]])
    return np.concatenate([x, np.zeros(-len(x) % 8)])


def _trig_errors(lib, x):
    """``(sin, cos)`` of the lanes at ``x`` and their errors against mpmath (50 digits), in
    units of 2^-53 max(|f(x)|, 2^-10), over the lanes with |x| <= 2^20."""
    import mpmath

    s, c = np.empty_like(x), np.empty_like(x)
    lib.lanes_sincos(ctypes.c_int(len(x)), *[a.ctypes.data_as(ctypes.c_void_p) for a in (x, s, c)])
    errors = []
    with mpmath.workdps(50):
        for got, f in ((s, mpmath.sin), (c, mpmath.cos)):
            worst = 0.0
            for xi, gi in zip(x, got):
                if np.isfinite(xi) and abs(xi) <= 2.0 ** 20:
                    exact = f(mpmath.mpf(float(xi)))
                    scale = max(abs(float(exact)), 2.0 ** -10) * 2.0 ** -53
                    worst = max(worst, float(abs(mpmath.mpf(float(gi)) - exact)) / scale)
            errors.append(worst)
    return s, c, errors


@pytest.mark.parametrize("defines", [(), ("-DSYMGEN_LANES_256",), ("-O2", "-ffp-contract=fast")])
def test_the_lanes_sin_and_cos_are_within_two_units_of_the_last_place(tmp_path, defines):
    """sin and cos of the lanes, inline polynomials, against 50-digit sin and cos on |x| <= 2^20
    (uniform points, multiples of pi/2 and their neighbours); beyond 2^20, infinite or NaN, the C
    library's own sin and cos (Python's math module calls the same), bit for bit; in this
    processor's lanes, in the 4 an AVX-512F processor takes on request, and with multiply-adds
    fused as the bindings build them."""
    import math

    lib = _trig_library(tmp_path, defines=defines)
    x = _trig_points()
    s, c, errors = _trig_errors(lib, x)
    assert max(errors) <= TRIG_ULPS, errors
    far = ~(np.abs(x) <= 2.0 ** 20)
    assert far.sum() >= 35
    for xi, si, ci in zip(x[far], s[far], c[far]):
        if np.isfinite(xi):
            assert si == math.sin(xi) and ci == math.cos(xi), xi
        else:
            assert np.isnan(si) and np.isnan(ci)


def test_the_scalar_sin_and_cos_are_the_lanes_bit_for_bit(tmp_path):
    """``symgen_sin``/``symgen_cos`` of the scalar functions (``trig.c.jinja``) give the lanes'
    bits at every point of the lanes' accuracy check (so they share its bound), the C library's
    beyond 2^20 and NaN for infinite or NaN arguments."""
    lib = _trig_library(tmp_path)
    x = _trig_points()
    s, c, _ = _trig_errors(lib, x)
    s1, c1 = np.empty_like(x), np.empty_like(x)
    lib.scalar_sincos(ctypes.c_int(len(x)), *[a.ctypes.data_as(ctypes.c_void_p) for a in (x, s1, c1)])
    finite = np.isfinite(x)
    assert np.array_equal(s1[finite].view(np.int64), s[finite].view(np.int64))
    assert np.array_equal(c1[finite].view(np.int64), c[finite].view(np.int64))
    assert np.isnan(s1[~finite]).all() and np.isnan(c1[~finite]).all()


@pytest.mark.parametrize("defines", [(), ("-DSYMGEN_NO_LANES",), ("-DSYMGEN_NO_VECTOR",), ("-DSYMGEN_LIBM_TRIG",),
                                     ("-DSYMGEN_VECTOR_512",)])
def test_sines_and_cosines_taken_together_are_the_scalar_ones_bit_for_bit(tmp_path, defines):
    """A scalar function takes its angles' sin and cos several per vector kernel
    (``symgen_sincos_n``, :mod:`symgen.codegen.targets.c_trig`): in groups of 1 to 9 angles (full
    and partial vectors), at every point of the accuracy check, each value has the bits of
    ``symgen_sin``/``symgen_cos`` one at a time (NaN for infinite or NaN), with the lanes, without
    them and with the C library's functions."""
    lib = _trig_library(tmp_path, defines=defines)
    x = _trig_points()
    pointers = lambda *arrays: [a.ctypes.data_as(ctypes.c_void_p) for a in arrays]  # noqa: E731
    s1, c1 = np.empty_like(x), np.empty_like(x)
    lib.scalar_sincos(ctypes.c_int(len(x)), *pointers(x, s1, c1))
    finite = np.isfinite(x)
    for m in range(1, 10):
        s, c = np.full_like(x, 7.0), np.full_like(x, 7.0)
        lib.grouped_sincos(ctypes.c_int(m), ctypes.c_int(len(x)), *pointers(x, s, c))
        assert np.array_equal(s[finite].view(np.int64), s1[finite].view(np.int64)), m
        assert np.array_equal(c[finite].view(np.int64), c1[finite].view(np.int64)), m
        assert np.isnan(s[~finite]).all() and np.isnan(c[~finite]).all(), m


def test_symgen_libm_trig_makes_the_scalar_functions_call_the_c_library(tmp_path):
    """With -DSYMGEN_LIBM_TRIG the scalar sin and cos are the C library's (Python's math module
    calls the same), bit for bit, at every point of the accuracy check."""
    import math

    lib = _trig_library(tmp_path, defines=("-DSYMGEN_LIBM_TRIG",))
    x = _trig_points()
    s, c = np.empty_like(x), np.empty_like(x)
    lib.scalar_sincos(ctypes.c_int(len(x)), *[a.ctypes.data_as(ctypes.c_void_p) for a in (x, s, c)])
    for xi, si, ci in zip(x, s, c):
        if np.isfinite(xi):
            assert si == math.sin(xi) and ci == math.cos(xi), xi
        else:
            assert np.isnan(si) and np.isnan(ci)


def test_the_sin_and_cos_check_catches_a_wrong_coefficient(tmp_path):
    """The polynomials are what the check measures: one sin coefficient off by 1e-9 relative
    (the r^7 term) puts the error far above the bound."""
    from symgen.codegen.targets.c_lanes import SIN_COEFFICIENTS

    wrong = list(SIN_COEFFICIENTS)
    wrong[2] *= 1 + 1e-9
    _, _, errors = _trig_errors(_trig_library(tmp_path, wrong), _trig_points())
    assert errors[0] > 10 * TRIG_ULPS


def test_the_trig_coefficients_are_the_fits_they_cite():
    """SIN_COEFFICIENTS and COS_COEFFICIENTS are mpmath's Chebyshev fits, each within 2.1e-17."""
    from symgen.codegen.targets.c_lanes import COS_COEFFICIENTS, SIN_COEFFICIENTS, fit_trig

    p, q, ep, eq = fit_trig()
    assert p == SIN_COEFFICIENTS and q == COS_COEFFICIENTS
    assert ep <= 2.1e-17 and eq <= 2.1e-17


def test_runs_of_sines_and_cosines_become_one_call_per_run():
    """:func:`~symgen.codegen.targets.c_trig.batch_trig`: a run of consecutive sin/cos statements
    becomes one ``sincos`` step over its distinct angles (sin and cos of one angle share it); a
    statement reading the run's own result starts a new run; a lone one stays a statement."""
    from symgen.codegen.emit import Lowered, Ref, Step
    from symgen.codegen.targets.c_trig import batch_trig

    q = lambda i: Ref("in", ("q", i))  # noqa: E731
    tmp = lambda name: Ref("tmp", name)  # noqa: E731
    steps = [Step("op", "c_a", op="cos", args=(q(0),)), Step("op", "s_a", op="sin", args=(q(0),)),
             Step("op", "c_b", op="cos", args=(q(1),)), Step("op", "u", op="sin", args=(tmp("c_b"),)),
             Step("op", "t0", op="mul", args=(tmp("u"), q(2))), Step("op", "v", op="sin", args=(tmp("t0"),))]
    out = batch_trig(Lowered(None, steps, [], {}))
    assert [s.kind for s in out.steps] == ["sincos", "op", "op", "op"]
    first = out.steps[0]
    assert [a.data for a in first.args] == [("q", 0), ("q", 1)]
    assert first.outputs == (("c_a", "cos", 0), ("s_a", "sin", 0), ("c_b", "cos", 1))
    assert [s.name for s in out.steps[1:]] == ["u", "t0", "v"]


def test_a_scalar_function_takes_its_joint_angles_in_one_call():
    """The generated chain's inverse dynamics evaluates the sines and cosines of its five joint
    angles in one ``symgen_sincos_n`` call, none one at a time but in the build without vectors."""
    gen = generate(derive(get_scene("chain:n=6")), "c", ["inverse_dynamics"])
    source = gen.files[f"{gen.module}.c"]
    body = source[source.index(f"int symgen_{gen.module}_inverse_dynamics("):]
    body = body[:body.index("\n}\n")]
    assert body.count("symgen_sincos_n(5, ") == 1
    vector, scalar = body.split("#if SYMGEN_VECTOR_TRIG")[1].split("#endif")[0].split("#else")
    assert "symgen_sincos_n(5, " in vector and "symgen_sin(" not in vector and "symgen_cos(" not in vector
    assert scalar.count("symgen_sin(") == scalar.count("symgen_cos(") == 5
    assert "symgen_sin(" not in body.replace(scalar, "")


def test_a_lane_kernel_asks_the_kernel_once_per_angle_for_what_it_reads():
    """In the lanes a ``sincos`` step is one ``symgen_lanes_sincos`` call per distinct angle,
    passing a null for a result no statement reads (a repeated result is a copy); the generated
    chain's lane kernel takes each joint angle's sine and cosine from one call."""
    from symgen.codegen.emit import Ref, Step
    from symgen.codegen.targets.c_lanes import LanePrinter, _sincos

    q = lambda i: Ref("in", ("q", i))  # noqa: E731
    step = Step("sincos", "symgen_trig0", args=(q(0), q(1), q(2)), n=3,
                outputs=(("c_a", "cos", 0), ("s_a", "sin", 0), ("s_b", "sin", 1), ("c_c", "cos", 2),
                         ("c_c2", "cos", 2)))
    assert _sincos(step, LanePrinter()) == [
        "symgen_lanes_t s_a, c_a;", "symgen_lanes_sincos(q[0], &s_a, &c_a);",
        "symgen_lanes_t s_b;", "symgen_lanes_sincos(q[1], &s_b, (symgen_lanes_t *)0);",
        "symgen_lanes_t c_c;", "symgen_lanes_sincos(q[2], (symgen_lanes_t *)0, &c_c);",
        "const symgen_lanes_t c_c2 = c_c;"]
    gen = generate(derive(get_scene("chain:n=6")), "c", ["inverse_dynamics"])
    source = gen.files[f"{gen.module}.c"]
    kernel = source[source.index(f"static void symgen_{gen.module}_inverse_dynamics_lanes("):]
    kernel = kernel[:kernel.index("\n}\n")]
    assert kernel.count("symgen_lanes_sincos(q[") == 5
    assert "symgen_lanes_sin(" not in kernel and "symgen_lanes_cos(" not in kernel


@pytest.mark.parametrize("spec", ["chain:n=6", "four_bar"])
def test_every_function_gives_the_same_bits_with_its_sines_taken_together(spec, tmp_path):
    """The default functions compiled with ``-DSYMGEN_NO_LANES`` (``_batch`` loops over the scalar
    function, which takes its sines and cosines together in vectors) and with
    ``-DSYMGEN_NO_VECTOR`` (one at a time, the statements the vector call replaced): every output
    at 8 loop-closed states, bit for bit."""
    model = derive(get_scene(spec))
    lowered = trace_all(model)
    gen = generate(model, "c", lowered=lowered)
    for name, text in gen.files.items():
        (tmp_path / name).write_text(text)
    assert "symgen_sincos_n(" in gen.files[f"{gen.module}.c"].split("symgen_sincos_n(int n")[1]
    libs = []
    for tag, flag in (("vector", "-DSYMGEN_NO_LANES"), ("one", "-DSYMGEN_NO_VECTOR")):
        path = tmp_path / f"{gen.module}_{tag}.so"
        subprocess.run([CC, *STRICT, "-march=native", flag, "-o", str(path), str(tmp_path / f"{gen.module}.c"),
                        "-lm"], check=True, capture_output=True, text=True)
        libs.append(Library(path, gen.module, lowered))
    for name in libs[0].functions:
        inputs = {k: v[:8] for k, v in batch_inputs(model, libs[0], name).items()}
        (_, got, status, _), (_, want, want_status, _) = (lib.batch_status(name, inputs) for lib in libs)
        assert list(status) == list(want_status) == [0] * 8, name
        for g, w in zip(got, want, strict=True):
            assert g.tobytes() == w.tobytes(), name
