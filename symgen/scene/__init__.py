"""The scene layer: what a user declares about a robot, checked as it is declared.

:class:`Scene` (in :mod:`.declaration`) holds bodies, joints, frames, constraints and the task-space
choice; :mod:`.elements` are its records, :mod:`.checks` the physical checks of masses, inertias
and topology, :mod:`.joint_kinds` the registry of joint kinds, and :mod:`.input_limits` the bounds
on every number a user may give. Readers of files live in :mod:`symgen.io`; what the derivation
makes of a scene lives in :mod:`symgen.model`.
"""
from .declaration import Scene
from .elements import CONSTRAINT_KINDS, WORLD, Body, Constraint, ContactForces, Frame, Joint, Motion, Pose

__all__ = ["CONSTRAINT_KINDS", "WORLD", "Body", "Constraint", "ContactForces", "Frame", "Joint", "Motion", "Pose",
           "Scene"]
