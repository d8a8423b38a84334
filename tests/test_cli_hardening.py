"""``symgen.cli.main`` never shows a traceback for a user error: a bad option value is refused by the
parser naming the option (status 2), a bad file or scene is one line (status 2), and every option
bounds the work. Also the small items: module names Python would load on its own, output folder
permissions, the magnitude message, a byte-order mark."""
from __future__ import annotations

import os
import stat

import pytest
import sympy as sp

import symgen
from symgen.cli import commands as cli
from symgen.cli import main
from symgen.codegen.generate import check_names, module_name
from symgen.io.writer import write_tree
from symgen.errors import SceneError
from symgen.identification.data import simulated_samples, write_csv
from symgen.identification.regressor import make_problem
from symgen.identification.states import random_states
from symgen.scene.input_limits import magnitude_problem
from symgen.io.scene_yaml import dump_scene


def _refused(capsys, argv, option, text):
    """The parser exits with status 2 naming ``option`` and saying ``text``."""
    with pytest.raises(SystemExit) as info:
        main(argv)
    err = capsys.readouterr().err
    assert info.value.code == 2 and f"argument {option}: " in err and text in err, err
    assert "Traceback" not in err


def _fails(capsys, argv, text, status=2):
    """The command runs, fails with ``status`` and one line holding ``text``."""
    assert main(argv) == status
    err = capsys.readouterr().err
    assert err.startswith("symgen: error: ") and text in err and err.count("\n") == 1, err


@pytest.fixture(scope="module")
def chain_csv(tmp_path_factory):
    model = symgen.derive(symgen.load("chain:n=2"))
    path = tmp_path_factory.mktemp("data") / "chain.csv"
    write_csv(path, simulated_samples(make_problem(model), random_states(model, 20, seed=1), noise=1e-3))
    return path


# ------------------------------------------------------------------ excite and params
@pytest.mark.parametrize("argv, option, text", [
    (["excite", "chain:n=2", "--budget", "0"], "--budget", "0 is out of range: give a finite number > 0"),
    (["excite", "chain:n=2", "--budget", "inf"], "--budget", "'inf' is not a finite number"),
    (["excite", "chain:n=2", "--max-evals", "0"], "--max-evals", "0 is out of range: give an integer >= 1"),
    (["excite", "chain:n=2", "--frequency", "0"], "--frequency", "0 is out of range: give a finite number > 0"),
    (["excite", "chain:n=2", "--harmonics", "0"], "--harmonics", "0 is out of range"),
    (["excite", "chain:n=2", "--samples", "1e3"], "--samples", "'1e3' is not an integer"),
    (["excite", "chain:n=2", "--seed", "-1"], "--seed", "-1 is out of range: give an integer >= 0"),
    (["excite", "chain:n=2", "--data", "x.csv", "--noise", "nan"], "--noise", "'nan' is not a finite number"),
    (["excite", "chain:n=2", "--data", "x.csv", "--noise", "-1"], "--noise", "-1 is out of range"),
    (["excite", "chain:n=2", "--data", "x.csv", "--data-samples", "0"], "--data-samples", "0 is out of range"),
    (["excite", "chain:n=2", "--data", "x.csv", "--data-samples", "1000000"], "--data-samples", "<= 100000"),
    (["params", "chain:n=2", "--states", "0"], "--states", "0 is out of range: give an integer >= 1 and <= 2000"),
])
def test_excite_and_params_options_out_of_range_are_refused_by_name(capsys, argv, option, text):
    _refused(capsys, argv, option, text)


def test_noise_without_data_is_refused(capsys):
    _fails(capsys, ["excite", "chain:n=2", "--noise", "0.1"], "--noise: has no effect without --data CSV")


def test_closed_chain_data_samples_are_capped_before_optimising(capsys, tmp_path):
    _fails(capsys, ["excite", "four_bar", "--data", str(tmp_path / "d.csv"), "--data-samples", "5000"],
           "--data-samples: 5000 is more than the 1000 allowed on scene 'four_bar'")


def test_a_data_path_in_a_missing_folder_is_refused_before_optimising(capsys, tmp_path):
    _fails(capsys, ["excite", "chain:n=2", "--data", str(tmp_path / "no" / "d.csv")], "--data: the folder of")


def test_excite_writes_data_that_identify_reads(capsys, tmp_path):
    path = tmp_path / "d.csv"
    assert main(["excite", "chain:n=2", "--max-evals", "1", "--samples", "10", "--data", str(path),
                 "--data-samples", "60", "--noise", "0.001"]) == 0
    assert "wrote 60 samples (noise 0.001 on tau)" in capsys.readouterr().out
    assert main(["identify", "chain:n=2", str(path), "--states", "20"]) == 0
    assert "60 samples, 120 rows" in capsys.readouterr().out


# ------------------------------------------------------------------ identify
def test_a_missing_data_file_is_one_line(capsys, tmp_path):
    _fails(capsys, ["identify", "chain:n=2", str(tmp_path / "missing.csv")], "missing.csv': cannot be read")


