"""The generated modules at run time: argument checking, singular solves reported with their
condition estimate, the standalone C test program, and ``symgen generate`` writing atomically."""
from __future__ import annotations

import json
import shutil
import subprocess

import numpy as np
import pytest

from symgen.cli import main
from symgen.codegen.catalogue import FUNCTIONS

from .codegen_util import build


@pytest.fixture(scope="module")
def four_bar(tmp_path_factory):
    return build("four_bar", tmp_path_factory.mktemp("four_bar"))


@pytest.fixture(scope="module")
def chain(tmp_path_factory):
    return build("chain:n=3", tmp_path_factory.mktemp("chain3"), ["inverse_dynamics", "mass_matrix"])


@pytest.mark.parametrize("target", [1, 2])
def test_wrong_shape_is_a_clear_error(chain, target):
    module = chain[target]
    with pytest.raises(ValueError, match=r"qd must have shape \(\.\.\., 3\), got \(4,\)"):
        module.inverse_dynamics(np.zeros(3), np.zeros(4), np.zeros(3))
    with pytest.raises(ValueError, match="batch shape"):
        module.inverse_dynamics(np.zeros((2, 3)), np.zeros((3, 3)), np.zeros((2, 3)))


@pytest.mark.parametrize("target", [1, 2])
def test_wrong_dtype_and_non_finite_are_clear_errors(chain, target):
    module = chain[target]
    with pytest.raises(TypeError, match="q must hold real numbers"):
        module.inverse_dynamics(np.array(["a", "b", "c"]), np.zeros(3), np.zeros(3))
    with pytest.raises(TypeError, match="complex"):
        module.inverse_dynamics(np.zeros(3, complex), np.zeros(3), np.zeros(3))
    with pytest.raises(ValueError, match="qdd contains NaN"):
        module.inverse_dynamics(np.zeros(3), np.zeros(3), np.array([0.0, np.nan, 0.0]))


@pytest.mark.parametrize("target", [1, 2])
def test_singular_solve_raises_with_condition(four_bar, target):
    """All four-bar angles 0: the links are collinear and [T_u1, T_a1] is singular."""
    module = four_bar[target]
    with pytest.raises(module.SingularSolveError) as info:
        module.inverse_dynamics(np.zeros(4), [1.0], [0.0])
    assert info.value.condition > 1e12
    # one bad state in a batch is reported too, never returned as NaN
    good = np.array([0.3, 2.0, 0.5, 1.0])
    with pytest.raises(module.SingularSolveError):
        module.inverse_dynamics(np.stack([good, np.zeros(4)]), np.ones((2, 1)), np.zeros((2, 1)))


def test_ctypes_binding_caches_the_library_by_content(chain):
    c = chain[2]
    first = c.library_path()
    assert first.exists() and c.library_path() == first
    assert first.name.startswith("chain_n3-")


@pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler on this machine")
def test_standalone_c_test_program_passes(four_bar, tmp_path):
    gen = four_bar[3]["c"]
    for name, text in gen.files.items():
        (tmp_path / name).write_text(text)
    exe = tmp_path / "check"
    subprocess.run(["cc", "-std=c99", "-O2", "-Wall", "-Wextra", "-pedantic", "-Werror", "-o", str(exe),
                    str(tmp_path / "test_four_bar.c"), str(tmp_path / "four_bar.c"), "-lm"], check=True)
    run = subprocess.run([str(exe)], capture_output=True, text=True)
    assert run.returncode == 0, run.stdout
    assert run.stdout.count("status 0") == len(FUNCTIONS) and run.stdout.strip().endswith("ok")


def test_generate_cli_writes_and_replaces_its_own_directory(tmp_path, capsys):
    out = tmp_path / "gen"
    assert main(["generate", "chain:n=2", "--target", "numpy", "--out", str(out),
                 "--functions", "inverse_dynamics"]) == 0
    ops = json.loads((out / "ops.json").read_text())
    assert list(ops["functions"]) == ["inverse_dynamics"]
    assert main(["generate", "chain:n=2", "--target", "c", "--out", str(out)]) == 0
    assert (out / "chain_n2.c").exists() and not (out / "chain_n2.py").exists()


