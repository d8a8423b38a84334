"""Exact checks of Section 4's regressors, joined to ``symgen prove`` (property (f)).

At rational sampled states (:func:`symgen.proofs.random_exact_state`) and rational required
velocities ``V_mr != V_m``:

* eq. (35): ``Y_r P_r = M_S dX_r/dt + C_S X_r + G_S`` with ``X_r`` of eq. (36), ``C_S`` at the
  actual velocity, and the scene's own parameters -- exactly;
* eqs. (34), (37): with ``V_mr = V_m``, ``dV_mr = dV_m`` and ``eta_fr = eta_f``, the control law
  ``T_S^T Y_r P_r + Y_m P_m + J_f^T eta_fr`` equals model (32)'s inverse dynamics
  ``[J_m; J_f]^T (M [dV_m; 0] + C [V_m; 0] + G + [0; eta_f])`` with the contact forces of a
  viscous-Coulomb law (:mod:`symgen.control.contact`) -- exactly.
"""
from __future__ import annotations

from fractions import Fraction

import numpy as np

from ..math.fields import ExactField
from ..errors import SingularConfigurationError
from ..proofs import MAX_REDRAWS, ProofResult, random_exact_state
from .contact import ContactLaw, contact_velocity
from .law import control, default_parameters
from .stacked import required_velocity, subsystem_regressor

METHOD = "exact rational arithmetic at sampled configurations"


def _rationals(rng, n, scale=1) -> list[Fraction]:
    return [Fraction(int(rng.integers(-9, 10)), int(rng.integers(1, 8))) * scale for _ in range(n)]


def _exact_data(model, rng):
    for _ in range(MAX_REDRAWS):
        cfg, v_m = random_exact_state(model, rng)
        fld = ExactField(model.tree.parameters)
        try:
            return cfg, fld, model.evaluate(cfg, V_m=v_m, field=fld)
        except SingularConfigurationError:
            continue
    raise SingularConfigurationError("every sampled configuration", float("inf"),
                                     f"{MAX_REDRAWS} exact samples near q0 were singular")


def _inverse_dynamics(model, cfg, fld, data, dv_m, eta_f, eta_m) -> np.ndarray:
    """``[J_m; J_f]^T (M [dV_m; 0] + C [V_m; 0] + G + [0; eta_f])`` of model (32)."""
    m = model.counts.m
    d = model.evaluate(cfg, V_m=data.V_m, field=fld, eta_m=eta_m)
    force = np.array([fld.zero] * m + list(eta_f), dtype=object)
    return d.maps.A.v.T @ (d.M[:, :m] @ np.array(dv_m, dtype=object) + d.c + d.G + force)


def prove_regressor(model, points: int = 1, seed: int = 0) -> list[ProofResult]:
    """Property (f): eqs. (35) and (34)/(37) exactly, at ``points`` sampled states."""
    rng = np.random.default_rng(seed + 35)
    m, n = model.counts.m, model.counts.n
    failed = {"35": "", "34": ""}
    for i in range(points):
        cfg, fld, data = _exact_data(model, rng)
        contact = (ContactLaw.for_scene(model.scene, Fraction(3, 2), Fraction(1, 3))
                   if model.scene.contact_forces is not None else None)
        params = default_parameters(model, contact, fld)
        v_mr, dv_mr = _rationals(rng, m), _rationals(rng, m, Fraction(1, 2))
        x_r, dx_r = required_velocity(data, v_mr, dv_mr)
        y_r = subsystem_regressor(model, data, params, x_r, dx_r)
        if not (y_r @ params.values == data.M_S @ dx_r + data.C_S @ x_r + data.G_S).all():
            failed["35"] = f"Y_r P_r differs at point {i}"
        if model.partition.u2:
            continue
        eta_f = _rationals(rng, n - m)
        out = control(model, data, params, params.values, data.V_m, dv_mr, eta_fr=eta_f, contact=contact)
        eta_m = contact.forces(contact_velocity(data), fld) if contact is not None else None
        if not (out.tau == _inverse_dynamics(model, cfg, fld, data, dv_mr, eta_f, eta_m)).all():
            failed["34"] = f"the control law differs from the inverse dynamics at point {i}"
    rows = [ProofResult("Y_r P_r = M_S dX_r + C_S X_r + G_S (X_r != X)", "(35), (36)", not failed["35"], METHOD,
                        points, failed["35"])]
    if not model.partition.u2:          # an underactuated scene has no control law (34) to check
        rows.append(ProofResult("control law = inverse dynamics when V_mr = V_m", "(34), (37)", not failed["34"],
                                METHOD, points, failed["34"]))
    return rows
