"""The documentation builds with Sphinx, warnings as errors (broken references, bad docstrings,
headings out of order, a missing include), and every benchmark table has its page."""
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"


def test_every_benchmark_table_has_a_page_that_includes_it():
    for table in sorted((ROOT / "benchmarks").rglob("*.md")):
        rel = table.relative_to(ROOT / "benchmarks")
        page = DOCS / "benchmarks" / rel
        assert page.exists(), f"no docs page for benchmarks/{rel}"
        (target,) = re.findall(r"```\{include\}\s+(\S+)", page.read_text(encoding="utf-8"))
        assert (page.parent / target).resolve() == table.resolve(), page


@pytest.mark.slow
def test_sphinx_builds_without_warnings(tmp_path):
    pytest.importorskip("sphinx", reason="sphinx is not installed (test extra)")
    run = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html",
                          "-d", str(tmp_path / "doctrees"), str(DOCS), str(tmp_path / "html")],
                         capture_output=True, text=True, timeout=600, cwd=ROOT)
    assert run.returncode == 0, (run.stdout + run.stderr)[-5000:]
    html = tmp_path / "html"
    api, cli = (html / "reference" / "api.html").read_text(), (html / "reference" / "cli.html").read_text()
    assert 'id="symgen.derive"' in api and 'id="symgen.Model.forward_dynamics"' in api    # autodoc ran
    assert "--uncertain" in cli and "identify" in cli                                     # the parser's options
    assert "stiff_friction" in (html / "benchmarks" / "stability" / "stability.html").read_text()


def test_the_generated_function_table_is_the_catalogue():
    """docs/generated/functions.md is the catalogue's own table (regenerate it with
    ``python -c "from symgen.codegen.catalogue import markdown_table; print(markdown_table(), end='')"
    > docs/generated/functions.md``), and the code-generation guide includes it."""
    from symgen.codegen.catalogue import CATALOGUE, markdown_table

    text = (ROOT / "docs" / "generated" / "functions.md").read_text(encoding="utf-8")
    assert text == markdown_table()
    assert all(f"`{name}`" in text for name in CATALOGUE)
    assert "{include} ../generated/functions.md" in (ROOT / "docs" / "guide" / "codegen.md").read_text(encoding="utf-8")
