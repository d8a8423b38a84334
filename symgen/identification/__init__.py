"""Inertial-parameter identification from the regressor of Section 4 (eqs. 34-37).

* :mod:`~symgen.identification.regressor` -- ``Y P = tau - J_f^T eta_f`` on the independent
  coordinates (or ``Omega^T`` of it when ``eta_f`` is not measured);
* :mod:`~symgen.identification.states` -- loop-closed states ``(q, qd, qdd)``;
* :mod:`~symgen.identification.base` -- base parameters by column-pivoted QR;
* :mod:`~symgen.identification.trajectory` -- optimised Fourier exciting trajectories;
* :mod:`~symgen.identification.data` -- the CSV format, its checks, simulated samples;
* :mod:`~symgen.identification.batch` -- the rows of every sample in one generated, batched call;
* :mod:`~symgen.identification.estimate` -- two-step weighted least squares with standard deviations;
* :mod:`~symgen.identification.consistent` -- every standard parameter under pseudo-inertia LMIs (cvxpy);
* :mod:`~symgen.identification.export` -- identified parameters back into a scene file;
* :mod:`~symgen.identification.errors` -- the typed errors.
"""
from .base import BaseParameters, base_from_regressor, base_parameters
from .data import Samples, read_csv, simulated_samples, write_csv
from .errors import (ConsistencyError, DataColumnError, DataFileError, IdentificationError, NonFiniteSampleError,
                     OptionError, SampleRangeError, TooFewSamplesError)
from .estimate import Estimate, identify, observations, weighted_least_squares
from .regressor import Problem, make_problem, sample_rows, stacked_regressor
from .states import State, random_states
from .trajectory import FourierTrajectory, optimise_trajectory, random_trajectory

__all__ = ["BaseParameters", "base_from_regressor", "base_parameters", "Samples", "read_csv", "simulated_samples",
           "write_csv", "ConsistencyError", "DataColumnError", "DataFileError", "IdentificationError",
           "NonFiniteSampleError", "OptionError", "SampleRangeError", "TooFewSamplesError", "Estimate", "identify",
           "observations", "weighted_least_squares", "Problem", "make_problem", "sample_rows", "stacked_regressor",
           "State", "random_states", "FourierTrajectory", "optimise_trajectory", "random_trajectory"]
