"""The model API's derivatives with spherical and free joints: ``Model.state_derivative_jacobian``
(in the entries of the state's quaternions) and ``Model.forward_dynamics_derivatives`` (three turn
columns per spherical joint), on a chain with a ball wrist and on a free-floating trunk.

* against the generated NumPy (and C) functions, which the API's function is also the reference
  of (:mod:`symgen.dynamics_jacobians`), to 1e-9 relative;
* against an independent float check: central differences of the right-hand side written here
  from the float model (``Model.forward_dynamics``, ``Model.joint_rates``) and the simulation's
  quaternion rate, each quaternion stepped *on* the unit sphere along three turns, plus its radial
  direction (which must move nothing): a full basis of the state, so the whole Jacobian is checked;
* planted errors (the quaternion rate taken in the parent frame, one column's sign) are caught;
  what is still refused, by name.
"""
from __future__ import annotations

import functools
import pathlib
import shutil

import numpy as np
import pytest

import symgen
from symgen import dynamics_jacobians
from symgen.codegen.catalogue import build_function
from symgen.codegen.generate import trace_all
from symgen.codegen.reference import reference_states
from symgen.codegen.runtime import call_by_name, load_generated
from symgen.dynamics_jacobians import state_layout
from symgen.errors import StateError
from symgen.math.fields import MpField
from symgen.simulation.state import quaternion_multiply, quaternion_rate

from .codegen_util import relative_error

DATA = pathlib.Path(__file__).parent / "data" / "derivatives"
#: revolute, revolute, prismatic, ball wrist: q has 7 entries, x 13
WRIST = str(DATA / "spherical_wrist.yaml")
#: a free joint (x, y, z, quaternion) and a hinge: q has 8 entries, x 15
FREE = str(DATA / "free_pendulum.yaml")
FUNCTIONS = ["state_derivative_jacobian", "forward_dynamics_derivatives"]
#: the API (50-digit differences) against the generated float code
GENERATED_TOL = 1e-9
#: against float central differences, step 1e-6: truncation and rounding both about 1e-10
FLOAT_FD_TOL = 1e-6
STEP = 1e-6
needs_cc = pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler")


class Case:
    """A scene, its generated NumPy module, one reference state and the API's state Jacobian there."""

    def __init__(self, spec: str, seed: int = 3):
        self.model = symgen.derive(symgen.load(spec))
        self.lowered = trace_all(self.model, FUNCTIONS)
        self.numpy = load_generated(self.model, "numpy", lowered=self.lowered)
        self.s = reference_states(self.model, 1, seed=seed)[0]
        s = self.s
        self.api = {k: MpField().to_float(v).astype(float) for k, v in
                    self.model.state_derivative_jacobian(s["config"], s["V_m"], s["tau"]).items()}


@functools.cache
def _case(spec: str) -> Case:
    return Case(spec)


@pytest.fixture(params=[WRIST, FREE], ids=["ball_wrist", "free_base"])
def case(request):
    return _case(request.param)


@pytest.fixture
def wrist():
    return _case(WRIST)


# ------------------------------------------------------------------ the independent float check
def _rhs(model, x: np.ndarray, tau: np.ndarray) -> np.ndarray:
    """The simulation's right-hand side from the float dense model: 1-DOF rates, each quaternion's
    ``1/2 (p/|p|) (x) (0, w)`` (:func:`symgen.simulation.state.quaternion_rate`), ``dV_m`` of (32)."""
    layout = state_layout(model)
    nq = sum(size for *_, size in layout)
    q, v_m = x[:nq], x[nq:]
    dv, _ = model.forward_dynamics(q, v_m, tau)
    rates = model.joint_rates(q, v_m)
    first = {}
    for c, coord in enumerate(model.tree.coordinates):
        first.setdefault(coord.joint, c)
    qdot = []
    for name, off, size in layout:
        c = first[name]
        if size == 1:
            qdot.append([rates[c]])
        else:
            p = q[off:off + 4] / np.linalg.norm(q[off:off + 4])
            qdot.append(quaternion_rate(p, rates[c:c + 3]))
    return np.concatenate(qdot + [dv])


