"""Independent oracles for symgen's models. :mod:`symgen.oracle.pinocchio_check` compares a scene
built from URDF files with Pinocchio run on the same files (extra ``oracle``: package ``pin``);
:mod:`symgen.oracle.pinocchio_tree` rebuilds any scene's spanning tree in Pinocchio and
:mod:`symgen.oracle.pinocchio_constrained` compares tree and constrained dynamics with it."""
from .pinocchio_check import (TOL_CONSTRAINED, TOL_JOINT_SPACE, Difference, check_against_pinocchio,
                              compare_constrained, compare_joint_space)
from .pinocchio_model import OracleError, PinocchioRobot, pinocchio_robot
from .pinocchio_tree import TreeRobot, tree_robot

__all__ = ["Difference", "OracleError", "PinocchioRobot", "TOL_CONSTRAINED", "TOL_JOINT_SPACE",
           "check_against_pinocchio", "compare_constrained", "compare_joint_space", "pinocchio_robot",
           "TreeRobot", "tree_robot"]
