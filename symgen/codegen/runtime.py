"""Generate, write and import a scene's code in one call, for simulation and benchmarks.

:func:`load_generated` renders the requested functions for one target, writes them into a cache
folder named after the SHA-256 of the files (``$SYMGEN_CACHE``, default ``~/.cache/symgen``) and
imports it through the target's loader (:meth:`symgen.codegen.targets.Target.load`): the NumPy
module itself, or the ctypes binding of the C target (which compiles the C source on first use).
The same scene and functions give the same folder, so a second call neither rewrites nor
recompiles anything.
"""
from __future__ import annotations

import hashlib
import os
import pathlib
import tempfile
from types import ModuleType

from .generate import generate, trace_all
from .targets import import_file, target as resolve_target


def call_by_name(module: ModuleType, function: str, values: dict) -> tuple:
    """Call generated ``function`` of ``module`` with the arguments it declares, taken by name
    from ``values`` (``q``, ``qd``, ``V_m``, ``tau``, ``eta_m``, ...); the outputs as a tuple."""
    import inspect

    fn = getattr(module, function)
    out = fn(*(values[p] for p in inspect.signature(fn).parameters))
    return out if isinstance(out, tuple) else (out,)


def cache_root() -> pathlib.Path:
    """The folder compiled and imported generated code lives in."""
    return pathlib.Path(os.environ.get("SYMGEN_CACHE", pathlib.Path.home() / ".cache" / "symgen"))


def _digest(files: dict[str, str]) -> str:
    h = hashlib.sha256()
    for name in sorted(files):
        h.update(name.encode() + b"\0" + files[name].encode() + b"\0")
    return h.hexdigest()[:16]


def _write_once(folder: pathlib.Path, files: dict[str, str]) -> None:
    """Write ``files`` into ``folder`` unless it exists; a rename makes the folder appear whole."""
    if folder.is_dir():
        return
    folder.parent.mkdir(parents=True, exist_ok=True)
    tmp = pathlib.Path(tempfile.mkdtemp(prefix=folder.name + ".", dir=folder.parent))
    for name, text in files.items():
        (tmp / name).write_text(text, encoding="utf-8")
    try:
        tmp.rename(folder)
    except OSError:  # another process wrote the same folder first; its content is identical
        for child in tmp.iterdir():
            child.unlink()
        tmp.rmdir()


def load_generated(model, target="numpy", functions=None, *, lowered=None,
                   python_extension: bool = False, parameters=None) -> ModuleType:
    """The imported generated module of ``model`` for ``target`` (a name from
    :data:`~symgen.codegen.targets.TARGETS`, ``"numpy"`` or ``"c"``, or a
    :class:`~symgen.codegen.targets.Target`).

    ``functions`` is a subset of :data:`~symgen.codegen.functions.FUNCTIONS` (default: all);
    ``lowered`` (from :func:`~symgen.codegen.generate.trace_all`) lets both targets share one
    trace. Compiling the C target needs a C compiler (``$CC``, default ``cc``).
    ``python_extension``: the C target's CPython extension module instead of its ctypes binding
    (one state per call, at the cost of a built-in function's call; compiling it also needs
    Python's and NumPy's headers). ``parameters``: inertial parameters every function reads from
    a last input ``p`` (:mod:`symgen.codegen.parameters`). The C self-test program is not
    generated (its 50-digit expected values serve ``symgen generate``'s output, not a loaded module).
    """
    tgt = resolve_target(target)
    if lowered is None:
        lowered = trace_all(model, functions, parameters=parameters)
        parameters = None
    gen = generate(model, tgt, lowered=lowered, python_extension=python_extension, parameters=parameters,
                   self_test=False)
    digest = _digest(gen.files)
    folder = cache_root() / "modules" / f"{gen.module}-{tgt.name}-{digest}"
    _write_once(folder, gen.files)
    name = f"symgen_generated_{gen.module}_{tgt.name}_{digest}"
    if python_extension:
        return import_file(folder / f"{gen.module}_ext.py", name + "_ext")
    return tgt.load(folder, gen.module, name)
