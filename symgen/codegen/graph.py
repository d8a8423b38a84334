"""A tracing expression graph: the optimiser behind the generated code.

The recursive algorithms of :mod:`symgen.dynamics.rnea` and the kinematics of
:mod:`symgen.kinematics` run unchanged on :class:`Node` scalars. Every operation is recorded once:

* **folding** -- operations on constants are evaluated at generation time (exactly, with
  :class:`fractions.Fraction`, where the constants are rational); ``x + 0``, ``x * 1``, ``x * 0``,
  ``x - x`` and double negations disappear, so the scene's zeros (offsets along one axis,
  diagonal inertias, axes along z) cost nothing;
* **hash-consing** -- an operation on the same operands returns the existing node, which is common
  subexpression elimination over the whole function in linear time (commutative operands sorted);
* **sign canonicalisation** -- ``a + (-b)`` becomes ``a - b`` and ``(-a) * b`` becomes ``-(a * b)``,
  so that a negation is free, as in the published operation counts;
* **dead code** -- only what an output needs is emitted (:meth:`Graph.live`).

Dense linear solves become *factor* and *solve* statements (a library call in the generated code,
counted apart from the scalar operations; :mod:`symgen.codegen.graph_solves`); a solve with a constant
matrix is done at generation time. A banded matrix product of nodes may become a *product*
statement (a library loop, its flops counted with them; :mod:`symgen.codegen.graph_products`).
"""
from __future__ import annotations

import math
from fractions import Fraction

import mpmath
import numpy as np
import sympy as sp

from .graph_products import Products
from .graph_solves import LinearSolves, PivotCheck, solve_flops

#: the private 40-digit context of :func:`_fold` (the global mpmath precision is left alone)
_MP = mpmath.MPContext()
_MP.dps = 40
#: constant rationals with larger denominators are kept as floats (generation speed)
MAX_DENOMINATOR = 2**64

COMMUTATIVE = frozenset({"add", "mul"})


def _fold(name: str, value) -> float | int:
    """``sin``, ``cos``, ``sqrt`` or ``sign`` of a constant, correctly rounded: evaluated at 40
    digits by mpmath, then rounded once, so a folded constant does not depend on the C library's
    ``sin`` (generated files are the same on every machine)."""
    if name == "sign":
        return (value > 0) - (value < 0)
    x = _MP.mpf(value.numerator) / value.denominator if isinstance(value, Fraction) else _MP.mpf(float(value))
    return float({"sin": _MP.sin, "cos": _MP.cos, "sqrt": _MP.sqrt}[name](x))


#: operation name -> counted as (in ops.json)
COUNTED_AS = {"add": "add", "sub": "add", "mul": "mul", "div": "mul", "sin": "trig", "cos": "trig",
              "sqrt": "sqrt", "sign": "cmp", "neg": "neg"}


class Node:
    """One scalar of a traced computation. Supports ``+ - * /`` with nodes and numbers."""

    __slots__ = ("graph", "id", "op", "args", "value", "name", "is_const")

    def __init__(self, graph, ident, op, args, value=None):
        self.graph = graph
        self.id = ident
        self.op = op
        self.args = args
        self.value = value
        self.name = None
        #: a constant (``op == "const"``; a node's operation never changes)
        self.is_const = op == "const"

    # arithmetic ------------------------------------------------------------------
    def __add__(self, other):
        if isinstance(other, np.ndarray):
            return NotImplemented
        return self.graph.add(self, other)

    def __radd__(self, other):
        if isinstance(other, np.ndarray):
            return NotImplemented
        return self.graph.add(other, self)

    def __sub__(self, other):
        if isinstance(other, np.ndarray):
            return NotImplemented
        return self.graph.sub(self, other)

    def __rsub__(self, other):
        if isinstance(other, np.ndarray):
            return NotImplemented
        return self.graph.sub(other, self)

    def __mul__(self, other):
        if isinstance(other, np.ndarray):
            return NotImplemented
        return self.graph.mul(self, other)

    def __rmul__(self, other):
        if isinstance(other, np.ndarray):
            return NotImplemented
        return self.graph.mul(other, self)

    def __truediv__(self, other):
        if isinstance(other, np.ndarray):
            return NotImplemented
        return self.graph.div(self, other)

    def __rtruediv__(self, other):
        if isinstance(other, np.ndarray):
            return NotImplemented
        return self.graph.div(other, self)

    def __neg__(self):
        return self.graph.neg(self)

    def __pos__(self):
        return self

    def __repr__(self) -> str:
        if self.is_const:
            return f"Node(const {float(self.value)!r})"
        return f"Node({self.id}: {self.op} {self.args})"


