"""Traced order against first-use order: machine code and time of generated C functions.

The C target reorders a function's statements so that each comes just before the first output
that needs it, and assigns each output entry right after the statement computing it
(:mod:`symgen.codegen.targets.c_schedule`). For each scene of ``SCENES`` and function of
``FUNCTIONS`` (traced once), the C file is rendered in each variant of ``ORDERS`` -- ``traced``
(the traced order, every output assigned at the end: the C target before the reordering),
``traced, early stores`` (the traced order, outputs stored early) and ``first use`` (both: the
default) -- compiled by each of ``cc`` and ``clang`` (``-O3 -march=native -std=c99
-DSYMGEN_NO_LANES -ffp-contract=fast``, as the bindings compile), and

* **kept**: the variant the C target generates (:func:`~symgen.codegen.targets.c_schedule.schedule`);
  **mean live**: temporaries alive per statement, on average (``c_schedule.mean_live``);
* **code KB**: machine code of the function and its blocks (``nm -S``);
* **stack refs**: instructions of that code that address the stack frame (``objdump -d``: an
  operand on ``%rsp`` or ``%rbp``; x86-64 only, else empty) -- values spilled and reloaded;
* **ns**: one call per state over 200 states (``codegen_timing.c``, thread CPU clock, the median of
  its repeats), the median over interleaved rounds (every variant once per round), and
  **/ traced**: that time over the traced order's, same build and round (median over rounds);
* **max rel diff**: outputs against the traced order's of the same build (the same operations;
  a compiler that fuses multiplies into adds may fuse others once the order changes).

Writes ``statement_order.md`` and ``statement_order.csv`` beside this file.

    python benchmarks/statement_order.py [--rounds R] [--scenes SPEC ...]
"""
from __future__ import annotations

import json
import platform
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from block_size import REPEATS, code_bytes, run  # noqa: E402
from codegen_speed import C_COMPILERS, CFLAGS, VARIANTS, compiler_name, fmt, machine, write_generated  # noqa: E402
from derivative_speed import GENERATED_CFLAGS, N_STATES  # noqa: E402

SCENES = ["chain:n=6", "ur5", "panda", "general_chain:n=7"]
#: ``{function: its timer's define}``: the Jacobians (three n x n outputs) and the primal functions
FUNCTIONS = {"inverse_dynamics_derivatives": "-DDERIVATIVES", "forward_dynamics_derivatives": "-DDERIVATIVES",
             "inverse_dynamics": None, "forward_dynamics": None}
#: ``{variant: (ORDER, EARLY_STORES)}`` of ``symgen.codegen.targets.c_schedule``
ORDERS = {"traced": ("traced", False), "traced, early stores": ("traced", True), "first use": ("first use", True)}
#: the generated file's builds timed (``codegen_speed.VARIANTS``): as the bindings compile
BUILDS = {" fused": VARIANTS[" fused"]}


def stack_references(obj: Path, symbol: str) -> int | None:
    """Instructions of ``symbol`` and its blocks in ``obj`` with an operand on the stack pointer or
    the frame pointer; None off x86-64."""
    if platform.machine() not in ("x86_64", "AMD64"):
        return None
    text = subprocess.run(["objdump", "-d", "--no-show-raw-insn", str(obj)], capture_output=True, text=True,
                          check=True).stdout
    count, inside = 0, False
    for line in text.splitlines():
        if line.endswith(">:"):
            name = line.split("<", 1)[1][:-2]
            inside = name == symbol or name.startswith(symbol + "_block")
        elif inside and ("(%rsp" in line or "(%rbp" in line):
            count += 1
    return count


