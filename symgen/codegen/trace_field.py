"""A :class:`~symgen.math.fields.Field` whose entries are traced :class:`~symgen.codegen.graph.Node` s.

With it, the reference kinematics of :mod:`symgen.kinematics` (frame Jacobians, the constraint
matrix ``T`` of eq. 6 and their time derivatives) runs unchanged and is recorded into a graph.
"""
from __future__ import annotations

import numpy as np

from ..math import jet
from ..math.fields import Field
from .graph import Graph, Node, is_zero
from .node_product import node_matmul
from .parameters import to_nodes

jet.PRODUCTS[Node] = node_matmul


class TraceField(Field):
    """Entries are graph nodes; every operation of the :class:`~symgen.math.fields.Field` protocol is
    recorded (``sign`` and ``sqrt`` as graph functions). Revolute positions must be ``CosSin``
    pairs of nodes (:meth:`cos_sin` refuses, as in the exact and symbolic fields)."""

    name = "trace"
    dtype = object

    def __init__(self, graph: Graph, params=None, inputs=None):
        """``inputs``: scene parameters (symbol -> input node) read at run time, not substituted
        (:mod:`symgen.codegen.parameters`)."""
        super().__init__({k: v for k, v in (params or {}).items() if k not in (inputs or {})})
        self.graph = graph
        self.inputs = dict(inputs or {})
        self.zero = graph.const(0)
        self.one = graph.const(1)

    def const(self, value):
        if isinstance(value, Node):
            return value
        if hasattr(value, "xreplace") and self.params:
            value = value.xreplace(self.params)
        if self.inputs and getattr(value, "free_symbols", None) and value.free_symbols <= set(self.inputs):
            return to_nodes(self.graph, value, self.inputs)
        if getattr(value, "free_symbols", None):
            raise TypeError(f"no value for parameter(s) {sorted(map(str, value.free_symbols))}")
        return self.graph.const(value)

    def is_zero(self, x) -> bool:
        """A structural zero: the number 0 or the constant-zero node (never a run-time value)."""
        return is_zero(x)

    def sign(self, x):
        """``sign(x)`` recorded as a graph function (emitted as ``np.sign`` / ``symgen_sign``)."""
        return self.graph.func("sign", x)

    def sqrt(self, x):
        return self.graph.func("sqrt", x)

    def solve(self, a, b, what="matrix"):
        return self.graph.solve(np.asarray(a, dtype=object), np.asarray(b, dtype=object), what)
