"""Reference values for the generated functions from the dense model (32) of
:meth:`symgen.model.Model.evaluate` -- an independent path (``O(n_S^2)`` matrices, no recursion,
no tracing) used by the equivalence tests and the standalone C test program."""
from __future__ import annotations

import numpy as np

from ..closure import random_consistent_states
from .trace import position_vector


def reference_states(model, count: int, seed: int = 0, spread: float = 0.3) -> list[dict]:
    """``count`` loop-closed states with every input a generated function may take."""
    rng = np.random.default_rng(seed + 1)
    n, m = model.counts.n, model.counts.m
    cf = model.scene.contact_forces
    out = []
    for config, v_m in random_consistent_states(model, count, seed=seed, spread=spread):
        d = model.evaluate(config, V_m=v_m)
        out.append(dict(config=config, q=position_vector(model, config), V_m=np.asarray(v_m, float),
                        qd=np.asarray(d.qd, float), qdd=rng.uniform(-1, 1, n), dV_m=rng.uniform(-1, 1, m),
                        eta_f=rng.uniform(-1, 1, n - m), tau=rng.uniform(-1, 1, n),
                        eta_m=rng.uniform(-1, 1, len(cf.components) if cf else 0)))
    return out


def reference_outputs(model, name: str, s: dict) -> dict[str, np.ndarray]:
    """The outputs of generated function ``name`` at state ``s``, from the dense model."""
    cfg, m = s["config"], model.counts.m
    eta_m = s["eta_m"] if s["eta_m"].size else None
    if name == "inverse_dynamics":
        d = model.evaluate(cfg, qd=s["qd"])
        return {"tau": d.M_q @ s["qdd"] + d.C_q @ s["qd"] + d.G_q}
    if name == "task_inverse_dynamics":
        return {"tau": model.inverse_dynamics(cfg, s["V_m"], s["dV_m"], s["eta_f"], eta_m)}
    if name == "forward_dynamics":
        dv, eta_f = model.forward_dynamics(cfg, s["V_m"], s["tau"], eta_m)
        return {"dV_m": dv, "eta_f": eta_f} if eta_f.size else {"dV_m": dv}
    if name == "mass_matrix":
        return {"M": model.evaluate(cfg).M}
    if name == "coriolis_times_v":
        d = model.evaluate(cfg, V_m=s["V_m"])
        return {"c": d.C[:, :m] @ s["V_m"]}
    if name == "gravity":
        return {"G": model.evaluate(cfg, V_m=s["V_m"], eta_m=eta_m).G}
    if name == "joint_rates":
        d = model.evaluate(cfg, V_m=s["V_m"])
        return {"qd_all": d.maps.P.v @ d.maps.Omega.v @ s["V_m"]}
    if name == "state_derivative":
        return {"dV_m": reference_outputs(model, "forward_dynamics", s)["dV_m"],
                **reference_outputs(model, "joint_rates", s)}
    if name == "dynamics_terms":
        d = model.evaluate(cfg, V_m=s["V_m"], eta_m=eta_m)
        return {"M": d.M, "c": d.C[:, :m] @ s["V_m"], "G": d.G}
    if name == "joint_accelerations":
        return {"qd_all": model.joint_rates(cfg, s["V_m"]),
                "qdd_all": model.joint_accelerations(cfg, s["V_m"], s["tau"], eta_m)}
    if name == "loop_forces":
        return {"lam": model.loop_forces(cfg, s["V_m"], s["tau"], eta_m)}
    raise KeyError(name)
