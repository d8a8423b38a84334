"""The C target: C99 functions without allocation, a ctypes binding and a standalone check.

Renders from ``templates/c/``: ``<scene>.h`` (prototypes, status codes), ``<scene>.c`` (LU helpers
only when a solve is emitted, the product loop only when a product is), ``<scene>_ctypes.py`` (the
binding :meth:`CTarget.load` imports; it compiles the source with ``$CC`` on first use, cached by
content hash) and ``test_<scene>.c`` (checks one state, seed :data:`C_TEST_SEED`, against symgen's dense reference model in 50-digit
arithmetic: :func:`~symgen.codegen.reference.pinned_state`).
"""
from __future__ import annotations

import numpy as np

from ...math.fields import MpField
from ...errors import CodegenError
from ..emit import Printer, Step, flat_index
from ..reference import ReferenceState, pinned_state
from .base import Target
from .c_blocks import BLOCK_STATEMENTS, SPLIT_STATEMENTS, needs_split, split
from .c_products import lay_out_products
from .c_schedule import schedule, with_stores
from .c_lanes import lane_context, product_lines, trig_context
from .c_trig import batch_trig, sincos_statements

#: how the ctypes binding and the CPython extension compile the source (``$CC`` and these flags)
BINDING_FLAGS = ("-std=c99", "-O2", "-fPIC", "-shared")
#: added on x86-64: this processor's vectors (the ``_batch`` entries' lanes: 8 states per vector
#: with AVX-512F, 4 with AVX2) and fused multiply-adds, which ``-std=c99`` alone turns off in GCC
X86_64_FLAGS = ("-march=native", "-ffp-contract=fast")
#: the state the standalone C test program checks (seed of :func:`reference_states`)
C_TEST_SEED = 7


class CPrinter(Printer):
    funcs = {"sin": "symgen_sin", "cos": "symgen_cos", "sqrt": "sqrt", "sign": "symgen_sign"}

    def input(self, array, index):
        return f"{array}[{index}]"

    def library_out(self, name, flat):
        return f"{name}[{flat}]"

    output = library_out


def _literal(x: float, digits: int = 15) -> str:
    """A C double literal; a non-finite value has none, and is never written."""
    if not np.isfinite(float(x)):
        raise CodegenError(f"{float(x)} has no C literal")
    text = format(float(x), f".{digits}g")
    return text if any(ch in text for ch in ".en") else text + ".0"


#: significant digits of the C test program's expected values (the program checks to 1e-9)
EXPECTED_DIGITS = 12


def _expected_literals(values) -> str:
    """Expected outputs as C literals, rounded to :data:`EXPECTED_DIGITS` digits."""
    values = np.ravel(np.asarray(values, dtype=float))
    return ", ".join(_literal(v, EXPECTED_DIGITS) for v in values)


def expected_outputs(reference: ReferenceState, function) -> dict[str, np.ndarray]:
    """The outputs of generated ``function`` at the reference's state, computed in its (50-digit)
    field and rounded to float64 (``inf`` beyond double range)."""
    own = getattr(function, "reference", None)
    want = own(reference.state, field=reference.field) if own else reference.outputs(function.name)
    return {k: reference.field.to_float(v) for k, v in want.items()}


def _test_inputs(model, lowered, contexts):
    """The inputs of the pinned state (:func:`~symgen.codegen.reference.pinned_state`) as C
    literals with 17 digits (the exact doubles); adds each output's expected literal, computed in
    50-digit arithmetic at those doubles, to ``contexts``, or, where the reference overflowed,
    ``test_finite = False`` (the test program then expects ``SYMGEN_NONFINITE``). No printed
    digit comes from a float library: the file is the same on every machine."""
    state = pinned_state(model, seed=C_TEST_SEED)
    fld = MpField(model.tree.parameters)
    for low in lowered:                  # a controller function adds its own inputs (V_mr, P_hat, ...)
        extra = getattr(low.function, "reference_inputs", None)
        state.update(extra(state) if extra else {})
    names = []
    for low in lowered:
        for a in low.function.inputs:
            if a.name not in names:
                names.append(a.name)
    for n in names:
        if not np.all(np.isfinite(np.asarray(state[n], dtype=float))):
            raise CodegenError(f"the C test program: the reference state's {n} is not finite; the scene's "
                               "numbers overflow double precision")
    inputs = [dict(name=n, size=len(state[n]), literal=", ".join(_literal(v, 17) for v in state[n])) for n in names]
    reference = ReferenceState(model, state, fld)
    for low, ctx in zip(lowered, contexts):
        want = expected_outputs(reference, low.function)
        ctx["test_finite"] = all(np.all(np.isfinite(want[o["name"]])) for o in ctx["outputs"])
        for o in ctx["outputs"]:
            o["literal"] = _expected_literals(want[o["name"]]) if ctx["test_finite"] else ""
    return inputs


