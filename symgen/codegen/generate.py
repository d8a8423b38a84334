"""``generate(model, target, functions)``: trace, lower and render the requested functions.

``target`` is a name from :data:`~symgen.codegen.targets.TARGETS` or a
:class:`~symgen.codegen.targets.Target`; the target renders its own files
(:mod:`symgen.codegen.targets`), beside the shared ``ops.json``.

Names that reach a template (scene, bodies, joints, frames, constraints) are checked to be plain
identifiers before anything is traced or rendered. Free text (the scene's description) reaches
the files only through :func:`comment_text`, and the files' module name is :func:`module_name`.
"""
from __future__ import annotations

import json
import keyword
import sys
import unicodedata
from dataclasses import dataclass

from ..conditioning import MAX_LOOP_ESTIMATE
from ..errors import CodegenError, SceneError
from ..math.numbers import is_identifier
from .progress import progress
from .emit import lower
from .parameters import parameterise, traced_parameters
from .catalogue import FUNCTIONS, ON_REQUEST, build_function
from .targets import REGISTERED
from .targets import target as resolve_target

#: suffix of the module name of a scene whose own name would shadow a module (:func:`module_name`)
MODULE_SUFFIX = "_model"
#: the C standard library's headers (``<name>.h``); a generated header of that name could be picked
#: up by ``#include <name.h>`` when the output folder is on the include path
C_HEADERS = frozenset("assert complex ctype errno fenv float inttypes iso646 limits locale math setjmp signal "
                      "stdalign stdarg stdatomic stdbool stddef stdint stdio stdlib stdnoreturn string tgmath "
                      "threads time uchar wchar wctype".split())


@dataclass
class Generated:
    module: str
    target: str
    files: dict[str, str]
    ops: dict[str, dict]


def check_names(model) -> None:
    """Every scene name that reaches generated code must be a plain identifier; the scene's own
    name (the module's) must not start with ``__``."""
    scene = model.scene
    if not is_identifier(scene.name):
        raise SceneError(f"scene {scene.name!r}", "the scene name becomes a C and Python identifier; "
                                                  "use letters, digits and underscores")
    if scene.name.startswith("__"):
        raise SceneError(f"scene {scene.name!r}", "the scene name becomes the generated module's name, and a name "
                                                  "starting with '__' is reserved (Python runs __main__.py and "
                                                  "__init__.py on its own; C reserves such identifiers); rename "
                                                  f"the scene, e.g. {scene.name.strip('_') or 'robot'!r}")
    for kind, table in (("body", scene.bodies), ("joint", scene.joints), ("frame", scene.frames),
                        ("constraint", scene.constraints)):
        for name in table:
            if not is_identifier(name):
                raise SceneError(f"{kind} {name!r}", "names must be plain identifiers before code is generated")


#: module names Python or its tools load on their own: ``sitecustomize``/``usercustomize`` at
#: start-up (when the folder is on the path) and pytest's ``conftest``. A ``__dunder__`` name
#: (``__main__`` runs as the folder's entry point, ``__init__`` makes the folder a package) is
#: refused by :func:`check_names`, and renamed here too for callers that skip that check
AUTO_LOADED = frozenset({"sitecustomize", "usercustomize", "conftest"})


def module_name(scene_name: str) -> str:
    """The name of a scene's generated module: the scene's name, or ``<name>_model`` when that
    name (compared case-insensitively, for case-insensitive file systems) is a Python keyword,
    a standard-library module (``sys.stdlib_module_names``), a module the generated files import
    (numpy, ctypes, ...), ``symgen``, a C standard header, a module Python or pytest loads on
    their own (:data:`AUTO_LOADED`) or a ``__dunder__`` name -- a generated ``math.py`` would
    otherwise shadow the standard library for every script run beside it, and a
    ``sitecustomize.py`` or ``conftest.py`` would run unasked.

    >>> module_name("four_bar"), module_name("math"), module_name("NumPy"), module_name("class")
    ('four_bar', 'math_model', 'NumPy_model', 'class_model')
    >>> module_name("__main__"), module_name("conftest"), module_name("SiteCustomize")
    ('__main___model', 'conftest_model', 'SiteCustomize_model')
    """
    folded = scene_name.lower()
    taken = {m.lower() for m in sys.stdlib_module_names} | {"symgen"} | C_HEADERS | AUTO_LOADED
    for tgt in REGISTERED:
        taken |= {m.lower() for m in tgt.imports}
    dunder = len(scene_name) > 4 and scene_name.startswith("__") and scene_name.endswith("__")
    if folded in taken or dunder or keyword.iskeyword(scene_name) or keyword.issoftkeyword(scene_name):
        return scene_name + MODULE_SUFFIX
    return scene_name


