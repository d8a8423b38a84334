"""MJCF (MuJoCo XML) robots, loops included: ``scene_from_mjcf(path)``.

:mod:`.parse` reads the file into exact, located data; :mod:`.build` makes the scene (equalities
``connect`` and ``weld`` become constraints, rows that vanish on the manifold are dropped with a
note). The Pinocchio cross-check of such a scene is :mod:`symgen.oracle.pinocchio_mjcf`.
"""
from .build import MjcfSource, scene_from_mjcf, scene_from_mjcf_model
from .parse import MjcfError, parse_mjcf, parse_mjcf_text

__all__ = ["MjcfError", "MjcfSource", "parse_mjcf", "parse_mjcf_text", "scene_from_mjcf", "scene_from_mjcf_model"]
