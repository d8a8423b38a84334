"""Operation counts of SymPy expressions, in symgen's convention, and SymPy's own ``count_ops``.

symgen counts (``symgen.codegen``, Featherstone's Table 10.1 convention): ``mul`` includes
divisions, ``add`` includes subtractions, negations are free, constants are literals (free),
sine/cosine (``trig``) and square roots apart. ``sympy.count_ops`` differs on every one of
these points, so both are reported and never mixed:

* ``count_ops`` counts ``NEG`` for a negated term, ``SUB`` and ``ADD`` apart, ``DIV`` for a
  rational constant such as ``3/10`` (even alone), ``POW`` once for any power, ``SIN``/``COS``
  as operations, and one ``FUNC`` per occurrence of an undefined function such as ``q0(t)``.
* :func:`operation_counts` walks the expression tree and counts, per occurrence (a tree has no
  sharing; common subexpressions are counted each time they occur, as ``count_ops`` does):

  - ``Add`` of k terms: k - 1 additions (a term with a negative coefficient is a subtraction,
    which is an addition here; the sign itself is free);
  - ``Mul``: its numeric coefficient is a literal factor unless it is +-1 (then free); factors
    with a negative integer exponent form the denominator. A numerator of p factors and a
    denominator of q factors cost (p - 1) + (q - 1) multiplications plus one division if q > 0;
  - ``Pow`` with integer exponent e: |e| - 1 multiplications (repeated products), plus one
    division when e < 0 and the power stands alone; exponent 1/2 is a square root;
  - ``sin``/``cos``: one ``trig`` each; any other function or power is counted under ``other``;
  - symbols and numbers: free.

So ``mul`` here equals ``MUL + DIV`` of ``count_ops`` less its constant-only divisions, plus
``|e| - 1`` per power, and ``add`` equals ``ADD + SUB``.
"""
from __future__ import annotations

from collections import Counter

import sympy as sp

KEYS = ("mul", "div", "add", "trig", "sqrt", "other")


def operation_counts(exprs) -> dict:
    """``{mul, div, add, trig, sqrt, other, total}`` of the expressions (an iterable or a matrix),
    every occurrence counted; ``mul`` includes ``div`` and ``total = mul + add``."""
    memo: dict = {}
    counts = Counter()
    for expr in _flatten(exprs):
        counts.update(_cost(sp.sympify(expr), memo))
    out = {k: int(counts[k]) for k in KEYS}
    out["mul"] += out["div"]
    out["total"] = out["mul"] + out["add"]
    return out


def sympy_count_ops(exprs) -> int:
    """SymPy's own ``count_ops(..., visual=False)`` summed over the expressions."""
    return int(sum(sp.count_ops(e, visual=False) for e in _flatten(exprs)))


def cse_operation_counts(exprs) -> tuple[dict, int]:
    """Counts after ``sympy.cse``: the replacements' right-hand sides plus the reduced
    expressions (the common-subexpression symbols are free), and the number of replacements."""
    replacements, reduced = sp.cse(list(_flatten(exprs)))
    counts = operation_counts([rhs for _, rhs in replacements] + list(reduced))
    return counts, len(replacements)


def _flatten(exprs):
    if isinstance(exprs, sp.MatrixBase):
        return list(exprs)
    if isinstance(exprs, sp.Basic):
        return [exprs]
    out = []
    for e in exprs:
        out.extend(_flatten(e) if isinstance(e, (list, tuple, sp.MatrixBase)) else [e])
    return out


def _cost(root, memo) -> Counter:
    """Counts of ``root`` (memoised per distinct subexpression, post-order, no recursion)."""
    stack = [(root, False)]
    while stack:
        node, expanded = stack.pop()
        if node in memo:
            continue
        children = _children(node)
        if not expanded and any(c not in memo for c in children):
            stack.append((node, True))
            stack.extend((c, False) for c in children if c not in memo)
            continue
        total = _local(node)
        for c in children:
            total.update(memo[c])
        memo[node] = total
    return memo[root]


def _children(node) -> list:
    """The subexpressions whose cost is added to ``node``'s own."""
    if isinstance(node, sp.Mul):
        return [_base_of(a) for a in node.args if not a.is_Number]
    if isinstance(node, sp.Pow):
        return [node.base]
    return list(node.args) if node.args else []


def _base_of(factor):
    """A Mul factor ``b**e`` with integer e contributes its base (its exponent is costed by the
    Mul); any other factor contributes itself."""
    if isinstance(factor, sp.Pow) and factor.exp.is_Integer:
        return factor.base
    return factor


def _local(node) -> Counter:
    """The operations of ``node`` itself, its children excluded."""
    if node.is_Atom:
        if isinstance(node, (sp.Symbol, sp.Number, sp.NumberSymbol)):
            return Counter()
        raise ValueError(f"cannot count the atom {node!r} ({type(node).__name__})")
    if isinstance(node, sp.Add):
        return Counter(add=len(node.args) - 1)
    if isinstance(node, sp.Mul):
        return _mul_local(node)
    if isinstance(node, sp.Pow):
        return _pow_local(node.exp, standalone=True)
    if isinstance(node, (sp.sin, sp.cos)):
        return Counter(trig=1)
    if isinstance(node, (sp.Derivative, sp.core.function.AppliedUndef)):
        raise ValueError(f"replace {node} by a plain symbol before counting")
    return Counter(other=1)


def _mul_local(node) -> Counter:
    numerator = denominator = 0
    out = Counter()
    for a in node.args:
        if a.is_Number:
            if abs(a) != 1:
                numerator += 1            # a literal coefficient (its sign is free)
            continue
        if isinstance(a, sp.Pow) and a.exp.is_Integer and a.exp < 0:
            denominator += 1
            out.update(_pow_local(-a.exp, standalone=False))
        elif isinstance(a, sp.Pow) and a.exp.is_Integer:
            numerator += 1
            out.update(_pow_local(a.exp, standalone=False))
        else:
            numerator += 1
    out["mul"] += max(numerator - 1, 0) + max(denominator - 1, 0)
    out["div"] += 1 if denominator else 0
    return out


def _pow_local(exp, standalone: bool) -> Counter:
    if exp.is_Integer:
        e = int(exp)
        return Counter(mul=abs(e) - 1, div=1 if (e < 0 and standalone) else 0)
    if exp == sp.Rational(1, 2):
        return Counter(sqrt=1)
    if exp == sp.Rational(-1, 2):
        return Counter(sqrt=1, div=1)
    return Counter(other=1)
