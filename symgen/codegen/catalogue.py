"""The catalogue of generated functions: one :class:`FunctionSpec` per function, in emission order.

A spec names the function, the builder that traces it (:mod:`symgen.codegen.functions`), whether
``symgen generate`` emits it by default or on request only, the generation options it takes and a
one-line summary. Its dense reference -- what the generated code must equal -- is the entry of the
same name in :data:`symgen.codegen.reference.REFERENCE_OUTPUTS`, or, for the controller, the
reference the traced function carries. Adding a generated function is one entry here plus its
build function (the test of the catalogue checks that every entry has a reference).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from ..conditioning import MAX_LOOP_CONDITION
from ..errors import CodegenError
from . import frame_functions as frames
from . import functions as fns
from . import sparse_lu
from .builder import Function
from .dynamics_derivatives import _inverse_dynamics_derivatives
from .forward_derivatives import _forward_dynamics_derivatives, _state_derivative_jacobian
from .trace import rates_by_solve


@dataclass(frozen=True)
class FunctionSpec:
    """One generated function: ``build(model, **options) -> Function``."""

    name: str
    build: Callable[..., Function]
    default: bool
    options: tuple[str, ...]
    summary: str
    #: its outputs use the maps' time derivatives (Coriolis terms): solves with the loop-closure
    #: block W (and, with constraints, with [J_m; J_f]) are held to the loop limit
    #: (:data:`~symgen.conditioning.MAX_LOOP_CONDITION`)
    map_rates: bool = True


CATALOGUE: dict[str, FunctionSpec] = {spec.name: spec for spec in (
    FunctionSpec("inverse_dynamics", fns._inverse_dynamics, True, (),
                 "(q, qd, qdd) -> tau = M_q qdd + C_q qd + G_q on the independent coordinates"),
    FunctionSpec("task_inverse_dynamics", fns._task_inverse_dynamics, True, (),
                 "(q, V_m, dV_m[, eta_f][, eta_m]) -> tau from model (32)"),
    FunctionSpec("forward_dynamics", fns._forward_dynamics, True, ("method",),
                 "(q, V_m, tau[, eta_m]) -> (dV_m[, eta_f]) from model (32)"),
    FunctionSpec("mass_matrix", fns._mass_matrix, True, (), "q -> M of model (32), n x n", map_rates=False),
    FunctionSpec("coriolis_times_v", fns._coriolis_times_v, True, (), "(q, V_m) -> C [V_m; 0] of model (32)"),
    FunctionSpec("gravity", fns._gravity, True, (), "(q[, V_m][, eta_m]) -> G of model (32)", map_rates=False),
    FunctionSpec("joint_rates", fns._joint_rates, True, (), "(q, V_m) -> qd_all = P [J_m; J_f]^-1 [V_m; 0]",
                 map_rates=False),
    FunctionSpec("state_derivative", fns._state_derivative, False, ("method",),
                 "(q, V_m, tau[, eta_m]) -> (dV_m, qd_all), the simulation's one pass"),
    FunctionSpec("dynamics_terms", fns._dynamics_terms, False, (), "(q, V_m[, eta_m]) -> (M, c, G) at one state"),
    FunctionSpec("joint_accelerations", fns._joint_accelerations, False, ("method",),
                 "(q, V_m, tau[, eta_m]) -> (qd_all, qdd_all) of every joint"),
    FunctionSpec("loop_forces", fns._loop_forces, False, (),
                 "(q, V_m, tau[, eta_m]) -> lam, the force of every loop-closure constraint"),
    FunctionSpec("control", fns._control, False, ("uncertain", "gain", "contact"),
                 "(q, V_m, V_mr, dV_mr[, eta_fr][, P_hat][, K_A]) -> tau, the adaptive law (34)"),
    FunctionSpec("adaptation", fns._adaptation, False, ("uncertain", "contact"),
                 "(q, V_m, V_mr, dV_mr) -> s = Y^T e of (38)"),
    FunctionSpec("inverse_dynamics_derivatives", _inverse_dynamics_derivatives, False, (),
                 "(q, qd, qdd) -> (dtau_dq, dtau_dqd, M): the Jacobians of inverse_dynamics"),
    FunctionSpec("forward_dynamics_derivatives", _forward_dynamics_derivatives, False, ("method",),
                 "(q, V_m, tau[, eta_m]) -> d(dV_m[, eta_f]) / d(q, V_m, tau): the Jacobians of forward_dynamics"),
    FunctionSpec("state_derivative_jacobian", _state_derivative_jacobian, False, ("method",),
                 "(q, V_m, tau[, eta_m]) -> (dxdot_dx, dxdot_dtau) of state_derivative, x = [q; V_m]"),
    FunctionSpec("frame_pose", frames._frame_pose, False, ("frame",),
                 "q -> (R, p): the named frame's axes and origin in the world", map_rates=False),
    FunctionSpec("frame_jacobian", frames._frame_jacobian, False, ("frame", "axes"),
                 "q -> J (6 x n), [v; w] = J qd in the frame's (local) or the world's axes", map_rates=False),
    FunctionSpec("frame_drift", frames._frame_drift, False, ("frame", "axes"),
                 "(q, qd) -> a = dJ/dt qd: the frame's classical acceleration at qdd = 0"),
    FunctionSpec("center_of_mass", frames._center_of_mass, False, (), "q -> c, world axes", map_rates=False),
    FunctionSpec("com_jacobian", frames._com_jacobian, False, (), "q -> J_c (3 x n), dc/dt = J_c qd",
                 map_rates=False),
    FunctionSpec("centroidal_momentum", frames._centroidal_momentum, False, (),
                 "(q, qd) -> h: linear and angular momentum about the centre of mass, world axes", map_rates=False),
    FunctionSpec("centroidal_momentum_derivatives", frames._centroidal_momentum_derivatives, False, (),
                 "(q, qd) -> (dh_dq, A_G): the Jacobians of centroidal_momentum, A_G = dh/dqd", map_rates=False),
)}

#: emitted by default, in this order
FUNCTIONS = tuple(name for name, spec in CATALOGUE.items() if spec.default)
#: emitted only when asked for by name (so ``generated/`` does not change when one is added)
ON_REQUEST = tuple(name for name, spec in CATALOGUE.items() if not spec.default)
#: generation options of the functions that take some
OPTIONS = {name: spec.options for name, spec in CATALOGUE.items() if spec.options}


def build_function(model, name: str, **options) -> Function:
    """Trace function ``name`` of the catalogue for ``model``; ``options`` (:data:`OPTIONS`) reach
    the functions that take them. For a closed chain, eq. (10) is traced both through ``P`` and by
    solves with ``W``, and the cheaper is kept."""
    spec = CATALOGUE.get(name)
    if spec is None:
        raise CodegenError(f"unknown function {name!r}; choose from {', '.join(CATALOGUE)}")
    unknown = sorted(set(options) - {o for taken in OPTIONS.values() for o in taken})
    if unknown:
        raise CodegenError(f"unknown generation option(s) {', '.join(map(repr, unknown))}")
    taken = {k: v for k, v in options.items() if k in spec.options}
    fn = spec.build(model, **taken)
    if model.partition.u1 and sparse_lu.enabled():
        with rates_by_solve():
            other = spec.build(model, **taken)
        if fns.traced_cost(other) < fns.traced_cost(fn):      # eq. (10) by solves, not through P
            fn = other
    fn.map_rates = spec.map_rates
    fn.constrained = model.counts.nc > 0
    return fn


def markdown_table() -> str:
    """The catalogue as the table of the documentation (``docs/generated/functions.md`` holds this
    text, and a test keeps it so)."""
    lines = ["| function | emitted | options | arguments -> result | loop limit |", "|---|---|---|---|---|"]
    for spec in CATALOGUE.values():
        options = ", ".join(f"`{o}`" for o in spec.options) or "-"
        limit = f"cond W, A <= {MAX_LOOP_CONDITION:g}" if spec.map_rates else "-"
        lines.append(f"| `{spec.name}` | {'by default' if spec.default else 'on request'} | {options} | "
                     f"`{spec.summary}` | {limit} |")
    return "\n".join(lines) + "\n"
