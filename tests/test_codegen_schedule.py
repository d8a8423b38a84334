"""The C target's statement order and output stores (symgen.codegen.targets.c_schedule).

The reordering may not change what a function computes: the same steps, each after what it
reads, the library factors and pivot checks in their order; every statement with the first output
entry that needs it (checked here against cones computed independently, by recursion over the
references); every early store right after the statement it stores, none of an output a product
writes into, none computed before a step that can return ``SYMGEN_SINGULAR`` -- a refused state
leaves the caller's output arrays as they were (checked on the compiled four-bar at its dead point).
"""
from __future__ import annotations

import ctypes
import re
import shutil
from dataclasses import replace

import numpy as np
import pytest

from symgen.codegen.emit import Ref, flat_index, lower
from symgen.codegen.functions import Argument, Function
from symgen.codegen.generate import generate, module_name, trace_all
from symgen.codegen.graph import Graph
from symgen.codegen.runtime import load_generated
from symgen.codegen.targets.c_products import lay_out_products
from symgen.codegen.targets.c_schedule import FAILING, KEEP_BELOW, early_stores, first_use_order, mean_live, schedule
from symgen.codegen.targets.c_trig import TRIG
from symgen.errors import CodegenError
from symgen.io.builtin import get_scene
from symgen.model import derive

CC = shutil.which("cc")
#: (scene, function): a reverse-mode Jacobian, a closed chain's factor and checks, the closed form's products
CASES = [("chain:n=6", "inverse_dynamics_derivatives"), ("four_bar", "forward_dynamics"),
         ("five_bar", "forward_dynamics_derivatives"), ("chain:n=17", "inverse_dynamics_derivatives")]


@pytest.fixture(scope="module", params=CASES, ids=lambda c: f"{c[0]}-{c[1]}")
def lowered(request):
    spec, function = request.param
    return trace_all(derive(get_scene(spec)), [function])[0]


def _names(step) -> list[str]:
    if step.kind == "sincos":
        return [out for out, _, _ in step.outputs]
    return [] if step.kind == "check" else [step.name]


def _read(step) -> set[str]:
    out = {r.data for r in step.args if r.kind == "tmp"}
    out |= {r.data[0] for r in step.args if r.kind == "library_out"}
    return out | ({step.factor} if step.kind == "solve" else set())


def test_the_same_steps_each_after_what_it_reads(lowered):
    low = first_use_order(lowered)
    assert sorted(map(id, low.steps)) == sorted(map(id, lowered.steps))
    assert low.outputs is lowered.outputs
    seen: set[str] = set()
    for step in low.steps:
        assert _read(step) <= seen, step.name
        seen.update(_names(step))
    failing = [s.name for s in lowered.steps if s.kind in FAILING]
    assert [s.name for s in low.steps if s.kind in FAILING] == failing


def test_each_statement_comes_with_the_first_output_that_needs_it(lowered):
    """Sorted by (the first cone that holds it, traced position): the sines and cosines of input
    angles, then each factor's and pivot check's cone in their order, then each output entry's,
    then the rest; the cones by plain recursion over the references."""
    steps = lowered.steps
    by_name = {n: i for i, s in enumerate(steps) for n in _names(s)}
    failing = [i for i, s in enumerate(steps) if s.kind in FAILING]

    def cone(i, into):
        if i in into:
            return
        into.add(i)
        for name in _read(steps[i]):
            cone(by_name[name], into)
        if i in failing and failing.index(i):
            cone(failing[failing.index(i) - 1], into)

    first: dict[int, int] = {}
    trig = [i for i, s in enumerate(steps)
            if s.kind == "op" and s.op in TRIG and all(r.kind in ("in", "const") for r in s.args)]
    for i in trig:
        first[i] = -1 - len(failing)
    for k, i in enumerate(failing):
        needed: set[int] = set()
        cone(i, needed)
        for j in needed:
            first.setdefault(j, k - len(failing))
    entry = 0
    for _, entries in lowered.outputs:
        for _, r in entries:
            if r.kind in ("tmp", "library_out"):
                needed: set[int] = set()
                cone(by_name[r.data if r.kind == "tmp" else r.data[0]], needed)
                for i in needed:
                    first.setdefault(i, entry)
            entry += 1
    for i in range(len(steps)):
        first.setdefault(i, entry)
    position = {id(s): i for i, s in enumerate(steps)}
    keys = [(first[position[id(s)]], position[id(s)]) for s in first_use_order(lowered).steps]
    assert keys == sorted(keys)


def test_the_order_kept_has_markedly_fewer_temporaries_alive():
    """Three products each squared into an output: traced, ``t1 t2 t3 o1 o2 o3`` keeps each ``t``
    alive 3 steps (9 / 6 = 1.5 per step; the outputs, stored early, none); first use,
    ``t1 o1 t2 o2 t3 o3``, 1 step (3 / 6 = 0.5): kept."""
    g = Graph()
    a = g.input("a", 6)
    t = [a[0] * a[1], a[2] * a[3], a[4] * a[5]]
    fn = Function("squares", "test", [Argument("a", (6,), "a")], [(Argument("o", (3,), "o"), np.array([x * x for x in t]))], g)
    low = lower(fn)
    assert mean_live(low) == 1.5 and mean_live(first_use_order(low)) == 0.5
    assert [s.name for s in schedule(low).steps] == [s.name for s in first_use_order(low).steps] != [s.name for s in low.steps]


