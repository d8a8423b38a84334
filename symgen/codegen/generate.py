"""``generate(model, target, functions)``: trace, lower and render the requested functions.

``target`` is a name from :data:`~symgen.codegen.targets.TARGETS` or a
:class:`~symgen.codegen.targets.Target`; the target renders its own files
(:mod:`symgen.codegen.targets`), beside the shared ``ops.json``.

Names that reach a template (scene, bodies, joints, frames, constraints) are checked to be plain
identifiers before anything is traced or rendered.
"""
from __future__ import annotations

import json
from dataclasses import dataclass

from ..errors import CodegenError, SceneError
from ..numbers import is_identifier
from .emit import lower
from .functions import FUNCTIONS, ON_REQUEST, build_function
from .targets import target as resolve_target


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


def trace_all(model, functions=None, options=None) -> list:
    """Traced and lowered ``functions``; ``options`` (e.g. ``{"uncertain": [...]}``) reach the
    functions that take them (:data:`~symgen.codegen.functions.OPTIONS`)."""
    check_names(model)
    return [lower(build_function(model, name, **(options or {}))) for name in resolve_functions(functions)]


def operation_counts(model, functions=None, options=None) -> dict[str, dict]:
    """``{function: ops}`` without rendering anything."""
    return {low.function.name: low.ops for low in trace_all(model, functions, options)}


def _ops_json(module, lowered) -> str:
    data = {"scene": module, "counting": "mul includes div; add includes sub; total = mul + add; trig, sqrt "
                                          "and the dense library solves (solve_flops) apart; negations free",
            "functions": {low.function.name: {**low.ops, **getattr(low.function, "metadata", {})}
                          for low in lowered}}
    return json.dumps(data, indent=1, sort_keys=True) + "\n"


def generate(model, target, functions=None, *, lowered=None, options=None) -> Generated:
    """Files (name -> text) of ``target`` (a name or a :class:`~symgen.codegen.targets.Target`) for
    ``model``; deterministic. ``lowered`` (from :func:`trace_all`) lets several targets share one trace."""
    tgt = resolve_target(target)
    if lowered is None:
        lowered = trace_all(model, functions, options)
    module = model.scene.name
    contexts = [tgt.function_context(low, module) for low in lowered]
    common = dict(scene=module, module=module, description=" ".join(model.scene.description.split()) or module,
                  functions=contexts, uses_solve=any("solve" in low.uses for low in lowered),
                  uses_sign=any("sign" in low.uses for low in lowered),
                  uses_transposed=any(s["transposed"] for low in lowered for s in low.ops["solves"]))
    files = {"ops.json": _ops_json(module, lowered)}
    files.update(tgt.render_files(dict(model=model, lowered=lowered, contexts=contexts, module=module), common))
    return Generated(module, tgt.name, files, {low.function.name: low.ops for low in lowered})
