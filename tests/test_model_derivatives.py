"""Time derivatives carried by the jets against central finite differences along the motion."""
import numpy as np
import pytest

from symgen.io.builtin import get_scene
from symgen.closure import random_consistent_states, solve_closure, _apply_step
from symgen.model import derive

STEP = 1e-6
FD_TOL = 1e-6


@pytest.mark.parametrize("spec", ["chain:n=5", "four_bar", "five_bar", "arm_on_plane"])
def test_mass_matrix_derivative_equals_c_plus_c_transpose(spec):
    """dM/dt = C + C^T (Remark 2.7), dM/dt by finite differences along qd = Omega V_m, the
    displaced configurations projected back onto the loop closures."""
    model = derive(get_scene(spec))
    for cfg, v_m in random_consistent_states(model, 2, seed=7, spread=0.2):
        d = model.evaluate(cfg, V_m=v_m)
        qd_all = d.maps.P.v @ d.qd
        coords = tuple(range(model.tree.n_coords))

        def mass_at(sign):
            moved = _apply_step(model, cfg, coords, sign * STEP * qd_all)
            return model.evaluate(solve_closure(model, moved), V_m=np.zeros(model.counts.m)).M

        mdot = (mass_at(+1) - mass_at(-1)) / (2 * STEP)
        assert np.max(np.abs(mdot - (d.C + d.C.T))) < FD_TOL * max(1.0, np.max(np.abs(mdot)))
