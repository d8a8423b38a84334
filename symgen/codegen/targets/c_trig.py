"""The sines and cosines of a C function, several angles per vector instruction.

A joint angle's ``sin`` and ``cos`` cost far more than the joint's arithmetic: the inline kernel of
``symgen_trig`` (a Cody-Waite reduction and two polynomials, ``templates/trig_kernel.jinja``) is
some forty dependent operations per angle. The traced statements take them one angle at a time.
Here every run of consecutive ``sin``/``cos`` statements of a scalar C function becomes one
``sincos`` step: its distinct angles are evaluated by ``symgen_sincos_n`` (``templates/trig.c.jinja``),
``SYMGEN_VECTOR`` angles (4 with AVX2) per evaluation of the lanes' kernel (rendered over a vector of
that width, ``symgen_vector_sincos``), and each original
temporary reads its value back; a file compiled without vectors keeps the original statements
(under ``#if SYMGEN_VECTOR_TRIG``). The kernel is the scalar one over a vector type, so every
sine and cosine has the bits the scalar statement gave; only the number of instructions changes
(the three builds side by side: ``benchmarks/trig_inline.py``).

The lanes kernels (one state per lane, :mod:`~symgen.codegen.targets.c_lanes`) are already
vectorised across states: there a ``sincos`` step asks the kernel once per distinct angle for the
results it needs (a chain's sine and cosine of one joint angle from one reduction). The NumPy target
keeps one statement per function call.
"""
from __future__ import annotations

from dataclasses import replace

from ..emit import Lowered, Ref, Step

#: the trigonometric ops the traced graph holds
TRIG = ("sin", "cos")


def _key(ref: Ref):
    """A hashable identity of an angle reference (an input element, a temporary, a literal)."""
    return ref.kind, ref.data


def _sincos(run: list[Step], index: int) -> Step:
    """One ``sincos`` step for a run of trig statements (distinct angles, in order of first use)."""
    angles: list[Ref] = []
    where: dict = {}
    outputs = []
    for step in run:
        key = _key(step.args[0])
        if key not in where:
            where[key] = len(angles)
            angles.append(step.args[0])
        outputs.append((step.name, step.op, where[key]))
    return Step("sincos", f"symgen_trig{index}", args=tuple(angles), n=len(angles), outputs=tuple(outputs))


def batch_trig(low: Lowered) -> Lowered:
    """``low`` with each run of two or more consecutive trig statements (no statement of the run
    reading another's result) replaced by one ``sincos`` step; the rest unchanged."""
    steps: list[Step] = []
    run: list[Step] = []
    count = 0

    def flush():
        nonlocal count
        if len(run) >= 2:
            steps.append(_sincos(run, count))
            count += 1
        else:
            steps.extend(run)
        run.clear()

    for step in low.steps:
        if step.kind == "op" and step.op in TRIG:
            arg = step.args[0]
            if arg.kind == "tmp" and any(s.name == arg.data for s in run):
                flush()
            run.append(step)
        else:
            flush()
            steps.append(step)
    flush()
    return replace(low, steps=steps) if count else low


def sincos_statements(step: Step, angle) -> list[str]:
    """The C lines of a ``sincos`` step (``angle`` prints an argument reference): where the file is
    compiled with vectors (``SYMGEN_VECTOR_TRIG``, ``templates/trig.c.jinja``), the angles, one
    call, each temporary read back; otherwise the statements it replaced, one angle at a time."""
    name, n = step.name, step.n
    lines = ["#if SYMGEN_VECTOR_TRIG",
             f"const double {name}_x[{n}] = {{{', '.join(angle(a) for a in step.args)}}};",
             f"double {name}_s[{n}], {name}_c[{n}];",
             f"symgen_sincos_n({n}, {name}_x, {name}_s, {name}_c);"]
    lines += [f"const double {out} = {name}_{op[0]}[{i}];" for out, op, i in step.outputs]
    lines.append("#else")
    lines += [f"const double {out} = symgen_{op}({angle(step.args[i])});" for out, op, i in step.outputs]
    lines.append("#endif")
    return lines