def test_a_header_only_data_file_is_one_line(capsys, tmp_path, chain_csv):
    path = tmp_path / "header.csv"
    path.write_text(chain_csv.read_text().splitlines()[0] + "\n")
    _fails(capsys, ["identify", "chain:n=2", str(path)], "data rows: 0 < 1 needed")


def test_non_utf8_data_is_one_line(capsys, tmp_path, chain_csv):
    path = tmp_path / "latin.csv"
    path.write_bytes(b"\xff" + chain_csv.read_bytes())
    _fails(capsys, ["identify", "chain:n=2", str(path)], "is not UTF-8 text (byte 0xff)")


def test_a_utf8_byte_order_mark_reads_as_the_same_data(capsys, tmp_path, chain_csv):
    path = tmp_path / "bom.csv"
    path.write_bytes(b"\xef\xbb\xbf" + chain_csv.read_bytes())
    assert main(["identify", "chain:n=2", str(path), "--states", "20"]) == 0
    with_bom = capsys.readouterr().out
    assert main(["identify", "chain:n=2", str(chain_csv), "--states", "20"]) == 0
    assert capsys.readouterr().out == with_bom


def test_another_robots_data_is_refused(capsys, chain_csv):
    _fails(capsys, ["identify", "four_bar", str(chain_csv)], "column 'q_j0': names no joint, coordinate or force "
                                                            "of scene 'four_bar'")


@pytest.mark.parametrize("weights, text", [("inf,1", "standard deviation inf is out of range"),
                                           ("0,1", "standard deviation 0 is out of range"),
                                           ("a,1", "'a' is not a number")])
def test_weights_out_of_range_are_refused_by_the_parser(capsys, chain_csv, weights, text):
    _refused(capsys, ["identify", "chain:n=2", str(chain_csv), "--weights", weights], "--weights", text)


def test_a_weight_count_that_is_not_the_channel_count_is_one_line(capsys, chain_csv):
    _fails(capsys, ["identify", "chain:n=2", str(chain_csv), "--states", "20", "--weights", "1"],
           "--weights: [1.0]: need 'residual', 'none' or 2 finite standard deviations")


def test_an_output_scene_in_a_missing_folder_is_refused_before_reading(capsys, tmp_path):
    _fails(capsys, ["identify", "chain:n=2", "unread.csv", "--consistent", "--out", str(tmp_path / "no" / "s.yaml")],
           "--out: the folder of")


# ------------------------------------------------------------------ control
@pytest.mark.parametrize("value, text", [("0", "0 is out of range: give a finite number > 0 and <= 60.0"),
                                         ("-1", "-1 is out of range"), ("inf", "'inf' is not a finite number"),
                                         ("1e9", "1e9 is out of range")])
def test_control_end_time_out_of_range_is_refused(capsys, value, text):
    _refused(capsys, ["control", "chain:n=2", "--t-end", value], "--t-end", text)


def test_a_symbolic_regressor_of_a_closed_chain_is_refused_at_once(capsys):
    _fails(capsys, ["control", "four_bar", "--regressor", "--field", "symbolic"],
           "scene 'four_bar' has loop closures or constraints: its symbolic regressor would take minutes; use "
           "--field float")


def test_a_symbolic_regressor_too_large_to_simplify_is_refused(capsys):
    _fails(capsys, ["control", "chain:n=4", "--regressor", "--field", "symbolic"],
           "operations before simplification (limit 2500")


@pytest.mark.parametrize("argv, text", [(["--field", "symbolic"], "--field applies to --regressor only"),
                                        (["--regressor", "--t-end", "1"], "--t-end applies to the closed-loop run"),
                                        (["--force"], "--force applies to --report DIR only")])
def test_control_options_that_do_not_apply_are_refused(capsys, argv, text):
    _fails(capsys, ["control", "chain:n=2", *argv], text)


# ------------------------------------------------------------------ main itself
def test_a_file_error_in_any_command_is_one_line(capsys, monkeypatch):
    def broken(args):
        raise PermissionError(13, "Permission denied", "locked.yaml")

    monkeypatch.setattr(cli, "cmd_export", broken)
    _fails(capsys, ["export", "chain:n=1"], "cannot use the file 'locked.yaml': Permission denied")


def test_a_closed_pipe_ends_quietly(capsys, monkeypatch):
    def closed(args):
        raise BrokenPipeError(32, "Broken pipe")

    monkeypatch.setattr(cli, "cmd_export", closed)
    assert main(["export", "chain:n=1"]) == 1
    assert capsys.readouterr().err == ""


# ------------------------------------------------------------------ small items
@pytest.mark.parametrize("name", ["__main__", "__init__", "__x__"])
def test_a_dunder_scene_name_is_refused_with_another_suggested(name):
    scene = symgen.load("chain:n=1")
    scene.name = name
    with pytest.raises(SceneError, match=rf"scene '{name}': .* rename the scene, e.g. '{name.strip('_')}'"):
        check_names(symgen.derive(scene))


