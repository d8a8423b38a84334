"""How the C target lays out banded products: written straight into an output, operands packed once.

A product's result (:mod:`~symgen.codegen.graph_products`) is ``n x k``, column ``c`` at
``c * n``. When an output array of ``n * k`` entries takes each entry the product computes at that
same flat index -- ``d tau/dq``, row-major, from a product whose column ``j`` is row ``j`` of the
output -- the C target passes the output itself to the library loop instead of a workspace array,
and leaves out the copies (at ``N = 32`` 2,576 of the closed form's 3,072 output entries; ``M``'s
upper triangle is still copied from its lower one) and the ``3 N^2`` doubles of workspace they
came from.

The library loop changes exactly each column's rows ``lo[c] <= r < hi[c]`` (a partial group of
rows is read and stored back with its other rows as they were: one call at a time may write an
output, no other thread at once); :func:`write_into_outputs` takes a product only if it can prove
the writes safe:

* every assignment to an output a product writes into runs after every statement
  (:func:`.c_schedule.early_stores` keeps those at the end; other outputs are stored as soon as
  they are computed), so a row a product computes but does not own (a range
  that covers more than the wanted rows, as on a tree declared breadth first) is overwritten by
  its own assignment, and a statement reading a product entry reads it before any assignment;
* an assignment that copies a product entry (``M``'s mirror) reads an entry its product owns
  (its assignment left out), which nothing overwrites;
* the row ranges of two products written into one output do not meet;
* no pivot check or library factor comes after the product: a ``SYMGEN_SINGULAR`` return leaves
  the outputs as they were before the call only when nothing was written into them.

A product whose factor ``A`` (or ``B``) is the same nodes as an earlier product's reads that
product's packed array (``Step.shares_a``, ``Step.shares_b``) instead of packing its own: the
closed form's ``d tau/dq`` and ``d tau/dqd`` products share their ``B``. One whose packed factor
would be a library result's entries in their own order (the inverse of a large mass matrix, by
which the forward-dynamics Jacobians multiply the explicit partials) reads that result's array:
``n^2`` copies fewer.

Two scan products with the same ``W``, ``rl`` and ``ru`` (a chain's ``M^-1 d tau/dq`` and
``M^-1 d tau/dqd``) share their running sums: the second's call computes both
(:func:`pair_scans`), where the first writes into an output and nothing reads its result before
the second.
"""
from __future__ import annotations

import dataclasses

from ..emit import Lowered, Ref, flat_index, product_factors
from .c_schedule import FAILING

def lay_out_products(low: Lowered) -> Lowered:
    """``low`` with its products written into outputs where they can be, their repeated factors
    packed once and scan products on the same running sums paired (module docstring)."""
    return pair_scans(share_operands(write_into_outputs(low)))


def write_into_outputs(low: Lowered) -> Lowered:
    """``low`` with each product that can write its result straight into an output doing so
    (``Step.into``: the output's name), its entries referenced as that output's entries (``Ref``
    kind ``out``) and the assignments it makes redundant left out; ``low`` itself when none can."""
    products = [s for s in low.steps if s.kind == "product"]
    if not products:
        return low
    last_check = max((i for i, s in enumerate(low.steps) if s.kind in FAILING), default=-1)
    position = {s.name: i for i, s in enumerate(low.steps)}
    assigned = {}                                # output name -> {flat: ref}
    for arg, entries in low.outputs:
        assigned[arg.name] = {flat_index(idx, arg.shape): r for idx, r in entries}
    sizes = {arg.name: arg.size for arg, _ in low.outputs}
    read_by_assign: dict[str, set[int]] = {}     # product -> the entries assignments read
    for _, entries in low.outputs:
        for _, r in entries:
            if r.kind == "library_out":
                read_by_assign.setdefault(r.data[0], set()).add(r.data[1])
    chosen: dict[str, str] = {}
    taken: dict[str, list[set[int]]] = {}
    for step in products:
        if position[step.name] < last_check:
            continue
        into = _destination(step, assigned, sizes)
        if into is None:
            continue
        owned = {c * step.n + r for c, (lo, hi) in enumerate(step.ranges) for r in range(lo, hi)}
        own = {f for f in owned if _is_entry(assigned[into].get(f), step.name, f)}
        if not read_by_assign.get(step.name, set()) <= own:
            continue                             # a copy would read a row another assignment overwrites
        if any(owned & other for other in taken.get(into, [])):
            continue
        taken.setdefault(into, []).append(owned)
        chosen[step.name] = into
    if not chosen:
        return low

    def redirect(r: Ref) -> Ref:
        if r.kind == "library_out" and r.data[0] in chosen:
            return Ref("out", (chosen[r.data[0]], r.data[1]))
        return r

    steps = []
    for s in low.steps:
        args = tuple(redirect(r) for r in s.args)
        if args != s.args or s.name in chosen:
            s = dataclasses.replace(s, args=args, into=chosen.get(s.name, ""))
        steps.append(s)
    outputs = []
    for arg, entries in low.outputs:
        kept = []
        for idx, r in entries:
            flat = flat_index(idx, arg.shape)
            if r.kind == "library_out" and chosen.get(r.data[0]) == arg.name and r.data[1] == flat:
                continue                         # the product wrote it there
            kept.append((idx, redirect(r)))
        outputs.append((arg, kept))
    return dataclasses.replace(low, steps=steps, outputs=outputs)


