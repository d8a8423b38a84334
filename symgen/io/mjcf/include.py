"""MJCF's ``<include file="...">``, expanded before anything else is read, as MuJoCo expands it.

The included file is XML with one top-level element (any tag, usually ``<mujoco>``); that element
is dropped and what it holds takes the place of the ``<include>``, wherever it stands. Its path
is relative to the directory of the *main* file (MuJoCo's rule, also for includes inside included
files). A file may be included once in the whole model, must hold at least one element, and is
held to the same text limits as the main file (:mod:`symgen.scene.input_limits`). Text read without
a path (:func:`~symgen.io.mjcf.parse.parse_mjcf_text`) has no directory: an ``<include>`` there is
refused.

Every element brought in keeps its file: :class:`Origins` maps it to its file's name, so an
:class:`~symgen.io.mjcf.values.MjcfError` names the included file and the line in it.
"""
from __future__ import annotations

from pathlib import Path

from ...scene import input_limits as limits
from ..textfile import read_text_file
from .values import MjcfError, describe

#: nested includes deeper than this are refused (a file includes itself through others)
MAX_INCLUDE_DEPTH = 16


class Origins(dict):
    """``{element: file name}`` for the elements that came from included files."""

    def source_of(self, el, default: str) -> str:
        return self.get(el, default)


def parse_xml(text: str, source: str):
    """The root element of ``text`` (lxml, no entities, no network), or an :class:`MjcfError`."""
    from ..urdf._deps import require

    etree = require("lxml.etree", "the MJCF reader")
    problem = limits.text_problem(text)
    if problem is not None:
        raise MjcfError("MJCF file", problem[1].replace("scene and URDF files", "MJCF files"), source, problem[0])
    parser = etree.XMLParser(remove_comments=True, remove_pis=True, resolve_entities=False, no_network=True)
    try:
        root = etree.fromstring(text.encode("utf-8"), parser)
    except etree.XMLSyntaxError as exc:
        raise MjcfError("MJCF file", f"is not well-formed XML: {exc.msg}", source, exc.lineno) from None
    if root.getroottree().docinfo.internalDTD is not None:
        raise MjcfError("<!DOCTYPE>", "a document type declaration is not read (MuJoCo expands no entities): "
                                      "write the values out", source, 1)
    return root


def expand_includes(root, source: str, directory: str | None) -> Origins:
    """Replace every ``<include>`` under ``root`` by the content of its file (module docstring);
    returns where each brought-in element came from."""
    origins = Origins()
    seen: set = set()
    pending = [(el, source, 0) for el in root.iter("include")]
    while pending:
        el, where, depth = pending.pop(0)
        file = el.get("file")
        if file is None or set(el.attrib) != {"file"}:
            raise MjcfError(describe(el), "takes exactly one attribute, file", where, el.sourceline)
        if directory is None:
            raise MjcfError(describe(el), "cannot be expanded: the text was not read from a file, so there is no "
                                          "directory to find it in (read the file with parse_mjcf(path))",
                            where, el.sourceline)
        if len(el):
            raise MjcfError(describe(el), "must be empty", where, el.sourceline)
        path = (Path(directory) / file).resolve()
        if path in seen:
            raise MjcfError(describe(el), f"file {file!r} is included twice (MuJoCo includes a file once)",
                            where, el.sourceline)
        if depth >= MAX_INCLUDE_DEPTH:
            raise MjcfError(describe(el), f"includes nest deeper than {MAX_INCLUDE_DEPTH}", where, el.sourceline)
        seen.add(path)
        included = parse_xml(read_text_file(path, f"included file {file!r}", MjcfError), str(path))
        content = [c for c in included if isinstance(c.tag, str)]
        if not content:
            raise MjcfError(describe(el), f"file {file!r} holds no element to include", where, el.sourceline)
        parent, index = el.getparent(), el.getparent().index(el)
        parent.remove(el)
        for offset, child in enumerate(content):
            parent.insert(index + offset, child)
            for sub in child.iter():
                origins[sub] = str(path)
            pending += [(inc, str(path), depth + 1) for inc in child.iter("include")]
    return origins
