"""Every Python example of the documentation runs: each is a file under docs/examples/ that a page
includes (``literalinclude``), and each is run here in a fresh interpreter, in a scratch folder,
with its own code cache. An example that asserts something checks it (e.g. the Python scene
equals the built-in, the generated code equals the model)."""
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = sorted((ROOT / "docs" / "examples").glob("*.py"))
PAGES = sorted((ROOT / "docs").rglob("*.md"))


def test_every_example_is_included_by_a_page():
    included = set()
    for page in PAGES:
        for ref in re.findall(r"```\{literalinclude\}\s+(\S+)", page.read_text(encoding="utf-8")):
            included.add((page.parent / ref).resolve())
    assert EXAMPLES and not [e.name for e in EXAMPLES if e.resolve() not in included]
    assert not [str(p) for p in included if not p.exists()]


def test_no_page_has_an_untested_python_block():
    """Python shown in a page comes from an example file, never from a ```python block."""
    offenders = [str(p.relative_to(ROOT)) for p in PAGES if "```python" in p.read_text(encoding="utf-8")]
    assert not offenders, offenders


@pytest.mark.parametrize("example", EXAMPLES, ids=lambda p: p.name)
def test_example_runs(example, tmp_path):
    env = dict(os.environ, SYMGEN_CACHE=str(tmp_path / "cache"), MPLBACKEND="Agg",
               PYTHONPATH=os.pathsep.join([str(ROOT)] + [p for p in [os.environ.get("PYTHONPATH")] if p]))
    run = subprocess.run([sys.executable, str(example)], cwd=tmp_path, env=env, capture_output=True, text=True,
                         timeout=600)
    assert run.returncode == 0, run.stderr[-3000:]
