"""Joint locking from the command line (``--lock joint=value,...``) and from a scene file's
``urdf:`` section (``lock: {joint: value}``): the locked joints leave the coordinates, their
child is merged at that position, and an unknown joint or a malformed entry is a typed error
naming it."""
import pytest

pytest.importorskip("yourdfpy", reason="yourdfpy is not installed (extra 'urdf')")

from symgen.cli import main  # noqa: E402
from symgen.errors import SceneError  # noqa: E402
from symgen.io.scene_yaml import load_scene  # noqa: E402
from symgen.io.urdf import UrdfError, scene_from_urdf  # noqa: E402

from .urdf_util import DATA  # noqa: E402

TILTED = DATA / "fixed_and_tilted.urdf"     # five moving joints j1..j5


def _info(capsys, *argv) -> tuple[int, str, str]:
    status = main(["info", str(TILTED), *argv])
    out = capsys.readouterr()
    return status, out.out, out.err


def test_the_command_line_lock_removes_the_joints_from_the_coordinates(capsys):
    status, out, _ = _info(capsys, "--lock", "j4=0.1,j5=-pi/4")
    assert status == 0 and "qd (eq. 14)   : j1, j2, j3\n" in out and "m=3" in out


def test_the_command_line_lock_gives_the_scene_of_the_python_api(capsys):
    from symgen.io.scene_yaml import dump_scene

    main(["export", str(TILTED), "--lock", "j4=0.1"])
    assert capsys.readouterr().out == dump_scene(scene_from_urdf(TILTED, lock={"j4": "0.1"}))


@pytest.mark.parametrize("lock, words", [("elbow=0", "lock 'elbow': no joint of this name"),
                                         ("j4=abc", "joint 'j4'")])
def test_a_lock_of_an_unknown_joint_or_value_is_one_line_naming_it(capsys, lock, words):
    status, _, err = _info(capsys, "--lock", lock)
    assert status == 2 and words in err and "Traceback" not in err, err


@pytest.mark.parametrize("lock, words", [("j4", "'j4' is not joint=value"), ("j4=0,j4=1", "'j4' is locked twice")])
def test_a_malformed_lock_is_refused_by_the_parser_naming_the_option(capsys, lock, words):
    with pytest.raises(SystemExit) as info:
        main(["info", str(TILTED), "--lock", lock])
    err = capsys.readouterr().err
    assert info.value.code == 2 and "argument --lock" in err and words in err


def test_lock_on_a_scene_that_is_not_a_urdf_file_is_refused(capsys):
    assert main(["info", "four_bar", "--lock", "j1=0"]) == 2
    assert "apply to URDF files only" in capsys.readouterr().err


def test_a_scene_files_lock_entry_locks_the_joint():
    scene = load_scene(f"name: t\nurdf:\n  file: {TILTED}\n  lock: {{j4: 0.1, j5: -pi/4}}\n")
    assert scene.motion.joints == ("j1", "j2", "j3")


def test_a_scene_files_lock_of_an_unknown_joint_is_named():
    with pytest.raises((UrdfError, SceneError), match="lock 'elbow': no joint of this name"):
        load_scene(f"name: t\nurdf:\n  file: {TILTED}\n  lock: {{elbow: 0}}\n")
