"""Generated code at scale: C functions cut into blocks, the NumPy workspace, the progress bar.

The block-split C (forced here with a small block size) must compile warning-free under
``-Wall -Wextra -Werror -pedantic`` and compute what the dense reference model (32) computes
(:mod:`symgen.codegen.reference`, no tracing); the workspace allocators must never give one
slot to two temporaries live at the same time; the NumPy module must agree with the reference
across chunk boundaries.
"""
from __future__ import annotations

import io
import json
import re
import shutil
import subprocess

import numpy as np
import pytest

from symgen.io.builtin import get_scene
from symgen.codegen.emit import Ref
from symgen.codegen.generate import generate, trace_all
from symgen.codegen.reference import reference_outputs, reference_states
from symgen.codegen.targets import target
from symgen.codegen.targets import numpy as numpy_target
from symgen.codegen.targets.c_blocks import _slots, _units, needs_split
from symgen.codegen.targets.c_schedule import defined as names_defined, early_stores
from symgen.codegen.targets.c_trig import batch_trig
from symgen.model import derive
from symgen.codegen.progress import progress

from .codegen_util import call, import_file, relative_error

#: block size forced on the C target so that small scenes are split
SMALL_BLOCK = 40
TOL = 1e-9
CC = shutil.which("cc")


@pytest.fixture(scope="module")
def five_bar():
    model = derive(get_scene("five_bar"))
    return model, trace_all(model)


@pytest.fixture
def small_blocks(monkeypatch):
    monkeypatch.setattr(target("c"), "split_statements", SMALL_BLOCK)
    monkeypatch.setattr(target("c"), "block_statements", SMALL_BLOCK)


def _flat(idx, shape) -> int:
    return 0


def _live_ranges(units):
    """For every temporary read outside its unit: (defining unit, last reading unit)."""
    defined, last = {}, {}
    for u, unit in enumerate(units):
        for step in unit.steps:
            for r in step.args:
                if r.kind == "tmp" and defined.get(r.data, u) != u:
                    last[r.data] = u
        for _, _, r in unit.assigns:
            if r.kind == "tmp" and defined.get(r.data, u) != u:
                last[r.data] = u
        if unit.kind == "block":
            defined.update({name: u for s in unit.steps for name in names_defined(s)})
    return {name: (defined[name], end) for name, end in last.items()}


def test_blocks_hold_at_most_the_block_size_and_keep_every_statement(five_bar):
    _, lowered = five_bar
    for low in lowered:
        units = _units(low, SMALL_BLOCK, _flat, early_stores(low)[1])
        ops = [s.name for u in units if u.kind == "block" for s in u.steps]
        assert ops == [s.name for s in low.steps if s.kind == "op"]
        assert all(len(u.steps) <= SMALL_BLOCK and len(u.assigns) <= SMALL_BLOCK for u in units if u.kind == "block")


def test_no_workspace_slot_holds_two_live_temporaries(five_bar):
    """Also with the sines and cosines taken together (a ``sincos`` step defines several)."""
    _, lowered = five_bar
    for low in [*lowered, *(batch_trig(low) for low in lowered)]:
        units = _units(low, SMALL_BLOCK, _flat, early_stores(low)[1])
        slots, size = _slots(units)
        ranges = _live_ranges(units)
        assert set(slots) == set(ranges)
        by_slot = {}
        for name, (start, end) in ranges.items():
            by_slot.setdefault(slots[name], []).append((start, end))
        for spans in by_slot.values():
            spans.sort()
            # a slot freed after unit `end` may be taken by a temporary defined in a later unit
            assert all(b[0] > a[1] for a, b in zip(spans, spans[1:]))
        if ranges:
            assert size <= len(ranges)


def test_small_functions_are_not_split(five_bar):
    _, lowered = five_bar
    assert not any(needs_split(low) for low in lowered)


