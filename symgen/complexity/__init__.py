"""Complexity tables: this formulation's op counts, derivation time and memory against DOF,
next to SymPy's ``physics.mechanics`` (Kane, Lagrange) and the published classical formulas.

Modules: :mod:`.published` (the formulas and their sources), :mod:`.mechanics` (the benchmark
chain in ``sympy.physics.mechanics``), :mod:`.sympy_ops` (op counts of SymPy expressions in
symgen's convention), :mod:`.tasks` / :mod:`.measure` (one measurement in a time-limited
subprocess), :mod:`.sweep` (all methods over all sizes), :mod:`.fits`, :mod:`.tables`,
:mod:`.report`, :mod:`.plots` (outputs) and :mod:`.cli` (``symgen complexity``).
"""
