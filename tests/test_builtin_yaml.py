"""Each built-in scene's YAML file loads to the same scene as its Python builder."""
import pytest

from symgen.io.builtin import get_scene
from symgen.io.scene_yaml import dump_scene, load_scene
from symgen.io.scenes import FILES, path


@pytest.mark.parametrize("file_name", sorted(FILES))
def test_yaml_file_equals_python_builder(file_name):
    from_file = load_scene(path(file_name))
    built = get_scene(FILES[file_name])
    for part in ("bodies", "joints", "frames", "constraints", "motion", "contact_forces",
                 "gravity", "parameters", "constraint_forces", "name"):
        assert getattr(from_file, part) == getattr(built, part), part


@pytest.mark.parametrize("file_name", sorted(FILES))
def test_yaml_file_is_what_export_writes(file_name):
    """The committed file is byte-identical to a fresh export (deterministic output)."""
    assert path(file_name).read_text() == dump_scene(get_scene(FILES[file_name]))


def test_cli_runs_on_a_yaml_path(capsys):
    from symgen.cli import main

    assert main(["info", str(path("four_bar.yaml")), "--json"]) == 0
    assert '"np": 3' in capsys.readouterr().out