@pytest.mark.skipif(CC is None, reason="no C compiler")
def test_split_c_compiles_warning_free_and_matches_the_dense_model(five_bar, small_blocks, tmp_path):
    model, lowered = five_bar
    gen = generate(model, "c", lowered=lowered)
    source = gen.files[f"{gen.module}.c"]
    assert "SYMGEN_BLOCK" in source
    first_block = source[source.index("SYMGEN_BLOCK symgen_"):]
    assert "symgen_sincos_n(" in first_block[:first_block.index("\n}\n")]
    for name, text in gen.files.items():
        (tmp_path / name).write_text(text)
    result = subprocess.run([CC, "-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic", "-O1", "-c",
                             str(tmp_path / f"{gen.module}.c"), "-o", str(tmp_path / "x.o")],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    module = import_file(tmp_path / f"{gen.module}_ctypes.py", "gen_c_blocks_five_bar")
    for state in reference_states(model, 3, seed=11):
        for low in lowered:
            name = low.function.name
            want = reference_outputs(model, name, state)
            got = call(module, name, state)
            for arg, value in zip([a for a, _ in low.function.outputs], got):
                assert relative_error(value, want[arg.name]) < TOL, (name, arg.name)


def test_numpy_rows_are_never_shared_by_live_temporaries(five_bar):
    _, lowered = five_bar
    for low in lowered:
        rows, size = numpy_target.allocate(low)
        last = {}
        for k, step in enumerate(low.steps):
            for r in step.args:
                if r.kind == "tmp":
                    last[r.data] = k
        holder = {}
        for k, step in enumerate(low.steps):
            reads = {r.data for r in step.args if r.kind == "tmp"}
            for name in reads:
                assert holder[rows[name]] == name, (low.function.name, name)
            if step.kind == "op":
                holder[rows[step.name]] = step.name
        assert size == len(set(rows.values()))


def test_numpy_module_matches_the_dense_model_across_chunks(five_bar, tmp_path):
    model, lowered = five_bar
    gen = generate(model, "numpy", lowered=lowered)
    for name, text in gen.files.items():
        (tmp_path / name).write_text(text)
    module = import_file(tmp_path / f"{gen.module}.py", "gen_np_blocks_five_bar")
    states = reference_states(model, 4, seed=5)
    count = 2 * module.CHUNK + 3                     # three chunks, the last one short
    picks = np.arange(count) % len(states)
    batch = {key: np.array([states[i][key] for i in picks]) for key in states[0]}
    for low in lowered:
        name = low.function.name
        got = call(module, name, batch)
        for arg, value in zip([a for a, _ in low.function.outputs], got):
            for s, state in enumerate(states):
                want = reference_outputs(model, name, state)[arg.name]
                rows = value[picks == s]
                assert all(relative_error(r, want) < TOL for r in rows), (name, arg.name, s)


def test_numpy_single_state_gives_the_unbatched_shape(five_bar, tmp_path):
    model, lowered = five_bar
    gen = generate(model, "numpy", lowered=lowered)
    (tmp_path / f"{gen.module}.py").write_text(gen.files[f"{gen.module}.py"])
    module = import_file(tmp_path / f"{gen.module}.py", "gen_np_blocks_single")
    state = reference_states(model, 1, seed=3)[0]
    (m,) = call(module, "mass_matrix", state)
    assert m.shape == (model.counts.m, model.counts.m)


class _Terminal(io.StringIO):
    def isatty(self):
        return True


def test_progress_is_silent_off_a_terminal():
    items = [1, 2, 3]
    stream = io.StringIO()
    assert progress(items, total=3, desc="tracing", stream=stream) is items
    assert stream.getvalue() == ""


def test_progress_draws_on_a_terminal_after_its_delay(monkeypatch):
    pytest.importorskip("tqdm")
    import symgen.codegen.progress as module

    monkeypatch.setattr(module, "DELAY", 0.0)
    stream = _Terminal()
    assert list(progress(["a", "b"], total=2, desc="tracing", stream=stream, label=str)) == ["a", "b"]
    assert "tracing" in stream.getvalue()


def test_printer_refs_a_library_result_by_flat_index():
    p = numpy_target.NumpyPrinter({"t0": 3})
    assert p.ref(Ref("tmp", "t0")) == "w3"
    assert p.ref(Ref("library_out", ("X5", 1))) == "X5[:, 1]"


def test_only_functions_beyond_the_split_size_are_cut_and_their_blocks_are_short():
    """The committed Stewart platform C: its functions beyond ``SPLIT_STATEMENTS`` statements (and
    only those) are cut, each block holding at most ``BLOCK_STATEMENTS`` operations (its sines and
    cosines, one step each, left out of the count), and each is cut into at least ``total // BLOCK_STATEMENTS``."""
    from pathlib import Path

    from symgen.codegen.targets.c_blocks import BLOCK_STATEMENTS, SPLIT_STATEMENTS

    root = Path(__file__).resolve().parents[1]
    source = (root / "generated" / "stewart" / "c" / "stewart.c").read_text()
    ops = json.loads((root / "generated" / "stewart" / "c" / "ops.json").read_text())["functions"]
    blocks: dict[str, list[int]] = {}
    for block in source.split("\nSYMGEN_BLOCK ")[1:]:
        name = block[:block.index("(")]
        body = re.sub(r"#if SYMGEN_VECTOR_TRIG.*?#endif", "", block[:block.index("\n}\n")], flags=re.S)
        function = name[len("symgen_stewart_"):name.rindex("_block")]
        blocks.setdefault(function, []).append(body.count("\n    const double "))
    long = {f for f, counts in ops.items() if counts["total"] > SPLIT_STATEMENTS}
    assert long and set(blocks) == long | {f"{f}_lanes" for f in long if f"{f}_lanes" in blocks}
    for function, sizes in blocks.items():
        assert max(sizes) <= BLOCK_STATEMENTS, function
        assert len(sizes) >= ops[function.removesuffix("_lanes")]["total"] // BLOCK_STATEMENTS, function


def test_the_split_size_and_the_block_size_are_separate(five_bar, monkeypatch):
    """Blocks of 40 statements with the split size beyond every function: nothing is cut."""
    model, lowered = five_bar
    monkeypatch.setattr(target("c"), "block_statements", SMALL_BLOCK)
    monkeypatch.setattr(target("c"), "split_statements", 10**9)
    gen = generate(model, "c", lowered=lowered)
    assert "SYMGEN_BLOCK symgen_" not in gen.files[f"{gen.module}.c"]
