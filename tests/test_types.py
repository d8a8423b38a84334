"""The typed core passes a strict type check (mypy, configured in pyproject.toml)."""
from __future__ import annotations

import pathlib
import subprocess
import sys
import tomllib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]


def test_the_typed_core_passes_mypy_strict():
    pytest.importorskip("mypy", reason="mypy comes with the test extra: pip install '.[test]'")
    run = subprocess.run([sys.executable, "-m", "mypy", "--config-file", str(ROOT / "pyproject.toml"),
                          "--cache-dir", str(ROOT / ".mypy_cache")], cwd=ROOT, capture_output=True, text=True,
                         timeout=600)
    assert run.returncode == 0, run.stdout[-4000:] + run.stderr[-2000:]


def test_the_strict_check_covers_math_steps_and_dynamics():
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["mypy"]
    assert config["strict"] is True
    assert {"symgen/math", "symgen/steps", "symgen/dynamics"} <= set(config["files"])


def test_the_package_ships_its_type_marker():
    assert (ROOT / "symgen" / "py.typed").is_file()
