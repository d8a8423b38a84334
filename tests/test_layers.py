"""The package is layered: every module belongs to one layer, and imports only go down.

From the bottom: ``errors``; ``math/`` (numbers, fields, jets, elimination, rotations,
configurations); ``scene/`` (the declaration and its checks); the model layer (the tree, the
kinematics, the closure, the twelve steps in ``steps/``, the recursions in ``dynamics/``, the
model and its proofs); ``io/`` (readers and writers, which check what they read with the model);
the applications (code generation, simulation, control, identification and the studies); ``cli/``;
and the package's own front door (``symgen/__init__.py``). An import of a module in a higher layer
is an error, lazy imports included. Units -- a folder, or a module at the top of the package -- form
no cycle either.
"""
from __future__ import annotations

from .test_import_graph import find_cycle, import_graph, module_names

#: lowest first; a unit is a folder (all its modules) or one top-level module
LAYERS: list[tuple[str, set[str]]] = [
    ("foundation", {"symgen.errors"}),
    ("math", {"symgen.math"}),
    ("scene", {"symgen.scene"}),
    ("model", {"symgen.tree", "symgen.kinematics", "symgen.closure", "symgen.subsystems", "symgen.steps",
               "symgen.dynamics", "symgen.model", "symgen.model_solves", "symgen.dynamics_jacobians", "symgen.motion", "symgen.task_frames",
               "symgen.vanishing_rows", "symgen.reference_kinematics", "symgen.proofs", "symgen.conditioning",
               "symgen.constraint_wrenches", "symgen.ground_contacts", "symgen.frame_kinematics"}),
    ("io", {"symgen.io"}),
    ("applications", {"symgen.codegen", "symgen.simulation", "symgen.control", "symgen.identification",
                      "symgen.complexity", "symgen.accuracy", "symgen.stability", "symgen.oracle"}),
    ("cli", {"symgen.cli"}),
    ("front door", {"symgen", "symgen.__main__"}),
]


def unit_of(module: str) -> str:
    """The unit a module belongs to: the top-level folder or module it sits in."""
    return ".".join(module.split(".")[:2])


def layer_of(module: str) -> int:
    unit = unit_of(module)
    found = [rank for rank, (_, units) in enumerate(LAYERS) if unit in units]
    assert len(found) == 1, f"{module} (unit {unit}) must be in exactly one layer of tests/test_layers.py"
    return found[0]


def upward_imports(graph: dict[str, set[str]]) -> list[str]:
    return sorted(f"{a} ({LAYERS[layer_of(a)][0]}) imports {b} ({LAYERS[layer_of(b)][0]})"
                  for a, targets in graph.items() for b in targets if layer_of(b) > layer_of(a))


def unit_graph(graph: dict[str, set[str]]) -> dict[str, set[str]]:
    """Edges between units; the front door (which imports everything) is left out."""
    out: dict[str, set[str]] = {}
    for a, targets in graph.items():
        if layer_of(a) == len(LAYERS) - 1:
            continue
        out.setdefault(unit_of(a), set()).update(unit_of(b) for b in targets if unit_of(b) != unit_of(a))
    return out


def test_every_module_has_a_layer():
    for name in module_names():
        layer_of(name)


def test_no_module_imports_from_a_higher_layer():
    offenders = upward_imports(import_graph())
    assert not offenders, "imports must go down the layers:\n" + "\n".join(offenders)


def test_folders_and_top_level_modules_form_no_cycle():
    cycle = find_cycle(unit_graph(import_graph()))
    assert cycle is None, " -> ".join(cycle)


def test_the_layer_check_sees_an_upward_import():
    graph = {"symgen.math.fields": {"symgen.model"}, "symgen.model": {"symgen.math.fields"}}
    assert upward_imports(graph) == ["symgen.math.fields (math) imports symgen.model (model)"]


def test_the_unit_check_sees_a_cycle_between_folders():
    graph = {"symgen.codegen.vdc": {"symgen.control.law"}, "symgen.control.closed_loop": {"symgen.simulation.state"},
             "symgen.simulation.state": {"symgen.codegen.trace"}}
    assert find_cycle(unit_graph(graph)) == ["symgen.codegen", "symgen.control", "symgen.simulation", "symgen.codegen"]
