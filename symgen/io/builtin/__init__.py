"""Built-in scenes, written with the :class:`~symgen.scene.Scene` API.

A scene is named by a *spec*: ``"name"`` or ``"name:param=value,param=value"`` with integer
values, e.g. ``"chain:n=8"``, ``"multi_arm:h=3"``, ``"four_bar"``. Omitted parameters take their
defaults.

========================  ========================================================================
``chain:n=6``             the n-link spatial benchmark chain (open chain, ``n_c = 0``)
``arm_on_plane``          6R arm sliding a gripped object on a plane (paper, Section 3.2)
``multi_arm:h=2``         h 6R arms rigidly holding one object (paper, Section 3.3)
``four_bar``              planar parallelogram four-bar, crank driven
``five_bar``              planar five-bar, both base joints driven
``stewart``               Stewart-Gough platform, six U-P-S legs
``general_chain:n=7``     n revolute joints in general geometry (modified DH) with general inertia
========================  ========================================================================

Real-robot examples, read from the URDF files of the ``example-robot-data`` package when it is
installed (:mod:`symgen.io.urdf.examples`; otherwise a :class:`~symgen.io.urdf._deps.MissingExtraError`
names the extra ``examples``). They are listed by :func:`list_examples`, not :func:`list_builtins`:

========================  ========================================================================
``ur5``, ``panda``        the UR5 and the Panda arm (fingers locked), open chains
``ur5_on_plane``          UR5 tool sliding on a plane (paper, Section 3.2)
``panda_on_plane``        Panda hand sliding on a plane, 4 joint rates as V_m
``multi_ur5:h=2``         h UR5s holding one object (paper, Section 3.3)
``solo12``                Solo12 quadruped on a free base (:mod:`symgen.io.urdf.legged`)
``solo12_standing``       Solo12 on its four point feet
``anymal``                ANYmal quadruped on a free base; ``anymal_standing``: on its four point feet
``talos``                 Talos humanoid on a free base, grippers locked
``talos_double_support``  Talos on its two flat soles
``space_ur5``             a UR5 on a free-floating base in zero gravity
``cassie``                Cassie biped on a free base, its four leg loops closed (SDF,
                          :mod:`symgen.io.sdf.cassie`); ``cassie_fixed``: pelvis welded
========================  ========================================================================

Every built-in scene has a reference configuration (the joints' ``q0``) at which every closure
and contact constraint holds (to about 1e-20) and the constraint and task Jacobians are well
conditioned.

>>> get_scene("chain:n=3").name
'chain_n3'
>>> [name for name, _, _ in list_builtins()][:2]
['chain', 'arm_on_plane']
"""
from __future__ import annotations

import re
from typing import Callable, NamedTuple

from ...errors import SceneError
from ...scene.declaration import Scene
from .arm_on_plane import arm_on_plane
from .chain import chain
from .closed_chains import five_bar, four_bar
from .general_chain import general_chain
from .multi_arm import multi_arm
from .stewart import stewart


_INT_RE = re.compile(r"^[+-]?[0-9]+$")


class Param(NamedTuple):
    """An integer parameter of a built-in scene: default and inclusive bounds."""

    default: int
    low: int
    high: int


class Builtin(NamedTuple):
    """A built-in scene: its builder, its parameters (name -> :class:`Param`) and a summary."""

    builder: Callable[..., Scene]
    params: dict
    description: str


BUILTINS: dict[str, Builtin] = {
    "chain": Builtin(chain, {"n": Param(6, 1, 200)},
                     "n-link spatial benchmark chain (revolute, axes alternating z/y)"),
    "arm_on_plane": Builtin(arm_on_plane, {},
                            "6R arm sliding a gripped object on a plane (paper Section 3.2)"),
    "multi_arm": Builtin(multi_arm, {"h": Param(2, 1, 16)},
                         "h coordinated 6R arms holding one object (paper Section 3.3)"),
    "four_bar": Builtin(four_bar, {}, "planar parallelogram four-bar, crank driven"),
    "five_bar": Builtin(five_bar, {}, "planar five-bar, both base joints driven"),
    "stewart": Builtin(stewart, {}, "Stewart-Gough platform with six U-P-S legs"),
    "general_chain": Builtin(general_chain, {"n": Param(7, 1, 64)},
                             "n revolute joints in general geometry with general inertia (published op-count tables)"),
}


def _example(name: str, module: str = "urdf.examples") -> Callable[..., Scene]:
    """The builder of a real-robot example, imported when called (it needs the extras)."""
    def build(**params):
        from importlib import import_module

        return getattr(import_module(f"symgen.io.{module}"), name)(**params)

    build.__name__ = name
    return build


