"""The ``lambdify`` column: ``sympy.lambdify`` of the dense symbolic model (32), as the codegen
benchmark (``benchmarks/codegen_speed.py``) builds it, run in a subprocess with a time limit.

The worker evaluates :meth:`symgen.model.Model.evaluate` in the ``symbolic`` field with symbols
for the positions (``c_j, s_j`` per revolute joint, ``d_j`` per prismatic one, ``R_j_ab`` per
spherical one) and the velocity inputs, forms each generated function's outputs from ``M``,
``C``, ``G``, ``[J_m; J_f]`` the way :mod:`symgen.accuracy.reference` does, lambdifies them
(``numpy`` module, no CSE, like the benchmark) and evaluates them at the states. A wrapper takes
the generated code's own inputs: it computes ``cos``/``sin`` of the angles and the rotation of
each quaternion, and for ``forward_dynamics`` solves ``M_mm dV_m = ...`` with
:func:`numpy.linalg.solve`. Its time is in the per-call time.

The symbolic field refuses inverses larger than 6x6, and symbolic inverses of large trigonometric
matrices may not finish: the worker prints one JSON line per finished function, and the caller
reports the rest as ``n/a`` with the reason.

    python -m symgen.accuracy.lambdify INPUT.json     (INPUT as written by :func:`run_lambdify`)
"""
from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import tempfile
import time

import numpy as np

from ..scene.joint_kinds import joint_kind
from .backends import ROUNDS

#: seconds the worker may take for the whole scene (symbolic model, lambdify, evaluation, timing)
DEFAULT_TIMEOUT = 60.0


# ---------------------------------------------------------------- positions
def position_symbols(model, cfg) -> list:
    """Position symbols in the order of the generated code's ``q`` layout."""
    from ..codegen.trace import position_layout

    out = []
    for name, kind, _, _ in position_layout(model):
        p, kind = cfg.positions[name], joint_kind(kind)
        out += [p.c, p.s] if kind.position_is_angle else [p] if kind.translates else [v for row in p for v in row]
    return out


def position_values(model, q) -> list[float]:
    """The values of :func:`position_symbols` at the generated code's ``q`` (float)."""
    from ..codegen.trace import position_layout
    from ..math.spatial import quaternion_matrix

    out = []
    for _, kind, off, _ in position_layout(model):
        kind = joint_kind(kind)
        if kind.position_is_angle:
            out += [np.cos(q[off]), np.sin(q[off])]
        elif kind.translates:
            out.append(q[off])
        else:
            quat = q[off:off + 4]
            out += list((np.array(quaternion_matrix(*quat)) / float(quat @ quat)).ravel())
    return out


# ---------------------------------------------------------------- symbolic outputs
class SymbolicModel:
    """Symbols and the two dense symbolic evaluations (joint space at ``qd``; model (32) at
    ``V_m``, ``eta_m``), built on first use."""

    def __init__(self, model):
        import sympy as sp

        self.sp, self.model = sp, model
        n, m = model.counts.n, model.counts.m
        cf = model.scene.contact_forces
        self.cfg = model.symbolic_configuration()
        self.sym = {"pos": position_symbols(model, self.cfg), "qd": model.symbolic_velocity(),
                    "qdd": list(sp.symbols(f"qdd0:{n}", real=True)), "V_m": list(sp.symbols(f"V0:{m}", real=True)),
                    "dV_m": list(sp.symbols(f"dV0:{m}", real=True)), "tau": list(sp.symbols(f"tau0:{n}", real=True)),
                    "eta_f": list(sp.symbols(f"eta_f0:{n - m}", real=True)),
                    "eta_m": list(sp.symbols(f"eta_m0:{len(cf.components) if cf else 0}", real=True))}
        self._done: dict = {}

    def _once(self, key, build):
        """``build()`` on first use; a failure is kept and raised again without recomputing."""
        if key not in self._done:
            try:
                self._done[key] = (build(), None)
            except Exception as exc:  # noqa: BLE001 - re-raised below, for every function that needs it
                self._done[key] = (None, exc)
        value, exc = self._done[key]
        if exc is not None:
            raise exc
        return value

    def joint(self):
        return self._once("joint", lambda: self.model.evaluate(self.cfg, qd=self.sym["qd"], field="symbolic"))

    def task(self):
        eta = self.sym["eta_m"] or None
        return self._once("task", lambda: self.model.evaluate(self.cfg, V_m=self.sym["V_m"], eta_m=eta,
                                                              field="symbolic"))

    def function(self, name: str) -> tuple[list[str], list[np.ndarray]]:
        """``(input groups, output expression arrays)`` of the parts lambdify evaluates."""
        m, s = self.model.counts.m, self.sym
        arr = lambda key: np.array(s[key], dtype=object)  # noqa: E731
        if name == "inverse_dynamics":
            d = self.joint()
            return ["pos", "qd", "qdd"], [d.M_q @ arr("qdd") + d.C_q @ arr("qd") + d.G_q]
        d = self.task()
        c_v = d.C[:, :m] @ arr("V_m")
        if name == "task_inverse_dynamics":
            eta_f = np.concatenate([np.zeros(m, dtype=object), arr("eta_f")])
            return ["pos", "V_m", "dV_m", "eta_f", "eta_m"], [d.maps.A.v.T @ (d.M[:, :m] @ arr("dV_m") + c_v + d.G + eta_f)]
        if name == "forward_dynamics":
            return ["pos", "V_m", "eta_m"], [d.M[:m, :m], d.M[m:, :m], d.maps.A_inv.v.T, c_v + d.G]
        table = {"mass_matrix": (["pos"], d.M), "coriolis_times_v": (["pos", "V_m"], c_v),
                 "gravity": (["pos", "V_m", "eta_m"], d.G), "joint_rates": (["pos", "V_m"], d.maps.P.v @ d.maps.Omega.v @ arr("V_m"))}
        groups, out = table[name]
        return groups, [out]

    def callable(self, name: str):
        """``(prepare(state) -> args, call(*args) -> tuple of outputs)`` for function ``name``."""
        sp, model = self.sp, self.model
        groups, outs = self.function(name)
        groups = [g for g in groups if self.sym[g]]
        flat = [sp.sympify(e) for o in outs for e in np.asarray(o).ravel()]
        fn = sp.lambdify([self.sym[g] for g in groups], flat, "numpy")
        shapes = [np.shape(o) for o in outs]
        m = model.counts.m
        need = ["q"] + [g for g in groups if g != "pos"] + (["tau"] if name == "forward_dynamics" else [])

        def call(q, *rest):
            values = np.array(fn(position_values(model, q), *rest[:len(groups) - 1]), dtype=float)
            parts, at = [], 0
            for shape in shapes:
                size = int(np.prod(shape))
                parts.append(values[at:at + size].reshape(shape))
                at += size
            if name != "forward_dynamics":
                return tuple(parts)
            m_mm, m_fm, a_inv_t, cg = parts
            rhs = a_inv_t @ rest[-1] - cg
            dv = np.linalg.solve(m_mm, rhs[:m])
            return (dv, rhs[m:] - m_fm @ dv) if rhs.size > m else (dv,)

        return (lambda st: tuple(np.asarray(st[k], dtype=float) for k in need)), call


