"""Shared by the URDF and Pinocchio tests: the test files' folder and the examples' skip mark."""
import importlib.metadata
from pathlib import Path

import pytest

DATA = Path(__file__).parent / "data" / "urdf"


def _has_examples() -> bool:
    try:
        importlib.metadata.distribution("example-robot-data")
        return True
    except importlib.metadata.PackageNotFoundError:
        return False


needs_examples = pytest.mark.skipif(not _has_examples(), reason="example-robot-data is not installed "
                                                                "(extra 'examples')")
