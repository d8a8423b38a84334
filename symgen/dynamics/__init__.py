"""The tree recursions of rigid-body dynamics, on any field (float, exact, mp, symbolic and the code
generator's traced nodes): one implementation that the evaluator, the exact proofs and the tracer
all run (DESIGN.md section 1).

* :mod:`~symgen.dynamics.algebra`: twists, wrenches, body inertia and their transport across a joint;
* :mod:`~symgen.dynamics.transforms`: ``(R_PC, p_PC)`` of every joint at a configuration;
* :mod:`~symgen.dynamics.rnea`: ``T_S^T (M_S dX + C_S X + G_S)`` applied by the recursive
  Newton-Euler passes (eqs. 21-25), and the joint friction of eqs. (22)-(23);
* :mod:`~symgen.dynamics.crba`: the joint-space mass matrix ``T_S^T M_S T_S`` by composite inertias;
* :mod:`~symgen.dynamics.aba`: forward dynamics of a tree by the articulated-body algorithm;
* :mod:`~symgen.dynamics.rnea_derivatives`: the partials of the joint forces in closed form;
* :mod:`~symgen.dynamics.grouping`: body parameters about each origin, grouped where the joint
  forces cannot see them;
* :mod:`~symgen.dynamics.origins`: body origins moved along the joint axes, for the same forces.

:func:`tree_inverse_dynamics`, :func:`tree_mass_matrix` and :func:`tree_forward_dynamics` run
them at a configuration for a :class:`~symgen.tree.Tree`, over every tree coordinate (``N_all``):
the spanning tree's dynamics, before any loop closure.
"""
from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ..math.fields import Field
from ..kinematics import ConstantCache, constants
from ..math.configuration import Configuration
from ..tree import Tree
from .aba import SingularArticulatedInertia, articulated_body
from .crba import tree_mass_matrix as _crba
from . import rnea
from .rnea import joint_friction, joint_springs
from .algebra import Transform
from .transforms import configuration_transforms

__all__ = ["SingularArticulatedInertia", "tree_inverse_dynamics", "tree_mass_matrix", "tree_forward_dynamics"]


def _setup(tree: Tree, field: Field, config: Configuration) -> tuple[ConstantCache, list[Transform]]:
    consts = constants(tree, field)
    return consts, configuration_transforms(tree, consts, field, config)


def _vector(field: Field, values: Sequence[Any], n: int) -> np.ndarray:
    out = field.zeros((n,))
    for i, v in enumerate(values):
        out[i] = v
    return out


def tree_inverse_dynamics(tree: Tree, field: Field, config: Configuration, qd_all: Sequence[Any],
                          qdd_all: Sequence[Any], *, gravity: bool = True,
                          friction: bool = True) -> np.ndarray:
    """``tau_all`` (``N_all``) of the spanning tree at ``config``: RNEA plus the joint friction
    ``xi`` of eqs. (22)-(23) (``friction=False`` leaves it out) and the joint springs
    ``k (q - q_spring)``. ``qd_all``, ``qdd_all``: numbers of ``field`` (floats are taken exactly
    by the extended fields)."""
    consts, transforms = _setup(tree, field, config)
    qd_all = [field.const(v) for v in qd_all]
    qdd_all = [field.const(v) for v in qdd_all]
    tau = rnea.rnea(tree, consts, transforms, qd_all, qdd_all, gravity=gravity)
    if friction:
        xi = joint_friction(tree, consts, qd_all, field.sign)
        tau = [a + b for a, b in zip(tau, xi)]
    for coord, term in joint_springs(tree, consts, config.positions).items():
        tau[coord] = tau[coord] + term
    return _vector(field, tau, tree.n_coords)


def tree_mass_matrix(tree: Tree, field: Field, config: Configuration) -> np.ndarray:
    """``M_tree`` (``N_all x N_all``) of the spanning tree at ``config`` by composite inertias."""
    consts, transforms = _setup(tree, field, config)
    rows = _crba(tree, consts, transforms)
    out = field.zeros((tree.n_coords, tree.n_coords))
    for i, row in enumerate(rows):
        for j, v in enumerate(row):
            out[i, j] = v
    return out


def tree_forward_dynamics(tree: Tree, field: Field, config: Configuration, qd_all: Sequence[Any],
                          tau_all: Sequence[Any], *, gravity: bool = True,
                          friction: bool = True) -> np.ndarray:
    """``qdd_all`` of the spanning tree under joint forces ``tau_all`` by the articulated-body
    algorithm: the inverse of :func:`tree_inverse_dynamics`. Raises
    :class:`SingularArticulatedInertia` where a subtree has no inertia along its joint."""
    consts, transforms = _setup(tree, field, config)
    qd_all = [field.const(v) for v in qd_all]
    tau_all = [field.const(v) for v in tau_all]
    if friction:
        xi = joint_friction(tree, consts, qd_all, field.sign)
        tau_all = [a - b for a, b in zip(tau_all, xi)]
    for coord, term in joint_springs(tree, consts, config.positions).items():
        tau_all[coord] = tau_all[coord] - term
    return _vector(field, articulated_body(tree, consts, transforms, qd_all, tau_all, gravity=gravity),
                   tree.n_coords)
