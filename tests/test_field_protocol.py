"""The Field protocol (symgen.math.fields.Field): sign, sqrt, norm and cos_sin in every field (float,
exact, symbolic, mp, trace), the constants cache that never writes into a field, and a lint that
no module outside the field modules asks a field its name or writes into it."""
from __future__ import annotations

import ast
import math
from fractions import Fraction
from pathlib import Path

import mpmath
import pytest
import sympy as sp

import symgen
from symgen.math.fields import ExactField, Field, FloatField, MpField, SymbolicField
from symgen.codegen.graph import Graph
from symgen.codegen.trace_field import TraceField
from symgen.kinematics import constants
from symgen.tree import build_tree

PACKAGE = Path(symgen.__file__).parent
FIELD_MODULES = {"math/fields.py", "codegen/trace_field.py"}
#: names under which code holds a field
FIELD_NAMES = {"field", "fld"}
#: float answers agree with the hand values to this
FLOAT_TOL = 1e-15
#: a 50-digit mp answer agrees with a 60-digit mpmath one to this
MP_TOL = mpmath.mpf(10) ** -48


def numeric_fields():
    return [FloatField(), ExactField(), SymbolicField(), MpField()]


def ids(f):
    return type(f).__name__


# ---------------------------------------------------------------- sign, sqrt, norm
@pytest.mark.parametrize("field", numeric_fields(), ids=ids)
def test_sign_is_minus_one_zero_or_one(field):
    got = [field.sign(field.const(v)) for v in (Fraction(-3, 2), 0, Fraction(7, 4))]
    assert got == [-1, 0, 1]


def test_symbolic_sign_of_a_symbol_stays_symbolic():
    x = sp.Symbol("x", real=True)
    assert SymbolicField().sign(x) == sp.sign(x)


@pytest.mark.parametrize("field", numeric_fields(), ids=ids)
def test_sqrt_and_norm_of_perfect_squares(field):
    assert field.sqrt(field.const(Fraction(9, 4))) == Fraction(3, 2)
    assert field.norm([field.const(3), field.const(-4), field.const(0)]) == 5


def test_exact_sqrt_rounds_through_float_and_says_so():
    f = ExactField()
    assert not f.rounded
    got = f.sqrt(Fraction(2))
    assert f.rounded
    assert got == Fraction(math.sqrt(2.0))


def test_symbolic_sqrt_is_exact():
    assert SymbolicField().sqrt(sp.Integer(2)) == sp.sqrt(2)


def test_mp_sqrt_has_the_fields_precision():
    f = MpField(dps=50)
    with mpmath.workdps(60):
        want = mpmath.sqrt(2)
        assert abs(f.sqrt(2) - want) < MP_TOL


# ---------------------------------------------------------------- cos_sin
def test_float_cos_sin():
    c, s = FloatField().cos_sin(math.pi / 3)
    assert c == pytest.approx(0.5, abs=FLOAT_TOL) and s == pytest.approx(math.sqrt(3) / 2, abs=FLOAT_TOL)


def test_mp_cos_sin_has_the_fields_precision():
    c, s = MpField(dps=50).cos_sin(Fraction(1, 3))
    with mpmath.workdps(60):
        third = mpmath.mpf(1) / 3
        assert abs(c - mpmath.cos(third)) < MP_TOL and abs(s - mpmath.sin(third)) < MP_TOL


@pytest.mark.parametrize("field", [ExactField(), SymbolicField(), TraceField(Graph())], ids=ids)
def test_fields_without_cos_sin_ask_for_cos_sin_pairs(field):
    with pytest.raises(TypeError, match=r"CosSin\(c, s\)"):
        field.cos_sin(0.5)


# ---------------------------------------------------------------- the trace field records
def test_trace_sign_and_sqrt_are_recorded_as_graph_functions():
    g = Graph()
    f = TraceField(g)
    x = g.input("x", 1)[0]
    assert (f.sign(x).op, f.sign(x).args) == ("sign", (x.id,))
    assert (f.sqrt(x).op, f.sqrt(x).args) == ("sqrt", (x.id,))


def test_trace_functions_of_constants_fold():
    f = TraceField(Graph())
    assert f.sign(f.const(-2)).value == -1
    assert f.sqrt(f.const(Fraction(9, 4))).value == 1.5
    assert f.norm([f.const(3), f.const(4)]).value == 5


# ---------------------------------------------------------------- the protocol is complete
def test_field_is_abstract():
    with pytest.raises(TypeError):
        Field()


@pytest.mark.parametrize("name", ["const", "solve", "sign", "sqrt", "norm", "cos_sin", "array", "zeros", "eye",
                                  "configuration"])
def test_every_field_answers_every_operation(name):
    for field in numeric_fields() + [TraceField(Graph())]:
        assert callable(getattr(field, name)), (type(field).__name__, name)
        assert hasattr(field, "zero") and hasattr(field, "one")


# ---------------------------------------------------------------- constants cache
def test_constants_are_cached_without_writing_into_the_field():
    tree = build_tree(symgen.load("four_bar"))
    other = build_tree(symgen.load("five_bar"))
    field = FloatField(tree.parameters)
    before = dict(vars(field))
    first = constants(tree, field)
    assert constants(tree, field) is first
    assert constants(other, field) is not first
    assert vars(field) == before


def test_each_field_has_its_own_constants():
    tree = build_tree(symgen.load("four_bar"))
    assert constants(tree, FloatField()) is not constants(tree, ExactField())


# ---------------------------------------------------------------- lint
def _is_field(node) -> bool:
    """``field``, ``fld``, ``self.field``, ``self.fld`` (and ``x.field`` for any ``x``)."""
    if isinstance(node, ast.Name):
        return node.id in FIELD_NAMES
    return isinstance(node, ast.Attribute) and node.attr in FIELD_NAMES


def _field_misuse(source: str, where: str) -> list[str]:
    out = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Attribute) and node.attr == "name" and _is_field(node.value):
            out.append(f"{where}:{node.lineno} reads a field's name")
        if isinstance(node, (ast.Assign, ast.AugAssign)):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            out += [f"{where}:{node.lineno} writes {t.attr!r} into a field" for t in targets
                    if isinstance(t, ast.Attribute) and _is_field(t.value) and t.attr != "rounded"]
        if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "setattr"
                and node.args and _is_field(node.args[0])):
            out.append(f"{where}:{node.lineno} setattr on a field")
    return out


def test_the_lint_sees_name_reads_and_writes():
    src = ("if field.name == 'x': pass\nif self.fld.name: pass\nsetattr(field, 'k', 1)\n"
           "self.field.cache = 1\nfield.rounded = True\nnode.name = 'y'\n")
    assert sorted(int(m.split(":")[1].split()[0]) for m in _field_misuse(src, "probe")) == [1, 2, 3, 4]


def test_no_module_asks_a_field_its_name_or_writes_into_it():
    offenders = []
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE).as_posix()
        if rel not in FIELD_MODULES:
            offenders += _field_misuse(path.read_text(), rel)
    assert not offenders, "use the Field protocol instead:\n" + "\n".join(offenders)


def test_a_float_fields_singularity_threshold_is_set_at_construction():
    assert FloatField(max_condition=float("inf")).max_condition == float("inf")
    assert FloatField().max_condition == FloatField.max_condition == 1e12
