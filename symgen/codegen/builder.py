"""The shared steps every emitted function of :mod:`symgen.codegen.functions` is traced from: its
arguments, the rates and accelerations of every joint from ``V_m`` (eqs. 10-11, 18), and the
terms ``M``, ``C [V_m; 0]``, ``G`` of model (32) on a :class:`~symgen.codegen.trace.Tracer`.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..dynamics import crba
from ..math.jet import matmul as product
from .graph import Graph
from .node_product import node_matmul
from .trace import Tracer, has_gravity, per_model, position_layout


@dataclass
class Argument:
    name: str
    shape: tuple[int, ...]
    doc: str

    @property
    def size(self) -> int:
        return int(np.prod(self.shape)) if self.shape else 1


@dataclass
class Function:
    """One traced function: arguments, outputs (arrays of nodes) and its graph."""

    name: str
    doc: str
    inputs: list[Argument]
    outputs: list[tuple[Argument, np.ndarray]]
    graph: Graph
    #: the outputs use the maps' time derivatives: solves with W get the loop limit
    #: (:mod:`symgen.conditioning`)
    map_rates: bool = True
    #: the scene has constraints: solves with [J_m; J_f] get the loop limit too
    constrained: bool = False


def parameter_arguments(parameters) -> list[Argument]:
    """The input ``p`` of run-time parameters (:mod:`symgen.codegen.parameters`), when there are some."""
    if not parameters:
        return []
    return [Argument("p", (len(parameters),), "run-time parameters, in order: " + ", ".join(parameters.names))]


def has_friction(model) -> bool:
    return any(j.viscous != 0 or j.coulomb != 0 for j in model.tree.joints)


def has_springs(model) -> bool:
    """Some joint has a spring: only then does generated code read the positions for it."""
    return any(j.stiffness != 0 for j in model.tree.joints)


#: what a failed factorisation of ``M_mm`` names
MOTION_BLOCK = "M_mm, the motion block of M (eq. 32)"


def projected_mass(w: np.ndarray, mw: np.ndarray) -> np.ndarray:
    """``W^T (M W)`` from ``W`` and the product ``M W`` (``N x m`` each, arrays of nodes): the
    motion block ``M_mm`` of the joint-space and null-space routes, symmetric, so each entry is
    traced once and the upper triangle shares the lower's nodes."""
    m = w.shape[1]
    wt = w.T
    mass = np.empty((m, m), dtype=object)
    for i in range(m):
        for j in range(i + 1):
            mass[i, j] = mass[j, i] = product(wt[i], mw[:, j])
    return mass


def eta_m_size(model) -> int:
    cf = model.scene.contact_forces
    return len(cf.components) if cf is not None else 0


def q_argument(model) -> Argument:
    size = sum(s for *_, s in position_layout(model))
    return Argument("q", (size,), "joint positions: angle, displacement or unit quaternion (w, x, y, z) "
                                  "per joint, in scene order")


#: ``{(id(model), run-time parameter names): "composite" | "columns"}``: the cheaper route of
#: :meth:`Builder.mass_in_joint_space` (the same for every function of a model), kept while the
#: model lives, so a generation traces the losing route once instead of once per function
_MASS_ROUTES: dict[tuple[int, tuple[str, ...]], str] = {}


