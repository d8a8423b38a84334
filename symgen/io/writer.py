"""Atomic output directories: write everything to a temporary sibling, then rename.

A directory symgen wrote carries a marker file; an existing directory without it is refused
unless ``force`` (it may hold the user's own files). Nothing is ever left half-written: on any
error the temporary directory is removed and the old output stays as it was. The output folder
gets the permissions of any folder the user creates (``0777`` less the umask), not the ``0700``
of a temporary folder.
"""
from __future__ import annotations

import os
import pathlib
import shutil
import tempfile

from ..errors import SymgenError

MARKER = ".symgen-generated"


class OutputError(SymgenError):
    """The output directory cannot be written (exists and is not symgen's, or is a file)."""


def _umask() -> int:
    """The process's umask (read by setting it and putting it back: the only portable way)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def write_tree(out: str | os.PathLike, files: dict[str, str | bytes], *, force: bool = False,
               command: str = "symgen generate") -> pathlib.Path:
    """Write ``files`` (relative path -> text, or bytes for binary files such as plots) as the
    directory ``out``, atomically; ``command`` is named in the marker file."""
    out = pathlib.Path(out)
    if out.exists():
        if not out.is_dir():
            raise OutputError(f"output {str(out)!r} exists and is not a directory")
        if not (out / MARKER).exists() and any(out.iterdir()) and not force:
            raise OutputError(f"output directory {str(out)!r} exists and was not created by symgen; "
                              "choose another --out or pass --force to replace it")
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = pathlib.Path(tempfile.mkdtemp(prefix=f".{out.name}.", dir=out.parent))
    try:
        for rel, content in files.items():
            path = tmp / rel
            path.parent.mkdir(parents=True, exist_ok=True)
            if isinstance(content, bytes):
                path.write_bytes(content)
            else:
                path.write_text(content, encoding="utf-8")
        (tmp / MARKER).write_text(f"This directory was written by `{command}`; it is replaced "
                                  "as a whole on the next run.\n", encoding="utf-8")
        os.chmod(tmp, 0o777 & ~_umask())
        if out.exists():
            old = pathlib.Path(tempfile.mkdtemp(prefix=f".{out.name}.old.", dir=out.parent))
            os.rmdir(old)
            os.replace(out, old)
            os.replace(tmp, out)
            shutil.rmtree(old)
        else:
            os.replace(tmp, out)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return out
