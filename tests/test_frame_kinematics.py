"""Frame kinematics, centre of mass and centroidal momentum (symgen.frame_kinematics) on closed
chains, against 50-digit central differences along a closed motion; in the exact field; the
generated NumPy and C against the Model's methods; and the typed errors of bad input. (The checks
against Pinocchio on trees are in test_frame_kinematics_pinocchio.py.)"""
from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

import symgen
from symgen.closure import random_consistent_states, refine_closure
from symgen.codegen.catalogue import build_function
from symgen.codegen.generate import trace_all
from symgen.codegen.reference import reference_states
from symgen.codegen.runtime import call_by_name, load_generated
from symgen.errors import CodegenError, StateError
from symgen.math.configuration import Configuration, CosSin
from symgen.math.fields import MpField

#: agreement of 50-digit central differences (step 10^-STEP, error O(10^-2 STEP)) with the exact derivative
STEP = 15
FD_TOL = 1e-20
#: the generated code against the Model's methods, and the float field against the exact one
TOL = 1e-12
FUNCTIONS = ("frame_pose", "frame_jacobian", "frame_drift", "center_of_mass", "com_jacobian", "centroidal_momentum",
             "centroidal_momentum_derivatives")


def _five_bar():
    """The five-bar linkage with a frame on a distal link (its dependent joints move it; the
    four-bar, a parallelogram, has ``dP/dt = 0``)."""
    scene = symgen.load("five_bar")
    scene.add_frame("probe", "distal1", xyz=(0.05, 0.02, 0.01), rpy=(0.2, -0.3, 0.4))
    return symgen.derive(scene)


#: closed chains and a frame that moves on each
CLOSED = {"five_bar": (_five_bar, "probe"), "arm_on_plane": (lambda: symgen.derive(symgen.load("arm_on_plane")), "O")}


def _vee(s):
    return np.array([s[2, 1], s[0, 2], s[1, 0]], dtype=object)


def _closed_motion(model, fld, seed=2):
    """A closed 50-digit state ``(positions, qd)`` and ``positions(t)`` at ``t = +-h`` along the motion
    with constant independent rates (``qdd = 0``): the independent angles moved by ``t qd``, the
    dependent ones re-solved (``refine_closure``)."""
    h = fld.const(10) ** -STEP            # in the field's own context (never mpmath's global 15 digits)
    (config, v_m), = random_consistent_states(model, 1, seed=seed)
    base = refine_closure(model, {n: fld.const(v) for n, v in config.positions.items()}, fld)
    qd = list(model.evaluate(Configuration(base), V_m=v_m, field=fld).qd)     # J_f qd = 0 to 50 digits
    names = model.coordinate_names()

    def at(t):
        return refine_closure(model, {**base, **{n: base[n] + t * r for n, r in zip(names, qd)}}, fld)
    return base, qd, h, {1: at(h), -1: at(-h)}


@pytest.mark.parametrize("scene", sorted(CLOSED))
def test_the_jacobians_are_50_digit_differences_of_the_pose_and_the_com_along_a_closed_motion(scene):
    make, frame = CLOSED[scene]
    model = make()
    fld = MpField(model.tree.parameters)
    base, qd, h, ends = _closed_motion(model, fld)
    cfg = {s: Configuration(p) for s, p in ends.items()}
    (r0, p0) = model.frame_pose(Configuration(base), frame, field=fld)
    (rp, pp), (rm, pm) = (model.frame_pose(cfg[s], frame, field=fld) for s in (1, -1))
    dr, dp = (rp - rm) / (2 * h), (pp - pm) / (2 * h)
    twist = {"local": np.concatenate([r0.T @ dp, _vee(r0.T @ dr)]),
             "world_aligned": np.concatenate([dp, _vee(dr @ r0.T)])}
    assert max(abs(x) for x in twist["local"]) > 1e-3           # the frame moves
    for axes, want in twist.items():
        jac = model.frame_jacobian(Configuration(base), frame, axes=axes, field=fld)
        assert max(abs(x) for x in jac @ np.array(qd, dtype=object) - want) < FD_TOL
    dc = (model.center_of_mass(cfg[1], field=fld) - model.center_of_mass(cfg[-1], field=fld)) / (2 * h)
    assert max(abs(x) for x in model.com_jacobian(Configuration(base), field=fld) @ np.array(qd, dtype=object)
               - dc) < FD_TOL
    mass = sum(fld.const(b.mass) for b in model.tree.bodies if not b.massless)
    h = model.centroidal_momentum(Configuration(base), qd, field=fld)
    assert max(abs(x) for x in h[:3] - mass * dc) < FD_TOL


