"""The ``symgen`` command: :func:`main` parses the arguments and dispatches to the commands.

:mod:`.commands` holds the parser, :func:`main` and the model commands (``scenes``, ``info``, ``steps``, ``export``,
``prove``, ``generate``, ``ops``); each other module adds the commands of one application package
(``simulate``, ``accuracy``, ``stability``, ``complexity``, ``check``, ``control``, ``params``,
``excite``, ``identify``). No library package imports this one.
"""
from .commands import build_parser, main

__all__ = ["build_parser", "main"]
