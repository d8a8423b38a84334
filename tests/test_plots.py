"""The SVG figures of the documentation (``docs/figures/``) are what ``benchmarks/plots.py`` draws
from the benchmark tables now, byte for byte: regenerated here and compared, so a rerun benchmark
without redrawn figures fails, and so does a writer that is not deterministic."""
from __future__ import annotations

import importlib.util
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]


def _plots():
    spec = importlib.util.spec_from_file_location("symgen_benchmark_plots", ROOT / "benchmarks" / "plots.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("name", ["dead_point", "forward_ops"])
def test_committed_figure_equals_a_fresh_drawing(tmp_path, name):
    pytest.importorskip("matplotlib")
    plots = _plots()
    (tmp_path / "again").mkdir()
    first = getattr(plots, name)(tmp_path)
    again = getattr(plots, name)(tmp_path / "again")
    assert first.read_bytes() == again.read_bytes(), "the SVG writer is not deterministic"
    committed = ROOT / "docs" / "figures" / f"{name}.svg"
    assert committed.read_bytes() == first.read_bytes(), f"redraw with `python benchmarks/plots.py` ({committed})"


def test_figures_are_shown_by_the_guide():
    text = "".join(p.read_text(encoding="utf-8") for p in (ROOT / "docs" / "guide").glob("*.md"))
    for name in ("dead_point", "forward_ops"):
        assert f"../figures/{name}.svg" in text
