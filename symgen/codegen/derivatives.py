"""Forward-mode differentiation of a traced graph, inside the same graph.

:func:`differentiate` walks the nodes of a :class:`~symgen.codegen.graph.Graph` in creation order
(a topological order) and builds, for every node an output needs, its partial derivatives with
respect to chosen input nodes as new nodes of the *same* graph. The derivative of a node is kept
sparse -- a dict ``input index -> node``, an absent index being a structural zero -- and every
derivative node goes through the graph's folding and hash-consing, so:

* a derivative that is zero by structure (an input a node does not depend on, an axis along z,
  a constant inertia) costs nothing and is never stored;
* a product already in the graph (``cos q`` in ``d(sin q)``, ``x/y`` in ``d(x/y)``) is reused,
  and derivatives shared by several outputs are computed once (common subexpressions).

The rules are the textbook ones for every scalar operation the graph records (``add``, ``sub``,
``mul``, ``div``, ``neg``, ``sin``, ``cos``, ``sqrt``; ``sign`` is piecewise constant and has
derivative 0 where it is differentiable). A library solve ``X = A^-1 B`` (a
:class:`~symgen.codegen.graph_solves.Solve` statement, ``A`` or ``A^T`` of a factor) is
differentiated as ``dX = A^-1 (dB - dA X)``, by one more solve with the same matrix entries, so
the generated code reuses the factorisation; a straight-line elimination is already scalar
operations, and its pivot checks need no derivative.

Cost: each live node adds at most a few operations per input it depends on (``O(k)`` times the
function for ``k`` inputs, less where the dependence is sparse, as in a serial chain).
"""
from __future__ import annotations

import numpy as np

from ..errors import CodegenError
from .graph import Graph, Node

#: sparse derivative of one node: input index -> derivative node
Partials = dict


def sweep_arguments(graph: Graph, outputs, inputs, held, seeds) -> tuple:
    """``(outputs, index, flat, given, held_ids)``: the arguments of :func:`differentiate` (and of
    the adjoint sweep, :func:`symgen.codegen.reverse.differentiate_reverse`) checked and keyed by
    node id: ``index`` input node id -> column, ``flat`` the output nodes, ``given`` node id ->
    its seeded partials, ``held_ids`` the held nodes."""
    outputs = np.asarray(outputs, dtype=object)
    index: dict[int, int] = {}
    for k, node in enumerate(inputs):
        if node is None:
            continue
        if not isinstance(node, Node) or node.graph is not graph or node.op != "in":
            raise CodegenError(f"differentiate: inputs[{k}] = {node!r} is not an input node of this graph")
        index.setdefault(node.id, k)
    flat = [graph._node(v) for v in outputs.flat]
    given = {graph._node(v).id: {k: graph._node(d) for k, d in part.items()} for v, part in (seeds or {}).items()}
    held_ids = {graph._node(v).id for v in held}
    # the graph folds a negation into its users (``a + (-b)`` is recorded as ``a - b``, ``c (-b)``
    # as ``-(c b)``), so a held or seeded ``-b`` is read through ``b`` as well: ``b`` is held too,
    # or seeded with the negated partials; a ``b`` that is a column, or held and seeded at once,
    # cannot be both and is refused
    for i in list(held_ids):
        node = graph.nodes[i]
        if node.op == "neg":
            _refuse_conflict(graph, node, index, given)
            held_ids.add(node.args[0])
    for i, part in list(given.items()):
        node = graph.nodes[i]
        if node.op == "neg":
            _refuse_conflict(graph, node, index, held_ids)
            negated = {k: graph.neg(d) for k, d in part.items()}
            known = given.setdefault(node.args[0], negated)
            if known is not negated and {k: v.id for k, v in known.items()} != {k: v.id for k, v in negated.items()}:
                raise CodegenError(f"differentiate: node {node.id} (a negation) and its operand are seeded apart")
    return outputs, index, flat, given, held_ids


