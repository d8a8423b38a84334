"""Lanes across states: the C ``_batch`` entry points evaluate several states at once.

The same lowered statements as the scalar function, printed over a vector type of
``SYMGEN_LANES`` doubles (GCC/Clang vector extensions): one vector statement computes one scalar
statement for ``SYMGEN_LANES`` states. The width is chosen when the file is *compiled*, by the
preprocessor (``templates/lanes.c.jinja``): 8 with AVX-512F (4 under ``-DSYMGEN_LANES_256``), 4 with
AVX2, otherwise 1 (the scalar loop) -- so the generated file is the same on every machine, and the
lane code compiles away under ``-DSYMGEN_NO_LANES`` or a compiler without the extensions.

Per lane, the kernel does what the scalar function does to its state:

* inputs are read from ``lanes`` consecutive states (the last state repeated to fill a partial
  group), a tile of ``SYMGEN_LANES`` entries at a time by whole-row loads and a transpose;
  outputs are written back the same way to the ``lanes`` states only (the unused lanes to a
  scratch row);
* sin and cos are computed inline (``symgen_lanes_sincos`` in the template): a Cody-Waite reduction
  by pi/2 and the polynomials :data:`SIN_COEFFICIENTS` and :data:`COS_COEFFICIENTS`; a lane with
  ``|x| > 2^20`` or not finite takes the C library's function. sin and cos of one angle then
  share one reduction, no call clobbers the kernel's vector registers, and every C library gets
  the same vector code (glibc's libmvec, called before, was no faster on the benchmark's
  processor, and other C libraries fell back to ``sin`` lane by lane). ``sqrt`` and the sign are
  exact lane by lane;
* a pivot check that fails marks its lane ``SYMGEN_SINGULAR`` with that check's estimate and
  leaves the other lanes alone (the failed lane computes on; its values are discarded);
* an output that is not finite marks its own lane ``SYMGEN_NONFINITE``.

A kernel whose arrays (outputs, their scratch rows, the blocks' workspace) would take more than
:data:`LANE_STACK_LIMIT` bytes at the widest lanes keeps them on the heap instead of its stack
frame (``heap``: their size in vectors): its ``_batch`` entries allocate them once per call, and
take the scalar loop when the allocation fails. A frame of hundreds of kilobytes (``chain:n=64``'s
``mass_matrix`` at 8 lanes) would overflow the stack of a thread that musl (128 KB) or macOS
(512 KB) starts.

With ``-std=c99`` alone GCC does not contract ``a * b + c`` into a fused multiply-add (in the
scalar code nor in the vector code; Clang contracts by default, and in the tests both paths fused
alike), so the two paths round alike, sin and cos included: the
scalar function's ``symgen_sin``/``symgen_cos`` are the same reduction and polynomials (outside
``|x| <= 2^20`` both take the C library's). The bindings add ``-ffp-contract=fast`` on x86-64: the
compiler then fuses where it finds a multiply feeding an add, in the lanes and the scalar code
alike but not always at the same statements, so the two agree to rounding (1e-13 relative in
``tests/test_codegen_lanes.py``), not bit for bit. A banded product (``product`` steps,
:mod:`~symgen.codegen.graph_products`) runs over the lanes as a loop of vector multiply-adds
(``symgen_lanes_product``, the terms in the scalar loop's order). A function with a library
factorisation (``factor``/``solve`` steps: the LU's row exchanges differ per lane, the symmetric
factor's loops are scalar) has no lane kernel: its ``_batch`` stays the scalar loop.
"""
from __future__ import annotations

from ..emit import Lowered, Printer, Step, flat_index, product_factors
from .c_blocks import WORK, needs_split, split
from .c_schedule import with_stores

#: the vector type of the generated lane code (``templates/lanes.c.jinja``)
LANE_TYPE = "symgen_lanes_t"
#: prefix of the raw (array-of-states) pointer arguments of a lane kernel; the gathered vector
#: arrays keep the arguments' own names, so the scalar statements print unchanged
RAW = "raw_"
#: bytes of a lane kernel's arrays beyond which they go to the heap (module docstring)
LANE_STACK_LIMIT = 64 * 1024
#: bytes of one lane vector at the widest lanes (8 doubles, AVX-512F)
LANE_BYTES = 64


