"""Scene variants for simulation studies: friction switched off or set, gravity changed.

>>> import symgen
>>> plain = scene_variant(symgen.load("arm_on_plane"), viscous=0)
>>> all(j.viscous == 0 for j in plain.joints.values())
True
"""
from __future__ import annotations

import copy
import functools
import dataclasses

import sympy as sp

from ..scene.declaration import Scene


def scene_variant(scene: Scene, *, viscous=None, coulomb=None, gravity=None, name: str | None = None) -> Scene:
    """A copy of ``scene`` with every moving joint's viscous and/or Coulomb friction set to the
    given value (``None``: unchanged) and, optionally, another gravity vector."""
    out = copy.deepcopy(scene)
    changes = {k: sp.nsimplify(v) for k, v in (("viscous", viscous), ("coulomb", coulomb)) if v is not None}
    if changes:
        out.joints = {k: (dataclasses.replace(j, **changes) if j.kind.moves else j)
                      for k, j in out.joints.items()}
    if gravity is not None:
        out.gravity = sp.ImmutableMatrix([sp.nsimplify(g) for g in gravity])
    if name is not None:
        out.name = name
    return out


@functools.lru_cache(maxsize=32)
def builtin_model(spec: str):
    """``derive(load(spec))`` for a built-in scene spec, cached: one :class:`~symgen.model.Model`
    object per spec and process, so the generated code traced for it by
    :func:`~symgen.simulation.dynamics.load_backend` is shared by every caller."""
    from ..io.builtin import get_scene
    from ..model import derive

    return derive(get_scene(spec))