def _refuse_conflict(graph: Graph, node: Node, index: dict, taken) -> None:
    """Refuse to hold or seed the operand of the negation ``node`` when it is a column (``index``)
    or already seeded / held otherwise (``taken``)."""
    operand = node.args[0]
    if operand in index or operand in taken:
        raise CodegenError(f"differentiate: the negation {node.id} is held or seeded, but its operand "
                           f"{operand} is {'a column' if operand in index else 'held and seeded at once'}")


def differentiate(graph: Graph, outputs, inputs, held=(), seeds=None) -> np.ndarray:
    """The Jacobian ``d outputs / d inputs`` as an object array of nodes of ``graph``, of shape
    ``outputs.shape + (len(inputs),)``.

    ``outputs``: an array (any shape) of nodes or numbers of ``graph``; ``inputs``: input nodes of
    ``graph`` (``Graph.input``), the independent variables, or ``None`` for a column that only
    ``seeds`` define; ``held``: computed nodes taken as constants (their partials are not
    followed: the explicit partials of an implicit function,
    :mod:`symgen.codegen.forward_derivatives`); ``seeds``: computed node -> its partials
    ``{column: node}``, given instead of derived (a direction that is not a partial of any input:
    a spherical joint's rotation turned in its child frame, :mod:`symgen.codegen.tangent`). A held
    or seeded negation ``-b`` holds (seeds, negated) ``b`` too, which the graph's folding lets its
    users read instead; every other reader of ``b`` is then held too -- the callers hold values
    (rates, accelerations, solutions) whose operands nothing else computes.
    A :class:`CodegenError` names an ``inputs`` entry that is not an input node, and a negation
    whose operand is a column or is both held and seeded.
    """
    outputs, index, flat, given, held_ids = sweep_arguments(graph, outputs, inputs, held, seeds)
    partials = _forward(graph, flat, index, held_ids, given)
    zero = graph.const(0)
    jac = np.empty((len(flat), len(inputs)), dtype=object)
    jac[:] = zero
    for row, node in enumerate(flat):
        for k, d in partials.get(node.id, {}).items():
            jac[row, k] = d
    return jac.reshape(outputs.shape + (len(inputs),))


def _forward(graph: Graph, outputs: list[Node], index: dict[int, int],
             held: set[int] = frozenset(), seeds: dict[int, Partials] | None = None) -> dict[int, Partials]:
    """The partials of every node the ``outputs`` need, by one walk in creation order (nodes
    added by the walk itself have larger ids and are not visited); ``held`` nodes have none,
    ``seeds`` nodes the partials given."""
    alive = graph.live([outputs])
    partials: dict[int, Partials] = {}
    seeds = seeds or {}
    for node in graph.nodes[:len(alive)]:
        if not alive[node.id] or node.id in held:
            continue
        if node.id in seeds:
            found = {k: v for k, v in seeds[node.id].items() if not _zero(v)}
            if found:
                partials[node.id] = found
        elif node.op == "in":
            if node.id in index:
                partials[node.id] = {index[node.id]: graph.const(1)}
        elif node.op == "solve":
            found = _solve_partials(graph, node.args[0], partials)
            partials.update({k: v for k, v in found.items() if k not in held})
        elif node.op == "product":
            if any(i in partials for i in graph.operands(node)):
                raise CodegenError(f"differentiate: the library product {node.args[0].what!r} (node {node.id}) "
                                   "depends on the inputs; it is not differentiated")
        elif node.op not in ("const", "factor", "check", "library_out"):
            d = _scalar_partials(graph, node, [partials.get(a, {}) for a in node.args])
            if d:
                partials[node.id] = d
    return partials