#: sin r = r + r^3 P(r^2) on |r| <= pi/4: P's coefficients, constant term first (:func:`fit_trig`)
SIN_COEFFICIENTS = (-0.16666666666666666, 0.008333333333330948, -0.00019841269836756774,
                    2.7557316101617874e-06, -2.505113165023518e-08, 1.5918115263265974e-10)
#: cos r = 1 - r^2 / 2 + r^4 Q(r^2) on |r| <= pi/4: Q's coefficients, constant term first
COS_COEFFICIENTS = (0.041666666666666664, -0.0013888888888887398, 2.480158729876456e-05,
                    -2.7557317271145144e-07, 2.087614614655861e-09, -1.1382623647474604e-11)


def fit_trig(digits: int = 40) -> tuple[tuple[float, ...], tuple[float, ...], float, float]:
    """``(P, Q, error of P, error of Q)``: Chebyshev fits (``mpmath.chebyfit``, 6 terms each, in
    ``digits`` digits) of P(z) = (sin r - r) / r^3 and Q(z) = (cos r - 1 + z/2) / z^2, z = r^2, over
    ``0 <= z <= (pi/4)^2 * 1.0001`` (a rounded k leaves |r| a hair above pi/4), rounded to doubles:
    how :data:`SIN_COEFFICIENTS` and :data:`COS_COEFFICIENTS` were made."""
    import mpmath

    with mpmath.workdps(digits):
        top = (mpmath.pi / 4) ** 2 * mpmath.mpf("1.0001")

        def p(z):
            if z == 0:
                return mpmath.mpf(-1) / 6
            r = mpmath.sqrt(z)
            return (mpmath.sin(r) - r) / (r * z)

        def q(z):
            if z == 0:
                return mpmath.mpf(1) / 24
            return (mpmath.cos(mpmath.sqrt(z)) - 1 + z / 2) / (z * z)

        fits = [mpmath.chebyfit(f, [0, top], 6, error=True) for f in (p, q)]
        return (tuple(float(c) for c in fits[0][0][::-1]), tuple(float(c) for c in fits[1][0][::-1]),
                float(fits[0][1]), float(fits[1][1]))


def horner(coefficients, var: str = "z") -> str:
    """``c0 + z * (c1 + z * (...))`` as C, each coefficient as the shortest repr of its double."""
    text = repr(float(coefficients[-1]))
    for c in reversed(coefficients[:-1]):
        text = f"{float(c)!r} + {var} * ({text})"
    return text


def trig_context() -> dict:
    """The polynomials of ``symgen_lanes_sincos`` and ``symgen_trig`` for the templates: sin's first
    coefficient apart (``sin_first``, ``sin_tail``: ``P(z) = sin_first + z sin_tail(z)``), as the
    kernel with the reduction's tail reads them."""
    return dict(sin_first=repr(float(SIN_COEFFICIENTS[0])), sin_tail=horner(SIN_COEFFICIENTS[1:]),
                cos_poly=horner(COS_COEFFICIENTS))


class LanePrinter(Printer):
    """Prints the scalar statements over :data:`LANE_TYPE`: the same names and operators (a
    literal operand is broadcast by the vector extension), the lane versions of the functions."""

    funcs = {"sin": "symgen_lanes_sin", "cos": "symgen_lanes_cos", "sqrt": "symgen_lanes_sqrt",
             "sign": "symgen_lanes_sign"}

    def input(self, array, index):
        return f"{array}[{index}]"

    def library_out(self, name, flat):
        return f"{name}[{flat}]"

    output = library_out

    def value(self, r) -> str:
        """``r`` where a whole vector is needed (an output entry): a literal is broadcast."""
        return broadcast(self.ref(r), r)


def broadcast(text: str, r) -> str:
    """An output entry's text ``text`` of reference ``r``: a literal is broadcast to all lanes."""
    return f"symgen_lanes_splat({text})" if r.kind == "const" else text


def has_lanes(low: Lowered) -> bool:
    """Whether ``low`` gets a lane kernel: every step is an operation, a pivot check or a
    ``sincos`` step (:func:`~symgen.codegen.targets.c_trig.batch_trig`) or a banded product: no
    library LU and no scan product (which reads a library factor's inverse)."""
    return all(step.kind in ("op", "check", "sincos", "product") and not step.scan for step in low.steps)


