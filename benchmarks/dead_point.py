"""How much the velocity terms lose near a loop's dead point, and where symgen refuses.

The four-bar (built-in ``four_bar``) is flat -- at a dead point of its loop -- on the family
``q = [t, -t, t - pi, pi - t]`` as ``t -> 0``. At each ``t`` this takes two 50-digit solutions of
model (32) for ``dV_m`` (``V_m = 1``, ``tau = 1``): at the exactly closed configuration of the family
(``t`` and ``pi`` in 50 digits) and at the same configuration rounded to doubles, which is what a
float caller can give. Their difference is what the rounding of the input alone costs; the float
evaluation adds only ``cond u`` to it. The last columns: the bound ``cond(W)^2 u`` of
``symgen.conditioning`` and what ``Model.forward_dynamics`` does there.

Run: ``python benchmarks/dead_point.py`` (writes ``benchmarks/dead_point.md``; about a minute).
"""
from __future__ import annotations

import pathlib
import sys

import mpmath
import numpy as np

import symgen
from symgen.conditioning import MAX_LOOP_CONDITION
from symgen.math.configuration import Configuration
from symgen.math.fields import make_field
from symgen.model_solves import solve_forward

HERE = pathlib.Path(__file__).resolve().parent
U = 2.0 ** -53
T_VALUES = (1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10)


def mp_dv(model, positions) -> mpmath.mpf:
    fld = make_field("mp", model.tree.parameters)
    names = [j.name for j in model.scene.joints.values() if j.dof]
    d = model.evaluate(Configuration(dict(zip(names, positions))), V_m=[fld.one], field=fld)
    dv, _ = solve_forward(d, [fld.one] * model.counts.n)
    return dv[0]


def row(model, t: float) -> str:
    mp = mpmath.mp
    mp.dps = 50
    exact = [mp.mpf(t), -mp.mpf(t), mp.mpf(t) - mp.pi, mp.pi - mp.mpf(t)]
    rounded = [t, -t, t - np.pi, np.pi - t]
    on_manifold, at_rounded = mp_dv(model, exact), mp_dv(model, [mp.mpf(x) for x in rounded])
    w = model.evaluate(np.array(rounded), field="float").maps.W.v
    cond = float(np.linalg.cond(np.asarray(w, float)))
    error = abs(float((at_rounded - on_manifold) / on_manifold))
    try:
        model.forward_dynamics(np.array(rounded), [1.0], [1.0])
        verdict = "result"
    except symgen.SingularConfigurationError:
        verdict = "SingularConfigurationError"
    return (f"| {t:.0e} | {cond:.3g} | {float(on_manifold):.10g} | {error:.2g} | {cond * cond * U:.2g} | "
            f"{verdict} |")


def main() -> int:
    model = symgen.derive(symgen.load("four_bar"))
    lines = ["# Near a loop's dead point: what the rounding of the input costs", "",
             "Produced by `python benchmarks/dead_point.py` (see its docstring). `dV_m` of model (32) at",
             "`V_m = 1`, `tau = 1` on the four-bar's flat family `q = [t, -t, t - pi, pi - t]`. Relative",
             "error: the 50-digit solution at the double-rounded configuration against the 50-digit",
             f"solution on the manifold. symgen refuses above cond(W) = {MAX_LOOP_CONDITION:g}.", "",
             "| t | cond(W) (2-norm) | dV_m on the manifold | relative error from rounding q | "
             "cond(W)^2 u | Model.forward_dynamics |",
             "|---|---|---|---|---|---|"]
    for t in T_VALUES:
        lines.append(row(model, t))
        print(lines[-1], file=sys.stderr)
    (HERE / "dead_point.md").write_text("\n".join(lines) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
