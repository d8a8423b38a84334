"""Benchmark scripts that share helpers with another script still call them as they are defined:
``closed_form_products.py`` builds its timers with ``derivative_speed.compile_timers`` (a changed
signature once left it failing at its first call)."""
import pathlib
import shutil
import sys

import pytest

from .codegen_util import import_file

ROOT = pathlib.Path(__file__).resolve().parent.parent


def _benchmark(name: str):
    sys.path.insert(0, str(ROOT / "benchmarks"))
    try:                                     # its own imports are of sibling scripts
        return import_file(ROOT / "benchmarks" / f"{name}.py", name)
    finally:
        sys.path.remove(str(ROOT / "benchmarks"))


@pytest.mark.skipif(shutil.which("clang") is None, reason="closed_form_products.py compiles with clang, absent here")
@pytest.mark.parametrize("looped", [False, True], ids=["dot-products", "library-products"])
def test_closed_form_products_builds_its_timers(looped, tmp_path):
    built = _benchmark("closed_form_products").build("chain:n=4", looped, tmp_path)
    assert built["timer"].exists() and built["n"] == 4 and built["pairs"] == 10
    assert (built["flops"] > 0) == looped