def test_generate_cli_refuses_a_foreign_directory(tmp_path, capsys):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("keep me")
    assert main(["generate", "chain:n=2", "--target", "numpy", "--out", str(out)]) == 2
    assert "not created by symgen" in capsys.readouterr().err
    assert (out / "notes.txt").read_text() == "keep me"
    assert main(["generate", "chain:n=2", "--target", "numpy", "--out", str(out), "--force"]) == 0
    assert not (out / "notes.txt").exists()


def test_failed_generation_leaves_nothing_behind(tmp_path, capsys):
    out = tmp_path / "never"
    assert main(["generate", "chain:n=2", "--target", "numpy", "--out", str(out),
                 "--functions", "inverse_dynamics,no_such_function"]) == 2
    assert "no_such_function" in capsys.readouterr().err
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_ops_json_matches_ops_command(tmp_path, capsys):
    out = tmp_path / "g"
    main(["generate", "five_bar", "--target", "c", "--out", str(out)])
    capsys.readouterr()
    assert main(["ops", "five_bar", "--json"]) == 0
    printed = json.loads(capsys.readouterr().out)
    assert printed["functions"] == json.loads((out / "ops.json").read_text())["functions"]


def test_ops_fit_prints_the_linear_fit(capsys):
    assert main(["ops", "--fit", "multi_arm", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["fit"]["r2"] > 0.999 and sorted(map(int, data["counts"])) == list(range(1, 9))


def test_unsupported_scene_features_are_typed_errors():
    """The generator names what it cannot emit instead of emitting something wrong."""
    import yaml

    from symgen.io.builtin import get_scene
    from symgen.codegen import generate
    from symgen.errors import CodegenError
    from symgen.model import derive
    from symgen.io.scene_yaml import dump_scene, scene_from_dict

    data = yaml.safe_load(dump_scene(get_scene("stewart")))
    data["joints"]["s1"]["friction"] = {"viscous": 0, "coulomb": 0.5}
    with pytest.raises(CodegenError, match="joint 's1': Coulomb friction on a spherical joint"):
        generate(derive(scene_from_dict(data)), "numpy", ["inverse_dynamics"])
    with pytest.raises(CodegenError, match="unknown target 'fortran'"):
        generate(derive(get_scene("chain:n=1")), "fortran")


def test_output_path_that_is_a_file_is_refused(tmp_path, capsys):
    target = tmp_path / "file.txt"
    target.write_text("x")
    assert main(["generate", "chain:n=1", "--target", "numpy", "--out", str(target)]) == 2
    assert "not a directory" in capsys.readouterr().err and target.read_text() == "x"


def test_ops_needs_a_scene_or_a_family(capsys):
    assert main(["ops"]) == 2
    assert "give a SCENE" in capsys.readouterr().err


@pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler on this machine")
def test_a_loaded_module_leaves_out_the_c_self_test(tmp_path, monkeypatch):
    """``load_generated`` writes and compiles the generated C without ``test_<scene>.c`` (whose
    50-digit expected values only ``symgen generate``'s output needs); everything else is the file
    ``generate`` writes, byte for byte, and the loaded module computes."""
    from symgen.codegen.generate import generate
    from symgen.codegen.runtime import load_generated
    from symgen.io.builtin import get_scene
    from symgen.model import derive

    monkeypatch.setenv("SYMGEN_CACHE", str(tmp_path))
    model = derive(get_scene("chain:n=2"))
    module = load_generated(model, "c", ["inverse_dynamics"])
    (folder,) = (tmp_path / "modules").iterdir()
    written = {f.name for f in folder.iterdir() if f.is_file()}
    full = generate(model, "c", ["inverse_dynamics"]).files
    assert "test_chain_n2.c" in full and "test_chain_n2.c" not in written
    assert {"chain_n2.c", "chain_n2.h", "ops.json"} <= written
    for name in written & set(full):
        assert (folder / name).read_text() == full[name], name
    tau = module.inverse_dynamics(np.zeros(2), np.zeros(2), np.zeros(2))
    assert np.all(np.isfinite(tau))
