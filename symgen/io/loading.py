"""``load(spec)``: a :class:`~symgen.scene.Scene` from whatever the user names.

A SCENE is a built-in name with parameters (``chain:n=8``, ``multi_arm:h=3``, ``ur5``), a path to
a YAML scene file, a URDF file, an SDF file (``.sdf``) or an MJCF file (``.xml``). Library code (the simulation, accuracy, complexity and check
commands) and the command line take scenes through this one function; the loaders it dispatches
to are imported on first use, so ``import symgen`` stays light.

>>> from symgen.io.loading import load
>>> load("chain:n=2").name
'chain_n2'
"""
from __future__ import annotations

import os


#: the reader options of an MJCF file (:func:`symgen.io.mjcf.scene_from_mjcf`)
MJCF_OPTIONS = ("fluid",)


def load(spec: str, **urdf_options):
    """A :class:`~symgen.scene.Scene` from a built-in spec, a YAML scene file, a URDF, SDF or MJCF file.

    ``urdf_options`` (e.g. ``inertia="repair"``) go to :func:`symgen.io.urdf.scene_from_urdf` and
    are refused for anything but a URDF file (a scene file sets them in its ``urdf:`` section); an
    MJCF file takes ``fluid="ignore"`` (:data:`MJCF_OPTIONS`) instead.
    """
    mjcf = spec.endswith((".xml", ".mjcf"))
    if urdf_options and not spec.endswith(".urdf") and not (mjcf and set(urdf_options) <= set(MJCF_OPTIONS)):
        from ..errors import SceneError

        raise SceneError(f"scene {spec!r}", f"options {', '.join(sorted(urdf_options))} apply to URDF files only"
                                            f"{f' (an MJCF file takes {chr(44).join(MJCF_OPTIONS)})' if mjcf else ''}")
    if mjcf:
        from .mjcf import scene_from_mjcf

        return scene_from_mjcf(spec, **urdf_options)
    if spec.endswith(".sdf"):
        from .sdf import scene_from_sdf

        return scene_from_sdf(spec)
    if spec.endswith(".urdf"):
        from .urdf import scene_from_urdf

        return scene_from_urdf(spec, **urdf_options)
    if spec.endswith((".yaml", ".yml")) or os.sep in spec or os.path.exists(spec):
        from .scene_yaml import load_scene

        return load_scene(spec)
    from .builtin import get_scene

    return get_scene(spec)
