"""Reference values for the generated functions from the dense model (32) of
:meth:`symgen.model.Model.evaluate` -- an independent path (``O(n_S^2)`` matrices, no recursion,
no tracing) used by the equivalence tests, ``symgen accuracy`` and the standalone C test program.

* :func:`reference_states`: random loop-closed float states (the tests' inputs);
* :func:`pinned_state`: one state whose every number is the float nearest a 50-digit value, so
  the files that print it are the same on every machine, whatever float library ran the generator;
* :class:`ReferenceState` and :func:`reference_outputs`: every generated function's outputs at a
  state, in any field -- ``float``, or ``mp`` at the state's float inputs taken exactly.
"""
from __future__ import annotations

from functools import cached_property

import numpy as np
import sympy as sp

from ..math.fields import Field, MpField
from ..closure import field_rot_exp, random_consistent_states, refine_closure, solve_closure
from ..errors import SingularConfigurationError
from ..scene.joint_kinds import joint_kind
from ..model_solves import field_vector, solve_forward, solve_inverse
from ..motion import JointMotion, motion_of_solution
from ..math.spatial import matrix_to_quat, quaternion_matrix
from ..math.configuration import Configuration
from ..steps.pipeline import joint_rate_maps
from .field_configuration import field_configuration
from .trace import position_layout, position_vector

#: the inputs a generated function may take, besides ``q``
INPUTS = ("qd", "qdd", "V_m", "dV_m", "eta_f", "tau", "eta_m")


def _inputs(model, rng, v_m, qd) -> dict:
    """The state's inputs other than positions: ``V_m`` and ``qd`` as given, the rest uniform."""
    n, m = model.counts.n, model.counts.m
    cf = model.scene.contact_forces
    return dict(V_m=np.asarray(v_m, float), qd=np.asarray(qd, float), qdd=rng.uniform(-1, 1, n),
                dV_m=rng.uniform(-1, 1, m), eta_f=rng.uniform(-1, 1, n - m), tau=rng.uniform(-1, 1, n),
                eta_m=rng.uniform(-1, 1, len(cf.components) if cf else 0))


def reference_states(model, count: int, seed: int = 0, spread: float = 0.3) -> list[dict]:
    """``count`` loop-closed float states with every input a generated function may take."""
    rng = np.random.default_rng(seed + 1)
    out = []
    for config, v_m in random_consistent_states(model, count, seed=seed, spread=spread):
        d = model.evaluate(config, V_m=v_m)
        out.append(dict(config=config, q=position_vector(model, config), **_inputs(model, rng, v_m, d.qd)))
    return out


# ------------------------------------------------------------------ library-independent state
def pinned_state(model, seed: int = 0, spread: float = 0.3, max_tries: int = 20) -> dict:
    """One loop-closed state, like :func:`reference_states`, in which no number depends on the
    float library: the independent coordinates are ``q0`` plus seeded uniform draws, taken in
    50-digit arithmetic (spherical joints turned by ``exp`` of a drawn vector); the dependent ones
    are solved there by :func:`~symgen.closure.refine_closure`; ``q`` and ``qd = Omega V_m``
    (eq. 20) are the floats nearest the 50-digit values. Only IEEE-exact float operations (the
    seeded draws) and correctly rounded conversions remain, so a generated file that prints this
    state, and the 50-digit reference outputs at it, is byte-identical on every machine."""
    fld = MpField(model.tree.parameters)
    rng = np.random.default_rng(seed)
    indep = model.partition.a2 + model.partition.u2
    for _ in range(max_tries):
        draws = rng.uniform(-spread, spread, len(indep))
        v_m = rng.uniform(-1.0, 1.0, model.counts.m)
        start = _perturbed_reference(model, fld, indep, draws)
        try:       # the float solve finds the closed state (or fails fast); 50 digits polish it
            guess = solve_closure(model, Configuration({k: _to_float(v, fld) for k, v in start.items()}))
            pos = refine_closure(model, _dependent_from(model, start, guess, fld), fld)
        except SingularConfigurationError:
            continue
        q = _nearest_q(model, pos, fld)
        config = field_configuration(model, q, fld)
        qd = fld.to_float(joint_rate_maps(model, config, fld, with_task=True)[1].v @ field_vector(fld, v_m))
        state = dict(q=q, **_inputs(model, np.random.default_rng(seed + 1), v_m, qd))
        state["config"] = field_configuration(model, q, model.float_field)
        return state
    raise SingularConfigurationError("pinned reference state", float("inf"),
                                     "the loop-closure solve failed at every draw; reduce the spread")


