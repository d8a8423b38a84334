"""YAML with exact numbers and line numbers, for scene files (safe: a ``SafeLoader`` subclass).

* Floats are read from their text as :class:`fractions.Fraction` (``0.1`` is exactly 1/10), so
  :func:`symgen.numbers.parse_exact` keeps them exact; ``.inf``/``.nan`` stay floats and are
  rejected there.
* Mappings are :class:`LocatedMap` s: a ``dict`` that also knows its line, each key's line, and
  any key given twice (plain YAML keeps the last silently; scene readers report it). Keys merged
  with ``<<`` may be overridden by the mapping's own keys, as YAML specifies.
* No ``yaml.load`` call: the loader is built and run directly, as ``yaml.safe_load`` does.
"""
from __future__ import annotations

from fractions import Fraction

import yaml

from .errors import SceneError

__all__ = ["ExactLoader", "LocatedMap", "parse_yaml"]


class LocatedMap(dict):
    """A YAML mapping that remembers its line, its keys' lines and any repeated keys."""

    def __init__(self, line: int | None = None):
        super().__init__()
        self.line, self.lines, self.duplicates = line, {}, []


class ExactLoader(yaml.SafeLoader):
    """``SafeLoader`` that reads floats exactly (as ``Fraction``) and keeps line numbers."""


def _construct_map(loader: ExactLoader, node) -> LocatedMap:
    """Like SafeConstructor's mapping, but located and recording (not dropping) repeated keys."""
    n_own = sum(1 for k, _ in node.value if k.tag != "tag:yaml.org,2002:merge")
    loader.flatten_mapping(node)  # merged (<<) pairs come first; the mapping's own keys override them
    n_merged = len(node.value) - n_own
    out, own = LocatedMap(node.start_mark.line + 1), set()
    for index, (key_node, value_node) in enumerate(node.value):
        key = loader.construct_object(key_node, deep=True)
        try:
            hash(key)
        except TypeError:
            raise yaml.constructor.ConstructorError(None, None, "a mapping key must be a plain name",
                                                    key_node.start_mark) from None
        line = key_node.start_mark.line + 1
        if index >= n_merged:
            if key in own:
                out.duplicates.append((key, out.lines[key], line))
                continue
            own.add(key)
        out[key] = loader.construct_object(value_node, deep=True)
        out.lines[key] = line
    return out


def _construct_float(loader: ExactLoader, node):
    """A YAML float as the exact ``Fraction`` of its text (``1_000.5`` -> 2001/2)."""
    try:
        return Fraction(loader.construct_scalar(node).replace("_", ""))
    except ValueError:  # .inf, .nan, sexagesimal: parse_exact rejects or reads the float
        return loader.construct_yaml_float(node)


ExactLoader.add_constructor("tag:yaml.org,2002:map", _construct_map)
ExactLoader.add_constructor("tag:yaml.org,2002:float", _construct_float)


def parse_yaml(text: str, source: str):
    """Parse one YAML document with :class:`ExactLoader`.

    Raises:
        SceneError: for a syntax error, an unsafe tag or an unhashable key; the message and the
            ``line`` attribute give the line where the parser stopped.
    """
    loader = ExactLoader(text)  # what yaml.safe_load does, with the exact constructors above
    try:
        return loader.get_single_data()
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None) or getattr(exc, "context_mark", None)
        problem = getattr(exc, "problem", None) or str(exc)
        err = SceneError(f"scene file {source!r}", f"invalid YAML: {problem}"
                         + (f" (line {mark.line + 1}, column {mark.column + 1})" if mark else ""))
        err.source, err.line = source, (mark.line + 1 if mark else None)
        raise err from None
    finally:
        loader.dispose()
