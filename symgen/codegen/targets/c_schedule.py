"""The order of a C function's statements, and where it stores its outputs.

The traced graph lists its statements in creation order: an algorithm's sweeps one after the
other, and every output assigned at the end. In straight-line code of thousands of statements that
order keeps many values alive at once -- a forward sweep's values until the reverse sweep reads
them, every output entry until the last statement -- and the compiler, which does not move
statements that far, keeps them in stack slots: a load or a store for about every second
arithmetic instruction, and machine code beyond a core's instruction cache (the Panda's
inverse-dynamics Jacobians, 4,766 operations: 2,666 instructions on the stack, clang -O3,
``benchmarks/statement_order.md``). Here the stores are moved, and the statements reordered where
that helps, without changing one operation:

* :func:`first_use_order` walks the output entries in their order and emits, before each, the
  statements it needs that no earlier entry needed, in their traced order: a statement comes just
  before the first output that reads it, and the sweeps' order (independent statements side by
  side, for the processor to overlap) holds within each entry's share. The sines and cosines of
  input angles stay first, in their order (one vector call evaluates them, :mod:`.c_trig`), then
  the library factors and pivot checks with what they need, in their order (the first to fail
  reports its matrix, as in the NumPy target; every output is then stored after the last one,
  below), then the walk over the outputs, then anything no output reads. :func:`schedule` keeps
  that order only where it has markedly fewer temporaries alive on average than the traced one
  (:func:`mean_live`, :data:`KEEP_BELOW`): where each output entry ends a long chain of its own
  (a reverse sweep per row of a Jacobian: the Panda's and the Stewart platform's inverse-dynamics
  Jacobians); not where many entries share late statements (a forward-dynamics Jacobian's
  ``M^-1`` times each column), whose first-use order keeps more alive, and ran slower.
* :func:`early_stores` assigns an output entry right after the statement computing it, so that
  value dies there. Kept at the end (after every statement) are the entries that are literals,
  inputs or library results, those computed before the last factor or pivot check (a
  ``SYMGEN_SINGULAR`` return then leaves every output untouched, as before), and every entry of
  an output a banded product writes into (the product may write rows it does not own, which their
  assignments overwrite afterwards, :mod:`.c_products`).

A function may thus write an output before it has read its last input: the header asks that no
output overlap an input. The NumPy target keeps the traced order (its statements are whole arrays).
Same statements, same operation count; the arithmetic differs only where the compiler fuses a
different multiply into an add (``-ffp-contract=fast``). Side by side: ``benchmarks/statement_order.py``.
"""
from __future__ import annotations

from dataclasses import replace

from ...errors import CodegenError
from ..emit import Lowered, Ref, Step, flat_index
from .c_trig import TRIG

#: steps whose failure returns ``SYMGEN_SINGULAR`` from the middle of a function
FAILING = ("factor", "check")
#: the statement order: ``"traced"``, ``"first use"``, or ``"fewer live"`` (the default: the first
#: use where it keeps markedly fewer temporaries alive on average, :func:`mean_live`); and whether
#: outputs are stored early -- switches for the side-by-side benchmark
ORDER = "fewer live"
EARLY_STORES = True
#: the first-use order is kept where its mean live count is below this fraction of the traced
#: order's (both storing outputs early). The Panda's inverse-dynamics Jacobians, 13 % fewer alive,
#: ran in 0.60 (clang) and 0.77 (cc) of the traced order's time, against 0.84 and 0.92 with early
#: stores alone; chain:n=6's, 3 % fewer, and the forward Jacobians, more, within the noise or slower
#: (``benchmarks/statement_order.md``): a small cut is not worth the order it breaks (the sweeps'
#: independent statements side by side).
KEEP_BELOW = 0.9


def defined(step: Step) -> list[str]:
    """The names a step defines: a temporary, a ``sincos`` step's every sine and cosine, a factor,
    a library result; a pivot check none."""
    if step.kind == "sincos":
        return [out for out, _, _ in step.outputs]
    return [] if step.kind == "check" else [step.name]


def _sources(refs, where: dict[str, int]) -> list[int]:
    """The positions of the steps whose results ``refs`` read, in order (literals and inputs none).
    A product's entry written into an output (``out``, :mod:`.c_products`) has no step here: the
    order is chosen before the products are laid out."""
    out = []
    for r in refs:
        if r.kind == "tmp":
            out.append(where[r.data])
        elif r.kind == "library_out":
            out.append(where[r.data[0]])
        elif r.kind not in ("const", "in"):
            raise CodegenError(f"a {r.kind!r} reference ({r.data}) cannot be ordered: schedule before "
                               "lay_out_products")
    return out


def _reads(step: Step, where: dict[str, int]) -> list[int]:
    """The positions of the steps whose results ``step`` reads, in argument order."""
    return _sources(step.args, where) + ([where[step.factor]] if step.kind == "solve" else [])


