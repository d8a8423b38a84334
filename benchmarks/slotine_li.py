"""Baseline: the classical Slotine-Li joint-space adaptive controller against symgen's Section 4
controller, on the UR5 (URDF of example-robot-data), the same task, gains and wrong start.

Slotine and Li (IJRR 1987): with ``s = qd - qd_r``, ``qd_r = qd_d + Lambda (q_d - q)``,

    tau = Y(q, qd, qd_r, qdd_r) P_hat - K_D s,         dP_hat/dt = -Gamma Y^T s   (projected)
    Y P = M(q) qdd_r + C(q, qd) qd_r + g(q)

with the Christoffel-consistent ``C`` of Pinocchio (``computeCoriolisMatrix``). The classical
regressor is formed here column by column from Pinocchio's ``crba``, ``computeCoriolisMatrix``
and ``computeGeneralizedGravity``: by linearity, column ``k`` is the difference between a model
whose parameter ``k`` is raised by one and the true model (61 models, 183 C++ calls through the
Python bindings). The plant
is Pinocchio's ``aba`` with the true inertias. symgen's controller runs on its own plant (the same
robot: the two agree to 1e-15, ``symgen check ur5 --against pinocchio``).

Both controllers: ``K_D = K_A = k M(q_0)``, the same ``Lambda``, the same joint path, the same three
links' parameters scaled by the same factors at the start, gains ``rho w_k^2`` and bounds
``P_k +- w_k`` (``w_k = max(|P_k|, 0.02)``). Per-call cost, side by side from Python: the classical
regressor and law, symgen's generated NumPy ``control``, and symgen's generated C ``control``
through its ctypes binding.

    python benchmarks/slotine_li.py           # writes benchmarks/slotine_li.md
"""
import dataclasses
import inspect
import time
from pathlib import Path

import numpy as np
import pinocchio as pin
from scipy.integrate import solve_ivp

import symgen
from symgen.codegen.generate import trace_all
from symgen.codegen.runtime import load_generated
from symgen.control.adaptation import clip_to_bounds, parameter_rate
from symgen.simulation.control_demo import BOUND_FLOOR, Demo, run_demo
from symgen.simulation.control_report import final
from symgen.control.tasks import Excursion
from symgen.oracle.pinocchio_model import pinocchio_robot

DEMO = Demo("ur5", {"upper_arm_link": 1.3, "forearm_link": 0.7, "wrist_1_link": 1.3}, amplitude=0.3,
            gain=5.0, task_gain=5.0, rho=50.0, t_end=8.0,
            description="UR5 tracking a joint path, three links' parameters +-30% off")
HERE = Path(__file__).parent


class SlotineLi:
    """The classical controller and its plant, in Pinocchio's parameters (module docstring)."""

    def __init__(self, model, demo: Demo):
        self.robot = pinocchio_robot(model.scene)
        self.pm = self.robot.model
        self.data = self.pm.createData()
        self.true = np.concatenate([self.pm.inertias[j].toDynamicParameters() for j in range(1, self.pm.njoints)])
        self.p0 = self.true.copy()
        names = [self.pm.names[j] for j in range(1, self.pm.njoints)]
        child = {j.name: model.tree.bodies[j.child].name for j in model.tree.joints}
        self.unc = []
        for k, joint in enumerate(names):
            factor = demo.factors.get(child[joint])
            if factor is not None:
                self.p0[10 * k:10 * k + 10] *= factor
                self.unc += list(range(10 * k, 10 * k + 10))
        self.unc = np.array(self.unc)
        w = np.maximum(np.abs(self.true[self.unc]), BOUND_FLOOR)
        self.lower, self.upper = self.true[self.unc] - w, self.true[self.unc] + w
        masses = self.unc[self.unc % 10 == 0]
        self.lower[np.isin(self.unc, masses)] = 0.1 * self.true[masses]
        self.gamma = demo.rho * w * w
        self.unit_models = [self._unit(k) for k in range(len(self.true))]
        q0 = pin.neutral(self.pm)
        self.k_d = demo.gain * pin.crba(self.pm, self.data, q0)
        self.k_d = np.triu(self.k_d) + np.triu(self.k_d, 1).T
        self.excursion = Excursion(np.full(self.pm.nv, demo.amplitude), demo.frequency)
        self.lam, self.q0, self.calls = demo.task_gain, q0, 0

    def _unit(self, k):
        """A model whose parameter ``k`` is one more than the true one (Pinocchio cannot hold a
        massless unit inertia, so each column is a difference, exact by linearity)."""
        m = self.pm.copy()
        j = k // 10 + 1
        p = m.inertias[j].toDynamicParameters()
        p[k % 10] += 1.0
        m.inertias[j] = pin.Inertia.FromDynamicParameters(p)
        return m, m.createData()

    @staticmethod
    def _terms(m, d, q, qd, qd_r, qdd_r) -> np.ndarray:
        mass = pin.crba(m, d, q)
        mass = np.triu(mass) + np.triu(mass, 1).T
        return mass @ qdd_r + pin.computeCoriolisMatrix(m, d, q, qd) @ qd_r + pin.computeGeneralizedGravity(m, d, q)

    def regressor(self, q, qd, qd_r, qdd_r) -> np.ndarray:
        """``Y`` column by column: ``M_k qdd_r + C_k(q, qd) qd_r + g_k``, each the difference of the
        terms of a model with parameter ``k`` raised by one and of the true model."""
        base = self._terms(self.pm, self.data, q, qd, qd_r, qdd_r)
        return np.array([self._terms(m, d, q, qd, qd_r, qdd_r) - base for m, d in self.unit_models]).T

    def control(self, t, q, qd, p_hat):
        x_d, v_d, a_d = self.excursion(t)
        q_d = self.q0 + x_d
        qd_r = v_d + self.lam * (q_d - q)
        qdd_r = a_d + self.lam * (v_d - qd)
        s = qd - qd_r
        y = self.regressor(q, qd, qd_r, qdd_r)
        return y @ p_hat - self.k_d @ s, y, s, np.linalg.norm(q_d - q)

    def __call__(self, t, x):
        self.calls += 1
        n, k = self.pm.nv, len(self.unc)
        q, qd, p_unc = x[:n], x[n:2 * n], x[2 * n:]
        p_hat = self.p0.copy()
        p_hat[self.unc] = clip_to_bounds(p_unc, self.lower, self.upper)
        tau, y, s, _ = self.control(t, q, qd, p_hat)
        qdd = pin.aba(self.pm, self.data, q, qd, tau)
        dp = parameter_rate(p_hat[self.unc], -(y.T @ s)[self.unc], self.lower, self.upper, self.gamma)
        assert len(dp) == k
        return np.concatenate([qd, qdd, dp])

    def run(self, adapt: bool = True, samples: int = 161):
        n = self.pm.nv
        x0 = np.concatenate([self.q0, np.zeros(n), self.p0[self.unc]])
        fun = self if adapt else (lambda t, x: np.concatenate([self(t, x)[:2 * n], np.zeros(len(self.unc))]))
        times = np.linspace(0, DEMO.t_end, samples)
        start = time.perf_counter()
        sol = solve_ivp(fun, (0, DEMO.t_end), x0, method="RK45", t_eval=times, rtol=1e-7, atol=1e-9)
        wall = time.perf_counter() - start
        errors = []
        for t, x in zip(sol.t, sol.y.T):
            p_hat = self.p0.copy()
            p_hat[self.unc] = x[2 * n:] if adapt else self.p0[self.unc]
            errors.append(self.control(t, x[:n], x[n:2 * n], p_hat)[3])
        return np.array(errors), wall


