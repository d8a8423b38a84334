"""The tree recursions of symgen.dynamics against the dense Step 12 of model (32), in every field.

Float: to 1e-12 relative at random states of every built-in. Exact: equal, with no tolerance, at
rational configurations (``symgen prove``'s property (g)). A planted error in each recursion (a
wrong transport sign, a missing gyroscopic term) is caught.
"""
from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

import symgen
from symgen import proofs
from symgen.math.fields import ExactField, MpField
from symgen.dynamics import (SingularArticulatedInertia, aba, algebra, crba, rnea, tree_forward_dynamics,
                             tree_inverse_dynamics, tree_mass_matrix)

#: float residuals of the recursions, relative to the largest entry of the dense result
FLOAT_TOL = 1e-12
SCENES = ["chain:n=6", "four_bar", "five_bar", "arm_on_plane", "multi_arm:h=2", "stewart", "general_chain:n=7"]
#: the scenes whose spanning tree has a regular articulated inertia everywhere
ABA_SCENES = ["chain:n=6", "arm_on_plane", "general_chain:n=7"]


@pytest.fixture(scope="module", params=SCENES)
def model(request):
    return symgen.derive(symgen.load(request.param))


def _exact_point(model, seed=0):
    rng = np.random.default_rng(seed)
    cfg, v_m = proofs.random_exact_state(model, rng)
    d = model.evaluate(cfg, V_m=v_m, field=ExactField(model.tree.parameters))
    qdd = np.array([Fraction(int(rng.integers(-9, 10)), int(rng.integers(1, 7))) for _ in range(model.counts.n)],
                   dtype=object)
    return cfg, d, qdd


def _rel(residual, scale):
    return float(np.max(np.abs(np.asarray(residual, dtype=float)))) / max(1.0, float(np.max(np.abs(scale))))


def test_float_recursions_equal_the_dense_joint_space_model(model):
    rng = np.random.default_rng(1)
    for cfg, v_m in symgen.closure.random_consistent_states(model, 3, seed=2):
        d = model.evaluate(cfg, V_m=v_m)
        qdd = rng.uniform(-1, 1, model.counts.n)
        res = proofs.recursion_residuals(model, cfg, d, qdd)
        assert _rel(res["rnea"], d.M_q @ qdd + d.C_q @ d.qd + d.G_q) < FLOAT_TOL
        assert _rel(res["crba"], d.M_q) < FLOAT_TOL
        if res["aba"] is not None:
            assert _rel(res["aba"], qdd) < 1e3 * FLOAT_TOL


#: exact here; ``symgen prove`` (property g, the slow cases of tests/test_proofs.py) covers the
#: two-arm scene and the Stewart platform, whose exact evaluation takes about 20 s each
QUICK = ["chain:n=6", "four_bar", "five_bar", "arm_on_plane"]


@pytest.mark.parametrize("spec", QUICK)
def test_exact_recursions_equal_the_dense_joint_space_model(spec):
    model = symgen.derive(symgen.load(spec))
    cfg, d, qdd = _exact_point(model)
    res = proofs.recursion_residuals(model, cfg, d, qdd)
    assert all(v == 0 for v in res["rnea"])
    assert all(v == 0 for v in np.ravel(res["crba"]))
    if model.scene.name in ("chain_n6", "arm_on_plane", "multi_arm_h2"):
        assert res["aba"] is not None and all(v == 0 for v in res["aba"])


@pytest.mark.parametrize("spec", ABA_SCENES)
def test_articulated_body_applies_where_expected(spec):
    model = symgen.derive(symgen.load(spec))
    cfg, d, qdd = _exact_point(model)
    assert proofs.recursion_residuals(model, cfg, d, qdd)["aba"] is not None


