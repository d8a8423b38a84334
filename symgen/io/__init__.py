"""Scenes in and out: the YAML format (:mod:`.scene_yaml`, :mod:`.scene_yaml_dump`,
:mod:`.yaml_exact`), the URDF (:mod:`.urdf`) and MJCF (:mod:`.mjcf`) readers, the built-in scenes
(:mod:`.builtin`, :mod:`.scenes`), :func:`.loading.load` that dispatches between them, bounded
text reading (:mod:`.textfile`) and the atomic writing of output directories (:mod:`.writer`).

The readers check what they read with the model layer (a loop drawn closed must close at ``q0``),
so this layer sits above :mod:`symgen.model`; the model never reads a file.
"""
