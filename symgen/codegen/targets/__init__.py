"""Code-generation targets: the registry of :class:`~symgen.codegen.targets.base.Target` objects.

>>> from symgen.codegen.targets import TARGETS, target
>>> TARGETS
('numpy', 'c')
>>> [out for _, out in target("c").files("four_bar")]
['four_bar.h', 'four_bar.c', 'four_bar_ctypes.py', 'test_four_bar.c']

Callers name a target by its string (``"numpy"``, ``"c"``: the command line's choices are
:data:`TARGETS`) or pass the object; :func:`target` turns either into the object, and code outside
this package asks the object (its files, printer, loader, ``compiled``) instead of comparing names.
Adding a target is one module here (a :class:`Target` subclass and its instance, named in
:data:`REGISTERED`) and one template folder (``templates/README.md``).
"""
from __future__ import annotations

from ...errors import CodegenError
from .base import Target, environment, import_file, render, templates_dir
from .c import C
from .numpy import NUMPY

#: every target, in the order commands and reports list them
REGISTERED: tuple[Target, ...] = (NUMPY, C)
_BY_NAME = {t.name: t for t in REGISTERED}
#: the target names (command-line choices)
TARGETS: tuple[str, ...] = tuple(_BY_NAME)


class UnknownTargetError(CodegenError):
    """A target name that is not registered (the message lists the choices)."""


def target(spec) -> Target:
    """The :class:`Target` named ``spec`` (a :class:`Target` is returned as it is)."""
    if isinstance(spec, Target):
        return spec
    if isinstance(spec, str) and spec in _BY_NAME:
        return _BY_NAME[spec]
    raise UnknownTargetError(f"unknown target {spec!r}; choose from {', '.join(TARGETS)}")


__all__ = ["REGISTERED", "TARGETS", "Target", "UnknownTargetError", "environment", "import_file", "render",
           "target", "templates_dir"]
