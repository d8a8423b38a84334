"""Code generation: trace the recursive algorithms into an expression graph, optimise
it (folding, CSE, dead code), and render NumPy or C through the Jinja templates in ``templates/``.

>>> from symgen.io.builtin import get_scene
>>> from symgen.model import derive
>>> from symgen.codegen import operation_counts
>>> ops = operation_counts(derive(get_scene("chain:n=2")), ["inverse_dynamics"])
>>> ops["inverse_dynamics"]["total"] > 0
True
"""
from .catalogue import FUNCTIONS
from .generate import Generated, generate, operation_counts

__all__ = ["FUNCTIONS", "Generated", "generate", "operation_counts"]
