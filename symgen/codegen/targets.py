"""Targets: which templates a target renders and how its statements are printed.

A target is a printer plus a list of ``(template, output file)`` pairs; the Jinja environment
uses ``StrictUndefined`` so a missing variable is an error, never an empty string. Everything the
templates need (statements, index maps, op counts) is computed here.
"""
from __future__ import annotations

import functools
import pathlib

import jinja2

from .emit import CPrinter, Lowered, NumpyPrinter, Printer, Step, ops_comment

TARGETS = ("numpy", "c")


def templates_dir() -> pathlib.Path:
    """The ``templates/`` folder: packaged as ``symgen.templates``, or beside the source tree."""
    import importlib.resources

    try:
        path = pathlib.Path(str(importlib.resources.files("symgen.templates")))
        if (path / "util.jinja").exists():
            return path
    except ModuleNotFoundError:
        pass
    return pathlib.Path(__file__).resolve().parents[2] / "templates"


@functools.lru_cache(maxsize=1)
def environment() -> jinja2.Environment:
    return jinja2.Environment(loader=jinja2.FileSystemLoader(str(templates_dir())),
                              undefined=jinja2.StrictUndefined, keep_trailing_newline=True,
                              trim_blocks=True, lstrip_blocks=True, autoescape=False)


def _numpy_step(step: Step, p: Printer) -> list[str]:
    if step.kind == "op":
        return [f"{step.name} = {p.expr(step)}"]
    if step.kind == "factor":
        n = step.n
        out = [f"{step.name} = np.empty(batch + ({n}, {n}))"]
        out += [f"{step.name}[..., {i // n}, {i % n}] = {p.ref(r)}" for i, r in enumerate(step.args)]
        out.append(f'_check_condition({step.name}, "{step.what}")')
        return out
    n, k = step.n, step.k
    rhs = "B" + step.name[1:]
    out = [f"{rhs} = np.empty(batch + ({n}, {k}))"]
    out += [f"{rhs}[..., {i // k}, {i % k}] = {p.ref(r)}" for i, r in enumerate(step.args)]
    matrix = f"np.swapaxes({step.factor}, -1, -2)" if step.transposed else step.factor
    out.append(f"{step.name} = np.linalg.solve({matrix}, {rhs})")
    return out


def _c_step(step: Step, p: Printer) -> list[str]:
    if step.kind == "op":
        return [f"const double {step.name} = {p.expr(step)};"]
    if step.kind == "factor":
        n, name = step.n, step.name
        idx = name[1:]
        out = [f"double {name}[{n * n}];", f"int piv{idx}[{n}];", f"double cond{idx};"]
        out += [f"{name}[{i}] = {p.ref(r)};" for i, r in enumerate(step.args)]
        out.append(f"/* {step.what} */")
        out.append(f"if (symgen_lu_factor({n}, {name}, piv{idx}, &cond{idx})) "
                   f"{{ if (cond) *cond = cond{idx}; return SYMGEN_SINGULAR; }}")
        out.append(f"if (cond{idx} > worst) worst = cond{idx};")
        return out
    n, k, name = step.n, step.k, step.name
    out = [f"double {name}[{n * k}];"]
    out += [f"{name}[{i}] = {p.ref(r)};" for i, r in enumerate(step.args)]
    solver = "symgen_lu_solve_t" if step.transposed else "symgen_lu_solve"
    out.append(f"{solver}({n}, {k}, {step.factor}, piv{step.factor[1:]}, {name});")
    return out


def _flat(idx, shape) -> int:
    out = 0
    for i, s in zip(idx, shape):
        out = out * s + i
    return out


def function_context(low: Lowered, target: str, module: str) -> dict:
    """What the templates need for one function."""
    fn = low.function
    p = NumpyPrinter() if target == "numpy" else CPrinter()
    inputs = [dict(name=a.name, size=a.size, doc=a.doc) for a in fn.inputs]
    outputs = []
    for arg, entries in low.outputs:
        shape = arg.shape
        if target == "numpy":
            assign = [f"{arg.name}[{', '.join(map(str, idx))}] = {p.ref(r)}" for idx, r in entries]
        else:
            assign = [f"{arg.name}[{_flat(idx, shape)}] = {p.ref(r)};" for idx, r in entries]
        size = 1
        for s in shape:
            size *= s
        outputs.append(dict(name=arg.name, shape=list(shape), size=size, doc=arg.doc, assign=assign))
    ctx = dict(name=fn.name, doc=fn.doc, inputs=inputs, outputs=outputs, ops_comment=ops_comment(low.ops))
    if target == "numpy":
        ctx["body"] = [line for step in low.steps for line in _numpy_step(step, p)]
        moved = [f"np.moveaxis({o['name']}, 0, -1)" if len(o["shape"]) == 1
                 else f"np.moveaxis({o['name']}, (0, 1), (-2, -1))" for o in outputs]
        ctx["returns"] = moved[0] if len(moved) == 1 else "(" + ", ".join(moved) + ")"
    else:
        ctx["body"] = [line for step in low.steps for line in _c_step(step, p)]
        ctx["symbol"] = f"symgen_{module}_{fn.name}"
        params = [f"const double {a['name']}[{a['size']}]" for a in inputs]
        params += [f"double {o['name']}[{o['size']}]" for o in outputs] + ["double *cond"]
        ctx["c_params"] = ", ".join(params)
        batch = [f"const double *{a['name']}" for a in inputs] + [f"double *{o['name']}" for o in outputs]
        ctx["c_batch_params"] = ", ".join(batch + ["double *cond"])
        call = [f"{a['name']} + (size_t)i * {a['size']}" for a in inputs]
        call += [f"{o['name']} + (size_t)i * {o['size']}" for o in outputs]
        ctx["c_batch_call"] = ", ".join(call + ["cond"])
        ctx["all_args"] = inputs + outputs
        ctx["test_call"] = ", ".join([a["name"] for a in inputs] + ["got_" + o["name"] for o in outputs] + ["&cond"])
        ctx["binding_returns"] = "outputs[0]" if len(outputs) == 1 else "tuple(outputs)"
    return ctx


def render(template: str, **context) -> str:
    return environment().get_template(template).render(**context)
