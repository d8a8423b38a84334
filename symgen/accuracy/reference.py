"""Extended-precision values of the generated functions' outputs, from the dense model (32).

:func:`mp_outputs` mirrors :func:`symgen.codegen.reference.reference_outputs` (same functions,
same output names, same formulas) but evaluates :meth:`symgen.model.Model.evaluate` in
:class:`~symgen.arith.MpField` at the generated function's own inputs: the float arrays of a
state (``q``, ``qd``, ``V_m``, ...) are taken at their exact binary values, so the reference is
the exact function of what the generated code receives, to about ``dps`` digits.

Positions come from ``q`` (:func:`mp_configuration`), not from the state's float
``Configuration``: a revolute angle gives ``cos`` and ``sin`` at ``dps`` digits, a prismatic
displacement its value, and a quaternion ``(w, x, y, z)`` the rotation ``R(q) / |q|^2`` -- the
rotation it stands for; the generated code assumes ``|q| = 1`` and drops the division, which
differs by the float rounding of ``|q|`` (about 1e-16). Closed chains are evaluated at ``q`` as
given (all joints), like the generated code: the identities hold whether or not the float ``q``
closes the loops exactly.
"""
from __future__ import annotations

from functools import cached_property

import numpy as np

from ..arith import MpField
from ..codegen.trace import position_layout, quaternion_matrix
from ..joint_kinds import joint_kind
from ..state import Configuration, CosSin
from . import AccuracyError

#: the inputs a generated function may take, besides ``q``
INPUTS = ("qd", "qdd", "V_m", "dV_m", "eta_f", "tau", "eta_m")


def mp_configuration(model, q, field: MpField) -> Configuration:
    """The configuration of the generated code's position vector ``q`` in ``field``."""
    q = np.asarray(q, dtype=float)
    layout = position_layout(model)
    size = sum(s for *_, s in layout)
    if q.shape != (size,):
        raise AccuracyError(f"q must have shape ({size},) for scene {model.scene.name!r}, got {q.shape}")
    pos = {}
    for name, kind, off, _ in layout:
        kind = joint_kind(kind)
        if kind.position_is_angle:
            pos[name] = CosSin(*field.cos_sin(q[off]))
        elif kind.translates:
            pos[name] = field.const(q[off])
        else:
            w, x, y, z = (field.const(v) for v in q[off:off + 4])
            norm2 = w * w + x * x + y * y + z * z
            if norm2 == 0:
                raise AccuracyError(f"joint {name!r}: the quaternion in q is zero")
            pos[name] = np.array([[v / norm2 for v in row] for row in quaternion_matrix(w, x, y, z)], dtype=object)
    return Configuration(pos)


