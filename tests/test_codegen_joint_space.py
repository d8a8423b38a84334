"""Generated forward dynamics by the joint-space route (``_forward_in_joint_space`` of
symgen.codegen.functions): ``M_mm = W_m^T M_q W_m``, the right-hand side ``W_m^T (tau - bias)``
from one recursion, ``eta_f`` by one solve with ``A^T``. Forced on every built-in family, trees
with ball, prismatic and fixed joints, friction and contact forces: equal to the dense model (32)
evaluated in 50 digits; the route kept is the cheapest one; a dropped term is caught."""
from __future__ import annotations

import pathlib

import pytest

import symgen
from symgen.codegen import builder
from symgen.codegen.catalogue import build_function
from symgen.model import derive

from .codegen_util import SCENES, route_error

TOL = 1e-11
DATA = pathlib.Path(__file__).parent / "data" / "aba"
#: trees with a ball joint, prismatic and fixed joints, viscous and Coulomb friction and contact
#: forces eta_m, a motion on a frame
TREES = ["spherical_arm", "prismatic_friction", "frame_motion"]


def _model(spec):
    return derive(symgen.load(str(DATA / f"{spec}.yaml")) if spec in TREES else symgen.load(spec))


def _worst(model, target="numpy", states=3):
    return route_error(model, "joint-space", target, states)


@pytest.mark.parametrize("spec", [s for s in SCENES if s != "multi_arm:h=3"] + ["chain:n=12"] + TREES)
def test_joint_space_route_equals_the_dense_model(spec):
    assert _worst(_model(spec)) < TOL


@pytest.mark.parametrize("spec", ["four_bar", "multi_arm:h=2"])
def test_joint_space_route_in_c_equals_the_dense_model(spec):
    assert _worst(_model(spec), target="c") < TOL


def test_a_dropped_contact_term_is_caught(monkeypatch):
    """The check sees the bias: the contact forces ``D_m^T eta_m`` left out of the recursion's
    forces make the joint-space route disagree with the dense model."""
    model = _model("prismatic_friction")
    assert _worst(model) < TOL
    monkeypatch.setattr(builder.Builder, "contact_term", lambda self, eta_m: [0] * self.n)
    assert _worst(model) > 1e-3


@pytest.mark.parametrize("spec", ["chain:n=6", "arm_on_plane", "four_bar", "multi_arm:h=2"])
def test_the_cheapest_route_is_kept(spec):
    meta = build_function(_model(spec), "forward_dynamics").metadata
    costs = meta["method_costs"]
    assert "joint-space" in costs and "dense" in costs
    assert costs[meta["method"]] == min(costs.values())
    if costs["joint-space"] == costs["dense"]:
        assert meta["method"] == "dense"          # a tie keeps the dense route


def test_arms_holding_an_object_are_cheaper_through_the_joint_space():
    """Two arms holding an object (m = 6 of n = 12): the joint-space route solves A for m
    columns where the dense one solves A^T for all n columns of M_q twice."""
    costs = build_function(_model("multi_arm:h=2"), "forward_dynamics").metadata["method_costs"]
    assert costs["joint-space"] < 0.8 * costs["dense"]
