"""The closed form's ancestor-pair entries as straight-line dot products or as library products.

``inverse_dynamics_derivatives`` by the closed form (``symgen.codegen.dynamics_derivatives``) is
generated twice per scene: its entries as straight-line six-vector dot products, and as the five
banded library products of ``looped_entries`` (``symgen_product`` in the C file, writing into the outputs). Both C files are
compiled by clang (``-O3 -march=native -std=c99 -DSYMGEN_NO_LANES``), linked into
``codegen_timing.c -DDERIVATIVES`` and timed one call per state over the same states, the two
interleaved round by round; **ratio** is products / dot products (median over the rounds). The
generator takes the products from ``LOOPED_PAIRS`` ancestor pairs (a coordinate and one at or below
it) on; this table is what that threshold rests on.

    python benchmarks/closed_form_products.py [--scenes SPEC ...]   # writes closed_form_products.md and .csv
"""
from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from codegen_speed import machine, write_generated, write_table  # noqa: E402
from derivative_speed import N_STATES, compile_timers, run  # noqa: E402

SCENES = ["general_chain:n=7", "chain:n=8", "chain:n=10", "chain:n=12", "chain:n=16", "chain:n=24", "chain:n=32"]
ROUNDS, REPEATS = 7, 9
FUNCTION = "inverse_dynamics_derivatives"


def build(spec: str, looped: bool, work: Path) -> dict:
    """The closed-form function's C file with the entries one way, compiled into a timer."""
    from symgen.codegen import dynamics_derivatives as dd
    from symgen.codegen.emit import lower
    from symgen.codegen.functions import library_flops
    from symgen.codegen.generate import generate
    from symgen.io.builtin import get_scene
    from symgen.model import derive

    model = derive(get_scene(spec))
    saved = dd.LOOPED_PAIRS
    dd.LOOPED_PAIRS = 0 if looped else 10**9
    try:
        low = lower(dd._traced_analytic(model))
    finally:
        dd.LOOPED_PAIRS = saved
    gen = generate(model, "c", lowered=[low])
    tag = "products" if looped else "dots"
    src = write_generated(gen, work / f"{gen.module}_{tag}")
    timer = work / f"timer_{gen.module}_{tag}"
    compile_timers("clang", [], src / f"{gen.module}.c", work / f"{gen.module}_{tag}.o",
                   {f"symgen_{gen.module}_{FUNCTION}": timer}, model.counts.n)
    return dict(timer=timer, n=model.counts.n, pairs=dd.ancestor_pairs(model.tree), ops=low.ops["total"], flops=library_flops(low.ops))


def measure(spec: str, work: Path) -> dict:
    dots, products = build(spec, False, work), build(spec, True, work)
    n = dots["n"]
    states = work / f"states_{n}.bin"
    rng = np.random.default_rng(3)
    np.concatenate([rng.uniform(-1, 1, N_STATES * n) for _ in range(3)]).tofile(states)
    out = work / "out.bin"
    times: dict[str, list[float]] = {"dots": [], "products": []}
    diff = 0.0
    for _ in range(ROUNDS):
        got = {}
        for name, b in (("dots", dots), ("products", products)):
            ns, got[name] = run([b["timer"], states, N_STATES, REPEATS, out], out, n)
            times[name].append(ns)
        scale = max(float(np.abs(got["dots"]).max()), 1e-300)
        diff = max(diff, float(np.abs(got["products"] - got["dots"]).max()) / scale)
    row = {"scene": spec, "pairs": dots["pairs"], "dots_ops": dots["ops"], "products_ops": products["ops"],
           "products_flops": products["flops"], "dots_ns": statistics.median(times["dots"]),
           "products_ns": statistics.median(times["products"]),
           "ratio": statistics.median(p / d for p, d in zip(times["products"], times["dots"])), "max_rel_diff": diff}
    print(f"{spec:<18} pairs {row['pairs']:>4}  dots {row['dots_ns']:9.1f} ns  products {row['products_ns']:9.1f} ns  "
          f"ratio {row['ratio']:.3f}", flush=True)
    return row


def main() -> None:
    from symgen.codegen.dynamics_derivatives import LOOPED_PAIRS

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", nargs="+", default=SCENES)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        rows = [measure(spec, Path(tmp)) for spec in args.scenes]
    lines = ["# The closed form's entries: straight-line dot products or library products", "",
             f"`python benchmarks/closed_form_products.py`. `inverse_dynamics_derivatives` by the closed form, "
             "generated with its ancestor-pair entries as straight-line dot products and as banded library "
             "products, both C files built by clang (`-O3 -march=native -std=c99 -DSYMGEN_NO_LANES`) and timed "
             f"one call per state over {N_STATES} states, interleaved, the median of {ROUNDS} rounds of "
             f"{REPEATS} repeats. **ratio**: products / dot products (median over the rounds); **pairs**: the "
             f"ancestor pairs (the generator takes the products from LOOPED_PAIRS = {LOOPED_PAIRS} on); ops: "
             "straight-line mul + add; library flops: the products'; max rel diff: the two builds' outputs. "
             f"{machine()}", "",
             "| scene | pairs | dot products: ops | ns | library products: ops | library flops | ns | ratio | max rel diff |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['scene']} | {r['pairs']} | {r['dots_ops']} | {r['dots_ns']:.0f} | {r['products_ops']} | "
                     f"{r['products_flops']} | {r['products_ns']:.0f} | {r['ratio']:.2f} | {r['max_rel_diff']:.1e} |")
    write_table(HERE / "closed_form_products", lines, rows)


if __name__ == "__main__":
    main()