class MpState:
    """One state in extended precision: its inputs as mpf arrays and the (at most two) dense
    evaluations every generated function's reference is read from (``O(n_S^2)`` each)."""

    def __init__(self, model, state: dict, field: MpField):
        self.model, self.field = model, field
        self.config = mp_configuration(model, state["q"], field)
        self.x = {k: field.array(np.asarray(state[k], dtype=float).tolist()) for k in INPUTS if k in state}
        if "eta_m" not in self.x:
            self.x["eta_m"] = field.zeros((0,))

    @property
    def _eta_m(self):
        return self.x["eta_m"] if self.x["eta_m"].size else None

    @cached_property
    def task(self):
        """Model (32) at ``(q, V_m, eta_m)``: ``M``, ``C``, ``G``, ``[J_m; J_f]`` and its inverse."""
        return self.model.evaluate(self.config, V_m=self.x["V_m"], eta_m=self._eta_m, field=self.field)

    @cached_property
    def joint(self):
        """The joint-space form at ``(q, qd)`` (``qd`` of eq. 14 as given, not ``Omega V_m``)."""
        return self.model.evaluate(self.config, qd=self.x["qd"], field=self.field)

    def outputs(self, name: str) -> dict[str, np.ndarray]:
        """Outputs of generated function ``name`` as mpf arrays (names as the generated code's)."""
        x, m = self.x, self.model.counts.m
        if name == "inverse_dynamics":
            d = self.joint
            return {"tau": d.M_q @ x["qdd"] + d.C_q @ x["qd"] + d.G_q}
        if name == "joint_rates":
            d = self.task
            return {"qd_all": d.maps.P.v @ d.maps.Omega.v @ x["V_m"]}
        d = self.task
        if name == "mass_matrix":
            return {"M": d.M}
        if name == "coriolis_times_v":
            return {"c": d.C[:, :m] @ x["V_m"]}
        if name == "gravity":
            return {"G": d.G}
        if name == "task_inverse_dynamics":
            eta_f = x["eta_f"] if "eta_f" in x else self.field.zeros((0,))
            lhs = d.M[:, :m] @ x["dV_m"] + d.C[:, :m] @ x["V_m"] + d.G + np.concatenate([self.field.zeros((m,)), eta_f])
            return {"tau": d.maps.A.v.T @ lhs}
        if name == "forward_dynamics":
            return self._forward(d)
        raise AccuracyError(f"no extended-precision reference for function {name!r}; choose from "
                            f"{', '.join(REFERENCE_FUNCTIONS)}")

    def _forward(self, d) -> dict[str, np.ndarray]:
        """Solve (32) for ``dV_m`` and ``eta_f`` (pivoted Gauss in mp)."""
        m = self.model.counts.m
        rhs = d.maps.A_inv.v.T @ self.x["tau"] - d.C[:, :m] @ self.x["V_m"] - d.G
        dv = self.field.solve(d.M[:m, :m], rhs[:m], "the motion block of M (eq. 32)")
        eta_f = rhs[m:] - d.M[m:, :m] @ dv
        return {"dV_m": dv, "eta_f": eta_f} if eta_f.size else {"dV_m": dv}


#: functions :meth:`MpState.outputs` knows
REFERENCE_FUNCTIONS = ("inverse_dynamics", "task_inverse_dynamics", "forward_dynamics", "mass_matrix",
                       "coriolis_times_v", "gravity", "joint_rates")


def mp_outputs(model, function_name: str, state: dict, *, dps: int = MpField.default_dps) -> dict[str, np.ndarray]:
    """Extended-precision outputs of generated function ``function_name`` at ``state`` (a dict
    as :func:`symgen.codegen.reference.reference_states` makes), rounded to float64.

    Same names as :func:`~symgen.codegen.reference.reference_outputs`; computed at ``dps``
    decimal digits (>= 20) from the state's float inputs taken exactly.
    """
    if function_name not in REFERENCE_FUNCTIONS:
        raise AccuracyError(f"no extended-precision reference for function {function_name!r}; choose from "
                            f"{', '.join(REFERENCE_FUNCTIONS)}")
    field = make_mp_field(model, dps)
    values = MpState(model, state, field).outputs(function_name)
    return {k: field.to_float(v) for k, v in values.items()}


def check_dps(dps) -> int:
    """``dps`` as an int; :class:`AccuracyError` unless it is an integer >= ``MpField.min_dps``."""
    if isinstance(dps, bool) or not isinstance(dps, (int, np.integer)) or dps < MpField.min_dps:
        raise AccuracyError(f"dps must be an integer >= {MpField.min_dps} (a reference needs more digits "
                            f"than float64's 16), got {dps!r}")
    return int(dps)


def make_mp_field(model, dps: int) -> MpField:
    """An :class:`MpField` for ``model``'s parameters; a typed error for too few digits."""
    return MpField(model.tree.parameters, dps=check_dps(dps))


def relative_error(got, want, field: MpField, floor: float) -> float:
    """Normwise relative error ``|got - want|_inf / max(|want|_inf, floor)`` with ``want`` the
    unrounded mpf reference and ``got`` (floats) taken exactly; the floor keeps an output that
    is zero in exact arithmetic from dividing rounding noise by nothing."""
    want = np.asarray(want, dtype=object).ravel()
    got = np.asarray(got, dtype=float).ravel()
    if got.shape != want.shape:
        raise AccuracyError(f"output has {got.size} entries, the reference {want.size}")
    if want.size == 0:
        return 0.0
    if not np.all(np.isfinite(got)):
        return float("inf")
    diff = max(abs(field.const(float(g)) - w) for g, w in zip(got, want))
    scale = max(max(abs(w) for w in want), field.const(floor))
    return float(diff / scale)
