"""The scan product of the tracing graph (symgen.codegen.graph_products.ScanProduct): ``D^T W`` for a
matrix ``D`` of two low-rank triangles, without forming ``D``. Its sampled values and the generated C
(groups of 8 rows, partial tiles, the rows beyond the last group, the plain-C fallback; by every
compiler there is, with the strict flags) and NumPy against forming ``D`` in NumPy; its flop count by
hand; its refusals. The forward-dynamics Jacobians of a serial chain that use it are checked against
50-digit central differences, with a planted error caught."""
from __future__ import annotations

import ctypes
import shutil
import subprocess

import numpy as np
import pytest

import symgen
from symgen.codegen import dynamics_derivatives, sparse_lu
from symgen.codegen.catalogue import build_function
from symgen.codegen.emit import lower
from symgen.codegen.functions import Argument, Function
from symgen.codegen.generate import generate, trace_all
from symgen.codegen.graph import Graph
from symgen.codegen.graph_products import SCAN_TERMS
from symgen.codegen.reference import reference_states
from symgen.codegen.runtime import call_by_name, load_generated

from .codegen_util import STRICT, loop_builds, relative_error
from .test_c_products import _SourceOnly
from .test_codegen_derivatives import FD_TOL

PL, PU = 3, 2


def _formed(w, rl, cl, ru, cu):
    """``D^T W`` with ``D`` formed: ``D[j, i] = rl_j . cl_i`` for ``j >= i``, ``ru_j . cu_i`` below."""
    n = w.shape[-2]
    lower, upper = rl @ np.swapaxes(cl, -1, -2), ru @ np.swapaxes(cu, -1, -2)
    d = np.where(np.tri(n, dtype=bool), lower, upper)
    return np.swapaxes(d, -1, -2) @ w


def _traced(n, k, pl=PL, pu=PU, zero=None):
    """A scan product of inputs; ``zero`` (``"rl"``, ``"cu"``, ...): that factor the constant 0, so its
    triangle has no term."""
    g = Graph()
    shapes = {"w": (n, k), "rl": (n, pl), "cl": (n, pl), "ru": (n, pu), "cu": (n, pu)}
    parts = {name: np.array(g.input(name, r * c), dtype=object).reshape(r, c) for name, (r, c) in shapes.items()}
    args = [np.zeros_like(x) if name == zero else x for name, x in parts.items()]
    return g, shapes, parts, g.scan_product(*args, "test scan")


def _values(shapes, rng, count=None):
    return {name: rng.normal(size=((count,) if count else ()) + shape) for name, shape in shapes.items()}


def test_sampled_values_equal_forming_the_matrix():
    g, shapes, _, x = _traced(7, 5)
    vals = _values(shapes, np.random.default_rng(3), count=4)
    g.samples = {name: v.reshape(4, -1) for name, v in vals.items()}
    got = g.sample_values(list(x.flat)).reshape(4, 7, 5)
    np.testing.assert_allclose(got, _formed(*vals.values()), rtol=1e-13, atol=1e-13)


def test_the_count_is_the_library_loops_multiply_adds():
    """Per row ``c`` of ``W``: the prefix total (``n p_u``), then per ``i`` two updates and two dot
    products (``2 (p_l + p_u)``), two flops each."""
    g, _, _, x = _traced(7, 5)
    counts = g.count(g.live([list(x.flat)]))
    assert counts["products"] == [{"rows": 7, "terms": 7, "columns": 5, "flops": 2 * 7 * 5 * (2 * PL + 3 * PU)}]
    assert counts["total"] == 0


def test_without_a_term_on_either_side_the_result_is_zero_and_no_statement_is_made():
    g = Graph()
    w = np.array(g.input("w", 6), dtype=object).reshape(3, 2)
    zeros = np.zeros((3, 2), dtype=object)
    x = g.scan_product(w, zeros, zeros, zeros, zeros, "nothing")
    assert not g.statements and all(v.is_const and v.value == 0 for v in x.flat)


def test_terms_zero_in_every_row_are_left_out_and_the_values_kept():
    g = Graph()
    w = np.array(g.input("w", 12), dtype=object).reshape(4, 3)
    rl, cl = (np.array(g.input(s, 8), dtype=object).reshape(4, 2) for s in ("rl", "cl"))
    ru, cu = (np.array(g.input(s, 4), dtype=object).reshape(4, 1) for s in ("ru", "cu"))
    rl[:, 1] = 0
    cu[:, 0] = 0
    rng = np.random.default_rng(8)
    g.samples = {s: rng.normal(size=(2, size)) for s, size in (("w", 12), ("rl", 8), ("cl", 8), ("ru", 4), ("cu", 4))}
    x = g.scan_product(w, rl, cl, ru, cu, "zero terms")
    (statement,) = g.statements
    assert (statement.pl, statement.pu) == (1, 0)
    vals = [g.samples[s].reshape(2, 4, -1) for s in ("w", "rl", "cl", "ru", "cu")]
    vals[1][:, :, 1] = 0
    vals[4][:, :, 0] = 0
    np.testing.assert_allclose(g.sample_values(list(x.flat)).reshape(2, 4, 3), _formed(*vals), rtol=1e-13)


