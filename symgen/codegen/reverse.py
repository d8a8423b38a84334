"""Reverse-mode differentiation of a traced graph, inside the same graph: the adjoint sweep.

:func:`differentiate_reverse` returns what :func:`symgen.codegen.derivatives.differentiate` returns
-- the Jacobian ``d outputs / d inputs`` as nodes of the same graph, with the same ``held`` and
``seeds`` -- but walks the graph once *backwards* from the outputs, carrying for every node its
adjoint: a sparse dict ``output row -> node``, ``d outputs[row] / d node``. Each operation hands
its operands their share by the transposed chain rule (``a + b``: both get the adjoint; ``a b``:
``a`` gets ``adj b`` and ``b`` gets ``adj a``; ``a / b``: ``adj / b`` and ``-adj (a/b) / b``;
``sin a``: ``adj cos a``; ...), and an input, or a seeded node, turns its adjoint into Jacobian
entries. Only operands that depend on an input (found by one forward pass over dependence bits)
get a share, and every new node goes through the graph's folding and hash-consing, so structural
zeros cost nothing and shared products are computed once.

Cost: about two operations per operand edge and output row that reaches it, where forward mode
pays about that per edge and input column. Inverse dynamics has ``n`` outputs and ``3 n``
inputs (``q``, ``qd``, ``qdd``), and on a serial chain every velocity of the outward pass reaches
every output while it depends on only the columns above it: the reverse sweep is the cheaper there
when the per-link work is large (general joint frames, full inertia tensors: the Panda). The
callers trace both and keep the cheaper (:mod:`symgen.codegen.dynamics_derivatives`).

A library solve (its ``factor`` and ``solve`` statements) is not differentiated backwards: :class:`ReverseUnsupported`
tells the caller to keep the forward sweep.
"""
from __future__ import annotations

import numpy as np

from ..errors import CodegenError
from .derivatives import sweep_arguments
from .graph import Graph, Node


class ReverseUnsupported(CodegenError):
    """The graph holds an operation the adjoint sweep does not take (a library solve)."""


_OPS = ("add", "sub", "mul", "div", "neg", "sin", "cos", "sqrt", "sign")


def differentiate_reverse(graph: Graph, outputs, inputs, held=(), seeds=None) -> np.ndarray:
    """The Jacobian ``d outputs / d inputs`` (shape ``outputs.shape + (len(inputs),)``) by the
    adjoint sweep; arguments as :func:`symgen.codegen.derivatives.differentiate`."""
    outputs, index, flat, given, held_ids = sweep_arguments(graph, outputs, inputs, held, seeds)
    count = len(graph.nodes)
    depends = _dependence(graph, count, {v.id for v in flat}, index, held_ids, given)
    adjoint: dict[int, dict[int, Node]] = {}
    for row, node in enumerate(flat):
        if depends[node.id]:
            _share(graph, adjoint, node.id, {row: graph.const(1)})
    zero = graph.const(0)
    jac = np.empty((len(flat), len(inputs)), dtype=object)
    jac[:] = zero
    for node in reversed(graph.nodes[:count]):
        adj = adjoint.pop(node.id, None)
        if not adj:
            continue
        if node.id in given:
            for k, d in given[node.id].items():
                for row, a in adj.items():
                    jac[row, k] = graph.add(jac[row, k], graph.mul(a, d))
            continue
        if node.op == "in":
            k = index[node.id]
            for row, a in adj.items():
                jac[row, k] = graph.add(jac[row, k], a)
            continue
        if node.op not in _OPS:
            raise ReverseUnsupported(f"differentiate_reverse: no adjoint of operation {node.op!r} (node {node.id})")
        for arg, coef in _local(graph, node):
            if depends[arg]:
                _share(graph, adjoint, arg, {row: _times(graph, coef, a) for row, a in adj.items()})
    return jac.reshape(outputs.shape + (len(inputs),))


def _dependence(graph: Graph, count: int, outputs: set, index, held, seeds) -> list[bool]:
    """Which nodes the sweep visits depend on an input (or are seeded): the nodes the outputs
    reach without passing through a ``held`` or seeded node."""
    reach = [False] * count
    stack = list(outputs)
    while stack:
        i = stack.pop()
        if reach[i]:
            continue
        reach[i] = True
        if i not in held and i not in seeds:
            stack.extend(a for a in graph.operands(graph.nodes[i]) if a < count)
    dep = [False] * count
    for node in graph.nodes[:count]:
        if not reach[node.id] or node.id in held:
            continue
        if node.id in seeds:
            dep[node.id] = bool(seeds[node.id])
        elif node.op == "in":
            dep[node.id] = node.id in index
        elif node.op in _OPS:
            dep[node.id] = any(dep[a] for a in node.args)
        elif any(dep[a] for a in graph.operands(node) if a < count):
            raise ReverseUnsupported(f"differentiate_reverse: a library {node.op} depends on the inputs")
    return dep


def _local(g: Graph, node: Node) -> list[tuple[int, object]]:
    """``(operand id, d node / d operand)`` (``None`` for 1, ``-1``, or a node)."""
    op, args = node.op, node.args
    a = [g.nodes[i] for i in args]
    if op == "add":
        return [(args[0], None), (args[1], None)]
    if op == "sub":
        return [(args[0], None), (args[1], -1)]
    if op == "neg":
        return [(args[0], -1)]
    if op == "mul":
        return [(args[0], a[1]), (args[1], a[0])]
    if op == "div":                      # d(a/b) = da / b - (a/b) db / b
        inv = g.div(g.const(1), a[1])
        return [(args[0], inv), (args[1], g.neg(g.mul(node, inv)))]
    if op == "sin":
        return [(args[0], g.func("cos", a[0]))]
    if op == "cos":
        return [(args[0], g.neg(g.func("sin", a[0])))]
    if op == "sqrt":
        return [(args[0], g.div(g.const(1), g.mul(2, node)))]
    return []                            # sign: piecewise constant


def _times(g: Graph, coef, a: Node) -> Node:
    if coef is None:
        return a
    if isinstance(coef, int):
        return g.neg(a) if coef == -1 else g.mul(coef, a)
    return g.mul(a, coef)


def _share(g: Graph, adjoint: dict, arg: int, part: dict) -> None:
    """Add ``part`` (row -> node) to the adjoint of node ``arg``; zeros dropped."""
    into = adjoint.setdefault(arg, {})
    for row, v in part.items():
        if v.is_const and v.value == 0:
            continue
        into[row] = g.add(into[row], v) if row in into else v