def _perturbed_reference(model, fld: Field, indep, draws) -> dict:
    """Exact ``q0`` in ``fld`` with the independent coordinates ``indep`` moved by ``draws``."""
    pos = {}
    for j in model.scene.joints.values():
        if not j.kind.dof:
            continue
        if j.kind.is_one_dof:
            pos[j.name] = fld.const(sp.sympify(j.q0))
        else:
            pos[j.name] = np.array([[fld.const(v) for v in row] for row in sp.Matrix(j.q0).tolist()], dtype=object)
    turns: dict[str, list] = {}
    for coord, d in zip(indep, draws):
        c = model.tree.coordinates[coord]
        if c.kind.is_one_dof:
            pos[c.joint] = pos[c.joint] + fld.const(d)
        else:
            turns.setdefault(c.joint, [fld.zero] * 3)[c.component] = fld.const(d)
    for joint, w in turns.items():
        pos[joint] = pos[joint] @ field_rot_exp(w, fld)
    return pos


def _to_float(value, fld: MpField):
    return fld.to_float(value) if isinstance(value, np.ndarray) else float(value)


def _dependent_from(model, start: dict, guess: Configuration, fld: MpField) -> dict:
    """``start`` with the joints of the dependent coordinates taken from the float ``guess``; a
    rotation goes through its normalised quaternion, so it is a rotation to ``dps`` digits."""
    part = model.partition
    joints = {model.tree.coordinates[c].joint for c in part.u1 + part.a1}
    pos = dict(start)
    for name in joints:
        value = guess.positions[name]
        if isinstance(value, np.ndarray):
            quat = [fld.const(v) for v in matrix_to_quat(value)]
            norm2 = sum(v * v for v in quat)
            pos[name] = np.array([[v / norm2 for v in row] for row in quaternion_matrix(*quat)], dtype=object)
        else:
            pos[name] = fld.const(value)
    return pos


#: decimals kept of a solved position before it is rounded to float: Newton's last iterate
#: differs from the exact root by about ``10^-dps`` in a way that depends on its float start, so
#: a root that is exactly zero must become 0, not a tiny number of either sign
PINNED_DECIMALS = 35


def _nearest_q(model, pos: dict, fld: MpField) -> np.ndarray:
    """The generated code's ``q`` nearest the extended-precision positions ``pos``, each first
    rounded to :data:`PINNED_DECIMALS` decimals."""
    out = []
    for name, kind, _, _ in position_layout(model):
        if joint_kind(kind).position_is_rotation:
            out.extend(matrix_to_quat(pos[name], sqrt=fld.sqrt))
        else:
            out.append(pos[name])
    scale = fld.const(10) ** PINNED_DECIMALS
    return fld.to_float(np.array([fld.ctx.nint(v * scale) / scale for v in out], dtype=object))


# ------------------------------------------------------------------ outputs in any field