def build(spec: str, work: Path) -> tuple[list[dict], int]:
    """Every variant's timers: one dict per (order, function, build)."""
    from symgen.codegen.generate import generate, trace_all
    from symgen.codegen.targets import c_schedule
    from symgen.io.builtin import get_scene
    from symgen.model import derive

    model = derive(get_scene(spec))
    n = model.counts.n
    lowered = trace_all(model, list(FUNCTIONS))
    kept = {low.function.name: "traced, early stores" if c_schedule.schedule(low) is low else "first use"
            for low in lowered}
    builds = []
    try:
        for order, (c_schedule.ORDER, c_schedule.EARLY_STORES) in ORDERS.items():
            live = {low.function.name: c_schedule.mean_live(c_schedule.schedule(low)) for low in lowered}
            gen = generate(model, "c", lowered=lowered)
            src = write_generated(gen, work / f"{gen.module}_{order.replace(' ', '_').replace(',', '')}")
            ops = {f: v["total"] for f, v in json.loads(gen.files["ops.json"])["functions"].items()}
            for cc in C_COMPILERS:
                for suffix, extra in BUILDS.items():
                    name = compiler_name(cc) + suffix
                    obj = src / f"{gen.module}_{name.replace(' ', '_')}.o"
                    subprocess.run([str(c) for c in [cc, *GENERATED_CFLAGS, *extra, "-c", src / f"{gen.module}.c",
                                                      "-o", obj]], capture_output=True, text=True, check=True)
                    for function, define in FUNCTIONS.items():
                        symbol = f"symgen_{gen.module}_{function}"
                        timer = src / f"timer_{function}_{name.replace(' ', '_')}"
                        cmd = [cc, *CFLAGS, "-Wall", *([define] if define else []), f"-DFUNC={symbol}",
                               f"-DNQ={n}", f"-DNV={n}", HERE / "codegen_timing.c", obj, "-lm", "-o", timer]
                        subprocess.run([str(c) for c in cmd], capture_output=True, text=True, check=True)
                        builds.append(dict(scene=spec, function=function, ops=ops[function], order=order,
                                           kept=order == kept[function], mean_live=live[function],
                                           build=name, code_kb=code_bytes(obj, symbol) / 1024,
                                           stack_refs=stack_references(obj, symbol), timer=timer))
    finally:
        c_schedule.ORDER, c_schedule.EARLY_STORES = "fewer live", True
    return builds, n


def traced_build(b: dict, builds: list[dict]) -> dict:
    """The traced order's build of ``b``'s function by ``b``'s compiler: what each row is compared with."""
    return next(t for t in builds if t["order"] == "traced" and t["function"] == b["function"]
                and t["build"] == b["build"])


def markdown(rows: list[dict], rounds: int) -> str:
    head = ["scene", "function", "ops", "order", "kept", "mean live", "build", "code KB", "stack refs", "ns",
            "/ traced", "max rel diff"]
    lines = ["# Statement order of generated C: traced against first use", "",
             "`python benchmarks/statement_order.py`. Each function traced once, its C rendered in the traced "
             "order (outputs assigned at the end) and in first-use order (`symgen.codegen.targets.c_schedule`: "
             "each statement just before its first reader, each output entry stored right after it), compiled "
             f"by each compiler (`{' '.join(GENERATED_CFLAGS)} -ffp-contract=fast`, as the bindings compile). **ops**: "
             "mul + add (`ops.json`); **kept**: the order the C target generates (of the two that store early, "
             "the one with fewer temporaries alive on average); **mean live**: temporaries alive per statement, on "
             "average (`c_schedule.mean_live`); **code KB**: machine code of the function and its blocks (`nm -S`); "
             "**stack refs**: its instructions with an operand on the stack (`objdump -d`); **ns**: one call "
             f"per state over {N_STATES} states (`codegen_timing.c`, thread CPU clock), median over interleaved "
             "rounds; **/ traced**: over the traced order's time, same build and round (median); **max rel "
             f"diff**: outputs against the traced order's, same build. {rounds} rounds of {REPEATS} repeats; "
             f"{machine()}.", "",
             "| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        refs = "" if r["stack_refs"] is None else str(r["stack_refs"])
        lines.append(f"| {r['scene']} | {r['function']} | {r['ops']} | {r['order']} | {'yes' if r['kept'] else ''} | "
                     f"{r['mean_live']:.1f} | {r['build']} | "
                     f"{r['code_kb']:.1f} | {refs} | {fmt(r['ns'])} | {r['vs_traced']:.2f} | {r['max_rel_diff']:.1e} |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> None:
    run(argv, __doc__.split("\n")[0], SCENES, build, "statement_order", markdown, traced_build, "vs_traced")


if __name__ == "__main__":
    main()