def _sincos(step: Step, p) -> list[str]:
    """A ``sincos`` step over the lanes: one kernel evaluation per distinct angle, for its sine,
    its cosine or both (a result no statement reads is passed as a null and folds away). Both
    results of one angle from one call: the compiler need not find the shared reduction itself."""
    wanted: list[dict] = [{} for _ in step.args]
    extra = []
    for out, op, i in step.outputs:
        if op in wanted[i]:
            extra.append(f"const {LANE_TYPE} {out} = {wanted[i][op]};")
        else:
            wanted[i][op] = out
    lines = []
    for angle, outs in zip(step.args, wanted):
        names = [outs[op] for op in ("sin", "cos") if op in outs]
        ptr = [f"&{outs[op]}" if op in outs else f"({LANE_TYPE} *)0" for op in ("sin", "cos")]
        lines.append(f"{LANE_TYPE} {', '.join(names)};")
        lines.append(f"symgen_lanes_sincos({p.ref(angle)}, {ptr[0]}, {ptr[1]});")
    return lines + extra


def _check(step: Step, p) -> list[str]:
    """A pivot check over the lanes: a lane above the bound is marked singular, once, with its
    estimate; the others go on."""
    big = repr(float(max(step.constants, default=0.0)))
    small = "HUGE_VAL" if not step.constants else repr(float(min(step.constants)))
    limit = "SYMGEN_MAX_LOOP_ESTIMATE" if step.loop_limit else "SYMGEN_MAX_CONDITION"
    return [f"/* {step.what}: pivots of the straight-line elimination, per lane */",
            f"{{ const {LANE_TYPE} piv[{step.n}] = {{{', '.join(p.ref(r) for r in step.args)}}};",
            f"  symgen_lanes_check(symgen_lanes_pivot_ratio({step.n}, piv, {big}, {small}), {limit}, "
            f"&singular, &failed, &worst); }}"]


def _statement(step: Step, p) -> list[str]:
    if step.kind == "op":
        return [f"const {LANE_TYPE} {step.name} = {p.expr(step)};"]
    if step.kind == "check":
        return _check(step, p)
    if step.kind == "sincos":
        return _sincos(step, p)
    if step.kind == "product":
        return product_lines(step, lambda r: broadcast(p.ref(r), r), LANE_TYPE, "symgen_lanes_product",
                             p.placed.get(step.name))
    raise NotImplementedError(step.kind)  # pragma: no cover - has_lanes() excludes it


def product_lines(step: Step, value, ctype: str, kernel: str, placed: dict | None = None) -> list[str]:
    """A banded or scan product (:mod:`~symgen.codegen.graph_products`) in C: its result (``ctype``,
    declared first: the block cutter moves it to the workspace; none when the product writes into an
    output, ``step.into``), its factors packed (``value(ref)``: an operand's text; or an earlier
    product's packed array or a library result read in place, ``step.shares_a``/``shares_b``/...,
    :mod:`.c_products`; a scan's factor without terms a one-entry array never read), the library
    loop called -- ``kernel`` for a banded product (``symgen_product`` in the scalar function,
    ``symgen_lanes_product`` over the lanes), ``symgen_scan_product_<pl>_<pu>`` for a scan product,
    with the arrays of an earlier one it computes too (``step.pair``), or none for a scan computed
    by a later one's call (``step.deferred``: its factors are still packed here).
    ``placed``: per factor (``"a"``, ``"b"``), ``(where, entries)`` -- the factor's array is the
    workspace at ``where`` and the blocks that compute the ``entries`` (flat positions) stored them
    there already (:func:`~symgen.codegen.targets.c_blocks.split`); only the others are copied."""
    n, m, k, name = step.n, step.m, step.k, step.name
    idx = name[1:]
    result = [f"{ctype} {name}[{n * k}];"] if not step.into else []
    into = f", into {step.into}" if step.into else ""
    if step.scan:
        out = result + [f"/* {step.what}: {n} x {n} in two triangles of {step.scan[0]} and {step.scan[1]} terms, "
                        f"by {n} x {k}{into} */"]
    else:
        lo = ", ".join(str(a) for a, _ in step.ranges)
        hi = ", ".join(str(b) for _, b in step.ranges)
        out = result + [f"/* {step.what}: {n} x {m} by {m} x {k}, banded{into} */",
                        f"static const int lo{idx}[{k}] = {{{lo}}};", f"static const int hi{idx}[{k}] = {{{hi}}};"]
    packed = []
    for part, refs, shared in product_factors(step):
        if shared:
            packed.append(shared)
            continue
        if not refs:                           # a scan product's triangle without terms: never read
            packed.append(f"p{part}{idx}")
            out.append(f"{ctype} p{part}{idx}[1] = {{0.0}};")
            continue
        packed.append(f"p{part}{idx}")
        where, done = (placed or {}).get(part, (None, ()))
        out.append(f"{ctype} p{part}{idx}[{len(refs)}];" if where is None else f"{ctype} *p{part}{idx} = {where};")
        out += [f"p{part}{idx}[{i}] = {value(r)};" for i, r in enumerate(refs) if i not in done]
    if step.scan:
        if not step.deferred:                  # packed as (W, rl, cl, ru, cu); called (W, rl, ru, cl, cu)
            w, rl, cl, ru, cu = packed
            second = ", ".join(step.pair) if step.pair else "NULL, NULL, NULL"
            out.append(f"symgen_scan_product_{step.scan[0]}_{step.scan[1]}({n}, {k}, {w}, {rl}, {ru}, {cl}, {cu}, "
                       f"{step.into or name}, {second});")
    else:
        out.append(f"{kernel}({n}, {m}, {k}, {packed[0]}, {packed[1]}, lo{idx}, hi{idx}, {step.into or name});")
    return out