class Builder:
    """One function being traced: its inputs, its :class:`~symgen.codegen.trace.Tracer` and graph,
    and the terms of model (32) it is assembled from."""

    def __init__(self, model, *, null_space_rows: bool = True):
        """``null_space_rows``: where no ``eta_f`` exists (``n = m``), every function of model (32)
        reads only the null space of the loop-closure rows (rates, accelerations, ``P^T``), and they
        are traced by :mod:`symgen.codegen.loop_rows`; ``False`` for a function that reads ``T`` or
        ``W`` themselves (the loop forces, the controller's mixed rates)."""
        self.model = model
        self.t = Tracer(model)
        if null_space_rows and model.counts.n == model.counts.m:
            self.t.use_null_space_rows()
        self.g = self.t.g
        self.n, self.m = model.counts.n, model.counts.m
        self.inputs = [q_argument(model)]
        self._mass_q = None                   # mass_in_joint_space, once traced

    def arg(self, name, size, doc):
        self.inputs.append(Argument(name, (size,), doc))
        return self.g.input(name, size)

    def task_rates(self, v_m):
        """``(A, qd_all)`` with ``qd = A^-1 [V_m; 0]`` completed by eq. (10)."""
        a = self.t.task_matrix()
        qd = self.t.solve_task(a, list(v_m) + [0] * (self.n - self.m))
        return a, self.t.complete_rates(list(qd))

    def joint_space_rates(self):
        """``(qd, qdd, qd_all, qdd_all)``: the inputs ``qd``, ``qdd`` of ``inverse_dynamics`` and
        the rates and accelerations of every joint, completed by eqs. (10)-(11) on a closed chain."""
        self.t.use_null_space_rows()          # only the null space of T is read below
        qd = self.arg("qd", self.n, "independent joint rates (eq. 14)")
        qdd = self.arg("qdd", self.n, "independent joint accelerations")
        qd_all = self.t.complete_rates(qd)
        return qd, qdd, qd_all, self.t.accelerations_of_rates(qdd, qd_all)

    def joint_space_forces(self):
        """``(qd, qdd, tau)``: the inputs ``qd``, ``qdd`` of ``inverse_dynamics`` and its
        ``tau = M_q qdd + C_q qd + G_q`` (eq. 30) (:meth:`joint_space_rates`)."""
        model = self.model
        qd, qdd, qd_all, qdd_all = self.joint_space_rates()
        tau = self.t.joint_forces(qd_all, qdd_all, gravity=has_gravity(model),
                                  friction_rates=qd_all if has_friction(model) else None,
                                  springs=has_springs(model))
        return qd, qdd, tau

    def task_accelerations(self, a, qd_all, dv_m):
        bias, _ = self.t.rate_bias(qd_all, kinematics=False)
        rhs = [x - y for x, y in zip(list(dv_m) + [0] * (self.n - self.m), self.t.task_bias_of_rates(qd_all, bias))]
        qdd = self.t.solve_task(a, rhs)
        return self.t.complete_accelerations(list(qdd), bias)

    def contact_term(self, eta_m):
        d_m = self.t.contact_map()
        return list(d_m.T @ np.array(eta_m, dtype=object))

    def mass_in_joint_space(self):
        """``M_q = P^T M_tree P`` (eqs. 10, 21-25) by the cheaper of two traced routes: the
        composite-rigid-body algorithm (:mod:`symgen.dynamics.crba`, on the body parameters of
        :attr:`~symgen.codegen.trace.Tracer.joint_force_inertias`), always kept for a tree,
        or, with loop closures, one recursion per column of ``P`` (``M_q e_k = P^T
        RNEA(qdd = P e_k)``), which a dense ``P`` on few coordinates can make cheaper. Traced
        once per function (a second call would make the same nodes again, at the tracing's cost:
        the Jacobians read it in the primal and in the implicit solve)."""
        if self._mass_q is None:
            self._mass_q = self._trace_mass_in_joint_space()
        return self._mass_q

    def use_tree_mass(self, tree_mass) -> None:
        """Take ``M_q = P^T M_tree P`` from ``tree_mass``, the nodes of the tree's mass matrix traced
        elsewhere in this graph (the closed-form derivatives' entries, which the Jacobians compute
        anyway), instead of tracing the composite-rigid-body algorithm for it."""
        p = self.t.p_full()
        nodes = np.array([[self.g.const(x) for x in row] for row in tree_mass], dtype=object)
        self._mass_q = node_matmul(p.T, node_matmul(nodes, p))

    def _trace_mass_in_joint_space(self):
        if not self.model.partition.u1:
            return self.mass_by_composite_inertia()
        key = (id(self.model), tuple(self.t.parameters.names) if self.t.parameters else ())
        traced = {}

        def cheaper() -> str:   # both traced once per model; the other functions trace the winner only
            traced.update(composite=self.mass_by_composite_inertia(), columns=self.mass_by_columns())
            return "composite" if self.operations(traced["composite"]) <= self.operations(traced["columns"]) \
                else "columns"
        route = per_model(_MASS_ROUTES, self.model, key, cheaper)
        if route in traced:
            return traced[route]
        return self.mass_by_composite_inertia() if route == "composite" else self.mass_by_columns()

    def tree_mass_matrix(self) -> np.ndarray:
        """``M_tree`` over every tree coordinate (``N_all x N_all`` nodes) by the composite-rigid-body
        algorithm on the body parameters of :attr:`~symgen.codegen.trace.Tracer.joint_force_inertias`."""
        t = self.t
        m_tree = crba.tree_mass_matrix(*t.force_frames, t.joint_force_inertias)
        return np.array([[t.field.const(x) for x in row] for row in m_tree], dtype=object)

    def mass_by_composite_inertia(self):
        p = self.t.p_full()
        return node_matmul(p.T, node_matmul(self.tree_mass_matrix(), p))

    def mass_by_columns(self):
        p = self.t.p_full()
        zero = [0] * self.model.tree.n_coords
        cols = [self.t.joint_forces(zero, list(p[:, k]), gravity=False, tag=f"_col{k}")
                for k in range(self.n)]
        return np.array(cols, dtype=object).T

    def operations(self, values) -> int:
        return self.g.count(self.g.live([values.flat]))["total"]

    def mass(self, a):
        """``M = A^-T M_q A^-1`` (32)."""
        m_q = self.mass_in_joint_space()
        y = self.t.solve_task(a, m_q, transpose=True)
        return self.t.solve_task(a, y.T, transpose=True).T

    def motion_rates(self, a) -> np.ndarray:
        """``W_m = A^-1 [I_m; 0]`` (``n x m``): the joint rates each motion coordinate gives
        (eq. 18), so that ``qd = W_m V_m`` and the rows ``m`` of ``A^-T`` are ``W_m^T``."""
        unit = np.array([[self.g.const(int(i == k)) for k in range(self.m)] for i in range(self.n)], dtype=object)
        return self.t.solve_task(a, unit)

    def bias_forces(self, a, qd_all, eta_m) -> list:
        """``A^T (C [V_m; 0] + G)`` in one recursion: the joint forces at ``dV_m = 0``, gravity,
        friction, springs and the contact term ``D_m^T eta_m`` included (``C [V_m; 0]`` and ``G``
        of :meth:`coriolis` and :meth:`gravity` before their solve with ``A^T``)."""
        model = self.model
        qdd_all = self.task_accelerations(a, qd_all, [0] * self.m)
        tau = self.t.joint_forces(qd_all, qdd_all, gravity=has_gravity(model),
                                  friction_rates=qd_all if has_friction(model) else None,
                                  springs=has_springs(model))
        if eta_m is not None:
            tau = [x + y for x, y in zip(tau, self.contact_term(eta_m))]
        return list(tau)

    def coriolis(self, a, qd_all):
        """``C [V_m; 0] = A^-T (C_q qd + M_q qdd_b)`` with ``qdd_b`` the acceleration at ``dV_m = 0``."""
        qdd_all = self.task_accelerations(a, qd_all, [0] * self.m)
        tau = self.t.joint_forces(qd_all, qdd_all, gravity=False)
        return list(self.t.solve_task(a, tau, transpose=True))

    def gravity(self, a, qd_all, eta_m):
        zero = [0] * self.model.tree.n_coords
        rates = qd_all if has_friction(self.model) else None
        tau = self.t.joint_forces(zero, zero, gravity=has_gravity(self.model), friction_rates=rates, tag="_g",
                                  springs=has_springs(self.model))
        if eta_m is not None:
            tau = [x + y for x, y in zip(tau, self.contact_term(eta_m))]
        return list(self.t.solve_task(a, tau, transpose=True))

    def finish(self, name, doc, outputs) -> Function:
        outs = [(Argument(n, np.shape(v), d), np.array(v, dtype=object)) for n, v, d in outputs]
        return Function(name, doc, self.inputs + parameter_arguments(self.t.parameters), outs, self.g)
