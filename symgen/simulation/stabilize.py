"""Position-level constraint stabilization: projection and Baumgarte.

``V_m`` parametrises only velocities that satisfy every constraint (``qd_all = P Omega V_m``,
eqs. 10, 18), so velocities never drift; positions integrated from those rates do, by the
integration error. Two remedies act on the *dependent* coordinates ``q_u1, q_a1`` of Step 5
(the columns of ``W = [T_u1, T_a1]``, eq. 8), leaving the independent ones and ``V_m`` alone:

* **projection** (fixed-step methods): after each step, Newton's method on the dependent
  coordinates, ``q_dep <- q_dep - (dr/dq_dep)^-1 r(q)``, until ``max |r| <= tol``;
* **Baumgarte** (any method, ``solve_ivp`` included): a correction added to the dependent rates,
  ``qd_dep += -k (dr/dq_dep)^-1 r(q)``. Since the uncorrected rates satisfy ``dr/dt = 0`` on the
  manifold, the residual obeys ``dr/dt = -k r`` to first order: it decays with rate ``k`` (1/s)
  instead of accumulating the integration error (steady state ``|r| ~ local error rate / k``).
  The correction helps long runs; on short ones at tight tolerances the drift is already at the
  round-off or tolerance level, and a large ``k`` only makes the problem stiff.

``r`` and ``dr/dq`` come from :class:`~symgen.simulation.poses.Poses` (the residual of
:func:`symgen.closure.closure_residual`: loop closures, welds and the plane contact of
``arm_on_plane``). The *drift* of a trajectory is ``max |r|`` over its recorded states.
"""
from __future__ import annotations

import numpy as np

from ..errors import SingularConfigurationError
from .errors import SimulationInputError
from .poses import Poses

#: default Baumgarte gain k (1/s): residuals decay as exp(-k t). Kept low on purpose: the
#: correction adds an eigenvalue -k, so an explicit method's steps h need k h inside its stability
#: region (about 3 to 6), and a stiff correction is resolved only to about atol anyway.
BAUMGARTE_GAIN = 5.0
#: projection stops when the largest residual is below this (m or rad)
PROJECTION_TOL = 1e-13
#: condition number above which dr/dq_dep counts as singular
MAX_CONDITION = 1e12

STABILIZATIONS = ("none", "projection", "baumgarte")


class Stabilizer:
    """Residuals, projection and Baumgarte correction of one model (see module docstring)."""

    def __init__(self, model, *, gain: float = BAUMGARTE_GAIN, tol: float = PROJECTION_TOL, max_iter: int = 20):
        if not np.isfinite(gain) or gain <= 0:
            raise SimulationInputError(f"Baumgarte gain must be positive, got {gain!r}")
        self.model = model
        self.poses = Poses(model)
        self.layout = self.poses.layout
        self.dependent = list(model.partition.u1 + model.partition.a1)
        self.gain, self.tol, self.max_iter = float(gain), float(tol), int(max_iter)

    @property
    def active(self) -> bool:
        """Whether the scene has constraints at all."""
        return bool(self.poses.constraints)

    def residual(self, q) -> np.ndarray:
        return self.poses.residual(q)

    def drift(self, q) -> float:
        """``max |r(q)|`` (0 for a scene without constraints)."""
        r = self.poses.residual(q)
        return float(np.max(np.abs(r))) if r.size else 0.0

    def worst_constraint(self, q) -> tuple[str, float]:
        """Name and residual of the most violated constraint."""
        r, row, worst, value = self.poses.residual(q), 0, "-", 0.0
        for con in self.poses.constraints:
            part = np.max(np.abs(r[row:row + con.dim]))
            if part > value:
                worst, value = con.name, float(part)
            row += con.dim
        return worst, value

    def _dependent_step(self, w, r, *, check: bool) -> np.ndarray:
        """``w^-1 r`` for ``w = dr/dq_dep``; with ``check``, a condition number above
        :data:`MAX_CONDITION` raises (the Baumgarte path skips the SVD: the generated
        ``joint_rates`` already refuses a near-singular ``[T_u1, T_a1]`` at the same state)."""
        if check:
            cond = np.linalg.cond(w)
            if not np.isfinite(cond) or cond > MAX_CONDITION:
                raise SingularConfigurationError("[T_u1, T_a1] (eq. 8) during constraint stabilization", float(cond),
                                                 "the mechanism is at or near a singular configuration")
        try:
            return np.linalg.solve(w, r)
        except np.linalg.LinAlgError:
            raise SingularConfigurationError("[T_u1, T_a1] (eq. 8) during constraint stabilization", float("inf"),
                                             "the mechanism is at a singular configuration") from None

    def baumgarte(self, q) -> np.ndarray:
        """The correction of all joint rates (``N_all``): ``-k (dr/dq_dep)^-1 r`` on the dependent
        coordinates, zero elsewhere."""
        out = np.zeros(self.layout.n_all)
        if not self.dependent:
            return out
        r, w = self.poses.residual_and_jacobian(q, self.dependent)
        out[self.dependent] = -self.gain * self._dependent_step(w, r, check=False)
        return out

    def project(self, q) -> np.ndarray:
        """``q`` moved onto the constraint manifold by Newton on the dependent coordinates."""
        if not self.dependent:
            return q
        rates = np.zeros(self.layout.n_all)
        for _ in range(self.max_iter):
            r = self.poses.residual(q)
            if np.max(np.abs(r)) <= self.tol:
                return q
            w = self.poses.residual_jacobian(q, self.dependent)
            rates[self.dependent] = -self._dependent_step(w, r, check=True)
            q = self.layout.advance(q, rates, 1.0)
        r = self.poses.residual(q)
        if np.max(np.abs(r)) <= 1e3 * self.tol:
            return q
        w = self.poses.residual_jacobian(q, self.dependent)
        raise SingularConfigurationError(
            "[T_u1, T_a1] (eq. 8) during constraint projection", float(np.linalg.cond(w)),
            f"Newton did not converge in {self.max_iter} iterations (residual {np.max(np.abs(r)):.3g}); take smaller "
            "steps, or the motion passes near a configuration where the dependent coordinates chosen at q0 "
            "(Step 5) lose rank")