def _is_entry(r, name: str, flat: int) -> bool:
    return r is not None and r.kind == "library_out" and r.data == (name, flat)


def _destination(step, assigned: dict, sizes: dict) -> str | None:
    """The output that takes the most of the product's entries at their own flat index, if it
    has exactly ``n * k`` entries."""
    counts: dict[str, int] = {}
    for out, table in assigned.items():
        if sizes[out] != step.n * step.k:
            continue
        hits = sum(1 for flat, r in table.items() if _is_entry(r, step.name, flat))
        if hits:
            counts[out] = hits
    return max(sorted(counts), key=counts.get) if counts else None


def share_operands(low: Lowered) -> Lowered:
    """``low`` with each product whose ``A`` or ``B`` entries are those of an earlier product's
    (the same references, in the same layout) reading that product's packed array, and each whose
    ``A^T`` or ``B^T`` is a library result's entries in their own order (a symmetric inverse given
    as its transpose, :meth:`~symgen.codegen.graph_solves.LinearSolves.solve_spd`) reading that
    result's array: ``shares_a``/``shares_b`` name the array."""
    sizes = {s.name: s.n * s.k for s in low.steps if s.kind == "solve"}
    seen: dict[tuple, str] = {}
    steps, changed = [], False
    for s in low.steps:
        if s.kind == "product":
            shares = {}
            for part, refs, _ in product_factors(s):
                key = (part, len(refs)) + tuple(id(r) for r in refs)
                whole = _library_result(refs, sizes)
                if whole:
                    shares[f"shares_{part}"] = whole
                elif key in seen:
                    shares[f"shares_{part}"] = seen[key]
                else:
                    seen[key] = f"p{part}{s.name[1:]}"
            if shares:
                s = dataclasses.replace(s, **shares)
                changed = True
        steps.append(s)
    return dataclasses.replace(low, steps=steps) if changed else low


def _library_result(refs, sizes: dict[str, int]) -> str:
    """The solve whose whole result ``refs`` are, entry ``i`` at position ``i``, or ``""``."""
    first = refs[0] if refs else None
    if first is None or first.kind != "library_out" or sizes.get(first.data[0]) != len(refs):
        return ""
    name = first.data[0]
    return name if all(r.kind == "library_out" and r.data == (name, i) for i, r in enumerate(refs)) else ""


def pair_scans(low: Lowered) -> Lowered:
    """``low`` with each scan product whose ``W``, ``rl`` and ``ru`` are a later one's computed by
    that one's call (one pass of the running sums for both: ``Step.deferred`` on the first, whose
    factors are still packed where it stands, ``Step.pair`` on the second). Only a scan written
    into an output is deferred, and only when nothing reads its result: no statement between the
    two reads it, nor any output assignment."""
    steps = list(low.steps)
    read_by_outputs = {r.data[0] for _, entries in low.outputs for _, r in entries
                       if r is not None and r.kind in ("library_out", "out")}
    changed = False
    for a_at, a in enumerate(steps):
        if not (a.kind == "product" and a.scan and a.into and not a.deferred and not a.pair
                and a.name not in read_by_outputs and a.into not in read_by_outputs):
            continue
        for b_at in range(a_at + 1, len(steps)):
            b = steps[b_at]
            if _reads(b, a):
                break
            if not (b.kind == "product" and b.scan == a.scan and (b.n, b.k) == (a.n, a.k) and not b.pair
                    and not b.deferred and _same_sums(a, b)):
                continue
            parts = {part: shared or f"p{part}{a.name[1:]}" for part, _, shared in product_factors(a)}
            steps[a_at] = dataclasses.replace(a, deferred=True)
            steps[b_at] = dataclasses.replace(b, pair=(parts["cl"], parts["cu"], a.into))
            changed = True
            break
    return dataclasses.replace(low, steps=steps) if changed else low


def _same_sums(a, b) -> bool:
    """Whether two scan products read the same ``W``, ``rl`` and ``ru`` (the same references)."""
    fa = {part: tuple(id(r) for r in refs) for part, refs, _ in product_factors(a)}
    fb = {part: tuple(id(r) for r in refs) for part, refs, _ in product_factors(b)}
    return all(fa[part] == fb[part] for part in ("b", "rl", "ru"))


def _reads(step, product) -> bool:
    """Whether ``step`` reads an entry of ``product``'s result (where it stands or in its output)."""
    return any(r is not None and ((r.kind == "library_out" and r.data[0] == product.name)
                                  or (r.kind == "out" and r.data[0] == product.into)) for r in step.args)

