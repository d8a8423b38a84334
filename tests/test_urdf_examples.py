"""Real-robot examples from the example-robot-data package: registered as built-in names, located
from the installed files, and a clear error without the package."""
import importlib.metadata

import pytest

pytest.importorskip("yourdfpy", reason="yourdfpy is not installed (extra 'urdf')")

import symgen  # noqa: E402
from symgen.io.builtin import get_scene, list_builtins, list_examples  # noqa: E402
from symgen.io.urdf._deps import MissingExtraError  # noqa: E402


from .urdf_util import needs_examples  # noqa: E402

COUNTS = {  # n1a, m, nc, n
    "ur5": (6, 6, 0, 6),
    "panda": (7, 7, 0, 7),
    "ur5_on_plane": (6, 3, 3, 6),
    "panda_on_plane": (7, 4, 3, 7),
    "multi_ur5:h=2": (12, 6, 6, 12),
    "multi_ur5:h=3": (18, 6, 12, 18),
}


@needs_examples
@pytest.mark.parametrize("spec", sorted(COUNTS))
def test_example_counts(spec):
    c = symgen.derive(get_scene(spec)).counts
    assert (c.n1a, c.m, c.nc, c.n) == COUNTS[spec]


def test_examples_are_listed_apart_from_the_builtins():
    names = [n for n, _, _ in list_examples()]
    assert names == ["ur5", "panda", "ur5_on_plane", "panda_on_plane", "multi_ur5", "solo12", "solo12_standing",
                     "anymal", "anymal_standing", "talos", "talos_double_support", "space_ur5", "cassie", "cassie_fixed"]
    assert not set(names) & {n for n, _, _ in list_builtins()}


def test_without_example_robot_data_an_example_names_the_extra(monkeypatch):
    def missing(name):
        raise importlib.metadata.PackageNotFoundError(name)

    monkeypatch.setattr(importlib.metadata, "distribution", missing)
    with pytest.raises(MissingExtraError, match=r"example-robot-data.*pip install 'symgen\[examples\]'"):
        get_scene("ur5")


@needs_examples
def test_the_urdf_is_read_from_the_installed_package():
    from symgen.io.urdf.examples import example_path

    path = example_path("ur5")
    assert path.is_file() and path.name == "ur5_robot.urdf" and "cmeel.prefix" in str(path)


@needs_examples
def test_snapping_the_ur5_rounded_half_pi_trades_agreement_for_operations():
    """What symgen.io.urdf.rotations states: fewer operations when snapped (357 vs 348 when written),
    Pinocchio agreement of ~6e-16 with the angles as written and ~3e-11 snapped to pi/2."""
    pytest.importorskip("pinocchio", reason="pin (Pinocchio) is not installed (extra 'oracle')")
    from symgen.codegen.generate import operation_counts
    from symgen.oracle import check_against_pinocchio
    from symgen.io.urdf import scene_from_urdf
    from symgen.io.urdf.examples import example_path

    results = {}
    for snap in (1e-14, 1e-9):
        model = symgen.derive(scene_from_urdf(example_path("ur5"), snap=snap))
        ops = operation_counts(model, ["inverse_dynamics"])["inverse_dynamics"]["total"]
        worst = max(d.worst for d in check_against_pinocchio(model, 20))
        results[snap] = (ops, worst)
    assert results[1e-9][0] < results[1e-14][0]
    assert results[1e-14][1] < 2e-15 and 1e-11 < results[1e-9][1] < 1e-10
