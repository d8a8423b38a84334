"""``generated/`` is exactly what the current generator emits (byte-identical, deterministic)."""
from __future__ import annotations

import difflib
import pathlib

import pytest

from symgen.codegen.golden import golden_files
from symgen.codegen.writer import MARKER, write_tree

GENERATED = pathlib.Path(__file__).resolve().parents[1] / "generated"


@pytest.fixture(scope="module")
def fresh():
    return golden_files()


def test_generated_folder_matches_generator(fresh, request):
    if request.config.getoption("--update-golden"):
        write_tree(GENERATED, fresh, force=True)
    on_disk = {str(p.relative_to(GENERATED)): p.read_text() for p in sorted(GENERATED.rglob("*"))
               if p.is_file() and p.name != MARKER}
    assert sorted(on_disk) == sorted(fresh), "files differ; run pytest --update-golden"
    for name, text in fresh.items():
        if on_disk[name] != text:
            diff = "".join(difflib.unified_diff(on_disk[name].splitlines(True), text.splitlines(True),
                                                f"generated/{name}", "regenerated", n=1))
            pytest.fail(f"generated/{name} is stale (pytest --update-golden rewrites it):\n{diff[:4000]}")


def test_generation_is_deterministic(fresh):
    """A second run in the same process gives the same bytes (no ids, timestamps or set order)."""
    again = golden_files(["four_bar", "arm_on_plane"])
    for name, text in again.items():
        assert fresh[name] == text, name
