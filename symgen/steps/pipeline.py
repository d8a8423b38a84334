"""Steps 4-11 composed at one configuration, in any field: the record every caller reads.

This is the only place the steps are chained; the dense evaluator (:meth:`symgen.model.Model.evaluate`),
the stability metrics and the proofs read the :class:`Maps` it returns, and the code generator's
tracer calls the same step functions on traced numbers.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol

from ..math.jet import Jet
from ..math.scalar import FieldVector
from ..kinematics import TreeKinematics, tree_kinematics
from .constraints import ConstraintBlocks, ConstraintMap, ConstraintMatrix, constraint_blocks, constraint_map, \
    constraint_matrix
from .joint_space import RateMap, rate_map
from .subsystem_space import VelocityMap, velocity_map
from .structure import Partition
from .task_space import ContactMap, InverseTaskMap, TaskMap, contact_map, inverse_task_map, task_map, task_matrix

if TYPE_CHECKING:
    from ..math.configuration import Configuration
    from ..math.fields import Field
    from ..scene.declaration import Scene
    from ..tree import Tree


class DerivedModel(Protocol):
    """What the steps read of a derived model (:class:`symgen.model.Model` is one; it imports
    this package, so the steps name it by what they use): the scene, its tree and Step 5's
    partition."""

    @property
    def scene(self) -> Scene: ...

    @property
    def tree(self) -> Tree: ...

    @property
    def partition(self) -> Partition: ...


@dataclass(frozen=True)
class Maps:
    """Every kinematic quantity of Steps 4-11 at one configuration (jets), by step."""

    kin: TreeKinematics
    constraints: ConstraintMatrix      # Step 4, eq. (6)
    blocks: ConstraintBlocks           # Step 6, eq. (9)
    constraint: ConstraintMap          # Step 7, eq. (12)
    rates: RateMap                     # Step 8, eqs. (10), (14)
    contact: ContactMap                # Step 9, eq. (16)
    task: TaskMap                      # Step 10, eq. (17)
    inverse: InverseTaskMap            # Step 10, eq. (18)
    velocity: VelocityMap              # Step 11, eq. (25)

    # the paper's names, for inspection (``symgen steps -q NAME``)
    T = property(lambda self: self.constraints.T)
    T_a = property(lambda self: self.constraints.T_a)
    T_u = property(lambda self: self.constraints.T_u)
    W = property(lambda self: self.blocks.W)
    T11 = property(lambda self: self.blocks.T11)
    T12 = property(lambda self: self.blocks.T12)
    T21 = property(lambda self: self.blocks.T21)
    T22 = property(lambda self: self.blocks.T22)
    T_c = property(lambda self: self.constraint.T_c)
    J_f = property(lambda self: self.constraint.J_f)
    P = property(lambda self: self.rates.P)
    D_m = property(lambda self: self.contact.D_m)
    J_m = property(lambda self: self.task.J_m)
    A = property(lambda self: self.inverse.A)
    A_inv = property(lambda self: self.inverse.A_inv)
    Omega = property(lambda self: self.inverse.Omega)
    Psi = property(lambda self: self.inverse.Psi)
    T_S = property(lambda self: self.velocity.T_S)

    #: the names above, in the order of the steps
    NAMES = ("T", "T_a", "T_u", "W", "T11", "T12", "T21", "T22", "T_c", "J_f", "P", "J_m", "D_m", "A",
             "Omega", "Psi", "T_S")


def _rates(model: DerivedModel, kin: TreeKinematics,
           field: Field) -> tuple[ConstraintMatrix, ConstraintBlocks, RateMap]:
    """Steps 4, 6 and 8: ``T`` (eq. 6), its blocks (eq. 9) and ``P`` (eq. 10)."""
    cm = constraint_matrix(kin, model.scene.constraints.values(), model.partition)  # Step 4
    blocks = constraint_blocks(field, cm, model.partition)                         # Step 6
    return cm, blocks, rate_map(field, blocks, model.partition)                    # Step 8


def _task(model: DerivedModel, kin: TreeKinematics, field: Field, cm: ConstraintMatrix, blocks: ConstraintBlocks,
          rates: RateMap) -> tuple[ConstraintMap, TaskMap, InverseTaskMap]:
    """Steps 7 and 10: ``J_f`` (eq. 12), ``J_m`` (eq. 17) and ``[J_m; J_f]^-1`` (eq. 18)."""
    scene = model.scene
    forces = constraint_map(field, cm, blocks, rates.P, model.partition, scene.constraint_forces)  # Step 7
    task = task_map(field, kin, scene.motion, rates.P)                                            # Step 10
    return forces, task, inverse_task_map(field, task, forces)                                    # Step 10


def evaluate_maps(model: DerivedModel, config: Configuration, field: Field,
                  qd_all: FieldVector | None = None) -> Maps:
    """Steps 4-11 of ``model`` at ``config`` in ``field``; time derivatives along ``qd_all``
    (all joint rates) when given, else zero."""
    kin = tree_kinematics(model.tree, field, config, qd_all)
    cm, blocks, rates = _rates(model, kin, field)
    forces, task, inverse = _task(model, kin, field, cm, blocks, rates)
    contact = contact_map(field, kin, model.scene.contact_forces, rates.P)          # Step 9
    velocity = velocity_map(field, kin, rates.P)                                    # Step 11
    return Maps(kin, cm, blocks, forces, rates, contact, task, inverse, velocity)


def joint_rate_maps(model: DerivedModel, config: Configuration, field: Field,
                    with_task: bool) -> tuple[RateMap, Jet | None]:
    """What turns velocity coordinates into the rates of every joint, before the time derivatives
    along those rates can be taken: Step 8's ``P`` (eq. 10) and, ``with_task``, Step 10's ``Omega``
    (eq. 18, ``qd = Omega V_m``), from Steps 4, 6, 7, 8 and 10 without derivatives (Steps 9 and 11
    are not needed)."""
    kin = tree_kinematics(model.tree, field, config)
    cm, blocks, rates = _rates(model, kin, field)
    if not with_task:
        return rates, None
    return rates, _task(model, kin, field, cm, blocks, rates)[2].Omega


def jet_names(maps: Maps) -> dict[str, Jet]:
    """The named jets of :attr:`Maps.NAMES`."""
    return {name: getattr(maps, name) for name in Maps.NAMES}


def task_matrix_at(model: DerivedModel, config: Configuration, field: Field) -> Jet:
    """``A = [J_m; J_f]`` (eq. 18) at ``config`` by Steps 4-10, without inverting it: what a
    singular ``A`` is diagnosed from."""
    kin = tree_kinematics(model.tree, field, config)
    cm, blocks, rates = _rates(model, kin, field)
    forces = constraint_map(field, cm, blocks, rates.P, model.partition, model.scene.constraint_forces)
    return task_matrix(field, task_map(field, kin, model.scene.motion, rates.P), forces)