def _directions(model, x: np.ndarray) -> np.ndarray:
    """A basis of the state's space (columns): a plain step per 1-DOF or ``V_m`` entry; per unit
    quaternion ``p`` the three turns ``1/2 p (x) (0, e_k)`` (orthogonal to ``p``) and ``p`` itself."""
    d = np.zeros((x.size, x.size))
    col = 0
    for _, off, size in state_layout(model):
        if size == 1:
            d[off, col] = 1.0
            col += 1
            continue
        p = x[off:off + 4]
        for k in range(3):
            d[off:off + 4, col + k] = 0.5 * quaternion_multiply(p, np.eye(4)[k + 1])
        d[off:off + 4, col + 3] = p
        col += 4
    d[col:, col:] = np.eye(x.size - col)
    return d


def _moved(model, x: np.ndarray, step: np.ndarray) -> np.ndarray:
    """``x + step`` with each quaternion put back on the unit sphere."""
    y = x + step
    for _, off, size in state_layout(model):
        if size == 4:
            y[off:off + 4] /= np.linalg.norm(y[off:off + 4])
    return y


def _float_worst(model, s: dict, d_x: np.ndarray) -> float:
    """Worst relative difference of ``d_x @ D`` from central differences along the columns of
    ``D`` (:func:`_directions`), the quaternions kept on the unit sphere."""
    x = np.concatenate([s["q"], s["V_m"]])
    x[:s["q"].size] = _moved(model, x, np.zeros(x.size))[:s["q"].size]
    d = _directions(model, x)
    fd = np.array([(_rhs(model, _moved(model, x, STEP * d[:, k]), s["tau"])
                    - _rhs(model, _moved(model, x, -STEP * d[:, k]), s["tau"])) / (2 * STEP)
                   for k in range(x.size)]).T
    return relative_error(d_x @ d, fd)


def _generated_worst(module, case: Case, api: dict) -> float:
    got = call_by_name(module, "state_derivative_jacobian", case.s)
    return max(relative_error(g, api[name]) for name, g in zip(("dxdot_dx", "dxdot_dtau"), got, strict=True))


# ------------------------------------------------------------------ the state Jacobian
def test_the_api_s_state_jacobian_has_the_generated_layout(case):
    nq, m, n = case.s["q"].size, case.model.counts.m, case.model.counts.n
    assert case.api["dxdot_dx"].shape == (nq + m, nq + m) and case.api["dxdot_dtau"].shape == (nq + m, n)
    assert any(size == 4 for *_, size in state_layout(case.model))


def test_the_api_s_state_jacobian_equals_the_generated_numpy(case):
    assert _generated_worst(case.numpy, case, case.api) < GENERATED_TOL


def test_the_api_s_state_jacobian_equals_float_differences_on_the_unit_sphere(case):
    assert _float_worst(case.model, case.s, case.api["dxdot_dx"]) < FLOAT_FD_TOL


def test_a_radial_change_of_a_quaternion_moves_nothing(case):
    d_x = case.api["dxdot_dx"]
    for _, off, size in state_layout(case.model):
        if size == 4:
            radial = np.zeros(d_x.shape[1])
            radial[off:off + 4] = case.s["q"][off:off + 4]
            assert np.max(np.abs(d_x @ radial)) < 1e-13 * np.max(np.abs(d_x))
            assert np.max(np.abs(d_x[:, off:off + 4])) > 1e-1


