"""Helpers for the code-generation tests: generate into a temporary directory and import."""
from __future__ import annotations

import ctypes
import importlib.util
import pathlib
import shutil
import subprocess

import numpy as np

from symgen.io.builtin import get_scene
from symgen.codegen.generate import generate, trace_all
from symgen.codegen.runtime import call_by_name
from symgen.model import derive

#: every built-in scene family, at the sizes the equivalence tests use
SCENES = ("chain:n=1", "chain:n=6", "arm_on_plane", "four_bar", "five_bar", "multi_arm:h=2", "multi_arm:h=3",
          "stewart", "general_chain:n=7")


def import_file(path: pathlib.Path, name: str):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


#: the strict flags every generated C file compiles with (``-Werror``: a warning is a failure)
STRICT = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic"]
#: the builds a library loop is checked in: vector extensions for this processor and for the
#: baseline instruction set (vectors wider than its registers), and plain loops
LOOP_FLAGS = (["-march=native"], [], ["-march=native", "-DSYMGEN_NO_VECTOR"])


def loop_builds(source: pathlib.Path, stem: str):
    """``(label, ctypes library)`` of the generated C file ``source`` compiled by every C compiler
    there is (``cc``, ``clang``) with the strict flags, in each of :data:`LOOP_FLAGS`."""
    compilers = [c for c in ("cc", "clang") if shutil.which(c)]
    assert compilers, "no C compiler"
    for cc in compilers:
        for flags in LOOP_FLAGS:
            lib = source.parent / f"{stem}_{cc}{len(flags)}{'-DSYMGEN_NO_VECTOR' in flags}.so"
            subprocess.run([cc, *STRICT, "-O2", "-fPIC", "-shared", *flags, "-o", str(lib), str(source), "-lm"],
                           check=True)
            yield f"{cc} {flags}", ctypes.CDLL(str(lib))


def build(spec: str, out: pathlib.Path, functions=None):
    """``(model, numpy module, ctypes module, {target: Generated})`` for a scene, written under ``out``."""
    model = derive(get_scene(spec))
    lowered = trace_all(model, functions)
    gens = {}
    for target in ("numpy", "c"):
        gen = generate(model, target, lowered=lowered)
        folder = out / target
        folder.mkdir(parents=True, exist_ok=True)
        for name, text in gen.files.items():
            (folder / name).write_text(text)
        gens[target] = gen
    module = gens["numpy"].module
    py = import_file(out / "numpy" / f"{module}.py", f"gen_np_{module}")
    c = import_file(out / "c" / f"{module}_ctypes.py", f"gen_c_{module}")
    return model, py, c, gens


def call(module, name: str, state: dict):
    """Call generated function ``name`` with the arguments it declares, taken from ``state``."""
    return call_by_name(module, name, state)


def relative_error(got, want, floor: float = 1e-2) -> float:
    """Normwise relative error ``|got - want|_inf / max(|want|_inf, floor)`` (the floor keeps a
    result that is exactly zero in theory from dividing rounding noise by rounding noise)."""
    got, want = np.asarray(got, float), np.asarray(want, float)
    if want.size == 0:
        return 0.0
    return float(np.max(np.abs(got - want)) / max(float(np.max(np.abs(want))), floor))


#: the functions that run forward dynamics (32), each traced by the route forced on it
FORWARD = ["forward_dynamics", "state_derivative", "joint_accelerations"]


def route_error(model, method: str, target: str = "numpy", states: int = 3) -> float:
    """Largest relative error of the :data:`FORWARD` functions traced by the forward-dynamics
    route ``method`` (forced), against the dense model evaluated in 50 digits
    (:func:`symgen.codegen.reference.reference_outputs`) at ``states`` reference states (seed 7)."""
    from symgen.codegen.reference import reference_outputs, reference_states
    from symgen.codegen.runtime import load_generated

    lowered = trace_all(model, FORWARD, {"method": method})
    assert all(low.function.metadata["method"] == method for low in lowered)
    module = load_generated(model, target, lowered=lowered)
    worst = 0.0
    for s in reference_states(model, states, seed=7):
        for function in FORWARD:
            want = reference_outputs(model, function, s)
            for got, value in zip(call_by_name(module, function, s), want.values(), strict=True):
                worst = max(worst, relative_error(got, value))
    return worst
