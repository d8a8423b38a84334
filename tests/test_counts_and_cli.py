"""Counts of Steps 1-8 against the paper (Sections 3.2, 3.3, footnote 5) and the CLI contract."""
import json
import subprocess
import sys

import pytest

from symgen.cli import main

# (n1a, n1u, n3a, n3u, m, nc, np, n) as stated in the paper / the issue, written out by hand
EXPECTED = {
    "arm_on_plane": (6, 0, 0, 0, 3, 3, 0, 6),          # Section 3.2
    "multi_arm:h=1": (6, 0, 0, 0, 6, 0, 0, 6),         # Section 3.3, h = 1
    "multi_arm:h=2": (12, 0, 0, 0, 6, 6, 0, 12),       # n = 6h, nc = 6(h-1)
    "multi_arm:h=3": (18, 0, 0, 0, 6, 12, 0, 18),
    "multi_arm:h=5": (30, 0, 0, 0, 6, 24, 0, 30),
    "four_bar": (1, 3, 0, 0, 1, 3, 3, 1),              # footnote 5: np = nc = n1u
    "five_bar": (2, 3, 0, 0, 2, 3, 3, 2),
    "stewart": (6, 12, 0, 6, 6, 30, 30, 6),            # footnote 5
    "chain:n=1": (1, 0, 0, 0, 1, 0, 0, 1),
    "chain:n=7": (7, 0, 0, 0, 7, 0, 0, 7),
}
KEYS = ("n1a", "n1u", "n3a", "n3u", "m", "nc", "np", "n")


@pytest.mark.parametrize("spec", sorted(EXPECTED))
def test_info_json_counts_match_the_paper(spec, capsys):
    assert main(["info", spec, "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    assert got == dict(zip(KEYS, EXPECTED[spec]))


def test_scenes_lists_every_builtin(capsys):
    assert main(["scenes"]) == 0
    out = capsys.readouterr().out
    for name in ("arm_on_plane", "multi_arm", "four_bar", "five_bar", "stewart", "chain"):
        assert name in out
    for name in ("ur5", "panda", "ur5_on_plane", "multi_ur5:h=2"):
        assert f"  {name} " in out


def test_urdf_path_loads_as_a_scene(capsys):
    from pathlib import Path

    from symgen.io.loading import load

    pytest.importorskip("yourdfpy", reason="URDF import needs the 'urdf' extra (yourdfpy)")
    urdf = Path(__file__).parent / "data" / "urdf" / "fixed_and_tilted.urdf"
    scene = load(str(urdf))
    assert {"j1", "j2", "j3", "j4", "j5"} <= set(scene.joints)
    assert main(["info", str(urdf), "--json"]) == 0


def test_unknown_scene_is_a_one_line_error_naming_it(capsys):
    assert main(["info", "no_such_robot"]) == 2
    err = capsys.readouterr().err
    assert "no_such_robot" in err and "Traceback" not in err


def test_prove_json_reports_method_and_points(capsys):
    assert main(["prove", "four_bar", "--json", "--points", "1"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["passed"] is True
    assert all(r["passed"] and r["method"] and r["points"] >= 1 for r in report["results"])


def test_console_entry_point_runs():
    out = subprocess.run([sys.executable, "-m", "symgen", "info", "chain:n=2", "--json"],
                         capture_output=True, text=True, check=True).stdout
    assert json.loads(out)["n"] == 2


def test_cli_start_up_does_not_import_scipy():
    """SciPy is a fifth of the start-up of every command; only the commands that use it (closed-chain
    partitions, simulation, identification) import it."""
    code = "import sys, symgen.cli; symgen.cli.build_parser(); print(any(m.startswith('scipy') for m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_steps_prints_the_task_map_of_the_four_bar(capsys):
    """V_m is the crank rate itself, so J_m = [1] (eq. 17)."""
    assert main(["steps", "four_bar", "-q", "J_m"]) == 0
    out = capsys.readouterr().out
    assert out.splitlines()[0] == "J_m (1, 1):" and "[[1.]]" in out


def test_symbolic_steps_give_the_one_link_mass_by_hand(capsys):
    """One link about z: M = I_zz + m (L/2)^2 = 3/100 + (1)(1/20)^2 = 13/400."""
    assert main(["steps", "chain:n=1", "-q", "M_q", "--field", "symbolic"]) == 0
    import re

    out = capsys.readouterr().out       # pretty-printed: 13 over a bar over 400
    assert re.search(r"13\s*.\n.*─+.*\n.*400", out), out


def test_steps_rejects_an_unknown_quantity(capsys):
    assert main(["steps", "four_bar", "-q", "T_X"]) == 2
    err = capsys.readouterr().err
    assert "T_X" in err and "T_S" in err


def test_export_round_trips_through_a_file(tmp_path, capsys):
    from symgen.io.builtin import get_scene
    from symgen.io.scene_yaml import load_scene

    assert main(["export", "five_bar"]) == 0
    path = tmp_path / "five_bar.yaml"
    path.write_text(capsys.readouterr().out)
    loaded, built = load_scene(path), get_scene("five_bar")
    assert (loaded.bodies, loaded.joints, loaded.constraints, loaded.motion) == \
        (built.bodies, built.joints, built.constraints, built.motion)
