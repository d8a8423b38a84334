"""The closed loop of :mod:`symgen.simulation.closed_loop` on generated code: plant and controller
from the generated functions of one trace, no dense evaluation per right-hand side.

Per right-hand side, with ``x = [q; V_m]`` and the estimates ``P_hat``::

    qd_all        = joint_rates(q, V_m)                          eqs. (10), (18)
    (R, p, V)     = the task frame's pose and twist              Poses (plain NumPy kinematics)
    V_mr, dV_mr   = the task's required velocity and its exact derivative (eq. 34)
    tau           = control(q, V_m, V_mr, dV_mr[, eta_fr], P_hat)          eq. (34), K_A folded
    s             = adaptation(q, V_m, V_mr, dV_mr)                        eq. (38)
    eta_m         = the true contact law at the contact frame's twist     eq. (37)
    dV_m, eta_f   = forward_dynamics(q, V_m, tau[, eta_m])                 model (32)

The Lyapunov function of Section 4 is ``1/2 x^T M x + 1/2 sum_k (P_hat_k - P_k)^2 / rho_k`` with
``x = [V_mr - V_m; 0]`` and ``M`` model (32)'s mass matrix in space O (``= e^T M_q e`` in space A),
from the generated ``mass_matrix``. :func:`pick_backend` takes C when a compiler is on the path,
NumPy otherwise; the C module is compiled once per content and cached.
"""
from __future__ import annotations

import os
import shutil

import numpy as np

from ..codegen.trace import position_layout
from ..control.adaptation import parameter_error_energy, parameter_rate
from ..control.tasks import FrameTask, MixedTask
from .closed_loop import ClosedLoop
from .dynamics import guarded_call
from .poses import Poses

#: the generated functions the closed loop runs on
LOOP_FUNCTIONS = ("joint_rates", "forward_dynamics", "mass_matrix", "control", "adaptation")
#: the last generated module (the adaptive and the frozen run of a demonstration share it)
_MODULES: dict = {}


def pick_backend() -> str:
    """``"c"`` when the C compiler (``$CC``, default ``cc``) is on the path, else ``"numpy"``."""
    return "c" if shutil.which(os.environ.get("CC", "cc")) else "numpy"


class GeneratedClosedLoop(ClosedLoop):
    """:class:`ClosedLoop` with plant and controller from generated code (module docstring)."""

    def __init__(self, model, params, p_hat0, task, settings, contact=None, *, backend: str | None = None):
        super().__init__(model, params, p_hat0, task, settings, contact)
        from ..codegen.generate import trace_all
        from ..codegen.runtime import load_generated

        self.backend = backend or pick_backend()
        names = [params.names[k] for k in self.unc]
        options = {"uncertain": names, "gain": np.asarray(settings.gain, float)}
        if contact is not None:
            options["contact"] = contact
        key = (id(model), self.backend, repr((names, options["gain"].tolist(), contact)))
        if key not in _MODULES or _MODULES[key][0] is not model:
            lowered = trace_all(model, list(LOOP_FUNCTIONS), options)
            _MODULES.clear()
            _MODULES[key] = (model, load_generated(model, self.backend, lowered=lowered))
        self.module = _MODULES[key][1]
        self.poses = Poses(model)
        offsets = {name: off for name, _, off, _ in position_layout(model)}
        joints = task.joint_task if isinstance(task, MixedTask) else task
        self.joint_offsets = ([offsets[j] for j in joints.names] if not isinstance(task, FrameTask) else None)
        cf = model.scene.contact_forces
        self.contact_select = ([("vx", "vy", "vz", "wx", "wy", "wz").index(c) for c in cf.components]
                               if contact is not None else None)
        self.n_m = model.counts.m

    def _call(self, t, fn, *args):
        return guarded_call(t, fn, *args)

    def evaluate(self, t, y) -> dict:
        q, v_m, p_unc, z = self.split(y)
        q = self.layout.normalized(q)
        qd_all = self._call(t, self.module.joint_rates, q, v_m)
        bodies = self.poses.bodies(q)
        if isinstance(self.task, MixedTask):
            r, p, twist = self.poses.frame_twist(q, qd_all, self.task.frame_task.frame, bodies)
            v_mr, dv_mr, e_task = self.task.required_at(t, r, p, twist, q[self.joint_offsets], v_m)
        elif self.joint_offsets is None:
            r, p, twist = self.poses.frame_twist(q, qd_all, self.task.frame, bodies)
            v_mr, dv_mr, e_task = self.task.required_at(t, r, p, twist)
        else:
            v_mr, dv_mr, e_task = self.task.required_at(t, q[self.joint_offsets], v_m)
        p_hat = self.estimates(p_unc)
        eta_fr = self.eta_fd + self.settings.force_gain * z
        args = (q, v_m, v_mr, dv_mr)
        tau = self._call(t, self.module.control, *args, *((eta_fr,) if len(z) else ()),
                         *((p_hat[self.unc],) if len(self.unc) else ()))
        s = self._call(t, self.module.adaptation, *args) if len(self.unc) else np.zeros(0)
        extra = ()
        if self.contact is not None:
            v_c = self.poses.frame_twist(q, qd_all, self.contact.frame, bodies)[2][self.contact_select]
            extra = (np.asarray(self.contact.forces(v_c, self.model.float_field), float),)
        out = self._call(t, self.module.forward_dynamics, q, v_m, tau, *extra)
        dv, eta_f = out if isinstance(out, tuple) else (out, np.zeros(0))
        return dict(q=q, v_m=v_m, qd_all=qd_all, p_hat=p_hat, v_mr=v_mr, e_task=e_task, tau=tau, s=s,
                    dv=np.asarray(dv, float), eta_f=np.asarray(eta_f, float))

    def __call__(self, t, y) -> np.ndarray:
        self.calls += 1
        ev = self.evaluate(t, y)
        q, rates = ev["q"], ev["qd_all"]
        if self.stabilizer.dependent:
            rates = rates + self.stabilizer.baumgarte(q)
        dp = (parameter_rate(ev["p_hat"][self.unc], ev["s"], self.lower, self.upper, self.rho)
              if self.settings.adapt else np.zeros(len(self.unc)))
        return np.concatenate([self.layout.position_rates(q, rates), ev["dv"], dp, self.eta_fd - ev["eta_f"]])

    def lyapunov(self, ev) -> float:
        x = ev["v_mr"] - ev["v_m"]
        mass = np.asarray(self._call(0.0, self.module.mass_matrix, ev["q"]), float)
        kinetic = 0.5 * float(x @ mass[:self.n_m, :self.n_m] @ x)
        if not self.settings.adapt or not len(self.unc):
            return kinetic
        return kinetic + float(parameter_error_energy(ev["p_hat"][self.unc], self.true[self.unc], self.rho))