class ReferenceState:
    """One state in a field (``float``, or ``mp`` at the state's float inputs taken exactly) and
    the (at most two) dense evaluations every generated function's reference is read from
    (``O(n_S^2)`` each). In the float field the state's own ``config`` is used where it has one."""

    def __init__(self, model, state: dict, fld: Field):
        self.model, self.field, self.state = model, fld, state
        if fld.dtype is float and "config" in state:
            self.config = state["config"]
        else:
            self.config = field_configuration(model, state["q"], fld)
        self.x = {k: field_vector(fld, state[k]) for k in INPUTS if k in state}
        if "eta_m" not in self.x:
            self.x["eta_m"] = fld.zeros((0,))

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
        """Outputs of generated function ``name`` in the field (names as the generated code's)."""
        x = self.x
        if name == "inverse_dynamics":
            return {"tau": self.joint.joint_force(x["qdd"])}
        d = self.task
        simple = {"joint_rates": lambda: {"qd_all": d.maps.P.v @ d.maps.Omega.v @ x["V_m"]},
                  "mass_matrix": lambda: {"M": d.M},
                  "coriolis_times_v": lambda: {"c": d.c},
                  "gravity": lambda: {"G": d.G},
                  "task_inverse_dynamics": lambda: {"tau": solve_inverse(d, x["dV_m"], x.get("eta_f"))},
                  "forward_dynamics": self._forward,
                  "state_derivative": lambda: {"dV_m": self._forward()["dV_m"], **self.outputs("joint_rates")},
                  "dynamics_terms": lambda: {"M": d.M, "c": d.c, "G": d.G}}
        if name in simple:
            return simple[name]()
        if name == "joint_accelerations":
            motion = self._motion(forces=False)
            return {"qd_all": motion.qd_all, "qdd_all": motion.qdd_all}
        if name == "inverse_dynamics_derivatives":
            return self._derivatives()
        if name in ("forward_dynamics_derivatives", "state_derivative_jacobian"):
            return self._forward_derivatives(name)
        if name == "loop_forces":
            return {"lam": self._motion(forces=True).lam}
        raise KeyError(name)

    def _derivatives(self) -> dict[str, np.ndarray]:
        """Central differences of the dense inverse dynamics in 50 digits (the float field's
        differences would keep only half its digits): :mod:`symgen.codegen.reference_derivatives`."""
        from .reference_derivatives import derivative_reference

        mp = self.field if isinstance(self.field, MpField) else None
        values = derivative_reference(self.model, self.state, mp)
        if mp is None:
            return {k: np.array(v, dtype=float) for k, v in values.items()}
        return values

    def _forward_derivatives(self, name: str) -> dict[str, np.ndarray]:
        """Central differences of the dense forward dynamics in 50 digits, at the state's float
        inputs (the generated ``q``) taken exactly: the functions the model API returns
        (:mod:`symgen.dynamics_jacobians`)."""
        from ..dynamics_jacobians import jacobians, state_jacobian

        mp = self.field if isinstance(self.field, MpField) else MpField(self.model.tree.parameters)
        s = self.state
        jacobian = state_jacobian if name == "state_derivative_jacobian" else jacobians
        values = jacobian(self.model, s["q"], s["V_m"], s["tau"], s.get("eta_m"), mp)
        if self.field is mp:
            return values
        return {k: mp.to_float(v) for k, v in values.items()}

    @cached_property
    def _solution(self) -> tuple[np.ndarray, np.ndarray]:
        """``(dV_m, eta_f)``: model (32) of :attr:`task` solved for the state's ``tau``."""
        return solve_forward(self.task, self.x["tau"])

    def _forward(self) -> dict[str, np.ndarray]:
        dv, eta_f = self._solution
        return {"dV_m": dv, "eta_f": eta_f} if eta_f.size else {"dV_m": dv}

    def _motion(self, forces: bool) -> JointMotion:
        """:meth:`symgen.model.Model.motion` under the state's ``tau`` (the loop forces with
        ``forces``), from :attr:`task` and its :attr:`_solution` instead of a new evaluation."""
        return motion_of_solution(self.model, self.task, *self._solution, self.x["tau"], forces)


#: the functions :meth:`ReferenceState.outputs` knows
REFERENCE_OUTPUTS = ("inverse_dynamics", "task_inverse_dynamics", "forward_dynamics", "mass_matrix",
                     "coriolis_times_v", "gravity", "joint_rates", "state_derivative", "dynamics_terms",
                     "joint_accelerations", "loop_forces", "inverse_dynamics_derivatives",
                     "forward_dynamics_derivatives", "state_derivative_jacobian")


def reference_outputs(model, name: str, s: dict, field: str | Field = "float") -> dict[str, np.ndarray]:
    """The outputs of generated function ``name`` at state ``s`` from the dense model, computed
    in ``field`` and rounded to float64."""
    fld = model.field_of(field)
    values = ReferenceState(model, s, fld).outputs(name)
    if fld.dtype is float:
        return {k: np.asarray(v, dtype=float) for k, v in values.items()}
    return {k: fld.to_float(v) for k, v in values.items()}