def per_call(fn, repeats: int = 200) -> float:
    fn()
    start = time.perf_counter()
    for _ in range(repeats):
        fn()
    return (time.perf_counter() - start) / repeats


def main() -> None:
    model = symgen.derive(symgen.load("ur5"))
    sl = SlotineLi(model, DEMO)
    rows = []
    runs = run_demo(dataclasses.replace(DEMO, t_end=DEMO.t_end))
    rows.append(("symgen Section 4 (dense reference, on symgen's plant)", final(runs["adaptive"].task_error),
                 final(runs["frozen"].task_error), runs["adaptive"].wall_time))
    err_a, wall = sl.run(True)
    err_f, _ = sl.run(False)
    rows.append(("Slotine-Li (Pinocchio regressor, on Pinocchio's aba)", final(err_a), final(err_f), wall))
    # per-call cost of one control evaluation, from Python
    rng = np.random.default_rng(3)
    q, qd = rng.uniform(-1, 1, 6), rng.uniform(-1, 1, 6)
    p_hat = sl.true.copy()
    t_sl = per_call(lambda: sl.control(0.3, q, qd, p_hat), 100)
    uncertain = ",".join(f"{qn}_{b}" for b in DEMO.factors for qn in ("m", "hx", "hy", "hz", "Ixx", "Iyy", "Izz",
                                                                          "Ixy", "Ixz", "Iyz"))
    timings = {}
    for target in ("numpy", "c"):
        lowered = trace_all(model, ["control"], {"uncertain": uncertain})
        module = load_generated(model, target, ["control"], lowered=lowered)
        args = dict(q=q, V_m=qd, V_mr=qd * 0.9, dV_mr=qd * 0.1, P_hat=np.ones(30))
        names = list(inspect.signature(module.control).parameters)
        timings[target] = per_call(lambda: module.control(*[args[a] for a in names if a in args]), 2000)
    lines = ["# Baseline: Slotine-Li against symgen's Section 4 controller (UR5)", "",
             "`python benchmarks/slotine_li.py`. " + DEMO.description + f"; k = {DEMO.gain}, Lambda = "
             f"{DEMO.task_gain}, rho = {DEMO.rho}, {DEMO.t_end:g} s, RK45 rtol 1e-7. Task error: |q_d - q| (rad), "
             "the largest over the last 20 % of the run. Time: integration only.", "",
             "| controller | task error, adaptive | task error, frozen | adaptive / frozen | integration (s) |",
             "|---|---|---|---|---|"]
    for name, a, f, w in rows:
        lines.append(f"| {name} | {a:.2g} | {f:.2g} | {a / f:.2g} | {w:.0f} |")
    lines += ["", "Per-call cost of one evaluation of the control law with its regressor, from Python, "
              "measured side by side in one run (30 uncertain parameters):", "",
              "| implementation | us per call | / symgen C |", "|---|---|---|",
              f"| Slotine-Li, classical regressor (60 columns from 61 models: Pinocchio's C++ crba, Coriolis matrix, "
              f"gravity via Python) | {t_sl * 1e6:.0f} | {t_sl / timings['c']:.0f} |",
              f"| symgen generated NumPy `control` | {timings['numpy'] * 1e6:.1f} | "
              f"{timings['numpy'] / timings['c']:.1f} |",
              f"| symgen generated C `control` (ctypes call) | {timings['c'] * 1e6:.1f} | 1 |",
              "", "Through Python the ctypes call's own overhead dominates symgen's C time; the C function "
              "itself, called from C, takes about 0.2 us (`benchmarks/control_speed.md`)."]
    (HERE / "slotine_li.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