@pytest.mark.parametrize("scene", sorted(CLOSED))
def test_the_drift_is_a_50_digit_difference_of_the_twist_along_a_closed_motion_at_zero_qdd(scene):
    """``J̇ qd`` with the dependent joints' ``dP/dt qd`` (eq. 11): the twist ``J(q(t)) qd`` along the
    closed motion differenced, then made classical (``+ w x v``)."""
    make, frame = CLOSED[scene]
    model = make()
    fld = MpField(model.tree.parameters)
    base, qd, h, ends = _closed_motion(model, fld)
    qd_v = np.array(qd, dtype=object)
    for axes in ("local", "world_aligned"):
        x0 = model.frame_jacobian(Configuration(base), frame, axes=axes, field=fld) @ qd_v
        xp, xm = (model.frame_jacobian(Configuration(ends[s]), frame, axes=axes, field=fld) @ qd_v for s in (1, -1))
        dx = (xp - xm) / (2 * h)
        v, w = x0[:3], x0[3:]
        want = dx if axes == "world_aligned" else np.concatenate([dx[:3] + np.cross(w, v), dx[3:]])
        got = model.frame_drift(Configuration(base), qd, frame, axes=axes, field=fld)
        assert max(abs(x) for x in got - want) < FD_TOL


def test_a_drift_without_the_dependent_joints_acceleration_is_caught(monkeypatch):
    """Planted error: ``dP/dt qd`` (eq. 11) left out of the five-bar's drift; the differences see it."""
    import symgen.frame_kinematics as fk

    model = _five_bar()
    fld = MpField(model.tree.parameters)
    base, qd, h, ends = _closed_motion(model, fld)
    qd_v = np.array(qd, dtype=object)
    xp, xm = (model.frame_jacobian(Configuration(ends[s]), "probe", axes="world_aligned", field=fld) @ qd_v
              for s in (1, -1))
    want = (xp - xm) / (2 * h)
    monkeypatch.setattr(fk, "rate_bias", lambda fld, cm, blocks, part, qd_all: fld.zeros((len(qd_all),)))
    got = model.frame_drift(Configuration(base), qd, "probe", axes="world_aligned", field=fld)
    assert max(abs(x) for x in got - want) > 1e-3


def test_the_exact_field_agrees_with_the_float_field():
    """On the chain at rational cosines and sines (3-4-5 and 5-12-13 triangles)."""
    model = symgen.derive(symgen.load("chain:n=3"))
    pairs = [(Fraction(3, 5), Fraction(4, 5)), (Fraction(5, 13), Fraction(-12, 13)), (Fraction(-4, 5), Fraction(3, 5))]
    exact = Configuration({f"j{i}": CosSin(c, s) for i, (c, s) in enumerate(pairs)})
    floats = Configuration({f"j{i}": float(np.arctan2(float(s), float(c))) for i, (c, s) in enumerate(pairs)})
    qd = [Fraction(1, 2), Fraction(-1, 3), Fraction(2, 7)]
    for method, args in (("com_jacobian", ()), ("center_of_mass", ()), ("centroidal_momentum", (qd,))):
        got = getattr(model, method)(exact, *args, field="exact")
        assert all(isinstance(x, Fraction) for x in np.ravel(got))
        want = getattr(model, method)(floats, *[[float(x) for x in a] for a in args])
        assert np.max(np.abs(np.asarray(got, float) - want)) < TOL


