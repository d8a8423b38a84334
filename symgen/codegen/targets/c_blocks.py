"""Long C functions cut into blocks the compiler handles in linear time.

A C compiler's optimiser is superlinear in the size of one function (register allocation and
scheduling over one basic block of ``10^5`` statements took minutes and gigabytes), and the
machine code of one long block is larger than that of the same statements cut into short ones
(more values spilled to a larger stack frame). A lowered function with more than
:data:`SPLIT_STATEMENTS` scalar statements is therefore emitted as a sequence of ``static`` block
functions of at most :data:`BLOCK_STATEMENTS` statements each, called in order by the public
function:

* a temporary used only inside its block stays a ``const double`` local (a register);
* a temporary used in a later block, or by a library statement (factor, solve, product), is also stored in the
  workspace ``work`` (one ``double`` array on the public function's stack); slots are given by
  liveness (a slot is reused once its temporary's last reader has run), so ``work`` holds only
  what is live across a block boundary -- except an entry of a product's factor, stored at its
  place in that factor's region (below);
* the library statements stay in the public function (a factor may return
  ``SYMGEN_SINGULAR``); a solve's or a product's result lives in ``work``, which later blocks read
  (a product written into an output, :mod:`.c_products`, has none there); a product's packed
  factors are regions of ``work`` too, into which the blocks store the entries they compute
  (:func:`_place_factors`), the public function copying only the others;
* an output entry a block computes is stored by that block, right after its statement
  (:func:`.c_schedule.early_stores`); the entries left for the end (literals, inputs, library
  results, those that must wait for the last factor or check) are blocks of assignments after
  the last step (a ``10^4``-entry mass matrix is ``10^4`` stores).

Every block has the same parameters (the function's inputs and outputs, then ``work``), so the
call sites are uniform; the operation count and the arithmetic are those of the unsplit function
(the same expressions, in the same order), only the storage of the crossing temporaries changes.
"""
from __future__ import annotations

import heapq
from dataclasses import dataclass, field

from ..emit import Lowered, Ref, Step, product_factors
from .c_schedule import defined, early_stores, store_line

#: most scalar statements (or output entries) of a function emitted whole; a longer one is cut
#: into blocks. Measured on chain:n=35 (all functions, cc -O2): blocks of 500 to 4000 statements
#: all compiled in 16-20 s of CPU and 340-510 MB, the unsplit file in 108 s and 1.2 GB. Below
#: this size the cut costs time: the crossing temporaries go through memory (chain:n=6's
#: forward-dynamics Jacobians, 3,941 operations, take 1.11-1.19 times as long cut into blocks of
#: 500 to 5000, clang, ``benchmarks/block_size.md``).
SPLIT_STATEMENTS = 5000
#: most scalar statements in one block of a cut function. The machine code of a long function
#: shrinks with its blocks (clang spills fewer values, to a smaller stack frame: 1,599 stack
#: references, 945 of them with 32-bit offsets, in blocks of 1000 against 2,924 and 2,514 in blocks
#: of 5000 for the function below), and code beyond a core's instruction cache streams from the
#: next level on every call: general_chain:n=7's inverse-dynamics Jacobians (7,219 operations,
#: clang -O3) take 76 KB whole, 69 KB in blocks of 5000 and 61 KB in blocks of 1000, and 1625, 1359
#: and 732 ns per call on a core with a 64 KB instruction cache (``benchmarks/block_size.md``). Not
#: every function gains: the Panda's forward Jacobians (7,090) take 65.5 KB whole and run fastest
#: so (763 ns), 67.5 KB and 1056 ns in blocks of 1000; the rule cannot see machine code and keeps
#: the size that gains on the others.
BLOCK_STATEMENTS = 1000
#: the workspace array's name (no traced temporary is named without a prefix)
WORK = "work"


@dataclass
class Unit:
    """One piece of a split function: a ``block`` of op steps or output assignments, or one
    library step (factor, solve, product) or pivot check run by the public function (``main``)."""

    kind: str                                      # "block" or "main"
    steps: list = field(default_factory=list)      # op steps, or the one library step
    assigns: list = field(default_factory=list)    # (output name, flat index, Ref)


