"""The twelve steps of Section 3.1 of the paper, one function each; read top to bottom.

=====  =====================================  ==============================================
step   function                               computes
=====  =====================================  ==============================================
1      :func:`count_joints`                   ``n1a, n1u, n3a, n3u`` (eqs. 3-4)
2      :func:`counts_from`                    ``m``, ``n_c`` (eq. 5)
3      :func:`assign_frames`                  body, joint and task frames (the spanning tree)
4      :func:`constraint_matrix`              ``T = [T_a, T_u]`` (eq. 6); ``n_p`` = rank ``T_u``
5      :func:`choose_partition`               ``q_u1, q_u2, q_a1, q_a2`` with ``[T_u1, T_a1]`` invertible (eq. 8)
6      :func:`constraint_blocks`              ``T11, T12, T21, T22`` (eq. 9)
7      :func:`constraint_map`                 ``T_c``, ``J_f`` (eq. 12)
8      :func:`counts_from`, :func:`rate_map`  ``n`` (eq. 13); ``qd`` (eq. 14) and ``P`` (eq. 10)
9      :func:`contact_map`                    ``D_m`` (eq. 16)
10     :func:`task_map`,                      ``J_m`` (eq. 17),
       :func:`inverse_task_map`               ``[J_m; J_f]^-1 = [Omega, Psi]`` (eq. 18)
11     :func:`velocity_map`                   ``T_S`` (eq. 25)
12     :func:`subsystem_terms`,               ``M_S, C_S, G_S`` (eqs. 21-24),
       :func:`task_space_model`               model (32) (and :func:`joint_space_model`)
=====  =====================================  ==============================================

Steps 1, 2, 5 and the dimensions of 4 and 8 are structural, decided once at the reference
configuration (:mod:`.structure`). The others take a field and jets and run unchanged in floats,
exact rationals, SymPy, 50-digit mpmath and the code generator's traced numbers.
:func:`evaluate_maps` composes Steps 4-11. :mod:`.loop_forces` adds the forces of every
loop-closure constraint (``lam``), from the same steps run on the tree with all joints free.
"""
from .constraints import (ConstraintBlocks, ConstraintMap, ConstraintMatrix, constraint_blocks, constraint_map,
                          constraint_matrix)
from .frames import assign_frames
from .joint_space import (RateMap, all_accelerations, all_rates, project, project_by_solve, rate_bias,
                          rate_bias_of_drift, rate_map, rates_by_solve)
from .loop_forces import (FORCE_NAMES, closure_multipliers, general_constraint_forces, tree_forces,
                          tree_velocity_map)
from .pipeline import Maps, evaluate_maps, jet_names, task_matrix_at
from .structure import (Counts, Partition, check_full_row_rank, choose_partition, count_joints, counts_from)
from .subsystem_space import (DynamicModel, SubsystemTerms, VelocityMap, congruence, coriolis_congruence, joint_force,
                              joint_space_model, mass_congruence, subsystem_terms, task_gravity, task_space_model,
                              velocity_map, velocity_product)
from .task_space import (ContactMap, InverseTaskMap, TaskMap, acceleration_bias, contact_map, contact_rows, frame_rows,
                         TASK_MATRIX, inverse_task_map, motion_rows, task_map, task_matrix)

__all__ = [
    "FORCE_NAMES", "ConstraintBlocks", "ConstraintMap", "ConstraintMatrix", "ContactMap", "Counts",
    "DynamicModel", "InverseTaskMap", "Maps", "Partition", "RateMap", "SubsystemTerms", "TaskMap", "VelocityMap",
    "acceleration_bias", "all_accelerations", "all_rates", "assign_frames", "check_full_row_rank",
    "choose_partition", "closure_multipliers", "congruence", "constraint_blocks", "coriolis_congruence", "constraint_map",
    "constraint_matrix", "contact_map", "contact_rows", "count_joints", "counts_from", "evaluate_maps",
    "frame_rows", "general_constraint_forces", "inverse_task_map", "jet_names", "joint_force", "joint_space_model",
    "mass_congruence", "motion_rows", "project", "project_by_solve", "rate_bias", "rate_bias_of_drift", "rate_map",
    "rates_by_solve", "TASK_MATRIX", "subsystem_terms", "task_gravity", "task_map", "task_matrix",
    "task_matrix_at", "task_space_model", "tree_forces", "tree_velocity_map", "velocity_map", "velocity_product",
]
