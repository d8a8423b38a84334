"""Dense linear solves on the tracing graph: factor, solve and pivot-check statements.

A solve with a constant matrix is done at generation time (exactly); a permutation costs nothing;
a matrix whose sampled values allow it is eliminated in straight-line code
(:mod:`symgen.codegen.sparse_lu`, with a run-time :class:`PivotCheck`); the rest becomes a
library :class:`Factor` shared by every :class:`Solve` with the same matrix (or its transpose): LU
with row exchanges, or, for a symmetric positive definite matrix (:meth:`LinearSolves.solve_spd`),
the same ``L U`` without them (``U = D L^T``: no pivot search, no row exchanges, one triangle's
updates).
:class:`LinearSolves` is the part of :class:`~symgen.codegen.graph.Graph` that records them.
"""
from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from ..errors import SingularConfigurationError


@dataclass
class Factor:
    """An LU factorisation of a dense ``n x n`` matrix of nodes (library call): with partial
    pivoting, or, where ``symmetric`` (a symmetric positive definite matrix, its entries the lower
    triangle's nodes mirrored), without row exchanges -- ``A = L (D L^T)``, the pivots ``D``
    checked positive."""

    id: int
    n: int
    entries: tuple            # row-major node ids
    what: str
    symmetric: bool = False


@dataclass
class Solve:
    """``X = A^-1 B`` for a factor and an ``n x k`` right-hand side of nodes (library call)."""

    id: int
    factor: int
    k: int
    rhs: tuple                # row-major node ids
    transposed: bool = False  # solve with A^T using the factors of A
    inverse: bool = False     # the right-hand side is the identity of a symmetric factor: A^-1 itself


@dataclass
class PivotCheck:
    """The run-time guard of a straight-line elimination (:mod:`symgen.codegen.sparse_lu`): its
    non-constant pivots, the reciprocals that use them (the check is live when one of them is), and
    the constant pivots' magnitudes (they enter the estimate ``max |pivot| / min |pivot|``)."""

    id: int
    pivots: tuple             # node ids
    guards: tuple             # node ids of the reciprocals
    constants: tuple          # |pivot| of the constant pivots
    what: str


