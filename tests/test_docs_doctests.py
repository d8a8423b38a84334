"""The ``>>>`` examples in the package's docstrings run and print what they show: every module of
symgen whose source has one is found by reading the files (so a new example is picked up) and run
by ``doctest``."""
import doctest
import importlib
from pathlib import Path

import pytest

import symgen

PACKAGE = Path(symgen.__file__).resolve().parent


def _modules_with_examples() -> list[str]:
    names = []
    for path in sorted(PACKAGE.rglob("*.py")):
        if ">>>" in path.read_text(encoding="utf-8"):
            parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
            names.append(".".join(parts[:-1] if parts[-1] == "__init__" else parts))
    return names


MODULES = _modules_with_examples()


def test_the_package_has_examples():
    assert "symgen" in MODULES and len(MODULES) >= 10


@pytest.mark.parametrize("module", MODULES)
def test_docstring_examples_pass(module):
    result = doctest.testmod(importlib.import_module(module), optionflags=doctest.ELLIPSIS)
    assert result.attempted > 0 and result.failed == 0, f"{module}: {result}"