def test_each_function_keeps_the_order_with_markedly_fewer_temporaries_alive(lowered):
    reordered = first_use_order(lowered)
    want = reordered if mean_live(reordered) < KEEP_BELOW * mean_live(lowered) else lowered
    assert [id(s) for s in schedule(lowered).steps] == [id(s) for s in want.steps]


def test_an_output_entry_a_product_wrote_cannot_be_ordered(lowered):
    """Once the products are laid out an entry may be a product's place in an output (``out``),
    which names no step: ordering then is refused, naming the reference, not done half-blind."""
    (arg, entries), *others = lowered.outputs
    idx, _ = entries[0]
    spoiled = replace(lowered, outputs=[(arg, [(idx, Ref("out", (arg.name, 0)))] + entries[1:]), *others])
    with pytest.raises(CodegenError, match=r"'out' reference \(\('" + arg.name):
        first_use_order(spoiled)


def test_early_stores_follow_their_statement_and_spare_what_may_not_be_written(lowered):
    low = lay_out_products(first_use_order(lowered))
    after, rest = early_stores(low)
    last = max((i for i, s in enumerate(low.steps) if s.kind in FAILING), default=-1)
    before = {n for s in low.steps[:last + 1] for n in _names(s)}
    into = {s.into for s in low.steps if s.kind == "product" and s.into}
    stored = [(out, flat) for entries in after.values() for out, flat, _ in entries]
    assert not (set(after) & before)
    assert not any(out in into for out, _ in stored)
    kept = [(arg.name, flat_index(idx, arg.shape)) for (arg, _), k in zip(low.outputs, rest) for idx, _ in k]
    every = [(arg.name, flat_index(idx, arg.shape)) for arg, entries in low.outputs for idx, _ in entries]
    assert sorted(stored + kept) == sorted(every)


def test_an_output_entry_is_stored_right_after_its_statement():
    """In the C text of chain:n=6's inverse-dynamics Jacobians: each ``out[k] = name;`` follows
    ``name``'s definition or another store of it; none is left after the last statement."""
    model = derive(get_scene("chain:n=6"))
    gen = generate(model, "c", ["inverse_dynamics_derivatives"])
    body = gen.files[f"{gen.module}.c"].split("int symgen_chain_n6_inverse_dynamics_derivatives(", 1)[1]
    lines = [line.strip() for line in body.split("\n}\n", 1)[0].splitlines()]
    stores = 0
    for k, line in enumerate(lines):
        store = re.fullmatch(r"(dtau_dq|dtau_dqd|M)\[\d+\] = (\w+);", line)
        if store and not re.fullmatch(r"[0-9.e+-]+", store.group(2)):
            stores += 1
            j = k - 1
            while re.fullmatch(rf"\w+\[\d+\] = {store.group(2)};", lines[j]):
                j -= 1
            assert lines[j].startswith(f"const double {store.group(2)} = "), line
    assert stores > 0.9 * 3 * 36


@pytest.mark.skipif(CC is None, reason="no C compiler")
def test_a_refused_state_leaves_the_outputs_as_they_were():
    """The four-bar's ``state_derivative`` with its links' inertial parameters a run-time input, all
    zero: the loop block ``[T_u1, T_a1]`` passes its check, the massless ``M_mm`` fails the last one
    (SYMGEN_SINGULAR), and every output entry keeps the caller's value -- three of the five (the
    joint rates) are computed between the two checks, so stored early they would have been written."""
    model = derive(get_scene("four_bar"))
    links = ["crank", "coupler", "rocker"]
    low = schedule(trace_all(model, ["state_derivative"], parameters=links)[0])
    checks = [i for i, s in enumerate(low.steps) if s.kind in FAILING]
    between = {n for s in low.steps[checks[0] + 1:checks[-1]] for n in _names(s)}
    assert sum(r.kind == "tmp" and r.data in between for _, entries in low.outputs for _, r in entries) == 3
    module = load_generated(model, "c", ["state_derivative"], parameters=links)
    symbol = getattr(module._library(), f"symgen_{module_name(model.scene.name)}_state_derivative")
    q = np.array([0.3, -0.3, 0.3 - np.pi, np.pi - 0.3])
    v, tau, p = np.ones(1), np.ones(1), np.zeros(low.function.inputs[-1].size)
    outputs = [np.full(arg.size, 12345.0) for arg, _ in low.outputs]
    cond = np.zeros(1)
    pointer = ctypes.POINTER(ctypes.c_double)
    status = symbol(*[a.ctypes.data_as(pointer) for a in (q, v, tau, p, *outputs, cond)])
    assert status == 1
    assert all(np.all(out == 12345.0) for out in outputs)
