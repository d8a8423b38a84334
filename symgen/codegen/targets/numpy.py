"""The NumPy target: one plain-NumPy module per scene, every function batched over leading axes.

Renders ``templates/numpy/module.py.jinja`` into ``<scene>.py``. A function works through its
batch in chunks of ``CHUNK`` states: every scalar statement is one ufunc call writing into a row
of one preallocated 2-D workspace (``np.multiply(w3, w5, out=w7)``), so no statement allocates;
rows are given by liveness (:func:`allocate`), so the workspace holds only what is live at once
and stays in cache. Output entries are copied into the output arrays as soon as they are
computed. Dense factor/solve statements call ``np.linalg.solve`` on the chunk after a condition
check, banded products (:mod:`symgen.codegen.graph_products`) ``np.matmul`` (every entry).
"""
from __future__ import annotations

import heapq

from ..emit import Lowered, Printer, Ref, Step, product_factors
from .base import Target

#: states per pass through a function's workspace (rendered as the module's ``CHUNK``): small
#: enough that the live rows stay in cache, large enough that a ufunc call's overhead is paid
#: on many states (benchmarks/codegen_speed.py)
CHUNK = 2048

#: ufunc of each traced operation
UFUNCS = {"add": "np.add", "sub": "np.subtract", "mul": "np.multiply", "div": "np.divide", "neg": "np.negative",
          "sin": "np.sin", "cos": "np.cos", "sqrt": "np.sqrt", "sign": "np.sign"}


class NumpyPrinter(Printer):
    """Inputs are rows ``q_3`` (unpacked per chunk), temporaries their workspace rows ``w7``."""

    funcs = {"sin": "np.sin", "cos": "np.cos", "sqrt": "np.sqrt", "sign": "np.sign"}

    def __init__(self, rows: dict[str, int] | None = None):
        self.rows = rows or {}
        self.constants: dict[str, int] = {}     # literal -> index of its 0-d array ``k<i>``

    def ref(self, r: Ref) -> str:
        if r.kind == "tmp":
            return f"w{self.rows[r.data]}"
        if r.kind == "const" and self.rows:     # a 0-d array: a ufunc converts a float each call
            literal = super().ref(r)
            return f"k{self.constants.setdefault(literal, len(self.constants))}"
        return super().ref(r)

    def input(self, array, index):
        return f"{array}_{index}"

    def library_out(self, name, flat):
        return f"{name}[:, {flat}]"


def allocate(low: Lowered) -> tuple[dict[str, int], int]:
    """Workspace row of every temporary and the number of rows, by linear scan: a row is freed at
    the last statement that reads it (so that statement may write its result in place), outputs
    are read where they are defined, and a freed row (the smallest first) is reused."""
    last: dict[str, int] = {}
    for k, step in enumerate(low.steps):
        for r in step.args:
            if r.kind == "tmp":
                last[r.data] = k
    rows, free, size = {}, [], 0
    for k, step in enumerate(low.steps):
        for name in dict.fromkeys(r.data for r in step.args if r.kind == "tmp"):
            if last[name] == k:
                heapq.heappush(free, rows[name])
        if step.kind == "op":
            if free:
                rows[step.name] = heapq.heappop(free)
            else:
                rows[step.name] = size
                size += 1
            if step.name not in last:        # read by no statement (an output only): free at once
                heapq.heappush(free, rows[step.name])
    return rows, size