# ---------------------------------------------------------------- worker and caller
def _short(exc: Exception) -> str:
    """The message up to its hint: the first ``"; "`` outside brackets (``[J_m; J_f]`` stays)."""
    return re.split(r";\s(?![^\[]*\])", str(exc), maxsplit=1)[0] or type(exc).__name__


def worker(path: str) -> None:
    """Subprocess body: one JSON line per function, as soon as it is done."""
    from ..io.loading import load
    from ..model import derive
    from .backends import per_call_seconds

    job = json.loads(open(path).read())
    model = derive(load(job["spec"]))
    symbolic = SymbolicModel(model)
    for name in job["functions"]:
        start = time.perf_counter()
        try:
            prepare, call = symbolic.callable(name)
            args = [prepare(s) for s in job["states"]]
            outputs = [[np.asarray(o, float).ravel().tolist() for o in call(*a)] for a in args]
            line = {"function": name, "status": "ok", "outputs": outputs,
                    "seconds": per_call_seconds(call, args, job["rounds"]), "build_seconds": time.perf_counter() - start}
        except Exception as exc:  # the reason becomes the table cell (e.g. SymbolicTooLargeError)
            line = {"function": name, "status": f"n/a: {_short(exc)}", "detail": f"{type(exc).__name__}: {exc}"}
        print(json.dumps(line), flush=True)


def run_lambdify(spec: str, functions: list[str], states: list[dict], *, timeout: float = DEFAULT_TIMEOUT,
                 rounds: int = ROUNDS) -> dict[str, dict]:
    """Run :func:`worker` on ``states`` in a fresh interpreter; ``{function: result}`` where
    result has ``status`` (``"ok"`` or ``"n/a: <reason>"``) and, when ok, ``outputs`` (per state,
    per output, flat lists) and ``seconds`` per call."""
    if timeout <= 0:
        return {f: {"status": "n/a: disabled (--lambdify-timeout 0)"} for f in functions}
    keys = ("q", "qd", "qdd", "V_m", "dV_m", "eta_f", "tau", "eta_m")
    job = {"spec": spec, "functions": list(functions), "rounds": rounds,
           "states": [{k: np.asarray(s[k], float).tolist() for k in keys if k in s} for s in states]}
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as fh:
        json.dump(job, fh)
    try:
        proc = subprocess.Popen([sys.executable, "-m", "symgen.accuracy.lambdify", fh.name],
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        try:
            out, err = proc.communicate(timeout=timeout)
            why = f"n/a: worker failed ({(err.strip().splitlines() or ['no message'])[-1]})"
        except subprocess.TimeoutExpired:
            proc.kill()
            out, err = proc.communicate()
            why = f"n/a: > {timeout:g} s limit (symbolic model + lambdify)"
    finally:
        os.unlink(fh.name)
    results = {}
    for line in out.splitlines():
        if line.startswith("{"):
            item = json.loads(line)
            results[item.pop("function")] = item
    return {f: results.get(f, {"status": why}) for f in functions}


if __name__ == "__main__":
    worker(sys.argv[1])
