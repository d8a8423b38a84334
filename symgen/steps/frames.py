"""Step 3: the frames. Every rigid link gets a body-fixed frame, every 1-DOF joint a single-axis
frame along its axis, and the motion and constraint specifications are written in named frames.

symgen takes the scene's frames and re-expresses them so that each 1-DOF joint moves along or
about its frame's z axis (``Z = e3`` or ``e6``, DESIGN.md section 2); the velocity configuration
space and the constraints (Step 3's other half) are the scene's ``motion`` and ``constraints``.
"""
from __future__ import annotations

from ..scene.declaration import Scene
from ..tree import Tree, build_tree


def assign_frames(scene: Scene) -> Tree:
    """Step 3: the scene's spanning tree in z-axis joint frames (:mod:`symgen.tree`): the bodies
    with their mass properties in their own frames, the joints with their placements, the named
    frames of the task and the constraints."""
    return build_tree(scene)
