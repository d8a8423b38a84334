"""The README's promises: its tour scene loads and gives the counts it shows; its first two
commands are the ones .ci/run runs."""
import re
from pathlib import Path

from symgen.model import derive
from symgen.io.scene_yaml import load_scene

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


def _layout_block() -> str:
    start = README.index("## Layout")
    return README[start:README.index("## Status", start)]


def test_layout_names_every_module_and_package_of_symgen():
    """The README's map of the code matches the tree: every top-level module and subpackage of
    symgen, and every module of the step pipeline, is named in the Layout section."""
    import pathlib

    import symgen

    pkg = pathlib.Path(symgen.__file__).parent
    layout = _layout_block()
    names = [p.stem + ".py" for p in pkg.glob("*.py") if p.stem not in ("__init__", "__main__")]
    names += [p.name + "/" for p in pkg.iterdir() if p.is_dir() and (p / "__init__.py").exists()]
    names += [p.name for p in (pkg / "steps").glob("*.py") if p.stem != "__init__"]
    missing = [n for n in names if n not in layout and n.replace(".py", "") not in layout]
    assert not missing, f"README Layout does not mention: {missing}"


def test_step_table_names_functions_that_exist():
    from symgen import steps

    table = README[README.index("| step | function (`symgen.steps`)"):README.index("`steps.evaluate_maps` composes")]
    functions = set(re.findall(r"`([a-z_]+)`", table)) - {"symgen", "symgen_steps"}
    functions = {f for f in functions if "_" in f and not f.startswith(("q_", "n_", "data", "model"))}
    assert functions and all(hasattr(steps, f) for f in functions), sorted(f for f in functions if not hasattr(steps, f))