class LinearSolves:
    """The solve methods of :class:`~symgen.codegen.graph.Graph` (which provides ``nodes``,
    ``statements``, ``checks``, ``_factors``, ``_sparse``, ``samples``, ``const``, ``_node``,
    ``_make``, ``_statement_node``, ``live`` and ``sample_values``)."""

    def solve(self, a, b, what: str = "matrix", symmetric: bool = False) -> np.ndarray:
        """``a^-1 b`` for an ``n x n`` array ``a`` and an ``n`` or ``n x k`` array ``b`` of nodes.

        A constant ``a`` is inverted exactly now; otherwise a factor (shared by every solve with
        the same matrix) and a solve statement are recorded, whose outputs are new nodes; a
        ``symmetric`` (positive definite) ``a`` is factored without row exchanges."""
        a = np.asarray(a, dtype=object)
        b = np.asarray(b, dtype=object)
        n = a.shape[0]
        vector = b.ndim == 1
        rhs = b.reshape(n, -1)
        if n == 0:
            return np.empty(b.shape, dtype=object)
        entries = [[self._node(v) for v in row] for row in a]
        if all(v.is_const for row in entries for v in row):
            perm = _permutation(entries)
            out = rhs[perm] if perm is not None else self._constant_inverse(entries, what) @ rhs
        elif all(self._node(v).is_const and self._node(v).value == 0 for v in rhs.flat):
            out = np.array([[self.const(0)] * rhs.shape[1] for _ in range(n)], dtype=object)
        elif (sparse := self._sparse_factors(entries, what)) is not None:
            from .sparse_lu import solve_transposed, solve

            factors, transposed = sparse
            run = solve_transposed if transposed else solve
            out = np.array([run(factors, list(rhs[:, j])) for j in range(rhs.shape[1])], dtype=object).T
        else:
            transposed_key = tuple(entries[j][i].id for i in range(n) for j in range(n))
            transposed = not symmetric and transposed_key in self._factors and transposed_key != tuple(
                v.id for row in entries for v in row)
            factor = self._factors[transposed_key] if transposed else self._factor(entries, what, symmetric)
            rhs_ids = tuple(self._node(v).id for v in rhs.flat)    # may create constants: before the id
            inverse = symmetric and rhs.shape[1] == n and _unit_columns(
                [[self._node(v) for v in row] for row in rhs]) == {i: i for i in range(n)}
            sol = Solve(len(self.nodes), factor.id, rhs.shape[1], rhs_ids, transposed, inverse)
            self.statements.append(sol)
            self._statement_node("solve", sol)
            out = np.empty(rhs.shape, dtype=object)
            for i in range(n):
                for j in range(rhs.shape[1]):
                    out[i, j] = self._make("library_out", (sol.id, i, j))
        return out.reshape(n) if vector else out

    def solve_spd(self, a, b, what: str = "matrix") -> np.ndarray:
        """``a^-1 b`` for a symmetric positive definite ``a`` (only its lower triangle is read):
        straight-line LDL^T, in the natural order up to :data:`~symgen.codegen.sparse_lu.LDLT_MAX`
        rows and in the minimum-degree order beyond where that keeps it sparse
        (:func:`~symgen.codegen.sparse_lu.ldlt_applies`); the library factor without row exchanges
        otherwise (:meth:`_library_spd`), or an exact inverse when ``a`` is constant."""
        from . import sparse_lu

        a = np.asarray(a, dtype=object)
        b = np.asarray(b, dtype=object)
        n = a.shape[0]
        entries = [[self._node(v) for v in row] for row in a]
        if n == 0 or all(v.is_const for row in entries for v in row):
            return self.solve(a, b, what)
        factors = self._ldlt(entries, what)
        if factors is None:
            return self._library_spd(a, b, what)
        rhs = b.reshape(n, -1)
        out = np.array([sparse_lu.solve(factors, list(rhs[:, j])) for j in range(rhs.shape[1])], dtype=object).T
        return out.reshape(b.shape)

    def spd_in_library(self, a, what: str = "matrix") -> bool:
        """Whether :meth:`solve_spd` solves with ``a`` by the library factor (neither a constant
        nor a straight-line ``LDL^T``)."""
        entries = [[self._node(v) for v in row] for row in np.asarray(a, dtype=object)]
        if not entries or all(v.is_const for row in entries for v in row):
            return False
        return self._ldlt(entries, what) is None

    def _ldlt(self, entries, what: str):
        """The straight-line ``LDL^T`` of the SPD matrix of nodes ``entries`` (made once per lower
        triangle), or ``None`` where :meth:`solve_spd` leaves it to the library factor."""
        from . import sparse_lu

        if not sparse_lu.enabled():
            return None
        n = len(entries)
        key = ("ldlt",) + tuple(entries[r][c].id for r in range(n) for c in range(r + 1))
        if key not in self._sparse:
            lower = np.array([[c <= r and not (entries[r][c].is_const and entries[r][c].value == 0)
                               for c in range(n)] for r in range(n)])
            order = sparse_lu.ldlt_applies(lower | lower.T)
            try:
                self._sparse[key] = None if order is None else sparse_lu.ldlt(self, entries, what, order)
            except sparse_lu.ConstantZeroPivot:
                self._sparse[key] = None
        return self._sparse[key]

    def _library_spd(self, a, b, what: str) -> np.ndarray:
        """``a^-1 b`` by the library factor of the symmetric positive definite ``a`` (its lower
        triangle mirrored, so the upper one's nodes are not needed). Where ``b``'s columns include
        every column of the identity (the inverse is wanted anyway: the forward-dynamics
        Jacobian's ``d/d tau`` block), the inverse is computed (a solve with the identity, which
        the C target makes one call, :attr:`Solve.inverse`) and ``b``'s other columns are
        library products with it (:mod:`~symgen.codegen.graph_products`): the same flops, in a loop
        that runs them faster than the substitutions do (the side-by-side time on ``chain:n=32`` is
        in the code-generation guide's section on the derivatives against Pinocchio). The products
        are transposed, ``B_j^T A^-T`` for each block ``B_j`` of ``n`` columns: the factor ``A^-T``
        (the inverse, to rounding) is then the solve's entries in their own order, read in place by
        the C target, and the result's column ``i`` is row ``i`` of ``A^-1 B_j``, so that a product
        whose block is a row-major output (``d dV_m / dq`` of ``n`` coordinates) is written straight
        into it (:mod:`~symgen.codegen.targets.c_products`)."""
        n = a.shape[0]
        lower = np.array([[a[max(r, c), min(r, c)] for c in range(n)] for r in range(n)], dtype=object)
        rhs = b.reshape(n, -1)
        units = _unit_columns([[self._node(v) for v in row] for row in rhs])
        if len(units) < n:
            return self.solve(lower, b, what, symmetric=True)
        eye = np.array([[self.const(int(r == c)) for c in range(n)] for r in range(n)], dtype=object)
        inverse = self.solve(lower, eye, what, symmetric=True)
        out = np.empty(rhs.shape, dtype=object)
        for c, i in units.items():
            out[:, c] = inverse[:, i]
        rest = [c for c in range(rhs.shape[1]) if c not in units]
        for start in range(0, len(rest), n):      # (A^-1 B)^T = B^T A^-T, n columns at a time
            chunk = rest[start:start + n]
            out[:, chunk] = self.product(rhs[:, chunk].T, inverse.T, [(0, len(chunk))] * n, what).T
        return out.reshape(b.shape)

    def _sparse_factors(self, entries, what):
        """``(factors, transposed)`` of a straight-line elimination of ``entries`` (or of its
        transpose, already factored), or ``None`` for the library LU (:mod:`symgen.codegen.sparse_lu`)."""
        from . import sparse_lu

        key = tuple(v.id for row in entries for v in row)
        n = len(entries)
        transposed_key = tuple(entries[j][i].id for i in range(n) for j in range(n))
        if key in self._sparse:
            return None if self._sparse[key] is None else (self._sparse[key], False)
        if transposed_key in self._sparse and self._sparse[transposed_key] is not None:
            return self._sparse[transposed_key], True
        if self.samples is None or n < 2 or not sparse_lu.enabled():
            return None
        pattern = np.array([[not (v.is_const and v.value == 0) for v in row] for row in entries])
        values = self.sample_values([v for row in entries for v in row]).reshape(-1, n, n)
        order = sparse_lu.plan(pattern, values) if np.all(np.isfinite(values)) else None
        try:
            self._sparse[key] = None if order is None else sparse_lu.factor(self, entries, order, what)
        except sparse_lu.ConstantZeroPivot:
            self._sparse[key] = None
        return None if self._sparse[key] is None else (self._sparse[key], False)

    def pivot_check(self, pivots, reciprocals, what: str) -> None:
        """Record the run-time check of a straight-line elimination's pivots (:class:`PivotCheck`);
        nothing when every pivot is a constant."""
        nodes = [self._node(p) for p in pivots]
        varying = [p.id for p in nodes if not p.is_const]
        if not varying:
            return
        guards = tuple(self._node(r).id for r in reciprocals if not self._node(r).is_const)
        constants = tuple(abs(float(p.value)) for p in nodes if p.is_const)
        check = PivotCheck(len(self.nodes), tuple(varying), guards, constants, what)
        self.checks.append(check)
        self.statements.append(check)
        self._statement_node("check", check)

    def _factor(self, entries, what, symmetric: bool = False) -> Factor:
        ids = tuple(v.id for row in entries for v in row)
        key = ("symmetric",) + ids if symmetric else ids
        found = self._factors.get(key)
        if found is None:
            found = Factor(len(self.nodes), len(entries), ids, what, symmetric)
            self.statements.append(found)
            self._statement_node("factor", found)
            self._factors[key] = found
        return found

    def _constant_inverse(self, entries, what) -> np.ndarray:
        from ..math.elimination import gauss_solve

        n = len(entries)
        mat = np.array([[Fraction(v.value) for v in row] for row in entries], dtype=object)
        eye = np.array([[Fraction(int(i == j)) for j in range(n)] for i in range(n)], dtype=object)
        try:
            inv = gauss_solve(mat, eye, what)
        except SingularConfigurationError:
            raise SingularConfigurationError(f"{what} (constant)", float("inf"),
                                             "the generated code would always fail") from None
        return np.vectorize(self.const, otypes=[object])(inv)