def test_mismatched_factors_and_too_many_terms_are_refused():
    g = Graph()
    w = np.array(g.input("w", 12), dtype=object).reshape(4, 3)
    three = np.array(g.input("f", 12), dtype=object).reshape(4, 3)
    with pytest.raises(ValueError, match="shapes"):
        g.scan_product(w, three, three[:, :2], three, three, "mismatched")
    wide = np.array(g.input("v", 4 * (SCAN_TERMS + 1)), dtype=object).reshape(4, SCAN_TERMS + 1)
    with pytest.raises(ValueError, match="at most"):
        g.scan_product(w, wide, wide, three, three, "too many terms")


def _scan_function(n, k, zero=None):
    """A function ``x[c, i] = (D^T W)[i, c]`` (row-major ``k x n``: the product's own layout, so the
    C target writes it straight into the output)."""
    g, shapes, _, x = _traced(n, k, zero=zero)
    args = [Argument(name, (r * c,), name) for name, (r, c) in shapes.items()]
    return shapes, Function("scan", "test scan product", args, [(Argument("x", (k, n), "D^T W"), x.T)], g)


def _generated(tmp_path, fn):
    gen = generate(symgen.derive(symgen.load("four_bar")), _SourceOnly(), lowered=[lower(fn)])
    for name, text in gen.files.items():
        (tmp_path / name).write_text(text)
    return gen


@pytest.mark.parametrize("n, k, zero", [(13, 11, None), (8, 8, None), (17, 3, None), (1, 9, None), (24, 17, None),
                                        (9, 10, "rl"), (9, 10, "cu")])
def test_the_c_loop_equals_forming_the_matrix(n, k, zero, tmp_path):
    """Whole and partial tiles of 8 entries, whole groups of 8 rows and the rows beyond them, a
    single entry, a triangle without terms; vector extensions for this processor and for the
    baseline instruction set (vectors wider than its registers), plain loops; every compiler there
    is, with the strict flags."""
    shapes, fn = _scan_function(n, k, zero)
    gen = _generated(tmp_path, fn)
    source = gen.files[f"{gen.module}.c"]
    pl, pu = (0 if zero == "rl" else PL), (0 if zero == "cu" else PU)
    assert f"symgen_scan_product_{pl}_{pu}({n}, {k}, " in source and ", x, NULL, NULL, NULL);" in source  # into x
    vals = _values(shapes, np.random.default_rng(n * k))
    if zero:
        vals[zero][:] = 0.0
    want = _formed(*vals.values()).T
    for label, lib in loop_builds(tmp_path / f"{gen.module}.c", "scan"):
        out = np.full(n * k, np.nan)
        args = [np.ascontiguousarray(v).ctypes.data_as(ctypes.c_void_p) for v in vals.values()]
        status = lib.symgen_four_bar_scan(*args, out.ctypes.data_as(ctypes.c_void_p), None)
        assert status == 0
        np.testing.assert_allclose(out.reshape(k, n), want, rtol=1e-12, atol=1e-12, err_msg=label)


