"""What every code-generation target has in common, and the Jinja templates they render.

A target (backend, after SymForce's) is one small object: its name, its template folder under
``templates/``, the ``(template, output file)`` pairs it renders, the printer and statement
lowering of its language, and how the rendered files are loaded back into Python. A subclass of
:class:`Target` fixes those; the templates only lay out code -- statements, index maps and
operation counts are computed here and passed in. The Jinja environment uses ``StrictUndefined``,
so a missing variable is an error, never an empty string.
"""
from __future__ import annotations

import functools
import importlib.util
import math
import pathlib
import sys
from types import ModuleType

import jinja2

from ...errors import CodegenError
from ..emit import Lowered, Printer, Step, ops_comment


def templates_dir() -> pathlib.Path:
    """The ``templates/`` folder: packaged as ``symgen.templates``, or beside the source tree."""
    import importlib.resources

    try:
        path = pathlib.Path(str(importlib.resources.files("symgen.templates")))
        if (path / "util.jinja").exists():
            return path
    except ModuleNotFoundError:
        pass
    return pathlib.Path(__file__).resolve().parents[3] / "templates"


@functools.lru_cache(maxsize=1)
def environment() -> jinja2.Environment:
    return jinja2.Environment(loader=jinja2.FileSystemLoader(str(templates_dir())),
                              undefined=jinja2.StrictUndefined, keep_trailing_newline=True,
                              trim_blocks=True, lstrip_blocks=True, autoescape=False)


def render(template: str, **context) -> str:
    """Render ``template`` (a path under ``templates/``) with ``context``."""
    return environment().get_template(template).render(**context)


def import_file(path: pathlib.Path, name: str) -> ModuleType:
    """Import the Python file ``path`` as module ``name`` (once per process)."""
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    sys.modules[name] = module
    return module


def check_constants(low: Lowered) -> None:
    """Refuse a non-finite constant (folded from extreme scene numbers): it would be written as
    ``inf``/``nan``, which is no literal in C and breaks the NumPy module's meaning."""
    refs = [r for step in low.steps for r in step.args] + [r for _, entries in low.outputs for _, r in entries]
    for r in refs:
        if getattr(r, "kind", None) == "const" and not math.isfinite(float(r.data)):
            raise CodegenError(f"function {low.function.name}: a constant folded from the scene's numbers is "
                               f"{float(r.data)}, outside double precision; scale the scene's units")


class Target:
    """A code-generation target. Subclasses set the class attributes and the hooks below.

    Attributes: ``name`` (what callers pass: ``"numpy"``, ``"c"``), ``folder`` (its templates,
    ``templates/<folder>/``), ``compiled`` (loading it builds native code, so it is the faster
    one to run long simulations on), ``printer_class`` (a :class:`~symgen.codegen.emit.Printer`
    for the language's expressions) and ``imports`` (what its Python files import).
    """

    name: str = ""
    folder: str = ""
    compiled: bool = False
    printer_class: type[Printer] = Printer
    #: modules the rendered Python files import (a scene of that name gets another module name)
    imports: tuple[str, ...] = ()
    #: ``generate(..., python_extension=True)`` adds a CPython extension module (:meth:`files`
    #: with ``python_extension``)
    python_extension: bool = False

    def __repr__(self) -> str:
        return f"<symgen target {self.name!r}>"

    def __str__(self) -> str:
        return self.name

    # ---------------------------------------------------------------- files
    #: the template of the target's self-test program, if it has one (:meth:`render_files`)
    self_test: str | None = None

    def files(self, module: str, python_extension: bool = False) -> list[tuple[str, str]]:
        """``(template under templates/, output file name)`` for every file rendered, in order
        (with the CPython extension's files when ``python_extension`` is asked for)."""
        raise NotImplementedError

    def entry_file(self, module: str) -> str:
        """The rendered file :meth:`load` imports."""
        raise NotImplementedError

    def file_context(self, template: str, job: dict) -> dict:
        """Variables one template needs beyond the common ones (``job``: ``model``, ``lowered``,
        ``contexts``, ``module``); none by default."""
        return {}

    def render_files(self, job: dict, common: dict) -> dict[str, str]:
        """Output file name -> rendered text, in the order of :meth:`files`; without the
        :attr:`self_test` program when ``job["self_test"]`` is false."""
        skip = None if job.get("self_test", True) else self.self_test
        return {out: render(template, **self.file_context(template, job), **common)
                for template, out in self.files(job["module"], job.get("python_extension", False))
                if template != skip}

    # ------------------------------------------------------------ statements
    def statement(self, step: Step, p: Printer) -> list[str]:
        """The lines of one lowered statement (an ``op``, a ``factor`` or a ``solve``)."""
        raise NotImplementedError

    def extend_context(self, ctx: dict, module: str) -> None:
        """Add what this target's templates need for one function to ``ctx``."""

    def function_context(self, low: Lowered, module: str) -> dict:
        """What the templates need for one function."""
        check_constants(low)
        fn = low.function
        p = self.printer_class()
        inputs = [dict(name=a.name, size=a.size, doc=a.doc) for a in fn.inputs]
        body, assigns, extra = self.lay_out(low, p, module)
        outputs = []
        for (arg, _), assign in zip(low.outputs, assigns):
            size = 1
            for s in arg.shape:
                size *= s
            outputs.append(dict(name=arg.name, shape=list(arg.shape), size=size, doc=arg.doc, assign=assign))
        matrices = list(dict.fromkeys(s.what for s in low.steps if s.kind in ("factor", "check")))
        ctx = dict(name=fn.name, doc=fn.doc, inputs=inputs, outputs=outputs, ops_comment=ops_comment(low.ops),
                   body=body, matrices=matrices, **extra)
        self.extend_context(ctx, module)
        return ctx

    def lay_out(self, low: Lowered, p: Printer, module: str) -> tuple[list[str], list[list[str]], dict]:
        """The function body's lines, per output the assignment lines left after them, and extra
        template variables (each target stores its outputs its own way: the NumPy target into
        workspace rows, the C target right after their statements, :mod:`.c_schedule`, and cuts a
        long function into blocks, :mod:`.c_blocks`)."""
        raise NotImplementedError

    # --------------------------------------------------------------- runtime
    def load(self, folder: pathlib.Path, module: str, import_name: str) -> ModuleType:
        """Import the rendered files in ``folder`` (written by the caller) as ``import_name``."""
        return import_file(folder / self.entry_file(module), import_name)
