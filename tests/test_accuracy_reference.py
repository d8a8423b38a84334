"""``mp_outputs``: the generated functions' outputs at 50 digits, from the generated code's own
float inputs -- names and values against the float reference, a closed form, typed errors."""
from __future__ import annotations

import mpmath
import numpy as np
import pytest

import symgen
from symgen.accuracy import AccuracyError
from symgen.accuracy.reference import MpState, make_mp_field, mp_configuration, mp_outputs, relative_error
from symgen.codegen.catalogue import FUNCTIONS
from symgen.codegen.reference import reference_outputs, reference_states

#: the dense float model against the 50-digit reference (relative, floor 1e-2)
FLOAT_TOL = 1e-12

_models: dict = {}


def model_of(spec):
    if spec not in _models:
        _models[spec] = symgen.derive(symgen.load(spec))
    return _models[spec]


def rel(got, want) -> float:
    return float(np.max(np.abs(got - want), initial=0) / max(np.max(np.abs(want), initial=0), 1e-2))


@pytest.mark.parametrize("spec", ["four_bar", "arm_on_plane"])
def test_mp_outputs_mirror_reference_outputs(spec):
    model = model_of(spec)
    s = reference_states(model, 1, seed=4)[0]
    for name in FUNCTIONS:
        want = reference_outputs(model, name, s)
        got = mp_outputs(model, name, s)
        assert list(got) == list(want), name
        for key in want:
            assert got[key].dtype == np.float64 and got[key].shape == np.shape(want[key])
            assert rel(got[key], want[key]) < FLOAT_TOL, (name, key)


def test_stewart_reference_from_quaternions():
    """Spherical joints enter through the quaternions of ``q``: the rotations are orthonormal to
    ~1e-45 and the outputs agree with the float model."""
    model = model_of("stewart")
    s = reference_states(model, 1, seed=1)[0]
    fld = make_mp_field(model, 50)
    cfg = mp_configuration(model, s["q"], fld)
    for name, value in cfg.positions.items():
        if np.ndim(value) == 2:
            err = value @ value.T - fld.eye(3)
            assert max(abs(v) for v in err.flat) < 1e-45, name
    st = MpState(model, s, fld)
    for name in ("forward_dynamics", "inverse_dynamics", "gravity"):
        want = reference_outputs(model, name, s)
        for key, value in st.outputs(name).items():
            assert rel(fld.to_float(value), want[key]) < FLOAT_TOL, (name, key)


def test_gravity_of_two_link_chain_matches_closed_form():
    """chain:n=2: joint j1 (axis y, at x = L) carries link1 (m = 11/10, com L/2 along x), gravity
    981/100 down, so G = (0, -m g (L/2) cos q1) -- computed here in mpmath at 60 digits."""
    model = model_of("chain:n=2")
    q = np.array([0.4, -1.1])
    state = dict(q=q, V_m=np.zeros(2), eta_m=np.zeros(0))
    got = mp_outputs(model, "gravity", state, dps=50)["G"]
    with mpmath.workdps(60):
        want = -mpmath.mpf(11) / 10 * mpmath.mpf(981) / 100 * mpmath.mpf(1) / 20 * mpmath.cos(mpmath.mpf(float(q[1])))
        assert got[0] == 0
        assert got[1] == float(want)              # correctly rounded: 50 digits leave no doubt


def test_relative_error_is_exact_against_mp_reference():
    fld = make_mp_field(model_of("four_bar"), 50)
    want = np.array([fld.const(1) / 3, fld.const(-2)], dtype=object)
    third = 1 / 3                                       # float: off by |1/3 - fl(1/3)| = 1/(3 * 2^54)
    got = relative_error([third, -2.0], want, fld, floor=1e-2)
    assert got == pytest.approx(1 / (3 * 2**54) / 2, rel=1e-12)
    assert relative_error([0.0, 1e-3], np.array([fld.zero, fld.zero], dtype=object), fld, floor=1e-2) == pytest.approx(0.1)
    assert relative_error([np.nan, 0.0], want, fld, floor=1e-2) == float("inf")


def test_bad_requests_are_typed_errors():
    model = model_of("four_bar")
    s = reference_states(model, 1, seed=0)[0]
    with pytest.raises(AccuracyError, match="no_such_function"):
        mp_outputs(model, "no_such_function", s)
    with pytest.raises(AccuracyError, match="dps"):
        mp_outputs(model, "mass_matrix", s, dps=10)
    with pytest.raises(AccuracyError, match="q must have shape"):
        mp_outputs(model, "mass_matrix", dict(s, q=np.zeros(7)))
