"""The installed package is what the source tree holds: every subpackage is listed in pyproject.toml.

The suite imports symgen from the source tree, so a subpackage missing from the ``packages`` list
would pass every other test and still be absent from ``pip install .``."""
from pathlib import Path
import tomllib

ROOT = Path(__file__).resolve().parents[1]


def _declared_packages() -> set[str]:
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    return set(config["tool"]["setuptools"]["packages"])


def test_every_subpackage_is_declared():
    on_disk = {".".join(init.parent.relative_to(ROOT).parts)
               for init in (ROOT / "symgen").rglob("__init__.py")}
    missing = sorted(on_disk - _declared_packages())
    assert not missing, f"add to [tool.setuptools] packages in pyproject.toml: {missing}"


def test_every_declared_package_exists():
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    mapped = config["tool"]["setuptools"].get("package-dir", {})
    for name in _declared_packages():
        where = ROOT / mapped[name] if name in mapped else ROOT.joinpath(*name.split("."))
        assert where.is_dir(), f"pyproject.toml lists {name!r}, but {where} does not exist"