class CTarget(Target):
    name = "c"
    folder = "c"
    compiled = True
    printer_class = CPrinter
    imports = ("ctypes", "hashlib", "os", "pathlib", "platform", "shlex", "subprocess", "tempfile", "numpy")

    python_extension = True
    self_test = "c/test.c.jinja"

    def files(self, module, python_extension=False):
        out = [(f"{self.folder}/header.h.jinja", f"{module}.h"), (f"{self.folder}/source.c.jinja", f"{module}.c"),
               (f"{self.folder}/binding.py.jinja", f"{module}_ctypes.py"),
               (f"{self.folder}/test.c.jinja", f"test_{module}.c")]
        if python_extension:
            out += [(f"{self.folder}/extension.c.jinja", f"{module}_ext.c"),
                    (f"{self.folder}/extension.py.jinja", f"{module}_ext.py")]
        return out

    def entry_file(self, module):
        return f"{module}_ctypes.py"

    def file_context(self, template, job):
        if template == f"{self.folder}/header.h.jinja":
            return dict(guard=f"SYMGEN_{job['module'].upper()}_H")
        if template == f"{self.folder}/test.c.jinja":
            return dict(inputs=_test_inputs(job["model"], job["lowered"], job["contexts"]))
        if template == f"{self.folder}/source.c.jinja":
            return trig_context()
        if template in (f"{self.folder}/binding.py.jinja", f"{self.folder}/extension.py.jinja"):
            return dict(flags=BINDING_FLAGS, x86_64_flags=X86_64_FLAGS)
        return {}

    def statement(self, step: Step, p: Printer) -> list[str]:
        if step.kind == "op":
            return [f"const double {step.name} = {p.expr(step)};"]
        if step.kind == "factor":
            n, name = step.n, step.name
            idx = name[1:]
            if step.symmetric:       # both triangles, from the lower one's values (graph_solves)
                scratch = f"double {name}_row[{2 * n}];"
                call = f"symgen_symmetric_factor({n}, {name}, {name}_row, &cond{idx})"
            else:
                scratch, call = f"int piv{idx}[{n}];", f"symgen_lu_factor({n}, {name}, piv{idx}, &cond{idx})"
            out = [f"double {name}[{n * n}];", scratch, f"double cond{idx};"]
            out += [f"{name}[{i}] = {p.ref(r)};" for i, r in enumerate(step.args)]
            out.append(f"/* {step.what} */")
            out.append(f"if ({call}) {{ if (cond) *cond = cond{idx}; return SYMGEN_SINGULAR; }}")
            if step.loop_limit:
                out.append(f"if (!(cond{idx} <= SYMGEN_MAX_LOOP_ESTIMATE)) "
                           f"{{ if (cond) *cond = cond{idx}; return SYMGEN_SINGULAR; }}")
            out.append(f"if (cond{idx} > worst) worst = cond{idx};")
            return out
        if step.kind == "check":
            return _pivot_check(step, p)
        if step.kind == "sincos":
            return sincos_statements(step, p.ref)
        if step.kind == "product":
            return product_lines(step, p.ref, "double", "symgen_product", p.placed.get(step.name))
        n, k, name = step.n, step.k, step.name
        out = [f"double {name}[{n * k}];"]
        if step.inverse:
            return out + [f"symgen_symmetric_inverse({n}, {step.factor}, {name});"]
        out += [f"{name}[{i}] = {p.ref(r)};" for i, r in enumerate(step.args)]
        if step.symmetric:
            out.append(f"symgen_symmetric_solve({n}, {k}, {step.factor}, {name});")
        else:
            solver = "symgen_lu_solve_t" if step.transposed else "symgen_lu_solve"
            out.append(f"{solver}({n}, {k}, {step.factor}, piv{step.factor[1:]}, {name});")
        return out

    #: most scalar statements of a C function emitted whole, and of one block of a longer one
    #: (:mod:`~symgen.codegen.targets.c_blocks`)
    split_statements = SPLIT_STATEMENTS
    block_statements = BLOCK_STATEMENTS

    def lay_out(self, low, p, module):
        """Whole up to :attr:`split_statements` statements, else cut into static blocks of at most
        :attr:`block_statements` statements (``blocks``: their names, parameters and lines, for
        the template)."""
        low = lay_out_products(batch_trig(schedule(low)))     # the scalar function and the lane kernel alike
        lanes = lane_context(low, f"symgen_{module}_{low.function.name}", self.split_statements,
                             self.block_statements)
        if not needs_split(low, self.split_statements):
            body, assigns = with_stores(low, lambda step: self.statement(step, p), p.ref)
            return body, assigns, dict(blocks=[], lanes=lanes)
        fn = low.function
        params = [f"const double *{a.name}" for a in fn.inputs] + [f"double *{arg.name}" for arg, _ in low.outputs]
        names = [a.name for a in fn.inputs] + [arg.name for arg, _ in low.outputs]
        done = split(low, p, self.statement, flat_index, f"symgen_{module}_{fn.name}", params, names,
                     self.block_statements)
        return done["body"], [[] for _ in low.outputs], dict(blocks=done["blocks"], lanes=lanes)

    def extend_context(self, ctx, module):
        inputs, outputs = ctx["inputs"], ctx["outputs"]
        ctx["symbol"] = f"symgen_{module}_{ctx['name']}"
        params = [f"const double {a['name']}[{a['size']}]" for a in inputs]
        params += [f"double {o['name']}[{o['size']}]" for o in outputs] + ["double *cond"]
        ctx["c_params"] = ", ".join(params)
        batch = [f"const double *{a['name']}" for a in inputs] + [f"double *{o['name']}" for o in outputs]
        ctx["c_batch_params"] = ", ".join(batch + ["double *cond"])
        ctx["c_status_params"] = ", ".join(batch + ["int *status", "double *cond"])
        call = [f"{a['name']} + (size_t)i * {a['size']}" for a in inputs]
        call += [f"{o['name']} + (size_t)i * {o['size']}" for o in outputs]
        ctx["c_batch_call"] = ", ".join(call + ["cond"])
        ctx["c_status_call"] = ", ".join(call + ["cond ? cond + i : NULL"])
        group = [f"{a['name']} + (size_t)i * {a['size']}" for a in inputs]
        group += [f"{o['name']} + (size_t)i * {o['size']}" for o in outputs]
        ctx["c_lanes_call"] = ", ".join(group)
        ctx["all_args"] = inputs + outputs
        ctx["test_call"] = ", ".join([a["name"] for a in inputs] + ["got_" + o["name"] for o in outputs] + ["&cond"])
        ctx["binding_returns"] = "outputs[0]" if len(outputs) == 1 else "tuple(outputs)"
        solved = _solved_matrices(ctx["matrices"])
        ctx["solved_py"], ctx["solved_c"] = repr(solved), _c_string(solved)