def test_a_massless_subtree_makes_the_articulated_inertia_singular():
    """The four-bar's spanning tree ends in a link whose joint carries no inertia once the loop is
    cut: ABA refuses it by name (the code generator keeps the dense route there)."""
    model = symgen.derive(symgen.load("four_bar"))
    fld = ExactField(model.tree.parameters)
    cfg, _ = proofs.random_exact_state(model, np.random.default_rng(0))
    with pytest.raises(SingularArticulatedInertia, match="joint '"):
        tree_forward_dynamics(model.tree, fld, cfg, [0] * model.tree.n_coords, [1] * model.tree.n_coords)


def test_mp_recursions_agree_with_float():
    model = symgen.derive(symgen.load("chain:n=6"))
    q = model.reference
    qd, qdd = np.linspace(-1, 1, 6), np.linspace(0.5, -0.5, 6)
    fld = MpField(model.tree.parameters)
    tau_mp = fld.to_float(tree_inverse_dynamics(model.tree, fld, q, qd, qdd))
    tau = tree_inverse_dynamics(model.tree, symgen.math.fields.make_field("float", model.tree.parameters), q, qd, qdd)
    assert np.max(np.abs(tau - tau_mp)) < 1e-12 * max(1.0, np.max(np.abs(tau_mp)))
    assert np.allclose(tree_mass_matrix(model.tree, fld, q).astype(float),
                       model.evaluate(q).M_q, rtol=0, atol=1e-12)


# ------------------------------------------------------------------ planted errors
def _proof_rows(model, points=1):
    return {r.name: r for r in proofs.prove_sampled(model, points=points)}


@pytest.fixture(scope="module")
def chain():
    return symgen.derive(symgen.load("chain:n=6"))


def test_a_missing_gyroscopic_term_is_caught(chain, monkeypatch):
    """The body moment without ``w x (I w)`` (only ``I dw``)."""
    monkeypatch.setattr(rnea, "euler_moment", lambda inertia, w, dw, is_zero: algebra.rotate(inertia, dw))
    rows = _proof_rows(chain)
    assert not rows["RNEA equals M_q qdd + C_q qd + G_q"].passed


def _rational(rng, lo=-9, hi=10):
    return Fraction(int(rng.integers(lo, hi)), int(rng.integers(1, 8)))


@pytest.mark.parametrize("zeros", [(), ((0, 1),), ((0, 1), (0, 2), (1, 2)), ((1, 1), (0, 2))])
def test_the_expanded_euler_moment_is_i_dw_plus_w_cross_i_w(zeros):
    """``euler_moment`` (the products of ``w`` shared with ``K``) equals ``I dw + w x (I w)`` computed
    the textbook way, exactly, for a full symmetric inertia and with structural zeros (dropped
    terms must be the zero ones)."""
    rng = np.random.default_rng(len(zeros))
    for _ in range(20):
        inertia = [[_rational(rng) for _ in range(3)] for _ in range(3)]
        for i in range(3):
            for j in range(i):
                inertia[i][j] = inertia[j][i]
        for i, j in zeros:
            inertia[i][j] = inertia[j][i] = 0
        w = [_rational(rng) for _ in range(3)]
        dw = [_rational(rng) for _ in range(3)]
        expected = algebra.add(algebra.rotate(inertia, dw), algebra.cross(w, algebra.rotate(inertia, w)))
        assert algebra.euler_moment(inertia, w, dw, lambda x: x == 0) == expected


@pytest.mark.parametrize("module, name, row", [
    (crba, "force_to_parent", "composite-rigid-body M_tree gives M_q = P^T M_tree P"),
    (aba, "motion_to_child", "articulated-body algorithm inverts RNEA on the spanning tree"),
])
def test_a_wrong_transport_sign_is_caught(chain, monkeypatch, module, name, row):
    """The offset of a joint transported with the wrong sign, in one recursion only: that
    recursion's property fails, RNEA's still holds."""
    real = getattr(module, name)

    def flipped(r, p, x):
        return real(r, tuple(-v for v in p), x)

    monkeypatch.setattr(module, name, flipped)
    rows = _proof_rows(chain)
    assert not rows[row].passed
    assert rows["RNEA equals M_q qdd + C_q qd + G_q"].passed
