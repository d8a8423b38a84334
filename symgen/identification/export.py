"""Identified parameters written back into a scene (YAML that ``symgen generate`` reads).

The standard parameters are in symgen's internal body frames (``internal = user * A``,
:mod:`symgen.tree`): per body ``r = h/m``, ``I_c = I_o + h^ h^/m`` (:func:`~symgen.control.parameters.body_inertial`),
then ``com = A r`` and ``inertia = A I_c A^T`` in the user's frame. Joints get their rotor inertia
and friction. Values are written as decimals with :data:`DIGITS` significant digits (exact
rationals in the scene); com and inertia entries below :data:`SNAP` of the largest (1e-12 m for
the com) are written as 0. The contact law's ``P_m`` is not part of a scene and is not written.
"""
from __future__ import annotations

import copy
import dataclasses

import numpy as np
import sympy as sp

from ..control.parameters import body_inertial
from ..io.scene_yaml_dump import save_scene
from .consistent import body_blocks

DIGITS = 12


#: entries below this fraction of their vector's (matrix's) largest are rounding noise, written as 0
SNAP = 1e-12


def _exact(x: float) -> sp.Rational:
    return sp.Rational(f"{float(x):.{DIGITS}g}")


def _exact_all(xs, floor: float = 0.0) -> list:
    xs = np.asarray(xs, float).ravel()
    cut = max(SNAP * float(np.max(np.abs(xs), initial=0.0)), floor)
    return [sp.Integer(0) if abs(v) <= cut else _exact(v) for v in xs]


def scene_with_parameters(model, params, values):
    """A copy of the model's scene with the bodies' and joints' parameters from ``values``
    (``params`` order); massless bodies and other elements unchanged."""
    scene = copy.deepcopy(model.scene)
    fld = model.float_field
    values = np.asarray(values, float)
    for owner, idx in body_blocks(params).items():
        body = next(b for b in model.tree.bodies if b.name == owner)
        a = np.array(body.align.tolist(), dtype=float)
        m, r, ic = body_inertial(values[idx], fld, owner)
        com, inertia = a @ np.asarray(r, float), a @ np.asarray(ic, float) @ a.T
        inertia = (inertia + inertia.T) / 2
        scene.bodies[owner] = dataclasses.replace(
            scene.bodies[owner], mass=_exact(m), com=sp.ImmutableMatrix(_exact_all(com, SNAP)),
            inertia=sp.ImmutableMatrix(3, 3, _exact_all(inertia)))
    fields = {"Ir": "rotor_inertia", "b": "viscous", "c": "coulomb"}
    for k, p in enumerate(params.parameters):
        if p.owner in scene.joints and p.quantity in fields:
            scene.joints[p.owner] = dataclasses.replace(scene.joints[p.owner], **{fields[p.quantity]: _exact(values[k])})
    return scene


def write_scene(model, params, values, path) -> None:
    """:func:`scene_with_parameters` saved atomically as YAML."""
    save_scene(scene_with_parameters(model, params, values), path)