def _units(low: Lowered, limit: int, flat, rest: list[list]) -> list[Unit]:
    """``low`` cut into units; the output entries of ``rest`` (per output, those
    :func:`.c_schedule.early_stores` leaves for the end) in assignment blocks after the last step."""
    units: list[Unit] = []
    current = Unit("block")
    for step in low.steps:
        if step.kind in ("op", "sincos"):
            if len(current.steps) >= limit:
                units.append(current)
                current = Unit("block")
            current.steps.append(step)
        else:
            if current.steps:
                units.append(current)
                current = Unit("block")
            units.append(Unit("main", [step]))
    if current.steps:
        units.append(current)
    current = Unit("block")
    for (arg, _), entries in zip(low.outputs, rest):
        for idx, ref in entries:
            if len(current.assigns) >= limit:
                units.append(current)
                current = Unit("block")
            current.assigns.append((arg.name, flat(idx, arg.shape), ref))
    if current.assigns:
        units.append(current)
    return units


def _reads(unit: Unit):
    for step in unit.steps:
        yield from step.args
    for _, _, ref in unit.assigns:
        yield ref


def _slots(units: list[Unit], placed: set[str] = frozenset()) -> tuple[dict[str, int], int]:
    """Workspace slot of every temporary read outside the unit that defines it (but those
    ``placed`` in a product's factor, :func:`_place_factors`), and the number of slots: linear-scan
    allocation over the units (a freed slot, smallest first, is reused)."""
    home, last = {}, {}                  # the unit defining each temporary, the last reading it
    for u, unit in enumerate(units):
        for ref in _reads(unit):
            if ref.kind == "tmp" and home.get(ref.data, u) != u and ref.data not in placed:
                last[ref.data] = u
        if unit.kind == "block":
            for step in unit.steps:
                for name in defined(step):
                    home[name] = u
    ending: dict[int, list[str]] = {}
    for name, u in last.items():
        ending.setdefault(u, []).append(name)
    slots, free, size = {}, [], 0
    for u, unit in enumerate(units):
        if unit.kind == "block":
            for name in (name for step in unit.steps for name in defined(step)):
                if name in last:
                    if free:
                        slots[name] = heapq.heappop(free)
                    else:
                        slots[name] = size
                        size += 1
        for name in ending.get(u, ()):       # read for the last time here: free after this unit
            heapq.heappush(free, slots[name])
    return slots, size


def _place_factors(units: list[Unit]) -> tuple[list, dict[str, tuple[int, int]]]:
    """Each product's packed factors (``A^T``, ``B^T``; not one it shares) as a region of the
    workspace, each temporary among their entries kept at its first position there (never in a
    reused slot: a region is never reused), so the block that computes it stores it in place and
    the public function copies only the rest (literals, inputs, repeats). Returns the regions,
    ``(product, factor, size, positions in place)`` in order, and each placed temporary's
    ``(region, position)``."""
    regions: list = []
    placed: dict[str, tuple[int, int]] = {}
    for unit in units:
        step = unit.steps[0] if unit.kind == "main" else None
        if step is None or step.kind != "product":
            continue
        for part, refs, shared in product_factors(step):
            if shared:
                continue
            done = set()
            for i, r in enumerate(refs):
                if r.kind == "tmp" and r.data not in placed:
                    placed[r.data] = (len(regions), i)
                    done.add(i)
            regions.append((step.name, part, len(refs), done))
    return regions, placed


