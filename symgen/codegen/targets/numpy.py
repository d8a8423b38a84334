"""The NumPy target: one plain-NumPy module per scene, every function batched over leading axes.

Renders ``templates/numpy/module.py.jinja`` into ``<scene>.py``; temporaries are arrays over the
batch dimensions, dense factor/solve statements call ``np.linalg.solve`` after a condition check.
"""
from __future__ import annotations

from ..emit import Printer, Step
from .base import Target


class NumpyPrinter(Printer):
    funcs = {"sin": "np.sin", "cos": "np.cos", "sqrt": "np.sqrt", "sign": "np.sign"}

    def input(self, array, index):
        return f"{array}[{index}]"

    def solve_out(self, name, i, j, k):
        return f"{name}[..., {i}, {j}]"


class NumpyTarget(Target):
    name = "numpy"
    folder = "numpy"
    compiled = False
    printer_class = NumpyPrinter
    imports = ("numpy",)

    def files(self, module):
        return [(f"{self.folder}/module.py.jinja", f"{module}.py")]

    def entry_file(self, module):
        return f"{module}.py"

    def statement(self, step: Step, p: Printer) -> list[str]:
        if step.kind == "op":
            return [f"{step.name} = {p.expr(step)}"]
        if step.kind == "factor":
            n = step.n
            out = [f"{step.name} = np.empty(batch + ({n}, {n}))"]
            out += [f"{step.name}[..., {i // n}, {i % n}] = {p.ref(r)}" for i, r in enumerate(step.args)]
            out.append(f'_check_condition({step.name}, "{step.what}")')
            return out
        if step.kind == "check":
            big = repr(float(max(step.constants, default=0.0)))
            small = "np.inf" if not step.constants else repr(float(min(step.constants)))
            pivots = ", ".join(p.ref(r) for r in step.args)
            return [f'_check_pivots(({pivots},), {big}, {small}, "{step.what}")']
        n, k = step.n, step.k
        rhs = "B" + step.name[1:]
        out = [f"{rhs} = np.empty(batch + ({n}, {k}))"]
        out += [f"{rhs}[..., {i // k}, {i % k}] = {p.ref(r)}" for i, r in enumerate(step.args)]
        matrix = f"np.swapaxes({step.factor}, -1, -2)" if step.transposed else step.factor
        out.append(f"{step.name} = np.linalg.solve({matrix}, {rhs})")
        return out

    def assignment(self, name, index, shape, value):
        return f"{name}[{', '.join(map(str, index))}] = {value}"

    def extend_context(self, ctx, module):
        ctx["quiet"] = any(line.startswith("_check_pivots(") for line in ctx["body"])
        moved = [f"np.moveaxis({o['name']}, 0, -1)" if len(o["shape"]) == 1
                 else f"np.moveaxis({o['name']}, (0, 1), (-2, -1))" for o in ctx["outputs"]]
        ctx["returns"] = moved[0] if len(moved) == 1 else "(" + ", ".join(moved) + ")"


NUMPY = NumpyTarget()
