"""Decisions and printed numbers that must not depend on the float library's last digits."""
from __future__ import annotations

import numpy as np
import pytest

from symgen import closure
from symgen.io.builtin import get_scene
from symgen.codegen import reference
from symgen.math.elimination import pivot_columns
from symgen.model import derive
from symgen.steps import choose_partition

#: far above any BLAS or libm difference (1e-16), far below the tie tolerance (1e-9)
NOISE = 1e-13


def test_pivot_columns_gives_an_exact_tie_to_the_lowest_index():
    col = np.array([1.0, 2.0, 3.0])
    a = np.column_stack([col, [0.0, 1.0, 0.0], col * (1 + NOISE)])
    b = np.column_stack([col * (1 + NOISE), [0.0, 1.0, 0.0], col])
    assert pivot_columns(a, 2)[0] == 0
    assert pivot_columns(b, 2)[0] == 0


def test_pivot_columns_takes_the_largest_projected_norm():
    a = np.array([[1.0, 0.0, 3.0], [0.0, 2.0, 0.0]])
    assert pivot_columns(a, 2) == [2, 1]           # after column 2, column 0 projects to zero


def test_two_arm_partition_survives_rounding_noise():
    """Two identical arms give exactly equal column norms in Step 5; perturbing the constraint
    matrix by 1e-13 relative (another float library) must not move the partition."""
    model = derive(get_scene("multi_arm:h=2"))
    from symgen.math.fields import make_field
    from symgen.kinematics import constraint_matrix, tree_kinematics

    kin = tree_kinematics(model.tree, make_field("float", model.tree.parameters), model.reference)
    t = constraint_matrix(kin, model.scene.constraints.values()).v
    rng = np.random.default_rng(3)
    for _ in range(5):
        noisy = t * (1 + NOISE * rng.choice([-1.0, 1.0], t.shape))
        assert choose_partition(noisy, model.tree) == model.partition


@pytest.mark.parametrize("spec", ["four_bar", "arm_on_plane", "stewart"])
def test_pinned_state_does_not_depend_on_the_float_closure_solve(spec, monkeypatch):
    """The float Newton solve only starts the 50-digit one: moving its result by 1e-12 leaves
    every number of the pinned state unchanged, bit for bit."""
    model = derive(get_scene(spec))
    plain = reference.pinned_state(model, seed=7)
    solve = closure.solve_closure

    def shaken(model_, config, **kw):
        out = solve(model_, config, **kw)
        moved = {}
        for name, value in out.positions.items():
            if isinstance(value, np.ndarray):
                moved[name] = value @ closure.rot_exp(np.full(3, 1e-12))
            else:
                moved[name] = value + 1e-12
        return type(out)(moved)

    monkeypatch.setattr(reference, "solve_closure", shaken)
    again = reference.pinned_state(model, seed=7)
    for key in ("q", "qd", "V_m", "tau"):
        assert np.asarray(plain[key]).tobytes() == np.asarray(again[key]).tobytes(), key


@pytest.mark.parametrize("spec", ["five_bar", "stewart"])
def test_pinned_state_closes_the_loops(spec):
    model = derive(get_scene(spec))
    state = reference.pinned_state(model, seed=7)
    assert np.max(np.abs(closure.closure_residual(model, state["config"]))) < 1e-14