def comment_text(text: str) -> str:
    r"""``text`` as one line that is inert in every target's comments (C ``//``, Python ``#``).

    Whitespace runs become one space. A character that is not printable text -- a control
    character (NUL included), a format character (the bidirectional overrides such as U+202E), a
    lone surrogate, a private-use or unassigned code point, a line or paragraph separator -- is
    written as ``U+XXXX``, and so are a backslash (it would continue a C ``//`` comment onto the
    next line) and a ``?`` after a ``?`` (the trigraph ``??/`` is a backslash). Letters of any
    script stay as they are.

    >>> comment_text("crank\\ ??/ \u202eevil\x00")
    'crankU+005C ?U+003F/ U+202EevilU+0000'
    """
    out: list[str] = []
    for ch in " ".join(text.split()):
        category = unicodedata.category(ch)
        if ch == "\\" or category[0] == "C" or category in ("Zl", "Zp") or (ch == "?" and out and out[-1] == "?"):
            out.append(f"U+{ord(ch):04X}")
        else:
            out.append(ch)
    return "".join(out)


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


#: functions that refuse run-time parameters, and why
NO_PARAMETERS = {
    **dict.fromkeys(("inverse_dynamics_derivatives", "forward_dynamics_derivatives", "state_derivative_jacobian",
                     "centroidal_momentum_derivatives"),
                    "their derivatives with respect to p are not traced yet; generate them without parameters"),
    **dict.fromkeys(("control", "adaptation"),
                    "the controller reads its inertial parameters from its own input P_hat (--uncertain)"),
}


def parameterised_model(model, parameters):
    """``(model, Parameters)``: the model re-derived with the chosen inertial parameters declared
    (:func:`~symgen.codegen.parameters.parameterise`; the numbers are the same), or ``(model, None)``
    when none are chosen."""
    if not parameters:
        return model, None
    from ..model import derive

    scene, chosen = parameterise(model.scene, parameters)
    return derive(scene), chosen


def trace_all(model, functions=None, options=None, *, show_progress: bool = False, parameters=None) -> list:
    """Traced and lowered ``functions``; ``options`` (e.g. ``{"uncertain": [...]}``) reach the
    functions that take them (:data:`~symgen.codegen.catalogue.OPTIONS`). ``show_progress``: a
    progress bar on stderr when it is a terminal (:mod:`symgen.codegen.progress`). ``parameters``:
    inertial parameters read from an extra input ``p`` instead of folded
    (:mod:`symgen.codegen.parameters`; names as :func:`~symgen.codegen.parameters.parameterise` takes them)."""
    check_names(model)
    names = resolve_functions(functions)
    refused = [n for n in names if n in NO_PARAMETERS]
    if parameters and refused:
        raise CodegenError(f"run-time parameters cannot be combined with {refused[0]}: {NO_PARAMETERS[refused[0]]}")
    model, chosen = parameterised_model(model, parameters)
    if show_progress:
        names = progress(names, total=len(names), desc="tracing", label=str)
    with traced_parameters(chosen):
        built = [build_function(model, name, **(options or {})) for name in names]
    if chosen:
        for fn in built:
            _with_parameters(fn, model, chosen)
    return [lower(fn) for fn in built]


def _with_parameters(fn, model, chosen) -> None:
    """Mark ``fn`` as taking ``p``: its parameters, its model (the parameterised one) and, for
    the C test program's pinned state, the defaults as ``p``."""
    extra = getattr(fn, "reference_inputs", None)
    fn.parameters = chosen
    fn.parameter_model = model
    fn.reference_inputs = lambda state: {**(extra(state) if extra else {}), "p": list(chosen.defaults)}


def _ops_entry(low) -> dict:
    """A function's counts and its generation-time choices (``metadata``: e.g. the route of forward
    dynamics, the controller's parameters), as ``ops.json`` and ``symgen ops`` show them."""
    return {**low.ops, **getattr(low.function, "metadata", {})}


def operation_counts(model, functions=None, options=None, parameters=None) -> dict[str, dict]:
    """``{function: ops}`` without rendering anything (the entries of ``ops.json``)."""
    return {low.function.name: _ops_entry(low) for low in trace_all(model, functions, options, parameters=parameters)}


