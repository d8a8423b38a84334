"""Sphinx configuration of symgen's documentation (``sphinx-build -W docs OUT``; a test builds it)."""
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))          # document the package of this checkout, not another install

project = "symgen"
author = "symgen developers"
copyright = "symgen developers"

extensions = [
    "myst_parser",              # the pages are Markdown (MyST), like the benchmark tables they include
    "sphinx.ext.autodoc",       # the API reference, from the docstrings
    "sphinx.ext.napoleon",      # NumPy / Google docstring sections
    "sphinxarg.ext",            # the command-line reference, from symgen.cli.build_parser()
]
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
exclude_patterns = ["_build", "examples", "generated"]   # generated/: parts included by pages
myst_heading_anchors = 3
myst_enable_extensions = ["colon_fence"]

autodoc_member_order = "bysource"
autodoc_default_options = {"members": True, "show-inheritance": False}
napoleon_google_docstring = True
napoleon_numpy_docstring = True

html_theme = "furo"
html_title = "symgen"