@pytest.mark.parametrize("read", [False, True], ids=["paired", "first-read-later"])
def test_two_scans_on_the_same_running_sums_are_one_call(read, tmp_path):
    """Two scan products of one ``W``, ``rl`` and ``ru`` (another ``cl``, ``cu``), each written into
    its output: one library call computes both, unless the second reads the first one's result
    (``read``: an entry of its ``cl`` twice one of the first's entries), which then keeps its own
    call, made before."""
    n, k = 13, 11
    g, shapes, parts, first = _traced(n, k)
    cl2 = np.array(g.input("cl2", n * PL), dtype=object).reshape(n, PL)
    cu2 = np.array(g.input("cu2", n * PU), dtype=object).reshape(n, PU)
    if read:
        cl2[0, 0] = g.mul(2, first[3, 4])
    second = g.scan_product(parts["w"], parts["rl"], cl2, parts["ru"], cu2, "second scan")
    args = [Argument(name, (r * c,), name) for name, (r, c) in shapes.items()]
    args += [Argument("cl2", (n * PL,), "cl2"), Argument("cu2", (n * PU,), "cu2")]
    outputs = [(Argument("x", (k, n), "first"), first.T), (Argument("y", (k, n), "second"), second.T)]
    gen = _generated(tmp_path, Function("scan", "two scans", args, outputs, g))
    source = gen.files[f"{gen.module}.c"]
    calls = [line for line in source.splitlines() if f"symgen_scan_product_{PL}_{PU}({n}" in line]
    assert len(calls) == (2 if read else 1)
    assert calls[-1].strip().endswith("NULL, NULL, NULL);") == read
    rng = np.random.default_rng(11)
    vals = _values(shapes, rng)
    vals.update(cl2=rng.normal(size=(n, PL)), cu2=rng.normal(size=(n, PU)))
    lib = tmp_path / "pair.so"
    subprocess.run([shutil.which("cc") or "cc", *STRICT, "-O2", "-march=native", "-fPIC", "-shared", "-o", str(lib),
                    str(tmp_path / f"{gen.module}.c"), "-lm"], check=True)
    outs = [np.full(n * k, np.nan) for _ in range(2)]
    status = ctypes.CDLL(str(lib)).symgen_four_bar_scan(
        *[np.ascontiguousarray(v).ctypes.data_as(ctypes.c_void_p) for v in vals.values()],
        *[o.ctypes.data_as(ctypes.c_void_p) for o in outs], None)
    assert status == 0
    want_x = _formed(vals["w"], vals["rl"], vals["cl"], vals["ru"], vals["cu"])
    cl2_val = vals["cl2"].copy()
    if read:
        cl2_val[0, 0] = 2 * want_x[3, 4]
    want_y = _formed(vals["w"], vals["rl"], cl2_val, vals["ru"], vals["cu2"])
    np.testing.assert_allclose(outs[0].reshape(k, n), want_x.T, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(outs[1].reshape(k, n), want_y.T, rtol=1e-12, atol=1e-12)


def test_the_numpy_target_equals_forming_the_matrix():
    shapes, fn = _scan_function(11, 9)
    module = load_generated(symgen.derive(symgen.load("four_bar")), "numpy", lowered=[lower(fn)])
    vals = _values(shapes, np.random.default_rng(2), count=3)
    got = module.scan(*[v.reshape(3, -1) for v in vals.values()])
    np.testing.assert_allclose(got, np.swapaxes(_formed(*vals.values()), 1, 2), rtol=1e-12)


# ------------------------------------------------------------------ the forward-dynamics Jacobians
ROUTE = "implicit-joint-space-analytic"


def _through_scans(monkeypatch):
    """A short chain taken through the scan products: its closed form in library products from any
    number of ancestor pairs, its mass matrix in the library factor from any size."""
    monkeypatch.setattr(dynamics_derivatives, "LOOPED_PAIRS", 0)
    monkeypatch.setattr(sparse_lu, "LDLT_MAX", 1)


@pytest.mark.parametrize("target", ["c", "numpy"])
@pytest.mark.parametrize("spec", ["chain:n=6", "general_chain:n=7", "friction"])
def test_chain_forward_jacobians_through_scan_products_equal_50_digit_central_differences(spec, target,
                                                                                         monkeypatch, tmp_path):
    """Revolute chains of special and general geometry, and a chain of prismatic and revolute
    joints with viscous and Coulomb friction and rotor inertias (its contact forces left out: the
    closed-form routes do not take them), whose viscous terms are added to the scans' results."""
    from .test_codegen_forward_derivatives import _reference
    from .test_rnea_derivatives import _without_contact

    _through_scans(monkeypatch)
    model = symgen.derive(symgen.load(_without_contact(tmp_path) if spec == "friction" else spec))
    assert dynamics_derivatives.serial_chain(model.tree)
    lowered = trace_all(model, ["forward_dynamics_derivatives"], {"method": ROUTE})
    assert len([step for step in lowered[0].steps if step.scan]) == 2
    module = load_generated(model, target, lowered=lowered)
    names = [a.name for a, _ in build_function(model, "forward_dynamics_derivatives", method=ROUTE).outputs]
    for s in reference_states(model, 2, seed=23):
        want = _reference(model, s)
        for out, got in zip(names, call_by_name(module, "forward_dynamics_derivatives", s), strict=True):
            assert relative_error(got, want[out]) < FD_TOL, f"{spec} {target} {out}"


def test_a_dropped_triangle_is_caught(monkeypatch):
    """The upper triangle's factors zeroed in the scan (as if the terms of the coordinates moved
    below each torque's were dropped): the 50-digit check fails on ``d dV_m / dq``."""
    from .test_codegen_forward_derivatives import _reference

    _through_scans(monkeypatch)
    original = Graph.scan_product

    def dropped(self, w, rl, cl, ru, cu, what):
        return original(self, w, rl, cl, np.zeros_like(ru), cu, what)

    monkeypatch.setattr(Graph, "scan_product", dropped)
    model = symgen.derive(symgen.load("chain:n=6"))
    module = load_generated(model, "c", lowered=trace_all(model, ["forward_dynamics_derivatives"], {"method": ROUTE}))
    s = reference_states(model, 1, seed=23)[0]
    got = call_by_name(module, "forward_dynamics_derivatives", s)[0]
    assert relative_error(got, _reference(model, s)["ddV_m_dq"]) > 1e-3
