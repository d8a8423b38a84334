"""Inertial parameters as run-time inputs of the generated functions.

On request, chosen inertial parameters -- a body's mass ``m``, centre of mass ``r`` and rotational
inertia ``I_c`` about it, the constants of the rigid body's ``M_alpha`` (eq. 21) -- or parameters
the scene declared itself (:meth:`~symgen.scene.declaration.Scene.add_parameter`) stop being folded
into the straight-line code and become one extra input array ``p`` of every generated function.

A request is a list of names:

* ``BODY`` -- the body's ten inertial parameters, in the order ``BODY.mass``, ``BODY.com_x``,
  ``BODY.com_y``, ``BODY.com_z``, ``BODY.ixx``, ``BODY.iyy``, ``BODY.izz``, ``BODY.ixy``,
  ``BODY.ixz``, ``BODY.iyz`` (body frame, inertia about the centre of mass with the sign of the
  matrix, as :meth:`~symgen.scene.declaration.Scene.add_body` takes them);
* ``BODY.mass``, ``BODY.com`` (three entries), ``BODY.inertia`` (six entries) -- a part of them;
* the name of a parameter the scene declared -- that parameter.

:func:`parameterise` turns the chosen body values into declared parameters of a copy of the
scene (so the derivation substitutes their values as before) and :func:`traced_parameters` makes
the tracer read them from ``p`` (:class:`~symgen.codegen.trace_field.TraceField`). The generated
code does not check that a ``p`` is physically possible: :func:`check_parameter_vector` does, for
callers in Python (negative mass, an inertia that is not positive semi-definite or breaks the
triangle inequality: a :class:`~symgen.errors.SceneError` naming the body).
"""
from __future__ import annotations

import copy
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass

import numpy as np
import sympy as sp

from ..errors import CodegenError, SceneError
from ..scene.checks import check_mass_properties
from ..scene.elements import Body

#: a body's ten inertial parameters, in the order of ``p``: (suffix of the name, getter)
BODY_ENTRIES = ("mass", "com_x", "com_y", "com_z", "ixx", "iyy", "izz", "ixy", "ixz", "iyz")
#: the groups a request may name after ``BODY.``
GROUPS = {"mass": BODY_ENTRIES[:1], "com": BODY_ENTRIES[1:4], "inertia": BODY_ENTRIES[4:]}
#: entries of the inertia matrix each inertia parameter stands for
_INERTIA_INDEX = {"ixx": (0, 0), "iyy": (1, 1), "izz": (2, 2), "ixy": (0, 1), "ixz": (0, 2), "iyz": (1, 2)}


@dataclass(frozen=True)
class Parameters:
    """The run-time parameters of a generated module: ``names`` (the order of ``p``), their
    ``symbols`` in the scene and their ``defaults`` (the scene's values)."""

    names: tuple[str, ...]
    symbols: tuple[sp.Symbol, ...]
    defaults: tuple[float, ...]

    def __len__(self) -> int:
        return len(self.names)


def _symbol_name(name: str) -> str:
    return name.replace(".", "__")


def _body_value(body: Body, entry: str) -> sp.Expr:
    if entry == "mass":
        return body.mass
    if entry.startswith("com_"):
        return body.com["xyz".index(entry[-1])]
    i, j = _INERTIA_INDEX[entry]
    return body.inertia[i, j]


def _resolve(scene, requested) -> list[tuple[str, str | None, str | None]]:
    """``(name, body, entry)`` per parameter of the request, in request order, without repeats;
    ``body`` and ``entry`` are ``None`` for a parameter the scene declared."""
    declared = {str(s): s for s in scene.parameters}
    out: list[tuple[str, str | None, str | None]] = []
    for item in requested:
        if not isinstance(item, str) or not item:
            raise CodegenError(f"run-time parameter {item!r}: give a body name, BODY.mass, BODY.com, "
                               "BODY.inertia or a declared parameter's name")
        body, _, group = item.partition(".")
        if not group and body in declared:
            entries = [(item, None, None)]
        elif body in scene.bodies:
            if group and group not in GROUPS and group not in BODY_ENTRIES:
                raise CodegenError(f"run-time parameter {item!r}: body {body!r} has no parameter {group!r}; "
                                   f"choose from {', '.join(list(GROUPS) + list(BODY_ENTRIES[1:]))}")
            chosen = GROUPS.get(group, (group,)) if group else BODY_ENTRIES
            entries = [(f"{body}.{e}", body, e) for e in chosen]
        else:
            raise CodegenError(f"run-time parameter {item!r}: the scene {scene.name!r} has no body "
                               f"{body!r}" + (" and no declared parameter of that name" if not group else ""))
        out.extend(e for e in entries if e[0] not in [o[0] for o in out])
    return out