def _permutation(entries) -> list[int] | None:
    """For a constant permutation matrix ``a`` (entries 0 and 1, one 1 per row and column), the
    rows of ``b`` that make ``a^-1 b = a^T b``: ``a^T b = b[perm]``; else ``None``."""
    n = len(entries)
    perm = [None] * n
    for i, row in enumerate(entries):
        ones = [j for j, v in enumerate(row) if v.value == 1]
        if len(ones) != 1 or any(v.value != 0 for j, v in enumerate(row) if j != ones[0]):
            return None
        if perm[ones[0]] is not None:
            return None
        perm[ones[0]] = i
    return perm


def _unit_columns(rhs) -> dict[int, int]:
    """``{column: i}`` of the columns of the node matrix ``rhs`` that are the identity's column ``i``
    (the first such column of each ``i``)."""
    found: dict[int, int] = {}
    taken: set[int] = set()
    for c in range(len(rhs[0]) if rhs else 0):
        column = [row[c] for row in rhs]
        if not all(v.is_const for v in column):
            continue
        ones = [i for i, v in enumerate(column) if v.value == 1]
        if len(ones) == 1 and ones[0] not in taken and all(v.value == 0 for i, v in enumerate(column) if i != ones[0]):
            found[c] = ones[0]
            taken.add(ones[0])
    return found