def _normalise(value):
    """A constant as Fraction (rational) or float."""
    if isinstance(value, bool):
        value = int(value)
    if isinstance(value, Fraction):
        return value if value.denominator <= MAX_DENOMINATOR else float(value)
    if isinstance(value, int):
        return Fraction(value)
    if isinstance(value, (float, np.floating)):
        if not math.isfinite(value):
            raise ValueError(f"constant {value!r} is not finite")
        return Fraction(float(value)) if float(value).is_integer() else float(value)
    if isinstance(value, sp.Basic):
        if value.is_Rational:
            return _normalise(Fraction(int(value.p), int(value.q)))
        return _normalise(float(value))
    raise TypeError(f"cannot use {type(value).__name__} {value!r} as a constant")


class Graph(LinearSolves, Products):
    """Records a computation on :class:`Node` scalars (see the module docstring)."""

    def __init__(self):
        self.nodes: list[Node] = []
        self.statements: list = []          # Factor, Solve, PivotCheck and Product, in creation order
        self._table: dict = {}
        self._factors: dict = {}
        self._sparse: dict = {}
        self._names: set[str] = set()
        self.checks: list[PivotCheck] = []
        #: input array -> ``S x size`` sample values (the reference configuration and perturbations
        #: of it), which choose static pivot orders; ``None``: every solve uses the library LU
        self.samples: dict | None = None
        self._zero = self._one = None       # the constant nodes 0 and 1, once made (fast paths)

    # construction ------------------------------------------------------------------
    def _make(self, op, args, value=None) -> Node:
        key = (op, args) if op != "const" else ("const", value, type(value))
        found = self._table.get(key)
        if found is not None:
            return found
        node = Node(self, len(self.nodes), op, args, value)
        self.nodes.append(node)
        self._table[key] = node
        if op == "const" and value in (0, 1):
            if value == 0:
                self._zero = node
            else:
                self._one = node
        return node

    def _statement_node(self, op: str, statement) -> None:
        """The node of a library statement (``factor``, ``solve``, ``check``, ``product``): its id is the
        statement's, given before the statement's own operands were made."""
        self.nodes.append(Node(self, len(self.nodes), op, (statement,)))

    def const(self, value) -> Node:
        if isinstance(value, Node):
            return value
        return self._make("const", (), _normalise(value))

    def input(self, array: str, size: int) -> list[Node]:
        """``size`` scalar inputs ``array[0..size-1]``."""
        return [self._make("in", (array, i)) for i in range(size)]

    def _node(self, x) -> Node:
        return x if isinstance(x, Node) else self.const(x)

    # folding rules -------------------------------------------------------------------
    def add(self, a, b) -> Node:
        a = a if a.__class__ is Node else self.const(a)
        b = b if b.__class__ is Node else self.const(b)
        if a is self._zero:               # identity tests first: most operands of a sparse
            return b                      # matrix product are the constant 0
        if b is self._zero:
            return a
        if a.is_const and b.is_const:
            return self.const(a.value + b.value)
        if a.is_const and a.value == 0:
            return b
        if b.is_const and b.value == 0:
            return a
        if a.op == "neg" and b.op == "neg":
            return self.neg(self.add(self.nodes[a.args[0]], self.nodes[b.args[0]]))
        if b.op == "neg":
            return self.sub(a, self.nodes[b.args[0]])
        if a.op == "neg":
            return self.sub(b, self.nodes[a.args[0]])
        if b.is_const and b.value < 0:
            return self.sub(a, self.const(-b.value))
        if a.is_const and a.value < 0:
            return self.sub(b, self.const(-a.value))
        return self._make("add", tuple(sorted((a.id, b.id))))

    def sub(self, a, b) -> Node:
        a, b = self._node(a), self._node(b)
        if a.is_const and b.is_const:
            return self.const(a.value - b.value)
        if b.is_const and b.value == 0:
            return a
        if a.is_const and a.value == 0:
            return self.neg(b)
        if a is b:
            return self.const(0)
        if b.op == "neg":
            return self.add(a, self.nodes[b.args[0]])
        if a.op == "neg":
            return self.neg(self.add(self.nodes[a.args[0]], b))
        if b.is_const and b.value < 0:
            return self.add(a, self.const(-b.value))
        return self._make("sub", (a.id, b.id))

    def mul(self, a, b) -> Node:
        a = a if a.__class__ is Node else self.const(a)
        b = b if b.__class__ is Node else self.const(b)
        zero = self._zero
        if a is zero or b is zero:
            return zero
        if a is self._one:
            return b
        if b is self._one:
            return a
        if a.is_const and b.is_const:
            return self.const(a.value * b.value)
        if b.is_const:
            a, b = b, a
        if a.is_const:
            if a.value == 0:
                return a
            if a.value == 1:
                return b
            if a.value < 0:
                return self.neg(self.mul(self.const(-a.value), b))
        if a.op == "neg":
            return self.neg(self.mul(self.nodes[a.args[0]], b))
        if b.op == "neg":
            return self.neg(self.mul(a, self.nodes[b.args[0]]))
        return self._make("mul", tuple(sorted((a.id, b.id))))

    def div(self, a, b) -> Node:
        a, b = self._node(a), self._node(b)
        if b.is_const:
            if b.value == 0:
                raise ZeroDivisionError("division by the constant 0 in generated code")
            inv = 1 / b.value if isinstance(b.value, Fraction) else 1.0 / b.value
            return self.mul(a, self.const(inv))
        if a.is_const and a.value == 0:
            return a
        if a.op == "neg":
            return self.neg(self.div(self.nodes[a.args[0]], b))
        if b.op == "neg":
            return self.neg(self.div(a, self.nodes[b.args[0]]))
        return self._make("div", (a.id, b.id))

    def neg(self, a) -> Node:
        a = self._node(a)
        if a.is_const:
            return self.const(-a.value)
        if a.op == "neg":
            return self.nodes[a.args[0]]
        return self._make("neg", (a.id,))

    def func(self, name: str, a) -> Node:
        """``sin``, ``cos``, ``sqrt`` or ``sign`` of a node."""
        a = self._node(a)
        if a.is_const:
            return self.const(_fold(name, a.value))
        return self._make(name, (a.id,))

    def sample_values(self, nodes) -> np.ndarray:
        """The values of ``nodes`` at the sample inputs (:attr:`samples`): an ``S x len(nodes)`` array.
        Inputs without samples take fixed pseudo-random values (deterministic)."""
        import zlib

        count = len(next(iter(self.samples.values()))) if self.samples else 1
        wanted = [self._node(v).id for v in nodes]
        alive = self.live([[self.nodes[i] for i in wanted]])
        vals: dict[int, np.ndarray] = {}
        solved: dict[int, np.ndarray] = {}
        for node, on in zip(self.nodes, alive):
            if not on:
                continue
            op, a = node.op, node.args
            if op == "const":
                vals[node.id] = np.full(count, float(node.value))
            elif op == "in":
                name, i = a
                if self.samples and name in self.samples:
                    vals[node.id] = np.asarray(self.samples[name], dtype=float)[:, i]
                else:
                    rng = np.random.default_rng(zlib.crc32(f"{name}[{i}]".encode()))
                    vals[node.id] = np.full(count, rng.uniform(-1, 1))
            elif op == "solve":
                sol = a[0]
                fac = self.nodes[sol.factor].args[0]
                mat = np.stack([vals[i] for i in fac.entries], axis=-1).reshape(count, fac.n, fac.n)
                rhs = np.stack([vals[i] for i in sol.rhs], axis=-1).reshape(count, fac.n, sol.k)
                solved[node.id] = np.linalg.solve(np.swapaxes(mat, 1, 2) if sol.transposed else mat, rhs)
            elif op == "product":
                solved[node.id] = a[0].values(vals, count)
            elif op == "library_out":
                vals[node.id] = solved[a[0]][:, a[1], a[2]]
            elif op in ("factor", "check"):
                continue
            else:
                x = [vals[i] for i in a]
                with np.errstate(all="ignore"):
                    vals[node.id] = _EVALUATE[op](*x)
        return np.stack([vals[i] for i in wanted], axis=-1)

    # naming, liveness, counting ---------------------------------------------------------
    def label(self, node, name: str) -> None:
        """Give a computed node a readable name (first label wins; names stay unique)."""
        if not isinstance(node, Node) or node.op in ("const", "in", "library_out") or node.name is not None:
            return
        base, k = name, 1
        while name in self._names:
            k += 1
            name = f"{base}_{k}"
        self._names.add(name)
        node.name = name

    def operands(self, node: Node) -> tuple[int, ...]:
        if node.op in ("const", "in"):
            return ()
        if node.op == "library_out":
            return (node.args[0],)
        if node.op == "solve":
            sol = node.args[0]
            return (sol.factor,) + sol.rhs
        if node.op == "product":
            return node.args[0].operands
        if node.op == "factor":
            return node.args[0].entries
        if node.op == "check":
            return node.args[0].pivots
        return node.args

    def live(self, outputs) -> list[bool]:
        """Which nodes the ``outputs`` (iterables of nodes) depend on."""
        alive = [False] * len(self.nodes)
        stack = [self._node(v).id for out in outputs for v in out]
        while stack:
            while stack:
                i = stack.pop()
                if alive[i]:
                    continue
                alive[i] = True
                stack.extend(self.operands(self.nodes[i]))
            # a pivot check runs when any of its elimination's reciprocals does, on all its pivots
            stack = [c.id for c in self.checks if not alive[c.id] and any(alive[g] for g in c.guards)]
        return alive

    def count(self, alive) -> dict:
        """Operation counts of the live nodes (module docstring and ``ops.json``)."""
        tally = {"mul": 0, "add": 0, "div": 0, "trig": 0, "sqrt": 0, "cmp": 0, "neg": 0}
        solves, products = [], []
        for node, on in zip(self.nodes, alive):
            if not on:
                continue
            kind = COUNTED_AS.get(node.op)
            if kind:
                tally[kind] += 1
            if node.op == "div":
                tally["div"] += 1
            if node.op == "solve":
                sol = node.args[0]
                solves.append({"n": self.nodes[sol.factor].args[0].n, "rhs": sol.k, "transposed": sol.transposed}
                              | ({"inverse": True} if sol.inverse else {}))
            if node.op == "product":
                prod = node.args[0]
                products.append({"rows": prod.n, "terms": prod.m, "columns": prod.k, "flops": prod.flops})
        factored = [self.nodes[i].args[0] for i, on in enumerate(alive) if on and self.nodes[i].op == "factor"]
        symmetric = [f.n for f in factored if f.symmetric]
        factors = [f.n for f in factored]
        tally["pivot_checks"] = [len(self.nodes[i].args[0].pivots) for i, on in enumerate(alive)
                                 if on and self.nodes[i].op == "check"]
        tally["total"] = tally["mul"] + tally["add"]
        tally["factorizations"] = factors
        tally["symmetric_factorizations"] = symmetric
        tally["solves"] = solves
        tally["solve_flops"] = solve_flops(factored, solves)
        tally["products"] = products
        tally["product_flops"] = sum(p["flops"] for p in products)
        return tally


_EVALUATE = {"add": np.add, "sub": np.subtract, "mul": np.multiply, "div": np.divide, "neg": np.negative,
             "sin": np.sin, "cos": np.cos, "sqrt": np.sqrt, "sign": np.sign}


def is_zero(x) -> bool:
    """``x`` is the number 0 or a constant node of value 0 (a structural zero)."""
    if isinstance(x, Node):
        return x.is_const and x.value == 0
    return x == 0
