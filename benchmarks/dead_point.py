"""How much the velocity terms lose near a loop's dead point, and where symgen refuses.

Table 1 -- the four-bar (built-in ``four_bar``) is flat -- at a dead point of its loop -- on the
family ``q = [t, -t, t - pi, pi - t]`` as ``t -> 0``. At each ``t`` this takes two 50-digit
solutions of model (32) for ``dV_m`` (``V_m = 1``, ``tau = 1``): at the exactly closed configuration
of the family (``t`` and ``pi`` in 50 digits) and at the same configuration rounded to doubles,
which is what a float caller can give. Their difference is what the rounding of the input alone
costs; the float evaluation adds only ``cond u`` to it. The last columns: the bound
``cond(W)^2 u`` of ``symgen.conditioning`` and what ``Model.forward_dynamics`` does there.

Table 2 -- every built-in with loops, on a closed family that runs into a singular configuration
(:mod:`symgen.accuracy.dead_points`: the four-bar and five-bar folds, the Stewart platform's
singular yaw, two arms holding an object with one wrist going singular), ``t = 1e-1 .. 1e-14``:
``forward_dynamics`` of the dense model, the generated NumPy and the generated C at the rounded
state, against the 50-digit answer at the exactly closed state. Each cell is the relative error of
``dV_m`` or the typed error raised; the bound is ``max(cond W, cond A)^2 u``. The last line per
scene: the largest ratio of the 2-norm condition number to the generated code's pivot-ratio
estimate (``symgen.conditioning.LOOP_ESTIMATE_MARGIN`` must exceed it).

Run: ``python benchmarks/dead_point.py`` (writes ``benchmarks/dead_point.md``; about five minutes).
"""
from __future__ import annotations

import pathlib
import sys

import mpmath
import numpy as np

import symgen
from symgen.accuracy.dead_points import FAMILIES, exact_configuration, float_positions, sweep_point
from symgen.codegen.runtime import load_generated
from symgen.conditioning import LOOP_ESTIMATE_MARGIN, MAX_LOOP_CONDITION, MAX_LOOP_ESTIMATE
from symgen.math.configuration import Configuration
from symgen.math.fields import make_field
from symgen.model_solves import solve_forward

HERE = pathlib.Path(__file__).resolve().parent
U = 2.0 ** -53
T_VALUES = (1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10)
SWEEP_T = tuple(10.0 ** -k for k in range(1, 15))
#: the scene spec of each family (table 2)
SPECS = {"four_bar": "four_bar", "five_bar": "five_bar", "stewart": "stewart", "multi_arm": "multi_arm:h=2"}


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


def _cell(answer: float | str, bound: float) -> str:
    if isinstance(answer, str):
        return answer
    return f"{answer:.2g}" + ("" if answer <= bound else " **above the bound**")


def estimate_ratio(model, family, t: float) -> float:
    """2-norm condition over the generated NumPy code's largest loop-limited estimate at ``t``:
    how far the estimate runs below the condition number (read from its refusal message)."""
    module = load_generated(model, "numpy", ["forward_dynamics"])
    fld = make_field("mp", model.tree.parameters)
    q = float_positions(model, exact_configuration(model, family, fld, t))
    from symgen.accuracy.dead_points import conditions

    cond = max(conditions(model, q))
    seen: list[float] = []
    check = module._check_pivots

    def spy(pivots, big, small, what, limit=module.MAX_CONDITION):
        if limit == MAX_LOOP_ESTIMATE:
            size = np.abs(np.stack(np.broadcast_arrays(*pivots)))
            seen.append(float(np.max(np.maximum(size.max(axis=0), big) / np.minimum(size.min(axis=0), small))))
        return check(pivots, big, small, what, limit)

    module._check_pivots = spy
    try:
        module.forward_dynamics(q, np.array(family.V_m), np.array(family.tau))
    except module.SingularSolveError:
        pass
    finally:
        module._check_pivots = check
    return cond / max(seen) if seen else float("nan")


def sweep_table() -> list[str]:
    lines = ["## Every built-in with loops, every door", "",
             f"Relative error of `dV_m` against the 50-digit answer at the exactly closed state, or the typed "
             f"error raised. The dense model refuses above max(cond W, cond A) = {MAX_LOOP_CONDITION:g} (A only "
             f"with constraints); the generated code holds its pivot-ratio estimate to {MAX_LOOP_ESTIMATE:g} "
             f"(a margin of {LOOP_ESTIMATE_MARGIN} for the estimate). The families:", ""]
    lines += [f"- `{SPECS[name]}`: {family.description}" for name, family in FAMILIES.items()]
    lines += ["", "| scene | t | cond W | cond A | max(cond)^2 u | dense | NumPy | C |",
              "|---|---|---|---|---|---|---|---|"]
    ratios = []
    for name, family in FAMILIES.items():
        model = symgen.derive(symgen.load(SPECS[name]))
        modules = {target: load_generated(model, target, ["forward_dynamics"]) for target in ("numpy", "c")}
        for t in SWEEP_T:
            p = sweep_point(model, family, t, modules)
            lines.append(f"| {SPECS[name]} | {t:.0e} | {p.cond_W:.3g} | {p.cond_A:.3g} | {p.bound:.2g} | "
                         + " | ".join(_cell(p.answers[d], p.bound) for d in ("dense", "numpy", "c")) + " |")
            print(lines[-1], file=sys.stderr)
        ratios.append(f"| {SPECS[name]} | {max(estimate_ratio(model, family, t) for t in (1e-4, 1e-6)):.3g} |")
    lines += ["", "How far the generated code's estimate runs below the 2-norm condition number: the largest",
              "ratio max(cond W, cond A) / (largest loop-limited pivot-ratio estimate) at t = 1e-4 and 1e-6.", "",
              "| scene | condition / estimate |", "|---|---|"] + ratios
    return lines


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
    lines += [""] + sweep_table()
    (HERE / "dead_point.md").write_text("\n".join(lines).rstrip("\n") + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