def parameterise(scene, requested) -> tuple[object, Parameters]:
    """A copy of ``scene`` whose chosen body values are declared parameters (named
    ``BODY__ENTRY``), and the :class:`Parameters` of the request. Raises
    :class:`~symgen.errors.CodegenError` naming an unknown body, entry or parameter."""
    entries = _resolve(scene, requested)
    out = copy.deepcopy(scene)
    declared = {str(s): s for s in out.parameters}
    symbols, defaults = [], []
    for name, body_name, entry in entries:
        if body_name is None:
            sym = declared[name]
        else:
            body = out.bodies[body_name]
            value = _body_value(body, entry).xreplace(out.parameters)
            if _symbol_name(name) in declared:
                raise CodegenError(f"run-time parameter {name!r}: the scene already declares a parameter "
                                   f"{_symbol_name(name)!r}")
            sym = out.add_parameter(_symbol_name(name), value)
            declared[str(sym)] = sym
            out.bodies[body_name] = _replaced(body, entry, sym)
        symbols.append(sym)
        defaults.append(float(out.parameters[sym]))
    return out, Parameters(tuple(e[0] for e in entries), tuple(symbols), tuple(defaults))


def _replaced(body: Body, entry: str, sym: sp.Symbol) -> Body:
    if entry == "mass":
        return Body(body.name, sym, body.com, body.inertia)
    if entry.startswith("com_"):
        com = sp.Matrix(body.com)
        com["xyz".index(entry[-1])] = sym
        return Body(body.name, body.mass, sp.ImmutableMatrix(com), body.inertia)
    inertia = sp.Matrix(body.inertia)
    i, j = _INERTIA_INDEX[entry]
    inertia[i, j] = inertia[j, i] = sym
    return Body(body.name, body.mass, body.com, sp.ImmutableMatrix(inertia))


def check_parameter_vector(scene, parameters: Parameters, p) -> np.ndarray:
    """``p`` as a float array after the checks the generated code leaves to its caller: length
    ``len(parameters)``, finite, and every body it touches physically possible (mass >= 0, inertia
    positive semi-definite and obeying the triangle inequality: :func:`~symgen.scene.checks.check_mass_properties`).
    ``scene`` is the scene the parameters were chosen on (:func:`parameterise`'s input or output).
    Raises :class:`~symgen.errors.SceneError` naming the body or the array."""
    values = np.asarray(p, dtype=float)
    if values.shape != (len(parameters),):
        raise SceneError("parameter array p", f"needs shape ({len(parameters)},) "
                                              f"({', '.join(parameters.names)}), got {values.shape}")
    if not np.all(np.isfinite(values)):
        bad = [n for n, v in zip(parameters.names, values) if not np.isfinite(v)]
        raise SceneError("parameter array p", f"{', '.join(bad)} not finite")
    given = dict(zip(parameters.symbols, values))
    subs = {**scene.parameters, **{s: sp.Float(v, 17) for s, v in given.items()}}
    touched: dict[str, Body] = {}
    for name, value in zip(parameters.names, values):
        body_name, _, entry = name.partition(".")
        if entry:
            body = touched.get(body_name) or _numeric_body(scene.bodies[body_name], subs)
            touched[body_name] = _replaced(body, entry, sp.Float(value, 17))
    for name, body in scene.bodies.items():      # declared parameters may sit in any body
        if name not in touched and (sp.sympify(body.mass).free_symbols | body.inertia.free_symbols) & set(given):
            touched[name] = body
    for name, body in touched.items():
        check_mass_properties(f"body {name!r}", body, subs)
    return values


def _numeric_body(body: Body, subs) -> Body:
    return Body(body.name, sp.sympify(body.mass).xreplace(subs), body.com.xreplace(subs), body.inertia.xreplace(subs))


_TRACED: ContextVar[Parameters | None] = ContextVar("traced_parameters", default=None)


@contextmanager
def traced_parameters(parameters: Parameters | None):
    """Tracers made inside read ``parameters`` from the input ``p`` instead of folding their values."""
    token = _TRACED.set(parameters if parameters else None)
    try:
        yield
    finally:
        _TRACED.reset(token)


def current() -> Parameters | None:
    """The parameters tracers made now read from ``p`` (:func:`traced_parameters`)."""
    return _TRACED.get()


def to_nodes(graph, expr, inputs: dict) -> object:
    """A SymPy expression in the parameters ``inputs`` (symbol -> input node) as graph nodes: sums,
    products and integer powers (what the spanning tree's frame changes make of body values).
    Raises :class:`~symgen.errors.CodegenError` for anything else."""
    if not expr.free_symbols:
        return graph.const(expr)
    if expr in inputs:
        return inputs[expr]
    syms = tuple(inputs)
    if isinstance(expr, sp.Add):
        rest, dep = expr.as_independent(*syms, as_Add=True)
        total = graph.const(rest) if rest != 0 else None
        for term in sp.Add.make_args(dep):
            node = to_nodes(graph, term, inputs)
            total = node if total is None else total + node
        return total
    if isinstance(expr, sp.Mul):
        coeff, dep = expr.as_independent(*syms, as_Add=False)
        prod = None if coeff == 1 else graph.const(coeff)
        for factor in sp.Mul.make_args(dep):
            node = to_nodes(graph, factor, inputs)
            prod = node if prod is None else prod * node
        return prod
    if isinstance(expr, sp.Pow) and expr.exp.is_Integer and expr.exp > 0:
        base = to_nodes(graph, expr.base, inputs)
        out = base
        for _ in range(int(expr.exp) - 1):
            out = out * base
        return out
    raise CodegenError(f"run-time parameters: the scene value {expr} is not a polynomial in the parameters "
                       f"{', '.join(sorted(map(str, expr.free_symbols)))}; generated code takes sums and products")