def _solved_matrices(matrices: list[str]) -> str:
    """What a singular status of a function names: the matrices it factors or eliminates (the
    status does not say which one failed when there are several)."""
    if not matrices:
        return ""
    return f" ({matrices[0]})" if len(matrices) == 1 else f" (one of: {'; '.join(matrices)})"


def _c_string(text: str) -> str:
    """``text`` as a C string literal (backslashes, quotes, question marks -- no trigraph -- and
    non-printable or non-ASCII characters escaped)."""
    out = []
    for ch in text:
        if ch in '\\"?':
            out.append("\\" + ch)
        elif " " <= ch <= "~":
            out.append(ch)
        else:
            out.extend(f"\\{b:03o}" for b in ch.encode("utf-8"))
    return '"' + "".join(out) + '"'


def _pivot_check(step: Step, p: Printer) -> list[str]:
    """The pivot check of a straight-line elimination: the estimate, and SYMGEN_SINGULAR above the bound."""
    idx = step.name[1:]
    big = repr(float(max(step.constants, default=0.0)))
    small = "HUGE_VAL" if not step.constants else repr(float(min(step.constants)))
    limit = "SYMGEN_MAX_LOOP_ESTIMATE" if step.loop_limit else "SYMGEN_MAX_CONDITION"
    return [f"/* {step.what}: pivots of the straight-line elimination */",
            f"const double piv{idx}[{step.n}] = {{{', '.join(p.ref(r) for r in step.args)}}};",
            f"const double cond{idx} = symgen_pivot_ratio({step.n}, piv{idx}, {big}, {small});",
            f"if (!(cond{idx} <= {limit})) {{ if (cond) *cond = cond{idx}; return SYMGEN_SINGULAR; }}",
            f"if (cond{idx} > worst) worst = cond{idx};"]


C = CTarget()