def lane_context(low: Lowered, symbol: str, split_at: int, limit: int) -> dict | None:
    """What the template needs for the lane kernel of ``low`` (``symbol``: the scalar function's
    C name), or None when it has none. Cut into blocks as the scalar function is
    (:mod:`~symgen.codegen.targets.c_blocks`: beyond ``split_at`` statements, ``limit`` each)."""
    if not has_lanes(low):
        return None
    fn = low.function
    p = LanePrinter()
    inputs = [dict(name=a.name, size=a.size) for a in fn.inputs]
    outputs = []
    for arg, _ in low.outputs:
        size = 1
        for s in arg.shape:
            size *= s
        outputs.append(dict(name=arg.name, size=size))
    raw = [f"const double *{RAW}{a['name']}" for a in inputs] + [f"double *{RAW}{o['name']}" for o in outputs]
    ctx = dict(symbol=f"{symbol}_lanes", inputs=inputs, outputs=outputs, blocks=[], heap=0)
    if not needs_split(low, split_at):
        ctx["body"], late = with_stores(low, lambda step: _statement(step, p), p.value)
        ctx["assign"] = [line for lines in late for line in lines]
        work = 0
    else:
        params = [f"const {LANE_TYPE} *{a['name']}" for a in inputs] + [f"{LANE_TYPE} *{o['name']}" for o in outputs]
        names = [a["name"] for a in inputs] + [o["name"] for o in outputs]
        done = split(low, p, _statement, flat_index, f"{symbol}_lanes", params, names, limit,
                     ctype=LANE_TYPE, value=broadcast)
        ctx.update(body=done["body"], assign=[], blocks=done["blocks"])
        work = done["work_size"]
    _place_on_heap(ctx, work)
    ctx["params"] = ", ".join(["int lanes"] + raw + ["int *status", "double *cond"]
                              + ([f"{LANE_TYPE} *heap"] if ctx["heap"] else []))
    return ctx


def _place_on_heap(ctx: dict, work: int) -> None:
    """Where the kernel's arrays (inputs, outputs, scratch rows, workspace) exceed
    :data:`LANE_STACK_LIMIT` bytes: ``heap`` (their size in vectors, the inputs left on the stack)
    and each output's offsets in it (``at``, ``sink_at``: its vectors, then its scratch row's
    doubles, in whole vectors), the workspace's last (its declaration in ``body`` becomes a pointer
    into the heap). Not counted: the packed factors and results of an unsplit kernel's products."""
    outputs = ctx["outputs"]
    vectors = sum(a["size"] for a in ctx["inputs"]) + sum(o["size"] for o in outputs) + work
    frame = LANE_BYTES * vectors + 8 * sum(o["size"] for o in outputs)     # the inputs stay on the stack
    if frame <= LANE_STACK_LIMIT:
        return
    at = 0
    for o in outputs:                   # a scratch row of n doubles fits in n / 4 vectors of 4 lanes or more
        o["at"], o["sink_at"] = at, at + o["size"]
        at += o["size"] + -(-o["size"] // 4)
    if work:
        declaration = f"{LANE_TYPE} {WORK}[{work}];"
        assert ctx["body"][0] == declaration, ctx["body"][0]
        ctx["body"][0] = f"{LANE_TYPE} *const {WORK} = heap + {at};"
        at += work
    ctx["heap"] = at