class BlockPrinter:
    """Wraps the target's printer: a temporary defined in the current block prints as its name,
    any other one as its workspace slot; a library result's element as its workspace entry (an
    entry of a product written into an output, :mod:`.c_products`, prints as that output's).
    ``placed``: the products' factors in the workspace (:func:`_place_factors`)."""

    def __init__(self, base, slots: dict[str, int], results: dict[str, int]):
        self.base = base
        self.slots = slots
        self.results = results
        self.local: set[str] = set()
        self.placed: dict = {}

    def ref(self, r: Ref) -> str:
        if r.kind == "tmp" and r.data not in self.local:
            return f"{WORK}[{self.slots[r.data]}]"
        if r.kind == "library_out":
            name, flat = r.data
            return f"{WORK}[{self.results[name] + flat}]"
        return self.base.ref(r)

    def expr(self, step: Step) -> str:
        a = [self.ref(x) for x in step.args]
        if step.op in self.base.binary:
            return f"{a[0]} {self.base.binary[step.op]} {a[1]}"
        if step.op == "neg":
            return f"-{a[0]}"
        return f"{self.base.funcs[step.op]}({a[0]})"


def needs_split(low: Lowered, limit: int = SPLIT_STATEMENTS) -> bool:
    """More scalar statements (or output entries) than ``limit``: the function is cut into blocks."""
    ops = sum(1 for s in low.steps if s.kind == "op")
    entries = sum(len(e) for _, e in low.outputs)
    return ops > limit or entries > limit


def split(low: Lowered, printer, statement, flat, symbol: str, params: list[str], names: list[str],
          limit: int = BLOCK_STATEMENTS, *, ctype: str = "double", value=None) -> dict:
    """The blocks of ``low`` and the public function's body.

    ``statement(step, printer)`` gives a library (or check, or ``sincos``) step's lines, ``flat(index, shape)`` an
    output's flat index; ``params`` are the block parameters before ``work`` (``names``: their
    names). ``ctype`` is the temporaries' C type (the lane kernels' vector type,
    :mod:`~symgen.codegen.targets.c_lanes`); ``value(text, ref)`` rewrites an output entry's text
    (a lane kernel broadcasts a literal). Returns ``blocks`` (``name``, ``lines``), ``body`` (the public function's lines) and
    ``work_size``."""
    after, rest = early_stores(low)
    units = _units(low, limit, flat, rest)
    regions, in_place = _place_factors(units)
    slots, size = _slots(units, set(in_place))
    results = {}
    for unit in units:
        for step in unit.steps:
            if step.kind in ("solve", "product") and not step.into:
                results[step.name] = size
                size += step.n * step.k
    p = BlockPrinter(printer, slots, results)
    starts = []
    for product, part, length, done in regions:
        starts.append(size)
        p.placed.setdefault(product, {})[part] = (f"{WORK} + {size}", done)
        size += length
    for name, (region, position) in in_place.items():
        slots[name] = starts[region] + position
    blocks, body = [], [f"{ctype} {WORK}[{max(size, 1)}];"]
    wrap = value or (lambda text, ref: text)

    def store(out: str, index: int, ref: Ref) -> str:
        return store_line(out, index, wrap(p.ref(ref), ref))

    call_args = ", ".join(names + [WORK])
    for unit in units:
        if unit.kind == "main":
            step = unit.steps[0]
            p.local = set()
            lines = statement(step, p)
            if step.name in results:                # the result lives in the workspace, for later blocks
                lines[0] = f"{ctype} *{step.name} = {WORK} + {results[step.name]};"
            body += lines
            continue
        name = f"{symbol}_block{len(blocks)}"
        p.local = {name for step in unit.steps for name in defined(step)}
        lines = [f"(void){n};" for n in names + [WORK]]
        for step in unit.steps:
            if step.kind == "sincos":
                lines += statement(step, p)
            else:
                lines.append(f"const {ctype} {step.name} = {p.expr(step)};")
            lines += [f"{WORK}[{slots[name]}] = {name};" for name in defined(step) if name in slots]
            lines += [store(*entry) for name in defined(step) for entry in after.get(name, ())]
        lines += [store(*entry) for entry in unit.assigns]
        blocks.append(dict(name=name, params=", ".join(params + [f"{ctype} *restrict {WORK}"]), lines=lines))
        body.append(f"{name}({call_args});")
    return dict(blocks=blocks, body=body, work_size=size)
