"""YAML with exact numbers and line numbers, for scene files (safe: a ``SafeLoader`` subclass).

* Floats are read from their text as :class:`fractions.Fraction` (``0.1`` is exactly 1/10), so
  :func:`symgen.math.numbers.parse_exact` keeps them exact; ``.inf``/``.nan`` stay floats and are
  rejected there.
* Mappings are :class:`LocatedMap` s: a ``dict`` that also knows its line, each key's line, and
  any key given twice (plain YAML keeps the last silently; scene readers report it). Keys merged
  with ``<<`` may be overridden by the mapping's own keys, as YAML specifies.
* No ``yaml.load`` call: the loader is built and run directly, as ``yaml.safe_load`` does.
* Bounded (:mod:`symgen.scene.input_limits`): the text is checked for NUL, control characters and lone
  surrogates before the parser sees it; while the document is composed, its nesting depth, its
  size with every alias expanded and the text of every number are checked, so a deep document, an
  alias bomb or a number of a million digits is refused before anything is built from it.
"""
from __future__ import annotations

from fractions import Fraction

import yaml

from ..scene import input_limits as limits
from ..errors import SceneError

__all__ = ["ExactLoader", "LocatedMap", "parse_yaml"]


class LocatedMap(dict):
    """A YAML mapping that remembers its line, its keys' lines and any repeated keys."""

    def __init__(self, line: int | None = None):
        super().__init__()
        self.line, self.lines, self.duplicates = line, {}, []


class LimitError(yaml.YAMLError):
    """A document breaks a limit of :mod:`symgen.scene.input_limits` (raised while it is composed)."""

    def __init__(self, where: str, problem: str, mark):
        super().__init__(problem)
        self.where, self.problem, self.problem_mark = where, problem, mark


class ExactLoader(yaml.SafeLoader):
    """``SafeLoader`` that reads floats exactly (as ``Fraction``) and keeps line numbers; the
    composer enforces the depth, expanded-size and number-text limits."""

    def __init__(self, stream):
        super().__init__(stream)
        self._path: list[str] = []

    def _where(self) -> str:
        parts = [p for p in self._path if p]
        if len(parts) > 6:
            parts = parts[:3] + ["..."] + parts[-2:]
        return "".join(p if p.startswith("[") or i == 0 else "." + p for i, p in enumerate(parts)) or "document"

    def compose_node(self, parent, index):
        """Compose one node, refusing it when it is too deep, too large once its aliases are
        expanded (sizes add up bottom-up, so this costs one pass), or a number out of bounds."""
        alias = self.check_event(yaml.AliasEvent)
        mark = self.peek_event().start_mark
        label = (index.value if isinstance(index, yaml.ScalarNode) else f"[{index}]" if isinstance(index, int)
                 else "" if parent is None else "(key)")
        self._path.append(str(label)[:40])
        if len(self._path) > limits.MAX_DEPTH:
            raise LimitError(self._where(), f"nested more than {limits.MAX_DEPTH} levels deep", mark)
        try:
            node = super().compose_node(parent, index)
            if alias:
                if not hasattr(node, "expanded_size"):
                    raise LimitError(self._where(), "an alias refers to the node that contains it", mark)
                return node
            node.expanded_size = _size(node)
            if node.expanded_size > limits.MAX_NODES:
                raise LimitError(self._where(), f"holds more than {limits.MAX_NODES} values once its aliases "
                                                "are expanded (an alias bomb?)", mark)
            if isinstance(node, yaml.ScalarNode):
                self._check_scalar(node)
            return node
        finally:
            self._path.pop()

    def _check_scalar(self, node) -> None:
        bad = limits.bad_character(node.value)
        if bad is not None:
            raise LimitError(self._where(), f"the text holds {bad[1]}", node.start_mark)
        problem = limits.number_text_problem(node.value)
        if problem is not None:
            raise LimitError(self._where(), f"{node.value[:40]!r}: {problem}", node.start_mark)


def _size(node) -> int:
    """Values in ``node`` with every alias expanded (its children already carry theirs)."""
    if isinstance(node, yaml.SequenceNode):
        return 1 + sum(getattr(child, "expanded_size", 1) for child in node.value)
    if isinstance(node, yaml.MappingNode):
        return 1 + sum(getattr(k, "expanded_size", 1) + getattr(v, "expanded_size", 1) for k, v in node.value)
    return 1


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
        SceneError: for a syntax error, an unsafe tag, an unhashable key, or a broken limit of
            :mod:`symgen.scene.input_limits` (control characters, depth, alias expansion, number text);
            the message and the ``line`` attribute give the line where the parser stopped.
    """
    element = f"scene file {source!r}"
    problem = limits.text_problem(text)
    if problem is not None:
        err = SceneError(element, problem[1] + (f" (line {problem[0]})" if problem[0] else ""))
        err.source, err.line = source, problem[0]
        raise err
    loader = None
    try:
        loader = ExactLoader(text)  # what yaml.safe_load does, with the exact constructors above
        return loader.get_single_data()
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None) or getattr(exc, "context_mark", None)
        problem = getattr(exc, "problem", None) or str(exc)
        if isinstance(exc, LimitError):
            element, problem = f"{element}, {exc.where}", exc.problem
        else:
            problem = f"invalid YAML: {problem}"
        err = SceneError(element, problem + (f" (line {mark.line + 1}, column {mark.column + 1})" if mark else ""))
        err.source, err.line = source, (mark.line + 1 if mark else None)
        raise err from None
    finally:
        if loader is not None:
            loader.dispose()
