"""The typed core passes a strict type check (mypy, configured in pyproject.toml)."""
from __future__ import annotations

import os
import pathlib
import subprocess
import sys
import textwrap
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


#: every protocol the typed core declares for a type of a higher layer (or of a module that imports
#: it), with that type; the last line is a control that must be refused
CONFORMANCE = textwrap.dedent("""
    import numpy as np
    from symgen.closure import ClosureModel
    from symgen.math.configuration import JointDeclarations
    from symgen.math.fields import JointTree
    from symgen.math.spatial import EntryIndexed
    from symgen.model import Model, ModelData
    from symgen.model_solves import Evaluation
    from symgen.motion import MotionModel
    from symgen.scene.declaration import Scene
    from symgen.steps.pipeline import DerivedModel
    from symgen.tree import Tree


    def conforms(scene: Scene, tree: Tree, array: np.ndarray, model: Model, data: ModelData) -> None:
        a: JointDeclarations = scene
        b: JointTree = tree
        c: EntryIndexed = array
        d: DerivedModel = model
        e: ClosureModel = model
        f: MotionModel = model
        g: Evaluation = data
        control: Evaluation = model
""")


def test_the_real_types_satisfy_the_protocols_that_stand_for_them(tmp_path):
    """Model, ModelData, Scene and Tree are named in the typed core by protocols (an import of
    them would go up a layer or close a cycle); each must satisfy its protocol."""
    pytest.importorskip("mypy", reason="mypy comes with the test extra: pip install '.[test]'")
    (tmp_path / "conformance.py").write_text(CONFORMANCE, encoding="utf-8")
    run = subprocess.run([sys.executable, "-m", "mypy", "--follow-imports=silent", "--ignore-missing-imports",
                          "--cache-dir", str(tmp_path / "cache"), "conformance.py"], cwd=tmp_path,
                         env={**os.environ, "MYPYPATH": str(ROOT)}, capture_output=True, text=True, timeout=600)
    errors = [line for line in run.stdout.splitlines() if ": error:" in line]
    assert len(errors) == 1 and '"Model", variable has type "Evaluation"' in errors[0], run.stdout + run.stderr


def test_the_package_ships_its_type_marker():
    assert (ROOT / "symgen" / "py.typed").is_file()
