"""Accuracy of the generated functions against an extended-precision reference.

* :mod:`.reference` -- the dense model (32) evaluated in :class:`~symgen.math.fields.MpField`
  (mpmath, 50 digits by default) at the generated functions' own float inputs:
  :func:`~symgen.accuracy.reference.mp_outputs`.
* :mod:`.backends` -- calling and timing the generated NumPy and C modules and the dense float
  model; :mod:`.lambdify` -- ``sympy.lambdify`` of the dense symbolic model, in a subprocess.
* :mod:`.table` -- the table of ``symgen accuracy SCENE`` (:mod:`.cli`).
* :mod:`.dead_points` -- closed families of the built-in loops running into a singular
  configuration, exact to 50 digits, and one point of the sweep of ``benchmarks/dead_point.py``.

Heavy imports stay inside these modules, so importing the package (as ``symgen --help`` does)
is cheap.
"""
from ..errors import SymgenError


class AccuracyError(SymgenError):
    """A bad request to the accuracy report: unknown function, no states, too few digits."""
