"""The README's promises: its tour scene loads and gives the counts it shows; its first two
commands are the ones .ci/run runs."""
import re
from pathlib import Path

from symgen.model import derive
from symgen.scene_yaml import load_scene

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()


def test_tour_scene_derives_with_the_counts_shown():
    text = re.search(r"Write a scene.*?```yaml\n(.*?)```", README, re.S).group(1)
    counts = derive(load_scene(text)).counts.as_dict()
    assert counts == {"n1a": 1, "n1u": 3, "n3a": 0, "n3u": 0, "m": 1, "nc": 3, "np": 3, "n": 1}


def test_readme_starts_with_the_two_commands_ci_runs():
    block = re.search(r"```bash\n(.*?)```", README, re.S).group(1).strip().splitlines()
    assert block == ['pip install . && symgen prove arm_on_plane', 'pip install ".[test]" && python -m pytest']
    ci = (ROOT / ".ci" / "run").read_text()
    assert "symgen prove arm_on_plane" in ci and "python -m pytest\n" in ci
