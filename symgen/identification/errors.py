"""Typed errors of identification, each naming the offending column, row or count."""
from __future__ import annotations

from ..errors import SymgenError


class IdentificationError(SymgenError):
    """Base class of the errors :mod:`symgen.identification` raises on purpose."""


class DataColumnError(IdentificationError):
    """A data table lacks a column the scene needs, has one it cannot use, or has the wrong shape."""

    def __init__(self, column: str, message: str):
        self.column = column
        super().__init__(f"column {column!r}: {message}")


class NonFiniteSampleError(IdentificationError):
    """A sample holds NaN or an infinity (row counted from 1, the header excluded)."""

    def __init__(self, row: int, column: str, value: float):
        self.row, self.column = row, column
        super().__init__(f"row {row}, column {column!r}: non-finite value {value!r}")


class TooFewSamplesError(IdentificationError):
    """The stacked regressor has fewer rows than the base parameters it must determine, or its rank
    on the data is below the base-parameter count (the motion does not excite them)."""

    def __init__(self, what: str, have: int, need: int, hint: str = ""):
        self.have, self.need = have, need
        super().__init__(f"{what}: {have} < {need} needed" + (f"; {hint}" if hint else ""))


class ConsistencyError(IdentificationError):
    """The physically consistent fit (semidefinite program) could not be solved or is not available."""


class DataFileError(IdentificationError):
    """A data file cannot be read as a CSV table: missing, not UTF-8 text, a malformed line, too
    many rows. ``path`` is the file as given."""

    def __init__(self, path, message: str):
        self.path = str(path)
        super().__init__(f"data file {self.path!r}: {message}")


class SampleRangeError(IdentificationError):
    """A sample's magnitude is beyond what the regressor's products keep inside double precision
    (row counted from 1, the header excluded)."""

    def __init__(self, row: int, column: str, value: float, limit: float):
        self.row, self.column, self.value = row, column, value
        super().__init__(f"row {row}, column {column!r}: magnitude {abs(value):.3g} is beyond {limit:g}; "
                         "give positions in rad or m and forces in N or N m")


class OptionError(IdentificationError):
    """An option of identification (a count, a frequency, a time budget) outside its range; the
    message names the option as the command line spells it."""

    def __init__(self, option: str, message: str):
        self.option = option
        super().__init__(f"{option}: {message}")
