"""``generated/`` is exactly what the current generator emits (byte-identical, deterministic)."""
from __future__ import annotations

import difflib
import pathlib

import pytest

from symgen.codegen.golden import golden_files
from symgen.io.writer import MARKER, write_tree

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


#: the built-ins whose generated files print states solved by a loop-closure (or contact) solve
SOLVED_STATE_SCENES = ["four_bar", "five_bar", "arm_on_plane", "multi_arm:h=2", "stewart"]


def _committed(fresh_names) -> dict[str, str]:
    return {name: (GENERATED / name).read_text() for name in fresh_names}


def _noisy(function, scale: float):
    """``function`` with its float results multiplied by ``1 + scale * (+-1)`` (a fixed sign
    pattern): another float library's last digits, made large enough to matter."""
    import numpy as np

    def call(*args, **kwargs):
        out = function(*args, **kwargs)
        arr = np.asarray(out)
        if arr.dtype.kind != "f" or arr.size == 0:
            return out
        signs = np.where(np.arange(arr.size).reshape(arr.shape) % 2 == 0, 1.0, -1.0)
        return arr * (1.0 + scale * signs)
    return call


@pytest.mark.slow
def test_generated_files_do_not_depend_on_float_rounding(monkeypatch):
    """Every float solve and transcendental of the generator perturbed in its last digits
    (relative 1e-13: a different BLAS, LAPACK or libm, exaggerated) still regenerates the
    committed files byte for byte: no printed number comes from those digits."""
    import numpy as np

    from symgen.codegen import graph

    monkeypatch.setattr(np.linalg, "solve", _noisy(np.linalg.solve, 1e-13))
    monkeypatch.setattr(np.linalg, "lstsq", _noisy(np.linalg.lstsq, 1e-13))
    for name in ("sin", "cos", "sqrt"):
        monkeypatch.setitem(graph._EVALUATE, name, _noisy(graph._EVALUATE[name], 1e-13))
    perturbed = golden_files(["four_bar", "arm_on_plane", "multi_arm:h=2"])   # Stewart: in the BLAS-kernel test
    committed = _committed(k for k in perturbed)
    changed = [k for k in perturbed if perturbed[k] != committed[k]]
    assert not changed, f"files that depend on float rounding: {changed}"


@pytest.mark.slow
def test_generated_files_match_under_another_blas_kernel(tmp_path):
    """A fresh interpreter with another OpenBLAS kernel (``OPENBLAS_CORETYPE=Prescott``, one
    thread: different summation orders in every BLAS and LAPACK call) writes the same bytes."""
    import os
    import subprocess
    import sys

    script = ("import pathlib, sys\n"
              "from symgen.codegen.golden import golden_files\n"
              f"files = golden_files({SOLVED_STATE_SCENES!r})\n"
              f"root = pathlib.Path({str(GENERATED)!r})\n"
              "bad = [k for k, v in files.items() if (root / k).read_text() != v]\n"
              "print('\\n'.join(bad))\n"
              "sys.exit(1 if bad else 0)\n")
    root = str(GENERATED.parent)
    path = os.pathsep.join([root] + ([os.environ["PYTHONPATH"]] if os.environ.get("PYTHONPATH") else []))
    env = dict(os.environ, PYTHONPATH=path, OPENBLAS_CORETYPE="Prescott", OPENBLAS_NUM_THREADS="1",
               OMP_NUM_THREADS="1")
    run = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True, timeout=600,
                         cwd=tmp_path)
    assert run.returncode == 0, f"files that differ under another BLAS kernel:\n{run.stdout}{run.stderr[-2000:]}"
