"""MuJoCo's ``<default>`` classes, resolved as MuJoCo resolves them.

* The top-level ``<default>`` is the class ``main``; several top-level sections all write into it,
  in file order. Each nested ``<default class="...">`` starts as a copy of its parent class, taken
  once the parent's own entries of that section are read, and then overrides them.
* An element takes its class from its ``class`` attribute, else from the ``childclass`` of the
  nearest enclosing body or frame that has one, else ``main``; its own attributes override the
  class's. An orientation given on the element replaces the class's orientation whatever its
  form (``quat`` on the element beats ``euler`` in the class).
* One entry per element kind and class. The actuator kinds (``motor``, ``position``, ...) share
  one entry per class, as in MuJoCo.

Classes may be used before they are declared (all ``<default>`` sections are read first).
"""
from __future__ import annotations

from .schema import READ_ACTUATORS, REFUSED_ACTUATORS
from .values import ORIENTATIONS, Attrs, MjcfError, Values

#: the element kinds whose defaults symgen reads, by tag (cameras, lights, ... have none that matter)
KIND_OF = {"joint": "joint", "site": "site", "geom": "geom", "equality": "equality", "tendon": "tendon", "mesh": "mesh",
           **{tag: "actuator" for tag in READ_ACTUATORS + tuple(REFUSED_ACTUATORS)}}
#: the default entry an element of the model takes, by tag (an equality takes the <equality> entry)
USE_KIND = {**KIND_OF, "connect": "equality", "weld": "equality", "fixed": "tendon", "spatial": "tendon"}
MAIN = "main"


class Defaults:
    """The default classes of one file: ``classes[name][kind]`` maps an attribute to
    ``(text, element written on)``."""

    def __init__(self, root, values: Values):
        """Read every top-level ``<default>`` section of ``root``, in file order."""
        self.values = values
        self.classes = {MAIN: {kind: {} for kind in set(KIND_OF.values())}}
        for section in root.findall("default"):
            if section.get("class", MAIN) != MAIN:
                values.fail(section, "the top-level <default> is the class 'main' and cannot be renamed")
            self._read(section, MAIN)

    def _read(self, section, name: str) -> None:
        """Read ``section`` into class ``name``, then its nested classes (copies taken after its own entries)."""
        pending = [(section, name)]
        while pending:
            el, cls = pending.pop()
            seen = set()
            for child in el:
                kind = KIND_OF.get(child.tag) if isinstance(child.tag, str) else None
                if kind is None:
                    continue
                key = "actuator" if kind == "actuator" else child.tag
                if key in seen:
                    self.values.fail(child, f"a default class holds one <{child.tag}> entry "
                                            f"(class {cls!r} has two)")
                seen.add(key)
                self.classes[cls][kind].update({a: (v, child) for a, v in child.attrib.items() if a != "class"})
            for child in el.findall("default"):        # after the parent's own entries, as MuJoCo
                sub = child.get("class")
                if not sub:
                    self.values.fail(child, "a nested <default> needs a class name")
                if sub in self.classes:
                    self.values.fail(child, f"default class {sub!r} is declared twice")
                self.classes[sub] = {k: dict(v) for k, v in self.classes[cls].items()}
                pending.append((child, sub))

    def attrs(self, el, childclass: str | None = None) -> Attrs:
        """The attributes ``el`` takes effect with (see the module docstring); ``childclass``: the
        class inherited from the enclosing bodies and frames."""
        cls = el.get("class") or childclass or MAIN
        self.check_class(el, cls)
        kind = USE_KIND.get(el.tag)
        values = dict(self.classes[cls].get(kind, {})) if kind else {}
        if any(a in el.attrib for a in ORIENTATIONS):
            for a in ORIENTATIONS:
                values.pop(a, None)
        values.update({a: (v, el) for a, v in el.attrib.items() if a != "class"})
        return Attrs(el, values)

    def check_class(self, el, cls: str) -> str:
        """``cls``, if declared; else an error at ``el``."""
        if cls not in self.classes:
            raise MjcfError(f"<{el.tag}>", f"default class {cls!r} is not declared", self.values.source_of(el),
                            el.sourceline)
        return cls
