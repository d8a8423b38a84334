"""Generated forward dynamics by the null-space route (symgen.codegen.null_space): ``V_m`` the
independent rates, ``qd_all = W V_m`` with ``W = [1; -T_d^-1 T_m]``, ``M_mm = W^T M_tree W``, one
recursion for the bias, the loop forces from the rows of ``T_d``. Forced on the closed chains, a
four-bar with every joint driven (operational ``eta_f``, friction, a spring, contact forces) and
Solo12 on its four feet (``T_c = 1``): equal to the dense model (32) evaluated in 50 digits; kept
where it is cheapest; a dropped term is caught; refused where it does not apply."""
from __future__ import annotations

import pathlib

import numpy as np
import pytest

import symgen
from symgen.codegen.catalogue import build_function
from symgen.codegen.generate import trace_all
from symgen.codegen.reference import reference_states
from symgen.codegen.runtime import call_by_name, load_generated
from symgen.codegen.trace import Tracer
from symgen.errors import CodegenError
from symgen.model import derive

from .codegen_util import route_error

TOL = 1e-11
DRIVEN = str(pathlib.Path(__file__).parent / "data" / "null_space" / "driven_four_bar.yaml")


def _worst(model, target="numpy", states=3):
    return route_error(model, "null-space", target, states)


@pytest.mark.parametrize("spec", ["four_bar", "five_bar", DRIVEN, "solo12_standing"])
def test_null_space_route_equals_the_dense_model(spec):
    assert _worst(derive(symgen.load(spec))) < TOL


def test_null_space_route_in_c_equals_the_dense_model():
    assert _worst(derive(symgen.load(DRIVEN)), target="c") < TOL


def test_a_dropped_constraint_drift_is_caught(monkeypatch):
    """The check sees the accelerations at ``dV_m = 0``: without ``dT/dt qd_all`` the route
    disagrees with the dense model (on the five-bar: the parallelogram four-bar's drift vanishes
    at the rates it can take)."""
    assert _worst(derive(symgen.load("five_bar"))) < TOL
    monkeypatch.setattr(Tracer, "constraint_drift", lambda self, qd_all: [0] * self.model.counts.nc)
    assert _worst(derive(symgen.load("five_bar"))) > 1e-3


def test_standing_robots_keep_the_null_space_route():
    """Solo12 on four feet: ``T_d`` is four 3 x 3 leg blocks where the joint-space route forms and
    solves the 12 x 12 ``[J_m; J_f]`` and ``P^T M_tree P``."""
    meta = build_function(derive(symgen.load("solo12_standing")), "forward_dynamics").metadata
    costs = meta["method_costs"]
    assert meta["method"] == "null-space"
    assert costs["null-space"] < 0.7 * min(costs["joint-space"], costs["dense"])


@pytest.mark.parametrize("spec", ["arm_on_plane", "chain:n=3"])
def test_the_route_is_refused_where_it_does_not_apply(spec):
    """Motion on a frame (the arm on a plane) or no constraint at all (a chain)."""
    model = derive(symgen.load(spec))
    assert "null-space" not in build_function(model, "forward_dynamics").metadata["method_costs"]
    with pytest.raises(CodegenError, match="null-space method needs motion given on joints"):
        build_function(model, "forward_dynamics", method="null-space")


@pytest.mark.parametrize("target", ["numpy", "c"])
def test_a_straight_leg_is_reported_singular_not_divided_through(target):
    """Solo12's front-left knee straight: that leg's 3 x 3 block of ``T_d`` loses rank (hip and knee
    move the foot along one direction), and the generated code reports the singular solve."""
    model = derive(symgen.load("solo12_standing"))
    module = load_generated(model, target, lowered=trace_all(model, ["forward_dynamics"], None))
    state = dict(reference_states(model, 1, seed=1)[0])
    q = np.array(state["q"], dtype=float)
    q[7 + model.all_coordinate_names().index("FL_KFE") - 6] = 0.0    # 3 positions + 4 quaternion entries
    state["q"] = q
    match = "T_d, the constraint rows"
    with pytest.raises(module.SingularSolveError, match=match):
        call_by_name(module, "forward_dynamics", state)
