"""Code-generation targets are objects: the registry, its typed error, each target's files, and a
lint that no code outside ``symgen/codegen/targets/`` compares a target name with a literal."""
from __future__ import annotations

import ast
import pathlib

import pytest

from symgen.io.builtin import get_scene
from symgen.codegen.generate import generate
from symgen.codegen.runtime import load_generated
from symgen.codegen.targets import TARGETS, Target, UnknownTargetError, target, templates_dir
from symgen.errors import CodegenError
from symgen.model import derive

PACKAGE = pathlib.Path(__file__).resolve().parents[1] / "symgen"
TARGETS_PACKAGE = PACKAGE / "codegen" / "targets"

#: each target's (template, output file) pairs for a scene named four_bar, written out by hand
EXPECTED_FILES = {
    "numpy": [("numpy/module.py.jinja", "four_bar.py")],
    "c": [("c/header.h.jinja", "four_bar.h"), ("c/source.c.jinja", "four_bar.c"),
          ("c/binding.py.jinja", "four_bar_ctypes.py"), ("c/test.c.jinja", "test_four_bar.c")],
}


@pytest.fixture(scope="module")
def four_bar():
    return derive(get_scene("four_bar"))


def test_registry_names_numpy_then_c():
    assert TARGETS == ("numpy", "c")
    for name in TARGETS:
        assert isinstance(target(name), Target) and target(name).name == name


def test_a_target_object_resolves_to_itself():
    c = target("c")
    assert target(c) is c
    assert str(c) == "c"


def test_only_the_c_target_is_compiled():
    assert [target(name).compiled for name in TARGETS] == [False, True]


@pytest.mark.parametrize("bad", ["fortran", "NumPy", "", None, 3])
def test_unknown_target_is_a_typed_error_naming_the_choices(bad):
    with pytest.raises(UnknownTargetError) as info:
        target(bad)
    assert isinstance(info.value, CodegenError)
    assert repr(bad) in str(info.value) and "choose from numpy, c" in str(info.value)


def test_generate_rejects_an_unknown_target_with_the_same_error(four_bar):
    with pytest.raises(UnknownTargetError, match="unknown target 'fortran'; choose from numpy, c"):
        generate(four_bar, "fortran", ["gravity"])


@pytest.mark.parametrize("name", TARGETS)
def test_each_target_lists_its_files(name):
    assert target(name).files("four_bar") == EXPECTED_FILES[name]


@pytest.mark.parametrize("name", TARGETS)
def test_each_listed_template_exists_in_the_target_folder(name):
    tgt = target(name)
    for template, _ in tgt.files("four_bar"):
        assert template.startswith(tgt.folder + "/")
        assert (templates_dir() / template).is_file()


def test_every_template_folder_belongs_to_a_target_that_renders_all_of_it():
    folders = {p.name: p for p in templates_dir().iterdir() if p.is_dir() and not p.name.startswith("_")}
    assert sorted(folders) == sorted(target(n).folder for n in TARGETS)
    for name in TARGETS:
        tgt = target(name)
        on_disk = sorted(f"{tgt.folder}/{p.name}" for p in folders[tgt.folder].glob("*.jinja"))
        assert on_disk == sorted(template for template, _ in tgt.files("x", python_extension=True))


@pytest.mark.parametrize("name", TARGETS)
def test_generated_files_are_ops_json_then_the_target_files(four_bar, name):
    gen = generate(four_bar, name, ["gravity"])
    assert list(gen.files) == ["ops.json"] + [out for _, out in EXPECTED_FILES[name]]
    assert gen.target == name


@pytest.mark.parametrize("name", TARGETS)
def test_a_target_object_generates_the_same_bytes_as_its_name(four_bar, name):
    assert generate(four_bar, target(name), ["gravity"]).files == generate(four_bar, name, ["gravity"]).files


def test_load_generated_accepts_a_target_object(four_bar):
    by_object = load_generated(four_bar, target("numpy"), ["gravity"])
    assert by_object is load_generated(four_bar, "numpy", ["gravity"])
    assert by_object.__file__.endswith("four_bar.py")


# ------------------------------------------------------------------------------ the lint
def _names(node) -> list[str]:
    """String constants ``node`` is or holds (a tuple, list or set of them)."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return [node.value]
    if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
        return [v for elt in node.elts for v in _names(elt)]
    return []


def target_name_comparisons(source: str, filename: str = "<source>") -> list[str]:
    """``file:line`` of every comparison (``==``, ``!=``, ``in``, ``is`` ...) with a target name
    written as a string literal."""
    found = []
    for node in ast.walk(ast.parse(source, filename)):
        if isinstance(node, ast.Compare):
            literals = [v for operand in [node.left, *node.comparators] for v in _names(operand)]
            hits = sorted(set(literals) & set(TARGETS))
            if hits:
                found.append(f"{filename}:{node.lineno} compares with {', '.join(map(repr, hits))}")
    return found


def test_lint_catches_comparisons_with_target_name_literals():
    source = ('a = t == "numpy"\nb = "c" != t\nc = t in ("numpy", "c")\nd = "c" in ts\n'
              'e = t == "both"\nf = {"c": 1}["c"]\ng = h(backend="numpy")\n')
    assert [hit.split()[0] for hit in target_name_comparisons(source)] == [
        "<source>:1", "<source>:2", "<source>:3", "<source>:4"]


def test_no_module_outside_the_targets_package_compares_target_names():
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        if TARGETS_PACKAGE in path.parents:
            continue
        found += target_name_comparisons(path.read_text(encoding="utf-8"), str(path.relative_to(PACKAGE.parent)))
    assert not found, "ask the target object instead:\n" + "\n".join(found)
