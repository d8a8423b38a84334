"""``generate(model, target, functions)``: trace, lower and render the requested functions.

Names that reach a template (scene, bodies, joints, frames, constraints) are checked to be plain
identifiers before anything is traced or rendered.
"""
from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np

from ..errors import CodegenError, SceneError
from ..numbers import is_identifier
from .emit import lower
from .functions import FUNCTIONS, ON_REQUEST, build_function
from .reference import reference_outputs, reference_states
from .targets import TARGETS, function_context, render

#: the state the standalone C test program checks (seed of :func:`reference_states`)
C_TEST_SEED = 7


@dataclass
class Generated:
    module: str
    target: str
    files: dict[str, str]
    ops: dict[str, dict]


def check_names(model) -> None:
    """Every scene name that reaches generated code must be a plain identifier."""
    scene = model.scene
    if not is_identifier(scene.name):
        raise SceneError(f"scene {scene.name!r}", "the scene name becomes a C and Python identifier; "
                                                  "use letters, digits and underscores")
    for kind, table in (("body", scene.bodies), ("joint", scene.joints), ("frame", scene.frames),
                        ("constraint", scene.constraints)):
        for name in table:
            if not is_identifier(name):
                raise SceneError(f"{kind} {name!r}", "names must be plain identifiers before code is generated")


def resolve_functions(names) -> list[str]:
    """The requested functions in canonical order; default: :data:`FUNCTIONS` (the on-request ones
    only by name)."""
    if not names:
        return list(FUNCTIONS)
    known = FUNCTIONS + ON_REQUEST
    unknown = [n for n in names if n not in known]
    if unknown:
        raise CodegenError(f"unknown function(s) {', '.join(map(repr, unknown))}; choose from {', '.join(known)}")
    return [n for n in known if n in names]


def trace_all(model, functions=None) -> list:
    check_names(model)
    return [lower(build_function(model, name)) for name in resolve_functions(functions)]


def operation_counts(model, functions=None) -> dict[str, dict]:
    """``{function: ops}`` without rendering anything."""
    return {low.function.name: low.ops for low in trace_all(model, functions)}


def _ops_json(module, lowered) -> str:
    data = {"scene": module, "counting": "mul includes div; add includes sub; total = mul + add; trig, sqrt "
                                          "and the dense library solves (solve_flops) apart; negations free",
            "functions": {low.function.name: low.ops for low in lowered}}
    return json.dumps(data, indent=1, sort_keys=True) + "\n"


def generate(model, target: str, functions=None, *, lowered=None) -> Generated:
    """Files (name -> text) of ``target`` for ``model``; deterministic. ``lowered`` (from
    :func:`trace_all`) lets several targets share one trace."""
    if target not in TARGETS:
        raise CodegenError(f"unknown target {target!r}; choose from {', '.join(TARGETS)}")
    if lowered is None:
        lowered = trace_all(model, functions)
    module = model.scene.name
    contexts = [function_context(low, target, module) for low in lowered]
    common = dict(scene=module, module=module, description=" ".join(model.scene.description.split()) or module,
                  functions=contexts, uses_solve=any("solve" in low.uses for low in lowered),
                  uses_sign=any("sign" in low.uses for low in lowered),
                  uses_transposed=any(s["transposed"] for low in lowered for s in low.ops["solves"]))
    files = {"ops.json": _ops_json(module, lowered)}
    if target == "numpy":
        files[f"{module}.py"] = render("numpy/module.py.jinja", **common)
    else:
        files[f"{module}.h"] = render("c/header.h.jinja", guard=f"SYMGEN_{module.upper()}_H", **common)
        files[f"{module}.c"] = render("c/source.c.jinja", **common)
        files[f"{module}_ctypes.py"] = render("c/binding.py.jinja", **common)
        files[f"test_{module}.c"] = render("c/test.c.jinja", inputs=_test_inputs(model, lowered, contexts), **common)
    return Generated(module, target, files, {low.function.name: low.ops for low in lowered})


def _literal(x: float, digits: int = 15) -> str:
    text = format(float(x), f".{digits}g")
    return text if any(ch in text for ch in ".en") else text + ".0"


#: significant digits of the C test program's expected values: the dense float model's last
#: digits depend on the BLAS build, and the program checks to 1e-9, so they are not printed
EXPECTED_DIGITS = 12


def _expected_literals(values) -> str:
    """Expected outputs as C literals, rounded to :data:`EXPECTED_DIGITS` digits and with
    rounding noise below ``10^-EXPECTED_DIGITS`` of the largest entry written as 0, so the same
    scene gives the same file whatever BLAS computed the reference."""
    values = np.ravel(np.asarray(values, dtype=float))
    floor = 10.0 ** -EXPECTED_DIGITS * max(1.0, float(np.max(np.abs(values), initial=0.0)))
    return ", ".join(_literal(0.0 if abs(v) < floor else v, EXPECTED_DIGITS) for v in values)


def _test_inputs(model, lowered, contexts):
    state = reference_states(model, 1, seed=C_TEST_SEED)[0]
    names = []
    for low in lowered:
        for a in low.function.inputs:
            if a.name not in names:
                names.append(a.name)
    inputs = [dict(name=n, size=len(state[n]), literal=", ".join(_literal(v) for v in state[n])) for n in names]
    for low, ctx in zip(lowered, contexts):
        want = reference_outputs(model, low.function.name, state)
        for o in ctx["outputs"]:
            o["literal"] = _expected_literals(want[o["name"]])
    return inputs