def _is_input_trig(step: Step) -> bool:
    return step.kind == "op" and step.op in TRIG and all(r.kind in ("in", "const") for r in step.args)


def schedule(low: Lowered) -> Lowered:
    """``low`` in the order :data:`ORDER` names: by default its first-use order where that keeps
    fewer temporaries alive on average, below :data:`KEEP_BELOW` times the traced order's
    (:func:`mean_live`, outputs stored early in both), else the traced order."""
    if ORDER == "traced":
        return low
    reordered = first_use_order(low)
    if ORDER == "first use" or reordered is low:
        return reordered
    return reordered if mean_live(reordered) < KEEP_BELOW * mean_live(low) else low


def mean_live(low: Lowered) -> float:
    """Temporaries alive per step, on average: each from its step to its last reader, or to the
    end of the function where an output entry holds it and is stored there (:func:`early_stores`,
    not knowing yet which outputs a product will write into: the products are laid out later)."""
    after, _ = early_stores(low)
    last: dict[str, int] = {}
    for i, step in enumerate(low.steps):
        for r in step.args:
            if r.kind == "tmp":
                last[r.data] = i
    for _, entries in low.outputs:
        for _, r in entries:
            if r.kind == "tmp" and r.data not in after:
                last[r.data] = len(low.steps)
    alive = sum(last[name] - i for i, step in enumerate(low.steps) for name in defined(step) if name in last)
    return alive / max(len(low.steps), 1)


def first_use_order(low: Lowered) -> Lowered:
    """``low`` with its steps in first-use order (module docstring); the same steps and outputs."""
    steps = low.steps
    where = {name: i for i, s in enumerate(steps) for name in defined(s)}
    needs = [_reads(s, where) for s in steps]
    previous = None
    for i, s in enumerate(steps):          # factors and checks stay in their order
        if s.kind in FAILING:
            if previous is not None:
                needs[i].insert(0, previous)
            previous = i
    done = [False] * len(steps)
    order: list[int] = []

    def visit(root: int) -> None:
        if done[root]:
            return
        done[root] = True
        stack = [(root, iter(needs[root]))]
        cone = []                  # the statements ``root`` needs that are not emitted yet
        while stack:
            i, pending = stack[-1]
            for j in pending:
                if not done[j]:
                    done[j] = True
                    stack.append((j, iter(needs[j])))
                    break
            else:
                stack.pop()
                cone.append(i)
        order.extend(sorted(cone))

    for i, s in enumerate(steps):
        if _is_input_trig(s):
            visit(i)
    for i, s in enumerate(steps):
        if s.kind in FAILING:
            visit(i)
    for i in _sources((r for _, entries in low.outputs for _, r in entries), where):
        visit(i)
    for i in range(len(steps)):
        visit(i)
    if order == list(range(len(steps))):
        return low
    return replace(low, steps=[steps[i] for i in order])


def early_stores(low: Lowered) -> tuple[dict[str, list[tuple[str, int, Ref]]], list[list]]:
    """Where ``low``'s output entries are assigned: ``({temporary: [(output, flat index, ref)]},
    rest)``, the first the entries stored right after the step defining that temporary (at their
    row-major flat index), ``rest`` per output its other ``(index, ref)`` entries, stored after
    every step (module docstring)."""
    last_failing = max((i for i, s in enumerate(low.steps) if s.kind in FAILING), default=-1)
    late = {name for s in low.steps[:last_failing + 1] for name in defined(s)}
    written = {s.into for s in low.steps if s.kind == "product" and s.into}
    after: dict[str, list[tuple[str, int, Ref]]] = {}
    rest = []
    for arg, entries in low.outputs:
        kept = []
        for idx, r in entries:
            if EARLY_STORES and r.kind == "tmp" and r.data not in late and arg.name not in written:
                after.setdefault(r.data, []).append((arg.name, flat_index(idx, arg.shape), r))
            else:
                kept.append((idx, r))
        rest.append(kept)
    return after, rest


def store_line(output: str, flat: int, value: str) -> str:
    """The C assignment of an output entry at its row-major ``flat`` index (scalar code, lanes, blocks)."""
    return f"{output}[{flat}] = {value};"


def with_stores(low: Lowered, statement, value) -> tuple[list[str], list[list[str]]]:
    """The lines of ``low``'s steps (``statement(step)``), each followed by the early stores of what
    it defines, and per output the store lines left for the end (:func:`early_stores`); ``value(ref)``
    is a stored reference's text."""
    after, rest = early_stores(low)
    body: list[str] = []
    for step in low.steps:
        body += statement(step)
        for name in defined(step):
            body += [store_line(out, index, value(r)) for out, index, r in after.get(name, ())]
    late = [[store_line(arg.name, flat_index(idx, arg.shape), value(r)) for idx, r in kept]
            for (arg, _), kept in zip(low.outputs, rest)]
    return body, late