def _scalar_partials(g: Graph, node: Node, d: list[Partials]) -> Partials:
    """The chain rule for one scalar operation, ``d`` the partials of its operands."""
    op = node.op
    args = [g.nodes[i] for i in node.args]
    if op == "add":
        return _combine(g, [(None, d[0]), (None, d[1])])
    if op == "sub":
        return _combine(g, [(None, d[0]), (-1, d[1])])
    if op == "neg":
        return _combine(g, [(-1, d[0])])
    if op == "mul":                      # d(ab) = b da + a db
        return _combine(g, [(args[1], d[0]), (args[0], d[1])])
    if op == "div":                      # d(a/b) = (da - (a/b) db) / b
        inner = _combine(g, [(None, d[0]), (g.neg(node), d[1])])
        return {k: v for k, v in ((k, g.div(v, args[1])) for k, v in inner.items()) if not _zero(v)}
    if op == "sin":
        return _combine(g, [(g.func("cos", args[0]), d[0])])
    if op == "cos":
        return _combine(g, [(g.neg(g.func("sin", args[0])), d[0])])
    if op == "sqrt":                     # d sqrt(a) = da / (2 sqrt(a))
        half = g.div(g.const(1), g.mul(2, node)) if d[0] else None
        return _combine(g, [(half, d[0])])
    if op == "sign":                     # piecewise constant
        return {}
    raise CodegenError(f"differentiate: no derivative rule for operation {op!r} (node {node.id})")


def _combine(g: Graph, terms) -> Partials:
    """``sum c_t d_t`` of sparse partials ``d_t`` with coefficients ``c_t`` (a node, a number, or
    ``None`` for 1); structural zeros are dropped."""
    out: Partials = {}
    for coef, part in terms:
        for k, v in part.items():
            term = v if coef is None else g.mul(coef, v)
            out[k] = g.add(out[k], term) if k in out else term
    return {k: v for k, v in out.items() if not _zero(v)}


def _zero(v: Node) -> bool:
    return v.is_const and v.value == 0


def _solve_partials(g: Graph, sol, partials: dict[int, Partials]) -> dict[int, Partials]:
    """Partials of the outputs ``X`` of ``X = E^-1 B`` (``E = A`` or ``A^T`` of the solve's
    factor): ``dX = E^-1 (dB - dE X)``, one solve with the same entries (the factor is reused)
    whose right-hand side holds one block of columns per input that ``E`` or ``B`` depends on."""
    factor = g.nodes[sol.factor].args[0]
    n, cols = factor.n, sol.k
    ids = np.array(factor.entries, dtype=object).reshape(n, n)
    if sol.transposed:
        ids = ids.T
    mat = np.vectorize(lambda i: g.nodes[i], otypes=[object])(ids)
    d_mat = [[partials.get(i, {}) for i in row] for row in ids]
    d_rhs = np.array([partials.get(i, {}) for i in sol.rhs], dtype=object).reshape(n, cols)
    x = np.array([[g._make("library_out", (sol.id, i, j)) for j in range(cols)] for i in range(n)], dtype=object)
    wanted = sorted({k for row in d_mat for p in row for k in p} | {k for p in d_rhs.flat for k in p})
    if not wanted:
        return {}
    rhs = np.empty((n, cols * len(wanted)), dtype=object)
    for b, k in enumerate(wanted):
        for i in range(n):
            for j in range(cols):
                terms = [(None, {0: d_rhs[i, j][k]} if k in d_rhs[i, j] else {})]
                terms += [(-1, {0: g.mul(d_mat[i][c][k], x[c, j])}) for c in range(n) if k in d_mat[i][c]]
                rhs[i, b * cols + j] = _combine(g, terms).get(0, g.const(0))
    dx = g.solve(mat, rhs, g.nodes[sol.factor].args[0].what + " (derivative)")
    out: dict[int, Partials] = {}
    for i in range(n):
        for j in range(cols):
            part = {k: dx[i, b * cols + j] for b, k in enumerate(wanted)}
            part = {k: v for k, v in part.items() if not _zero(v)}
            if part:
                out[x[i, j].id] = part
    return out