EXAMPLES: dict[str, Builtin] = {
    "ur5": Builtin(_example("ur5"), {}, "UR5 from example-robot-data's URDF (6 revolute joints)"),
    "panda": Builtin(_example("panda"), {}, "Franka Panda arm from example-robot-data's URDF, fingers locked"),
    "ur5_on_plane": Builtin(_example("ur5_on_plane"), {}, "UR5 tool0 sliding on a plane (paper Section 3.2)"),
    "panda_on_plane": Builtin(_example("panda_on_plane"), {}, "Panda hand sliding on a plane, V_m = 4 joint rates"),
    "multi_ur5": Builtin(_example("multi_ur5"), {"h": Param(2, 1, 6)}, "h UR5s holding one object (Section 3.3)"),
    "solo12": Builtin(_example("solo12", "urdf.legged"), {}, "Solo12 quadruped on a free base, no contact"),
    "solo12_standing": Builtin(_example("solo12_standing", "urdf.legged"), {}, "Solo12 standing on four point feet"),
    "anymal": Builtin(_example("anymal", "urdf.legged"), {}, "ANYmal quadruped on a free base, no contact"),
    "anymal_standing": Builtin(_example("anymal_standing", "urdf.legged"), {}, "ANYmal standing on four point feet"),
    "talos": Builtin(_example("talos", "urdf.legged"), {}, "Talos humanoid on a free base (grippers locked), no contact"),
    "talos_double_support": Builtin(_example("talos_double_support", "urdf.legged"), {},
                                    "Talos standing on its two flat soles"),
    "space_ur5": Builtin(_example("space_ur5", "urdf.legged"), {}, "UR5 on a free-floating base in zero gravity"),
    "cassie": Builtin(_example("cassie", "sdf.cassie"), {}, "Cassie biped on a free base, four leg loops closed (SDF)"),
    "cassie_fixed": Builtin(_example("cassie_fixed", "sdf.cassie"), {}, "Cassie biped, pelvis fixed, leg loops closed"),
}


def list_examples() -> list[tuple[str, dict, str]]:
    """``(name, {param: default}, description)`` of every real-robot example (needs example-robot-data)."""
    return [(name, {k: p.default for k, p in b.params.items()}, b.description) for name, b in EXAMPLES.items()]


def list_builtins() -> list[tuple[str, dict, str]]:
    """``(name, {param: default}, description)`` of every built-in scene."""
    return [(name, {k: p.default for k, p in b.params.items()}, b.description)
            for name, b in BUILTINS.items()]


def _usage() -> str:
    parts = []
    for name, b in {**BUILTINS, **EXAMPLES}.items():
        params = ",".join(f"{k}={p.default} ({p.low}..{p.high})" for k, p in b.params.items())
        parts.append(f"{name}:{params}" if params else name)
    return "valid scenes: " + "; ".join(parts)


def parse_spec(spec: str) -> tuple[str, dict[str, int]]:
    """Split ``"name:k=v,k=v"`` into the scene name and its validated integer parameters."""
    element = f"built-in scene {spec!r}"
    if not isinstance(spec, str) or not spec.strip():
        raise SceneError(element, f"expected 'name' or 'name:param=value'; {_usage()}")
    name, colon, rest = spec.strip().partition(":")
    name = name.strip()
    table = BUILTINS if name in BUILTINS else EXAMPLES
    if name not in table:
        raise SceneError(element, f"unknown scene {name!r}; {_usage()}")
    allowed = table[name].params
    if colon and not rest.strip():
        raise SceneError(element, f"empty parameter list after ':'; {_usage()}")
    values: dict[str, int] = {}
    for item in (s.strip() for s in rest.split(",")) if colon else ():
        key, eq, text = (s.strip() for s in item.partition("="))
        if not eq or not key or not text:
            raise SceneError(element, f"parameter {item!r} must be written key=value; {_usage()}")
        if key not in allowed:
            valid = ", ".join(allowed) or "none"
            raise SceneError(element, f"unknown parameter {key!r} for {name!r} (parameters: {valid}); {_usage()}")
        if key in values:
            raise SceneError(element, f"parameter {key!r} given twice; {_usage()}")
        if not _INT_RE.match(text):
            raise SceneError(element, f"parameter {key}={text!r} must be an integer; {_usage()}")
        value, p = int(text), allowed[key]
        if not p.low <= value <= p.high:
            raise SceneError(element, f"parameter {key}={value} is out of range ({p.low} <= {key} <= {p.high}); {_usage()}")
        values[key] = value
    return name, {k: values.get(k, p.default) for k, p in allowed.items()}


def get_scene(spec: str) -> Scene:
    """Build the built-in scene named by ``spec`` (e.g. ``"chain:n=8"``, ``"stewart"``)."""
    name, params = parse_spec(spec)
    return (BUILTINS.get(name) or EXAMPLES[name]).builder(**params)


__all__ = ["BUILTINS", "EXAMPLES", "Builtin", "Param", "get_scene", "list_builtins", "list_examples", "parse_spec"]