class NumpyTarget(Target):
    name = "numpy"
    folder = "numpy"
    compiled = False
    printer_class = NumpyPrinter
    imports = ("numpy",)

    def files(self, module, python_extension=False):
        return [(f"{self.folder}/module.py.jinja", f"{module}.py")]

    def entry_file(self, module):
        return f"{module}.py"

    def file_context(self, template, job):
        return dict(chunk=CHUNK)

    def statement(self, step: Step, p: Printer) -> list[str]:
        if step.kind == "op":
            args = ", ".join(p.ref(r) for r in step.args)
            line = f"{UFUNCS[step.op]}({args}, {p.ref(Ref('tmp', step.name))})"
            named = not (step.name[0] == "t" and step.name[1:].isdigit())
            return [line + f"  # {step.name}" if named else line]
        if step.kind == "factor":
            n = step.n
            out = [f"{step.name} = np.empty((size, {n}, {n}))"]
            out += [f"{step.name}[:, {i // n}, {i % n}] = {p.ref(r)}" for i, r in enumerate(step.args)]
            limit = ", MAX_LOOP_ESTIMATE" if step.loop_limit else ""
            out.append(f'_check_condition({step.name}, "{step.what}"{limit})')
            return out
        if step.kind == "check":
            big = repr(float(max(step.constants, default=0.0)))
            small = "np.inf" if not step.constants else repr(float(min(step.constants)))
            pivots = ", ".join(p.ref(r) for r in step.args)
            limit = ", MAX_LOOP_ESTIMATE" if step.loop_limit else ""
            return [f'_check_pivots(({pivots},), {big}, {small}, "{step.what}"{limit})']
        if step.kind == "product" and step.scan:      # D formed from its triangles, then one matmul
            n, k, idx = step.n, step.k, step.name[1:]
            out = []
            for part, refs, _ in product_factors(step):
                cols = len(refs) // n if n else 0
                out.append(f"S{part.upper()}{idx} = np.empty((size, {n}, {cols}))")
                out += [f"S{part.upper()}{idx}[:, {i // cols}, {i % cols}] = {p.ref(r)}" for i, r in enumerate(refs)]
            return out + [
                f"D{idx} = np.where(np.tri({n}, dtype=bool), SRL{idx} @ np.swapaxes(SCL{idx}, 1, 2), "
                f"SRU{idx} @ np.swapaxes(SCU{idx}, 1, 2))",
                f"{step.name} = np.swapaxes(np.swapaxes(D{idx}, 1, 2) @ SB{idx}, 1, 2).reshape(size, {k * n})"
                f"  # {step.what}"]
        if step.kind == "product":
            n, m, k, idx = step.n, step.m, step.k, step.name[1:]
            out = [f"PA{idx} = np.empty((size, {m}, {n}))", f"PB{idx} = np.empty((size, {k}, {m}))"]
            out += [f"PA{idx}[:, {i // n}, {i % n}] = {p.ref(r)}" for i, r in enumerate(step.args[:m * n])]
            out += [f"PB{idx}[:, {i // m}, {i % m}] = {p.ref(r)}" for i, r in enumerate(step.args[m * n:])]
            return out + [f"{step.name} = np.matmul(PB{idx}, PA{idx}).reshape(size, {k * n})  # {step.what}"]
        n, k = step.n, step.k
        if step.inverse:
            return [f"{step.name} = np.linalg.inv({step.factor}).reshape(size, {n * n})"]
        rhs = "B" + step.name[1:]
        out = [f"{rhs} = np.empty((size, {n}, {k}))"]
        out += [f"{rhs}[:, {i // k}, {i % k}] = {p.ref(r)}" for i, r in enumerate(step.args)]
        matrix = f"np.swapaxes({step.factor}, -1, -2)" if step.transposed else step.factor
        out.append(f"{step.name} = np.linalg.solve({matrix}, {rhs}).reshape(size, {n * k})")
        return out

    def assignment(self, name, index, shape, value):
        flat = 0
        for i, s in zip(index, shape):
            flat = flat * s + i
        return f"{name}[{flat}, start:stop] = {value}"

    def lay_out(self, low, p, module):
        """Statements into workspace rows; each output entry stored right after the statement that
        computes it (a temporary's, a library call's; constants and inputs first). Extra variables:
        ``work_rows``, per input the row names to unpack per chunk (``_`` for unused rows), and
        the constants (0-d arrays made once, at import)."""
        rows, size = allocate(low)
        p = self.printer_class(rows)
        stores: dict[str, list[str]] = {}
        first = []
        for arg, entries in low.outputs:
            for idx, r in entries:
                line = self.assignment(arg.name, idx, arg.shape, p.ref(r))
                key = r.data if r.kind == "tmp" else r.data[0] if r.kind == "library_out" else None
                (first if key is None else stores.setdefault(key, [])).append(line)
        body = list(first)
        for step in low.steps:
            body += self.statement(step, p)
            if step.kind != "factor":
                body += stores.get(step.name, [])
        used = {r.data for step in low.steps for r in step.args if r.kind == "in"}
        used |= {r.data for _, entries in low.outputs for _, r in entries if r.kind == "in"}
        unpack = []
        for a in low.function.inputs:
            names = [f"{a.name}_{i}" if (a.name, i) in used else "_" for i in range(a.size)]
            if any(n != "_" for n in names):
                unpack.append(dict(name=a.name, rows=", ".join(names) + ("," if a.size == 1 else "")))
        work = ", ".join(f"w{i}" for i in range(size)) + ("," if size == 1 else "")
        consts = list(p.constants)
        constants = dict(names=", ".join(f"k{i}" for i in range(len(consts))) + ("," if len(consts) == 1 else ""),
                         values=", ".join(c.strip("()") for c in consts) + ("," if len(consts) == 1 else ""))
        return body, [[] for _ in low.outputs], dict(work_rows=size, work_names=work, unpack=unpack,
                                                     constants=constants if consts else None)

    def extend_context(self, ctx, module):
        ctx["quiet"] = any(line.startswith("_check_pivots(") for line in ctx["body"])
        moved = [f"np.moveaxis({o['name']}, 0, -1)" if len(o["shape"]) == 1
                 else f"np.moveaxis({o['name']}, (0, 1), (-2, -1))" for o in ctx["outputs"]]
        ctx["returns"] = moved[0] if len(moved) == 1 else "(" + ", ".join(moved) + ")"


NUMPY = NumpyTarget()