def solve_flops(factors: list[Factor], solves) -> int:
    """Textbook flop count of the library calls: LU ``2n^3/3`` each (with row exchanges), ``n^3/3``
    for the factor of a symmetric positive definite matrix (one triangle's updates), ``2n^2`` per
    right-hand side; a symmetric inverse (:attr:`Solve.inverse`) by its algorithm's panels
    (:func:`inverse_flops`). The adds that combine a vector loop's partial sums are not counted
    (they depend on the build: the plain-C fallback has none)."""
    total = sum(round((1 if f.symmetric else 2) * f.n**3 / 3) for f in factors)
    return total + sum(inverse_flops(s["n"]) if s.get("inverse") else 2 * s["n"] ** 2 * s["rhs"] for s in solves)


#: columns of the symmetric inverse's panels (``SYMGEN_INVERSE_PANEL`` of the C library loop)
INVERSE_PANEL = 8


def inverse_flops(n: int) -> int:
    """Flops of the C library's symmetric inverse from the factors ``A = L (D L^T)`` (multiply-adds,
    scalings and reciprocals, as :func:`solve_flops` counts the substitutions): per panel of
    ``w`` columns starting at column ``j0`` (panels of :data:`INVERSE_PANEL`, then the last
    columns one at a time), the ``m = n - j0`` rows below ``j0`` of ``Z = L^-1`` and of
    ``D L^T X = Z`` take ``m (m - 1)`` multiply-adds per column between them, and each of the
    ``m`` rows a reciprocal of its pivot and ``w`` multiplies by it; the triangle above is
    mirrored. About ``2 n^3 / 3`` for large ``n``, where substitutions on the identity's columns
    take ``2 n^3``."""
    whole = n // INVERSE_PANEL * INVERSE_PANEL
    panels = [(j0, INVERSE_PANEL) for j0 in range(0, whole, INVERSE_PANEL)] + [(j, 1) for j in range(whole, n)]
    return sum(w * (2 * (n - j0) * (n - j0 - 1) + (n - j0)) + (n - j0) for j0, w in panels)