def _ops_json(module, lowered) -> str:
    chosen = _parameters_of(lowered)
    extra = {"parameters": {"names": list(chosen.names), "defaults": list(chosen.defaults)}} if chosen else {}
    data = {**extra, "scene": module, "counting": "mul includes div; add includes sub; total = mul + add; trig, sqrt "
                                          "and the library loops (dense solves: solve_flops, banded products: product_flops) apart; "
                                          "negations free",
            "functions": {low.function.name: _ops_entry(low) for low in lowered}}
    return json.dumps(data, indent=1, sort_keys=True) + "\n"


def _parameters_of(lowered):
    """The run-time parameters of the lowered functions (:func:`trace_all`), or ``None``."""
    return getattr(lowered[0].function, "parameters", None) if lowered else None


def parameter_context(chosen) -> dict | None:
    """What the templates print of the run-time parameters: names, defaults (17 digits), count."""
    if not chosen:
        return None
    return dict(names=list(chosen.names), size=len(chosen),
                defaults=[repr(float(v)) for v in chosen.defaults])


def generate(model, target, functions=None, *, lowered=None, options=None, show_progress: bool = False,
             python_extension: bool = False, parameters=None, self_test: bool = True) -> Generated:
    """Files (name -> text) of ``target`` (a name or a :class:`~symgen.codegen.targets.Target`) for
    ``model``; deterministic. ``lowered`` (from :func:`trace_all`) lets several targets share one
    trace; ``show_progress`` draws a bar on a terminal's stderr (never in the files);
    ``python_extension`` adds a CPython extension module's source and loader (targets whose
    ``python_extension`` is true: the C target's ``<scene>_ext.c`` and ``<scene>_ext.py``).
    ``parameters`` (e.g. ``["payload"]`` or ``["payload.mass", "link2.inertia"]``): inertial
    parameters every function reads from an extra last input ``p`` instead of folding them
    (:mod:`symgen.codegen.parameters`); the files then hold their names and default values.
    ``self_test=False`` leaves out the target's self-test program (the C target's
    ``test_<scene>.c``, whose expected values are the dense model in 50-digit arithmetic: most of
    the generation time of a large robot), for code that is loaded rather than handed out
    (:func:`~symgen.codegen.runtime.load_generated`)."""
    tgt = resolve_target(target)
    if python_extension and not tgt.python_extension:
        raise CodegenError(f"target {tgt.name!r} has no CPython extension; the C target has one")
    if lowered is not None and parameters:
        raise CodegenError("generate: pass parameters to trace_all when giving lowered functions (they were traced "
                           "with their parameters or without)")
    if lowered is None:
        lowered = trace_all(model, functions, options, show_progress=show_progress, parameters=parameters)
    chosen = _parameters_of(lowered)
    if chosen:
        model = lowered[0].function.parameter_model
    module = module_name(model.scene.name)
    contexts = [tgt.function_context(low, module) for low in lowered]
    common = dict(scene=model.scene.name, module=module, description=comment_text(model.scene.description) or module,
                  functions=contexts, uses_solve=any("solve" in low.uses for low in lowered),
                  uses_lu=any("lu" in low.uses for low in lowered),
                  uses_symmetric=any("symmetric" in low.uses for low in lowered),
                  uses_inverse=any("inverse" in low.uses for low in lowered),
                  uses_substitute=any("substitute" in low.uses for low in lowered),
                  uses_symmetric_solve=any("symmetric_solve" in low.uses for low in lowered),
                  uses_lu_solve=any("lu_solve" in low.uses for low in lowered),
                  uses_lane_heap=any((ctx.get("lanes") or {}).get("heap") for ctx in contexts),
                  uses_product=any("product" in low.uses for low in lowered),
                  uses_scan_product=any("scan_product" in low.uses for low in lowered),
                  scan_shapes=sorted({s.scan for low in lowered for s in low.steps if s.scan}),
                  uses_sign=any("sign" in low.uses for low in lowered),
                  uses_trig=any("trig" in low.uses for low in lowered),
                  uses_pivots=any("pivots" in low.uses for low in lowered),
                  uses_loop_limit=any("loop_limit" in low.uses for low in lowered),
                  max_loop_estimate=repr(MAX_LOOP_ESTIMATE), parameters=parameter_context(chosen),
                  uses_transposed=any(s["transposed"] for low in lowered for s in low.ops["solves"]))
    files = {"ops.json": _ops_json(module, lowered)}
    files.update(tgt.render_files(dict(model=model, lowered=lowered, contexts=contexts, module=module,
                                       python_extension=python_extension, self_test=self_test), common))
    return Generated(module, tgt.name, files, {low.function.name: low.ops for low in lowered})