def test_generate_refuses_a_dunder_scene_in_one_line(capsys, tmp_path):
    path = tmp_path / "main.yaml"
    path.write_text(dump_scene(symgen.load("chain:n=1")).replace("name: chain_n1", "name: __main__", 1))
    _fails(capsys, ["generate", str(path), "--target", "numpy", "--out", str(tmp_path / "out")],
           "scene '__main__': the scene name becomes the generated module's name")
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("name", ["sitecustomize", "usercustomize", "conftest", "Conftest", "__init__"])
def test_names_python_or_pytest_load_on_their_own_get_another_module_name(name):
    assert module_name(name) == name + "_model"


@pytest.mark.parametrize("mask", [0o022, 0o077, 0o002])
def test_output_folders_follow_the_umask(tmp_path, mask):
    old = os.umask(mask)
    try:
        out = write_tree(tmp_path / "out", {"a.txt": "x", "sub/b.txt": "y"})
    finally:
        os.umask(old)
    assert stat.S_IMODE(out.stat().st_mode) == 0o777 & ~mask
    assert stat.S_IMODE((out / "sub").stat().st_mode) == 0o777 & ~mask


@pytest.mark.parametrize("value, text", [(10 ** 400, "~1e+400"), (10 ** 31, "1e+31"),
                                         (sp.Rational(1, 10 ** 400), "~1e-400"),
                                         (sp.Float("3e500"), "~1e+500")])
def test_the_magnitude_message_names_the_actual_magnitude(value, text):
    assert magnitude_problem(value).startswith(f"magnitude {text} is outside the range 1e-30 .. 1e30")


# ---------------------------------------------------------------- generate --gain
def test_a_generated_controller_needs_its_gain(capsys, tmp_path):
    _fails(capsys, ["generate", "chain:n=2", "--target", "numpy", "--out", str(tmp_path / "a"),
                    "--functions", "control"], "--gain K")
    assert not (tmp_path / "a").exists()


@pytest.mark.parametrize("value", ["0", "-1", "nan", "soft"])
def test_a_bad_gain_is_refused(capsys, tmp_path, value):
    with pytest.raises(SystemExit) as info:
        main(["generate", "chain:n=2", "--target", "numpy", "--out", str(tmp_path / "a"), "--functions", "control",
              "--gain", value])
    assert info.value.code == 2 and "argument --gain" in capsys.readouterr().err


def test_the_gain_reaches_the_generated_controller(tmp_path):
    import json

    for gain in ("1", "4", "input"):
        out = tmp_path / gain
        assert main(["generate", "chain:n=2", "--target", "numpy", "--out", str(out), "--functions", "control",
                     "--gain", gain]) == 0
        meta = json.loads((out / "ops.json").read_text())["functions"]["control"]
        assert meta["K_A"] == ("input" if gain == "input" else "folded at generation time")
        source = (out / "chain_n2.py").read_text()
        assert ("K_A" in source.split("def control(")[1].split(")")[0]) == (gain == "input")
    assert (tmp_path / "4" / "chain_n2.py").read_text() != (tmp_path / "1" / "chain_n2.py").read_text()


# ------------------------------------------------------------------ found by the command-line fuzzer
@pytest.mark.parametrize("argv, option, text", [
    (["simulate", "four_bar", "--t-end", "1e6"], "--t-end", "1e6 is out of range: give a finite number > 0 and <= 10000"),
    (["simulate", "four_bar", "--t-end", "0.1", "--step", "0"], "--step", "0 is out of range: give a finite number > 0"),
    (["accuracy", "four_bar", "--lambdify-timeout", "1e309"], "--lambdify-timeout", "'1e309' is not a finite number"),
    (["accuracy", "four_bar", "--lambdify-timeout", "-1"], "--lambdify-timeout", "-1 is out of range"),
])
def test_options_that_set_the_work_are_bounded_by_the_parser(capsys, argv, option, text):
    _refused(capsys, argv, option, text)


def test_a_fixed_step_run_beyond_the_call_budget_is_refused_before_it_starts(capsys):
    """--step 1e-300 over 0.02 s would be 2e298 rk4 steps: refused at once, naming step and t_end."""
    _fails(capsys, ["simulate", "four_bar", "--t-end", "0.02", "--backend", "numpy", "--method", "rk4",
                    "--step", "1e-300"], "step 1e-300 s over t_end 0.02 s needs 2e+298 steps of rk4")


@pytest.mark.parametrize("argv, text", [
    (["stability", "--cases", ""], "--cases: no case named in ''"),
    (["stability", "--cases", " , "], "--cases: no case named in ' , '"),
    (["accuracy", "four_bar", "--states", "5000"], "--states must be an integer from 1 to 2000"),
    (["accuracy", "four_bar", "--dps", "5000"], "--dps must be at most 1000"),
])
def test_empty_case_lists_and_huge_reports_are_refused_not_run(capsys, argv, text):
    _fails(capsys, argv, text)
