"""Reading the text of a scene or URDF file, with a typed error naming the file.

The lowest layer of the loaders: :mod:`symgen.io.scene_yaml` and :mod:`symgen.io.urdf.parse` both read
their files through :func:`read_text_file`, so neither imports the other for it.
"""
from __future__ import annotations

from pathlib import Path

from ..errors import SceneError


def read_text_file(path, element: str, error: type[SceneError] = SceneError) -> str:
    """The UTF-8 text of ``path``; a missing or unreadable file raises ``error(element, ...)``."""
    try:
        return Path(path).read_text(encoding="utf-8")
    except FileNotFoundError:
        raise error(element, "not found") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise error(element, f"cannot be read: {exc}") from None
    except ValueError as exc:   # a path holding a NUL byte (often: text that was meant, not a path)
        raise error(element[:80], f"is not a file name ({exc}); pass a path or the file's text") from None
