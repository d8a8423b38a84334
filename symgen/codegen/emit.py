"""From a traced :class:`~symgen.codegen.functions.Function` to target-language statements.

:func:`lower` walks the live nodes in creation order (a valid evaluation order) and produces a
:class:`Lowered` function: temporaries named after what they hold where the algorithm labelled
them (``w_link3_x``, ``f_link3_z``, ``tau_j3``) and ``t<k>`` otherwise, library calls for the
factor, solve and product statements, and the output assignments. Each target (:mod:`symgen.codegen.targets`)
subclasses :class:`Printer` for its syntax and turns these into text; the Jinja templates lay out
the files around it.
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np

from ..conditioning import loop_limited
from .functions import Function
from .graph_products import Product, ScanProduct
from .graph_solves import Factor, PivotCheck, Solve


@dataclass
class Step:
    """One statement: ``kind`` is ``op`` (name = expr), ``factor``, ``solve``, ``product`` (a
    banded matrix product, :mod:`symgen.codegen.graph_products`: ``n x m`` by ``m x k``, ``args``
    its ``A^T`` then its ``B^T`` entries, ``ranges`` each column's rows), ``check`` (the pivot
    check of a straight-line elimination, :mod:`symgen.codegen.sparse_lu`) or ``sincos`` (a C
    target's sin and cos of several angles at once, :mod:`symgen.codegen.targets.c_trig`)."""

    kind: str
    name: str
    op: str = ""
    args: tuple = ()
    n: int = 0
    k: int = 0
    m: int = 0
    ranges: tuple = ()         # product: (lo, hi) of each column's wanted rows
    what: str = ""
    factor: str = ""
    transposed: bool = False
    symmetric: bool = False    # factor, solve: the library factor without row exchanges (graph_solves.Factor)
    inverse: bool = False      # solve: the symmetric factor's inverse, no right-hand side (graph_solves.Solve)
    constants: tuple = ()
    loop_limit: bool = False   # held to MAX_LOOP_ESTIMATE, not MAX_CONDITION (symgen.conditioning)
    outputs: tuple = ()        # sincos: (temporary name, "sin" or "cos", index of its angle in args)
    into: str = ""             # product: the output array its result is written into (C target)
    shares_a: str = ""         # product: the C array it reads as its A^T, packed by an earlier product or a
                               # library result's own (C target, symgen.codegen.targets.c_products)
    shares_b: str = ""         # product: the same for its B^T
    scan: tuple = ()           # product: (p_l, p_u) of a scan product (graph_products.ScanProduct), whose factors
                               # are W (n x k, named b), rl, cl (n x p_l), ru, cu (n x p_u)
    shares_rl: str = ""        # scan product: the C array it reads as rl (an earlier product's packed one)
    shares_cl: str = ""        # scan product: the same for cl, ru and cu
    shares_ru: str = ""
    shares_cu: str = ""
    deferred: bool = False     # scan product: computed by a later one's call (c_products.pair_scans)
    pair: tuple = ()           # scan product: (cl, cu, result) arrays of an earlier one computed with it


def product_factors(step: Step) -> tuple[tuple[str, tuple, str], ...]:
    """A product step's factors: ``(name, entries, shared)`` for ``"a"`` (its ``A^T``, ``m n``
    entries) and ``"b"`` (its ``B^T``), ``shared`` the C array it reads instead of packing its own;
    a scan product's ``"b"`` (``W``), ``"rl"``, ``"cl"``, ``"ru"``, ``"cu"`` in that order."""
    if step.scan:
        pl, pu = step.scan
        sizes = (("b", step.n * step.k), ("rl", step.n * pl), ("cl", step.n * pl), ("ru", step.n * pu),
                 ("cu", step.n * pu))
        out, start = [], 0
        for part, size in sizes:
            out.append((part, step.args[start:start + size], getattr(step, f"shares_{part}", "")))
            start += size
        return tuple(out)
    split = step.m * step.n
    return ("a", step.args[:split], step.shares_a), ("b", step.args[split:], step.shares_b)


@dataclass
class Lowered:
    function: Function
    steps: list[Step]
    outputs: list[tuple[object, list[tuple[tuple[int, ...], object]]]]   # (Argument, [(index, ref)])
    ops: dict
    uses: set = field(default_factory=set)        # 'sign', 'trig', 'solve' ('lu', 'symmetric'; 'substitute',
    #                                               'lu_solve', 'symmetric_solve', 'inverse'), 'product',
    #                                               'scan_product', 'pivots'


def flat_index(idx, shape) -> int:
    """The row-major flat index of ``idx`` in an array of ``shape`` (how the C target stores outputs)."""
    out = 0
    for i, s in zip(idx, shape):
        out = out * s + i
    return out


def _float_literal(value) -> str:
    text = repr(float(value))
    return text if ("." in text or "e" in text or "n" in text) else text + ".0"


class Ref:
    """A reference to a value: a literal, an input element, a temporary or an entry of a library
    call's result (``library_out``: the result's name and the entry's flat index in it -- row-major
    ``n x k`` for a solve, column by column for a product), or of an output a product was written
    into (``out``: the output's name and flat index, :mod:`symgen.codegen.targets.c_products`)."""

    __slots__ = ("kind", "data")

    def __init__(self, kind, data):
        self.kind = kind
        self.data = data


def _loop_limited(fn: Function, what: str) -> bool:
    """A solve with the loop-closure block W (or, with constraints, with ``[J_m; J_f]``) in a
    function that uses the maps' time derivatives (:func:`symgen.conditioning.loop_limited`)."""
    return fn.map_rates and loop_limited(what, fn.constrained)


def lower(fn: Function) -> Lowered:
    g = fn.graph
    alive = g.live([arr.flat for _, arr in fn.outputs])
    refs: dict[int, Ref] = {}
    steps: list[Step] = []
    uses: set[str] = set()
    counter = 0
    for node, on in zip(g.nodes, alive):
        if not on:
            continue
        if node.op == "const":
            refs[node.id] = Ref("const", node.value)
        elif node.op == "in":
            refs[node.id] = Ref("in", node.args)
        elif node.op == "factor":
            fac: Factor = node.args[0]
            name = f"A{node.id}"
            refs[node.id] = Ref("factor", name)
            steps.append(Step("factor", name, n=fac.n, args=tuple(refs[i] for i in fac.entries), what=fac.what,
                              loop_limit=_loop_limited(fn, fac.what), symmetric=fac.symmetric))
            uses.update(("solve", "symmetric" if fac.symmetric else "lu"))
            if steps[-1].loop_limit:
                uses.add("loop_limit")
        elif node.op == "solve":
            sol: Solve = node.args[0]
            name = f"X{node.id}"
            refs[node.id] = Ref("solve", name)
            fac = g.nodes[sol.factor].args[0]
            steps.append(Step("solve", name, n=fac.n, k=sol.k,
                              args=() if sol.inverse else tuple(refs[i] for i in sol.rhs),
                              factor=refs[sol.factor].data, transposed=sol.transposed, symmetric=fac.symmetric,
                              inverse=sol.inverse))
            uses.add("inverse" if sol.inverse else "substitute")
            if fac.symmetric and not sol.inverse:
                uses.add("symmetric_solve")
            if not fac.symmetric and not sol.transposed:
                uses.add("lu_solve")
        elif node.op == "product":
            prod: Product | ScanProduct = node.args[0]
            name = f"X{node.id}"
            refs[node.id] = Ref("product", name)
            steps.append(Step("product", name, n=prod.n, m=prod.m, k=prod.k,
                              args=tuple(refs[i] for i in prod.operands), what=prod.what,
                              ranges=tuple(zip(prod.lo, prod.hi)),
                              scan=(prod.pl, prod.pu) if isinstance(prod, ScanProduct) else ()))
            uses.add("scan_product" if isinstance(prod, ScanProduct) else "product")
        elif node.op == "check":
            chk: PivotCheck = node.args[0]
            steps.append(Step("check", f"P{node.id}", n=len(chk.pivots), args=tuple(refs[i] for i in chk.pivots),
                              what=chk.what, constants=chk.constants, loop_limit=_loop_limited(fn, chk.what)))
            uses.add("pivots")
            if steps[-1].loop_limit:
                uses.add("loop_limit")
        elif node.op == "library_out":
            call, (i, j) = g.nodes[node.args[0]].args[0], node.args[1:]
            flat = j * call.n + i if isinstance(call, (Product, ScanProduct)) else i * call.k + j
            refs[node.id] = Ref("library_out", (refs[node.args[0]].data, flat))
        else:
            if node.name is None:
                name = f"t{counter}"
                counter += 1
            else:
                name = node.name
            if node.op in ("sign", "sin", "cos"):
                uses.add("trig" if node.op != "sign" else "sign")
            refs[node.id] = Ref("tmp", name)
            steps.append(Step("op", name, op=node.op, args=tuple(refs[i] for i in node.args)))
    outputs = []
    for arg, arr in fn.outputs:
        entries = [(idx, refs[g._node(v).id]) for idx, v in np.ndenumerate(arr)]
        outputs.append((arg, entries))
    return Lowered(fn, steps, outputs, g.count(alive), uses)


class Printer:
    """Turns references and steps into text; subclasses fix the target syntax."""

    binary = {"add": "+", "sub": "-", "mul": "*", "div": "/"}
    funcs: dict[str, str] = {}
    #: per product, its factors already in the workspace (the C target's block cutter,
    #: :func:`~symgen.codegen.targets.c_blocks.split`, gives its own printer one; none otherwise)
    placed: Mapping = MappingProxyType({})

    def ref(self, r: Ref) -> str:
        if r.kind == "const":
            text = _float_literal(r.data)
            return f"({text})" if text.startswith("-") else text
        if r.kind == "in":
            return self.input(*r.data)
        if r.kind == "tmp":
            return r.data
        if r.kind == "library_out":
            return self.library_out(*r.data)
        if r.kind == "out":
            return self.output(*r.data)
        raise ValueError(r.kind)

    def expr(self, step: Step) -> str:
        a = [self.ref(x) for x in step.args]
        if step.op in self.binary:
            return f"{a[0]} {self.binary[step.op]} {a[1]}"
        if step.op == "neg":
            return f"-{a[0]}"
        return f"{self.funcs[step.op]}({a[0]})"

    def input(self, array: str, index: int) -> str:  # pragma: no cover - interface
        raise NotImplementedError

    def library_out(self, name: str, flat: int) -> str:  # pragma: no cover
        raise NotImplementedError

    def output(self, name: str, flat: int) -> str:  # pragma: no cover - the C printers only
        raise NotImplementedError


def ops_comment(ops: dict) -> str:
    """One line of operation counts, as in the file headers."""
    text = (f"{ops['mul']} mul ({ops['div']} div), {ops['add']} add, total {ops['total']}; "
            f"{ops['trig']} sin/cos, {ops['sqrt']} sqrt")
    if ops["cmp"]:
        text += f", {ops['cmp']} sign"
    if ops.get("pivot_checks"):
        text += f"; straight-line eliminations, {sum(ops['pivot_checks'])} pivots checked"
    if ops["factorizations"]:
        symmetric = len(ops.get("symmetric_factorizations", ()))
        text += (f"; library calls: LU of {', '.join(f'{n}x{n}' for n in ops['factorizations'])}"
                 + (f" ({symmetric} symmetric, without row exchanges)" if symmetric else "")
                 + f", {len(ops['solves'])} solves (~{ops['solve_flops']} flops)")
    if ops.get("products"):
        text += f"; library products: {len(ops['products'])} (~{ops['product_flops']} flops)"
    return text
