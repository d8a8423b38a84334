"""Operation counts of the combined ``dynamics_terms`` (M, C [V_m; 0], G of model (32) in one
pass) against ``mass_matrix`` + ``coriolis_times_v`` + ``gravity`` called separately, on the
built-in scenes. Counts: mul + add, sin/cos and the flops of the dense solves included.

    python benchmarks/dynamics_terms.py        # writes benchmarks/dynamics_terms.md and .csv
"""
from pathlib import Path

from symgen.io.builtin import get_scene
from symgen.codegen.generate import generate
from symgen.model import derive

from codegen_speed import write_table

SCENES = ["chain:n=6", "chain:n=12", "four_bar", "five_bar", "arm_on_plane", "multi_arm:h=2", "stewart"]
SEPARATE = ("mass_matrix", "coriolis_times_v", "gravity")


def cost(ops: dict) -> int:
    return ops["total"] + ops["solve_flops"] + ops["trig"]


def main() -> None:
    lines = ["# `dynamics_terms`: M, C and G in one pass", "", "`python benchmarks/dynamics_terms.py`. "
             "Operations: mul + add + sin/cos + dense-solve flops, as `ops.json` counts them.", "",
             "| scene | mass_matrix + coriolis_times_v + gravity | dynamics_terms | ratio |", "|---|---|---|---|"]
    rows = []
    for spec in SCENES:
        ops = generate(derive(get_scene(spec)), "numpy", list(SEPARATE) + ["dynamics_terms"]).ops
        separate = sum(cost(ops[name]) for name in SEPARATE)
        combined = cost(ops["dynamics_terms"])
        lines.append(f"| {spec} | {separate} | {combined} | {combined / separate:.3f} |")
        rows.append({"scene": spec, "separate": separate, "dynamics_terms": combined, "ratio": combined / separate})
    write_table(Path(__file__).parent / "dynamics_terms", lines, rows)


if __name__ == "__main__":
    main()