def test_the_symbolic_field_gives_the_centre_of_mass_jacobian_by_hand():
    """On ``chain:n=2`` (masses 1 and 1.1 kg, centres of mass 0.05 m along each link, the second
    joint 0.1 m along the first link and about its y axis): the x row of ``J_c`` over the first
    joint is ``-s0 (1 * 0.05 + 1.1 (0.1 + 0.05 c1)) / 2.1 = -s0 (11 c1 + 32) / 420`` by hand."""
    import sympy as sp

    model = symgen.derive(symgen.load("chain:n=2"))
    config = model.symbolic_configuration()
    c1, s0 = sp.Symbol("c_j1", real=True), sp.Symbol("s_j0", real=True)
    jac = model.com_jacobian(config, field="symbolic")
    assert sp.simplify(jac[0, 0] + s0 * (11 * c1 + 32) / 420) == 0


@pytest.fixture(scope="module")
def five_bar_generated():
    model = _five_bar()
    lowered = trace_all(model, FUNCTIONS, {"frame": "probe", "axes": "world_aligned"})
    return model, {target: load_generated(model, target, lowered=lowered) for target in ("numpy", "c")}


@pytest.mark.parametrize("target", ["numpy", "c"])
def test_the_generated_functions_equal_the_model_methods(five_bar_generated, target):
    model, modules = five_bar_generated
    for s in reference_states(model, 3, seed=5):
        config, qd = s["config"], s["qd"]
        want = {"frame_pose": model.frame_pose(config, "probe"),
                "frame_jacobian": (model.frame_jacobian(config, "probe", axes="world_aligned"),),
                "frame_drift": (model.frame_drift(config, qd, "probe", axes="world_aligned"),),
                "center_of_mass": (model.center_of_mass(config),), "com_jacobian": (model.com_jacobian(config),),
                "centroidal_momentum": (model.centroidal_momentum(config, qd),)}
        for name, outputs in want.items():
            got = call_by_name(modules[target], name, s)
            for g, w in zip(got, outputs):
                assert np.max(np.abs(np.asarray(g) - w)) < TOL, name


@pytest.mark.parametrize("target", ["numpy", "c"])
def test_the_generated_momentum_derivatives_equal_50_digit_differences_on_a_closed_chain(five_bar_generated, target):
    """``dh_dq`` along the five-bar's independent coordinates, the loops re-closed at 50 digits for
    every step; ``A_G`` column by column from ``Model.centroidal_momentum``."""
    model, modules = five_bar_generated
    fn = build_function(model, "centroidal_momentum_derivatives")
    for s in reference_states(model, 2, seed=6):
        want = fn.reference(s)
        got = call_by_name(modules[target], "centroidal_momentum_derivatives", s)
        assert np.max(np.abs(got[0] - want["dh_dq"])) < TOL
        assert np.max(np.abs(got[1] - want["A_G"])) < TOL
        assert np.max(np.abs(want["dh_dq"])) > 1e-2            # h does depend on q


def test_an_unknown_frame_is_named_by_the_model_and_by_the_generator():
    model = _five_bar()
    config = model.reference
    with pytest.raises(StateError, match="no frame 'tool'.*probe"):
        model.frame_jacobian(config, "tool")
    with pytest.raises(CodegenError, match="no frame 'tool'"):
        build_function(model, "frame_pose", frame="tool")
    with pytest.raises(CodegenError, match="need a frame.*probe"):
        build_function(model, "frame_jacobian")
    with pytest.raises(CodegenError, match="axes must be one of local, world_aligned"):
        build_function(model, "frame_drift", frame="probe", axes="world")
    with pytest.raises(StateError, match="qd"):
        model.centroidal_momentum(config, [1.0, 2.0, 3.0])


def test_the_command_line_generates_a_frame_jacobian_for_the_named_frame(tmp_path, capsys):
    import json

    from symgen.cli import main

    out = tmp_path / "gen"
    assert main(["generate", "five_bar", "--target", "numpy", "--out", str(out), "--functions",
                 "frame_jacobian,centroidal_momentum", "--frame", "pin_frame", "--axes", "world_aligned"]) == 0
    ops = json.loads((out / "ops.json").read_text())["functions"]
    assert ops["frame_jacobian"]["frame"] == "pin_frame" and ops["frame_jacobian"]["axes"] == "world_aligned"
    assert "def frame_jacobian(q)" in (out / "five_bar.py").read_text()
    assert main(["ops", "five_bar", "--functions", "frame_drift"]) == 2
    err = capsys.readouterr().err
    assert "need a frame" in err and "pin_frame" in err and "Traceback" not in err
