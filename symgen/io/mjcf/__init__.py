"""MJCF (MuJoCo XML) robots, loops included: ``scene_from_mjcf(path)``.

:mod:`.include` expands ``<include>`` files; :mod:`.schema` is the allow-list (every element and
attribute read, ignored with its reason, or refused); :mod:`.values` reads exact numbers and
orientations within the shared input limits; :mod:`.defaults` resolves ``<default>`` classes;
:mod:`.bodies` reads the body tree (several joints per body), :mod:`.geoms` a body's mass
properties from its geoms (:mod:`.meshes` those of mesh geoms, from their files), and
:mod:`.parse` the rest into the records of :mod:`.records`; :mod:`.build` makes the scene
(equalities ``connect`` and ``weld`` become constraints, rows that vanish on the manifold are
dropped with a note). The Pinocchio cross-check of such a scene is
:mod:`symgen.oracle.pinocchio_mjcf`.
"""
from .build import MjcfSource, scene_from_mjcf, scene_from_mjcf_model
from .parse import FluidWarning, parse_mjcf, parse_mjcf_text
from .values import MjcfError

__all__ = ["FluidWarning", "MjcfError", "MjcfSource", "parse_mjcf", "parse_mjcf_text", "scene_from_mjcf", "scene_from_mjcf_model"]
