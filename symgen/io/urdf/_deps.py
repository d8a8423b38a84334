"""Optional dependencies of the URDF, example and oracle packages, imported only when used.

Each one belongs to an extra of the ``symgen`` distribution; a missing one raises
:class:`MissingExtraError` (a :class:`~symgen.errors.SymgenError`) that names the extra to install,
so the command line prints one line instead of a traceback.
"""
from __future__ import annotations

import importlib

from ...errors import SymgenError

#: import name -> (distribution, extra of symgen that installs it)
EXTRAS = {
    "yourdfpy": ("yourdfpy", "urdf"),
    "lxml.etree": ("lxml", "urdf"),
    "pinocchio": ("pin", "oracle"),
}


class MissingExtraError(SymgenError):
    """An optional package is not installed; the message names ``pip install 'symgen[extra]'``."""

    def __init__(self, what: str, distribution: str, extra: str):
        self.distribution, self.extra = distribution, extra
        super().__init__(f"{what} needs the Python package {distribution!r}, which is not installed: "
                         f"pip install 'symgen[{extra}]'")


def require(module: str, what: str):
    """Import ``module`` (a key of :data:`EXTRAS`) or raise :class:`MissingExtraError` for ``what``."""
    distribution, extra = EXTRAS[module]
    try:
        return importlib.import_module(module)
    except ImportError:
        raise MissingExtraError(what, distribution, extra) from None
