"""The README's and the getting-started page's promises: the tour scene loads and gives the counts
shown and is the built-in four-bar; the first two commands are the ones .ci/run runs; the README
stays short and its Python example is the one the docs' test runs; the Layout page maps the code."""
import re
from pathlib import Path

from symgen.io.builtin import get_scene
from symgen.io.scene_yaml import load_scene
from symgen.model import derive

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")
DOCS = ROOT / "docs"
TOUR_SCENE = DOCS / "examples" / "four_bar.yaml"
LAYOUT = (DOCS / "layout.md").read_text(encoding="utf-8")
STEPS = (DOCS / "guide" / "steps.md").read_text(encoding="utf-8")


def test_tour_scene_derives_with_the_counts_shown():
    counts = derive(load_scene(TOUR_SCENE.read_text(encoding="utf-8"))).counts.as_dict()
    assert counts == {"n1a": 1, "n1u": 3, "n3a": 0, "n3u": 0, "m": 1, "nc": 3, "np": 3, "n": 1}
    page = (DOCS / "getting_started.md").read_text(encoding="utf-8")
    assert "```{literalinclude} examples/four_bar.yaml" in page
    assert "n1a=1  n1u=3  n3a=0  n3u=0  m=1  nc=3  np=3  n=1" in page


def test_tour_scene_is_the_builtin_four_bar():
    """The page says the tour's YAML is the built-in ``four_bar`` with its defaults left out."""
    from_file, built = load_scene(TOUR_SCENE.read_text(encoding="utf-8")), get_scene("four_bar")
    for part in ("bodies", "joints", "frames", "constraints", "motion", "contact_forces", "gravity",
                 "parameters", "constraint_forces", "name"):
        assert getattr(from_file, part) == getattr(built, part), part


def test_readme_starts_with_the_two_commands_ci_runs():
    block = re.search(r"```bash\n(.*?)```", README, re.S).group(1).strip().splitlines()
    assert block == ['pip install . && symgen prove arm_on_plane', 'pip install ".[test]" && python -m pytest']
    ci = (ROOT / ".ci" / "run").read_text()
    assert "symgen prove arm_on_plane" in ci and "python -m pytest\n" in ci


def test_readme_is_short_and_its_example_is_the_tested_file():
    assert len(README.splitlines()) <= 200
    example = re.search(r"```python\n(.*?)```", README, re.S).group(1)
    assert example.strip() == (DOCS / "examples" / "quickstart.py").read_text(encoding="utf-8").strip()
    assert len(example.strip().splitlines()) <= 20


def test_readme_links_resolve():
    links = re.findall(r"\]\(([^)#:]+)\)", README)
    assert links and all((ROOT / link).exists() for link in links), [l for l in links if not (ROOT / l).exists()]


def test_layout_names_every_module_and_package_of_symgen():
    """The docs' map of the code (docs/layout.md) matches the tree: every top-level module and
    subpackage of symgen, and every module of the step pipeline, is named there."""
    import symgen

    pkg = Path(symgen.__file__).parent
    names = [p.stem + ".py" for p in pkg.glob("*.py") if p.stem not in ("__init__", "__main__")]
    names += [p.name + "/" for p in pkg.iterdir() if p.is_dir() and (p / "__init__.py").exists()]
    names += [p.name for p in (pkg / "steps").glob("*.py") if p.stem != "__init__"]
    missing = [n for n in names if n not in LAYOUT and n.replace(".py", "") not in LAYOUT]
    assert not missing, f"docs/layout.md does not mention: {missing}"


def test_step_table_names_functions_that_exist():
    from symgen import steps

    table = STEPS[STEPS.index("| step | function (`symgen.steps`)"):STEPS.index("`steps.evaluate_maps` composes")]
    functions = set(re.findall(r"`([a-z_]+)`", table)) - {"symgen", "symgen_steps"}
    functions = {f for f in functions if "_" in f and not f.startswith(("q_", "n_", "data", "model"))}
    assert functions and all(hasattr(steps, f) for f in functions), sorted(f for f in functions if not hasattr(steps, f))
