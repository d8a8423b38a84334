"""The catalogue of generated functions is the one list: defaults, on-request ones, options and
their dense references all come from it."""
from __future__ import annotations

import pytest

import symgen
from symgen.codegen import catalogue
from symgen.codegen.reference import REFERENCE_OUTPUTS
from symgen.errors import CodegenError

#: traced functions that carry their own dense reference (the controller's and the frame functions', with their options)
OWN_REFERENCE = {"control", "adaptation", "frame_pose", "frame_jacobian", "frame_drift", "center_of_mass",
                 "com_jacobian", "centroidal_momentum", "centroidal_momentum_derivatives"}


def test_every_function_has_a_dense_reference():
    missing = [name for name in catalogue.CATALOGUE if name not in REFERENCE_OUTPUTS and name not in OWN_REFERENCE]
    assert not missing


def test_defaults_and_on_request_partition_the_catalogue():
    assert set(catalogue.FUNCTIONS) | set(catalogue.ON_REQUEST) == set(catalogue.CATALOGUE)
    assert not set(catalogue.FUNCTIONS) & set(catalogue.ON_REQUEST)
    assert catalogue.FUNCTIONS[0] == "inverse_dynamics"


def test_an_unknown_function_lists_the_catalogue():
    model = symgen.derive(symgen.load("chain:n=2"))
    with pytest.raises(CodegenError, match="choose from inverse_dynamics, task_inverse_dynamics"):
        catalogue.build_function(model, "kinetic_energy")


def test_an_option_goes_only_to_the_functions_that_take_it():
    model = symgen.derive(symgen.load("chain:n=2"))
    fn = catalogue.build_function(model, "mass_matrix", method="dense")       # ignored: not an option of it
    assert fn.name == "mass_matrix"
    with pytest.raises(CodegenError, match="unknown generation option"):
        catalogue.build_function(model, "mass_matrix", colour="red")