def test_a_flat_q_and_a_mapping_of_quaternions_give_the_same_jacobian(wrist):
    """The state itself (the generated ``q``), and a mapping with the wrist's quaternion, read as
    the rotation matrix of ``s['config']`` is (:func:`symgen.dynamics_jacobians.state_positions`)."""
    model, s = wrist.model, wrist.s
    q = dict(zip([name for name, *_ in state_layout(model)], [s["q"][0], s["q"][1], s["q"][2], s["q"][3:7]]))
    for config in (s["q"], q):
        got = model.state_derivative_jacobian(config, s["V_m"], s["tau"], field="mp:30")
        assert relative_error(MpField().to_float(got["dxdot_dx"]), wrist.api["dxdot_dx"]) < 1e-12


def test_the_float_check_catches_one_column_of_the_wrong_sign(wrist):
    planted = wrist.api["dxdot_dx"].copy()
    planted[:, 4] *= -1                                  # a quaternion entry of the wrist
    assert _float_worst(wrist.model, wrist.s, planted) > 1e3 * FLOAT_FD_TOL


def test_the_checks_catch_the_quaternion_rate_taken_in_the_parent_frame(wrist, monkeypatch):
    """``1/2 (0, w) (x) p`` instead of ``1/2 p (x) (0, w)``, planted in the API's right-hand side:
    both the generated code and the float differences disagree."""
    right = dynamics_jacobians.quaternion_product
    monkeypatch.setattr(dynamics_jacobians, "quaternion_product", lambda a, b: right(b, a))
    s = wrist.s
    planted = {k: MpField().to_float(v).astype(float) for k, v in
               wrist.model.state_derivative_jacobian(s["config"], s["V_m"], s["tau"], field="mp:30").items()}
    assert _generated_worst(wrist.numpy, wrist, planted) > 1e3 * GENERATED_TOL
    assert _float_worst(wrist.model, s, planted["dxdot_dx"]) > 1e3 * FLOAT_FD_TOL


# ------------------------------------------------------------------ forward dynamics: three turns
def _forward_worst(module, case: Case) -> float:
    """The generated ``forward_dynamics_derivatives`` against the API's (computed once per case):
    same outputs, same shapes -- ``d/dq`` with three turn columns per spherical joint."""
    model, s = case.model, case.s
    if not hasattr(case, "forward"):
        case.forward = {k: MpField().to_float(v).astype(float) for k, v in
                        model.forward_dynamics_derivatives(s["config"], s["V_m"], s["tau"]).items()}
    names = [a.name for a, _ in build_function(model, "forward_dynamics_derivatives").outputs]
    got = call_by_name(module, "forward_dynamics_derivatives", s)
    assert set(case.forward) == set(names)
    columns = sum(1 if size == 1 else 3 for *_, size in state_layout(model))
    assert case.forward["ddV_m_dq"].shape == (model.counts.m, columns) == got[names.index("ddV_m_dq")].shape
    return max(relative_error(g, case.forward[name]) for name, g in zip(names, got, strict=True))


def test_the_api_s_forward_derivatives_equal_the_generated_numpy(case):
    assert _forward_worst(case.numpy, case) < GENERATED_TOL


@needs_cc
def test_the_api_s_forward_derivatives_equal_the_generated_c(wrist):
    assert _forward_worst(load_generated(wrist.model, "c", lowered=wrist.lowered), wrist) < GENERATED_TOL


# ------------------------------------------------------------------ what is refused
def test_a_zero_quaternion_in_the_state_is_refused_by_name(wrist):
    q = wrist.s["q"].copy()
    q[3:7] = 0.0
    with pytest.raises(StateError, match="joint 'wrist'.*zero quaternion"):
        wrist.model.state_derivative_jacobian(q, wrist.s["V_m"], wrist.s["tau"])


def test_a_q_of_the_wrong_length_is_refused_with_the_layout(wrist):
    with pytest.raises(StateError, match=r"7 real numbers.*wrist \(w, x, y, z\)"):
        wrist.model.state_derivative_jacobian(np.zeros(6), wrist.s["V_m"], wrist.s["tau"])
