"""Imports inside ``symgen`` flow one way: the module import graph has no cycle.

The graph is built from the source with :mod:`ast`: every ``import`` and ``from ... import``
statement counts, also those inside functions (a lazy import still ties the two modules
together), and relative imports are resolved against the importing module's package. An edge
goes to the most specific module named: ``from .urdf import build`` is an edge to
``symgen.io.urdf.build``, ``from .urdf import scene_from_urdf`` one to ``symgen.io.urdf``.
"""
from __future__ import annotations

import ast
import pathlib

ROOT = pathlib.Path(__file__).resolve().parents[1] / "symgen"


def module_names(root: pathlib.Path = ROOT) -> dict[str, pathlib.Path]:
    """``{dotted module name: file}``; a package is named by its ``__init__.py``."""
    out = {}
    for path in sorted(root.rglob("*.py")):
        parts = (root.name,) + path.relative_to(root).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


def _package_of(name: str, path: pathlib.Path) -> str:
    return name if path.name == "__init__.py" else name.rpartition(".")[0]


def _targets(node, name: str, path: pathlib.Path, known) -> list[str]:
    """The modules of ``known`` one import statement refers to."""
    if isinstance(node, ast.Import):
        found = []
        for alias in node.names:
            parts = alias.name.split(".")
            prefixes = [".".join(parts[:k]) for k in range(len(parts), 0, -1)]
            found += [next((p for p in prefixes if p in known), None)]
        return [f for f in found if f]
    if node.level:
        base = _package_of(name, path).split(".")
        base = base[:len(base) - (node.level - 1)]
        module = ".".join(base + ([node.module] if node.module else []))
    else:
        module = node.module or ""
    found = []
    for alias in node.names:
        if f"{module}.{alias.name}" in known:
            found.append(f"{module}.{alias.name}")
        elif module in known:
            found.append(module)
    return found


def import_graph(root: pathlib.Path = ROOT) -> dict[str, set[str]]:
    """``{module: modules it imports}`` within the package (imports inside functions included)."""
    known = module_names(root)
    graph = {}
    for name, path in known.items():
        edges = set()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                edges.update(_targets(node, name, path, known))
        edges.discard(name)
        graph[name] = edges
    return graph


def find_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """One cycle ``[a, b, ..., a]`` of ``graph`` (depth-first search), or ``None``."""
    state: dict[str, int] = {}          # 1: on the current path, 2: finished
    path: list[str] = []

    def visit(node):
        state[node] = 1
        path.append(node)
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == 1:
                return path[path.index(nxt):] + [nxt]
            if nxt not in state:
                cycle = visit(nxt)
                if cycle:
                    return cycle
        state[node] = 2
        path.pop()
        return None

    for node in sorted(graph):
        if node not in state:
            cycle = visit(node)
            if cycle:
                return cycle
    return None


def test_cycle_finder_sees_a_cycle_through_a_function_level_import(tmp_path):
    pkg = tmp_path / "pkg"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("from .sub import b\n")
    (pkg / "sub" / "__init__.py").write_text("")
    (pkg / "sub" / "b.py").write_text("def f():\n    from ..a import g\n")
    (pkg / "c.py").write_text("import pkg.a\n")
    graph = import_graph(pkg)
    assert graph["pkg.a"] == {"pkg.sub.b"} and graph["pkg.sub.b"] == {"pkg.a"} and graph["pkg.c"] == {"pkg.a"}
    assert find_cycle(graph) == ["pkg.a", "pkg.sub.b", "pkg.a"]


def test_cycle_finder_accepts_a_layered_graph():
    assert find_cycle({"a": {"b", "c"}, "b": {"c"}, "c": set()}) is None


def test_package_graph_is_resolved():
    graph = import_graph()
    assert "symgen.errors" in graph["symgen.scene.declaration"]
    assert "symgen.codegen.generate" in graph["symgen.codegen.runtime"]


def test_symgen_imports_have_no_cycle():
    cycle = find_cycle(import_graph())
    assert cycle is None, "import cycle: " + " -> ".join(cycle)
