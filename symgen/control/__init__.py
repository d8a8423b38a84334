"""Foundations of the virtual-decomposition adaptive controller of Section 4 (eqs. 34-38).

Per subsystem and independent of the robot's velocity maps, in every field:

* :mod:`~symgen.control.parameters` -- the parameter vector ``P_r`` of eq. (35), its names,
  conversions and adaptation data (:class:`ParameterSet`);
* :mod:`~symgen.control.regressor` -- the regressors ``Y_1j``, ``Y_3i``, ``Y_alpha`` of eq. (35)
  and their applied forms ``Y P``;
* :mod:`~symgen.control.adaptation` -- the projected adaptation law of eq. (38);
* :mod:`~symgen.control.gains` -- positive-definiteness checks of feedback gains (``K_A``, eq. 34);
* :mod:`~symgen.control.pose_error` -- the required task velocity with pose feedback (float).
"""
from .adaptation import (adaptation_step, clip_to_bounds, parameter_error_energy, parameter_rate,
                         projection)
from .errors import (ControlError, ControlInputError, GainMatrixError, ParameterBoundsError,
                     ParameterError, UnknownParameterError, UpdateGainError)
from .gains import check_positive_definite, gain_matrix
from .parameters import Parameter, ParameterSet, body_inertial, body_parameters, tree_parameters
from .pose_error import (desired_twist_in_frame, log_rate_matrix, pose_error, required_twist,
                         required_twist_rate)
from .regressor import (Y_1j, Y_3i, Y_alpha, linear_coriolis, required_body_force,
                        required_joint_force, required_spherical_moment)

__all__ = [
    "ControlError", "ControlInputError", "GainMatrixError", "ParameterBoundsError", "ParameterError",
    "UnknownParameterError", "UpdateGainError", "Parameter", "ParameterSet", "body_inertial",
    "body_parameters", "tree_parameters", "Y_1j", "Y_3i", "Y_alpha", "linear_coriolis",
    "required_body_force", "required_joint_force", "required_spherical_moment", "clip_to_bounds",
    "parameter_error_energy", "parameter_rate", "projection", "adaptation_step", "check_positive_definite",
    "gain_matrix", "desired_twist_in_frame", "pose_error", "required_twist", "required_twist_rate",
    "log_rate_matrix",
]
