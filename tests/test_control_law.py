"""Section 4's controller composed from the step pipeline: the regressor identity (35), the law
(34) against the inverse dynamics (32), and its typed errors."""
from fractions import Fraction

import numpy as np
import pytest

import symgen
from symgen.control import stacked
from symgen.control.errors import ControlInputError, GainMatrixError
from symgen.control.law import control, default_parameters
from symgen.control.proofs import prove_regressor

FAST = ["chain:n=3", "four_bar", "five_bar", "arm_on_plane"]
SLOW = ["multi_arm:h=2", "stewart"]


def _derive(name):
    return symgen.derive(symgen.load(name))


@pytest.mark.parametrize("name", FAST)
def test_regressor_and_control_law_are_exact(name):
    rows = prove_regressor(_derive(name), points=2)
    assert len(rows) == 2 and all(r.passed for r in rows), [r.detail for r in rows]


@pytest.mark.slow
@pytest.mark.parametrize("name", SLOW)
def test_regressor_and_control_law_are_exact_on_large_scenes(name):
    assert all(r.passed for r in prove_regressor(_derive(name), points=1))


def test_a_required_acceleration_without_dB_dt_is_caught(monkeypatch):
    """Dropping d/dt(T_S [J_m; J_f]^-1) [V_mr; 0] from dX_r (eq. 36) breaks the law's agreement
    with the inverse dynamics (eq. 35 itself holds for any dX_r: both sides take the same one)."""
    def broken(data, v_mr, dv_mr):
        x_r, _ = original(data, v_mr, dv_mr)
        b, n, m = data.B, data.B.shape[1], len(data.V_m)
        dv = np.concatenate([np.asarray(dv_mr, dtype=object), np.array([Fraction(0)] * (n - m), dtype=object)])
        return x_r, b.v @ dv

    original = stacked.required_velocity
    monkeypatch.setattr(stacked, "required_velocity", broken)
    import symgen.control.law as law
    import symgen.control.proofs as proofs
    monkeypatch.setattr(law, "required_velocity", broken)
    monkeypatch.setattr(proofs, "required_velocity", broken)
    rows = {r.equation: r.passed for r in prove_regressor(_derive("arm_on_plane"), points=1)}
    assert rows == {"(35), (36)": True, "(34), (37)": False}


def _state(model):
    data = model.evaluate(model.reference, V_m=np.full(model.counts.m, 0.2))
    return data, default_parameters(model)


def test_gain_that_is_not_positive_definite_is_refused():
    model = _derive("chain:n=3")
    data, params = _state(model)
    with pytest.raises(GainMatrixError, match="K_A"):
        control(model, data, params, params.values, data.V_m, np.zeros(3), gain=np.diag([1.0, -1.0, 1.0]))


def test_desired_force_on_a_scene_without_constraint_forces_is_refused():
    model = _derive("four_bar")
    data, params = _state(model)
    with pytest.raises(ControlInputError, match="no constraint forces"):
        control(model, data, params, params.values, data.V_m, [0.0], eta_fr=[1.0])


def test_an_unactuated_independent_coordinate_is_refused():
    scene = symgen.load("four_bar")
    import dataclasses
    scene.joints["j1"] = dataclasses.replace(scene.joints["j1"], actuated=False)
    model = symgen.derive(scene)
    assert model.partition.u2
    data, params = _state(model)
    with pytest.raises(ControlInputError, match="not actuated"):
        control(model, data, params, params.values, data.V_m, [0.0])


def test_regressor_can_be_read_as_formulas(capsys):
    """The rotor inertia's column of Y on a 2-link chain is the required acceleration of its own
    joint and zero on the other (eq. 22): read off the symbolic regressor."""
    from symgen.cli.control import print_regressor

    print_regressor("chain:n=2", "symbolic")
    text = capsys.readouterr().out
    assert "Ir_j0:\n  j0: dV_r0\n  j1: 0\n" in text
    assert "c_j1:\n  j0: 0\n  j1: sign(qd_j1)\n" in text
