"""Generated C at scale: generation time of the command line, and ``cc -O2`` time and memory.

For every scene of ``SCENES`` (all default functions, target C): the wall time of
``symgen generate SCENE --target c`` in a fresh interpreter (imports, derive, trace, render,
write), the size of the ``.c`` file, the number of block functions long functions were cut into
(:mod:`symgen.codegen.targets.c_blocks`), then ``cc -std=c99 -O2 -c`` of the file under
``/usr/bin/time -v``: wall and user time and peak resident memory. With ``--whole``, the same
source rendered without blocks (one C function per generated function, as before blocks
existed) is compiled too, for the scenes up to ``WHOLE_MAX_N`` joints (at 100 joints it needs
more than 24 GB). Writes ``compile_scale.md`` and ``compile_scale.csv`` beside this file.

With ``--overhead``, the per-call cost of the blocks: for the built-in scenes of at most 12
degrees of freedom whose functions are cut (``OVERHEAD_SCENES``), every split function's
``_batch`` entry point, whole and in blocks, is timed through the ctypes binding (both compiled
with the binding's ``-O2``) on the same states, alternating calls; each variant's best call is
its cost (on a shared machine most calls lose time slices to other processes).

    python benchmarks/compile_scale.py [--whole] [--overhead] [--scenes chain:n=6,chain:n=35]
"""
from __future__ import annotations

import argparse
import csv
import os
import platform
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))
from ctypes_variants import best_ns_per_state, load_variant, state_batch  # noqa: E402
SCENES = ["chain:n=6", "chain:n=12", "chain:n=35", "chain:n=100"]
CC = os.environ.get("CC", "cc")
CFLAGS = ["-std=c99", "-O2"]
#: the unsplit sources are compiled up to this many joints
WHOLE_MAX_N = 35
#: targets: scene -> (generation s, compile s, compile MB)
TARGETS = {"chain:n=35": (3.0, 10.0, 500.0), "chain:n=100": (20.0, 60.0, 2000.0)}
#: renders the C files of a scene without blocks (SPLIT_STATEMENTS beyond any function's size)
WHOLE_SCRIPT = """
import sys, pathlib
import symgen
from symgen.codegen.generate import generate
from symgen.codegen.targets import target
target("c").split_statements = 10**12
gen = generate(symgen.derive(symgen.load(sys.argv[1])), "c")
out = pathlib.Path(sys.argv[2]); out.mkdir(parents=True, exist_ok=True)
for name, text in gen.files.items():
    (out / name).write_text(text)
"""


#: built-in scenes of at most 12 degrees of freedom with functions beyond one block
OVERHEAD_SCENES = ("stewart", "multi_arm:h=2")
OVERHEAD_STATES, OVERHEAD_CALLS = 1_000, 40


def overhead(scene: str, work: Path) -> list[dict]:
    """ns per state of each split function, whole and in blocks (best call), and their ratio."""
    sys.path.insert(0, str(ROOT))
    import symgen
    from symgen.codegen.generate import generate, trace_all
    from symgen.codegen.targets import target
    from symgen.codegen.targets.c_blocks import SPLIT_STATEMENTS, needs_split

    model = symgen.derive(symgen.load(scene))
    lowered = trace_all(model)
    split = [low.function.name for low in lowered if needs_split(low)]
    modules = {}
    for variant, size in (("whole", 10**12), ("blocks", SPLIT_STATEMENTS)):
        target("c").split_statements = size
        modules[variant] = load_variant(generate(model, "c", lowered=lowered), work, f"{scene}_{variant}")
    target("c").split_statements = SPLIT_STATEMENTS
    batch = state_batch(model, OVERHEAD_STATES)
    rows = []
    for fn in split:
        ns = best_ns_per_state(modules, fn, batch, OVERHEAD_CALLS)
        rows.append(dict(scene=scene, function=fn, whole_ns=ns["whole"], blocks_ns=ns["blocks"],
                         ratio=ns["blocks"] / ns["whole"]))
        print(rows[-1], flush=True)
    return rows


def timed(cmd: list[str], env=None) -> dict:
    """Run ``cmd`` under ``/usr/bin/time -v``: wall and user seconds, peak resident MB, status."""
    start = time.perf_counter()
    result = subprocess.run(["/usr/bin/time", "-v", *cmd], capture_output=True, text=True, env=env)
    wall = time.perf_counter() - start
    report = result.stderr

    def field(label):
        m = re.search(rf"{label}: ([0-9.]+)", report)
        return float(m.group(1)) if m else float("nan")

    return dict(wall=wall, user=field(r"User time \(seconds\)"), mb=field(r"Maximum resident set size \(kbytes\)") / 1024,
                ok=result.returncode == 0, error=report.strip().splitlines()[-1] if result.returncode else "")


def source_of(folder: Path) -> Path:
    return next(p for p in folder.glob("*.c") if not p.name.startswith("test_"))


def compile_row(src: Path) -> dict:
    return timed([CC, *CFLAGS, "-c", str(src), "-o", str(src.with_suffix(".o"))])


def measure(scene: str, work: Path, whole: bool) -> dict:
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    out = work / re.sub(r"\W", "_", scene)
    gen = timed([sys.executable, "-m", "symgen", "generate", scene, "--target", "c", "--out", str(out), "--force"],
                env=env)
    if not gen["ok"]:
        raise RuntimeError(f"symgen generate {scene} failed: {gen['error']}")
    src = source_of(out)
    text = src.read_text()
    row = dict(scene=scene, gen_s=gen["wall"], gen_user_s=gen["user"], gen_mb=gen["mb"], c_mb=len(text) / 2**20,
               functions=len(re.findall(r"^int symgen_\w+\(", text, re.M)) // 2,
               blocks=len(re.findall(r"^SYMGEN_BLOCK ", text, re.M)))
    cc = compile_row(src)
    row.update(cc_wall_s=cc["wall"], cc_user_s=cc["user"], cc_mb=cc["mb"], cc_ok=cc["ok"])
    n = int(re.search(r"n=(\d+)", scene).group(1)) if "n=" in scene else 0
    if whole and n <= WHOLE_MAX_N:
        folder = work / (out.name + "_whole")
        subprocess.run([sys.executable, "-c", WHOLE_SCRIPT, scene, str(folder)], env=env, check=True)
        cc = compile_row(source_of(folder))
        row.update(whole_wall_s=cc["wall"], whole_user_s=cc["user"], whole_mb=cc["mb"], whole_ok=cc["ok"])
    return row


def fmt(x, digits=3) -> str:
    if isinstance(x, str):
        return x
    if x != x:
        return "not run"
    return f"{x:.{digits}g}"


def verdict(row) -> str:
    goal = TARGETS.get(row["scene"])
    if goal is None:
        return ""
    gen, cc_s, cc_mb = goal
    parts = [f"generation <= {gen:g} s: {'met' if row['gen_s'] <= gen else 'MISSED'}",
             f"cc <= {cc_s:g} s: {'met' if row['cc_ok'] and row['cc_wall_s'] <= cc_s else 'MISSED'}",
             f"<= {cc_mb:g} MB: {'met' if row['cc_ok'] and row['cc_mb'] <= cc_mb else 'MISSED'}"]
    return "; ".join(parts)


def machine() -> str:
    cc = subprocess.run([CC, "--version"], capture_output=True, text=True).stdout.splitlines()[0]
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return (f"{os.cpu_count()} cores, {cc}, Python {platform.python_version()}; load average at the end "
            f"{load:.1f} (the machine is shared: wall times include waiting for a core, user times do not)")


def write(rows, whole: bool, over: list[dict]) -> None:
    cols = ["scene", "functions", "c_mb", "blocks", "gen_s", "gen_user_s", "gen_mb", "cc_wall_s", "cc_user_s",
            "cc_mb", "cc_ok"] + (["whole_wall_s", "whole_user_s", "whole_mb", "whole_ok"] if whole else [])
    with open(HERE / "compile_scale.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: r.get(k, "") for k in cols})
    lines = ["# Generated C at scale: generation and compile time", "",
             f"Machine: {machine()}. Reproduce with `python benchmarks/compile_scale.py"
             f"{' --whole' if whole else ''}{' --overhead' if over else ''}`.", "",
             "* **generate**: `symgen generate SCENE --target c` (all default functions), wall time of the process "
             "(imports, derive, trace, render, write) and its peak memory.",
             f"* **cc**: `{CC} {' '.join(CFLAGS)} -c` of the generated `.c` under `/usr/bin/time -v`: wall, user time, "
             "peak resident memory. **blocks**: static functions the long generated functions were cut into "
             "(functions beyond `SPLIT_STATEMENTS` statements, at most `BLOCK_STATEMENTS` statements each, `symgen/codegen/targets/c_blocks.py`).",
             "* **whole**: the same functions emitted as one C function each (no blocks), as before; "
             f"compiled up to n = {WHOLE_MAX_N} only." if whole else "", "",
             "| scene | functions | .c (MB) | blocks | generate wall (s) | generate user (s) | generate MB | "
             "cc wall (s) | cc user (s) | cc MB |" + (" whole: cc wall (s) | whole: cc user (s) | whole: cc MB |"
                                                       if whole else "") + " targets |",
             "|---" * (10 + (3 if whole else 0) + 1) + "|"]
    for r in rows:
        cells = [f"`{r['scene']}`", str(r["functions"]), fmt(r["c_mb"]), str(r["blocks"]), fmt(r["gen_s"]),
                 fmt(r["gen_user_s"]), fmt(r["gen_mb"]),
                 fmt(r["cc_wall_s"]) if r["cc_ok"] else "failed", fmt(r["cc_user_s"]), fmt(r["cc_mb"])]
        if whole:
            cells += [fmt(r.get("whole_wall_s", float("nan"))) if r.get("whole_ok", True) else "failed",
                      fmt(r.get("whole_user_s", float("nan"))), fmt(r.get("whole_mb", float("nan")))]
        lines.append("| " + " | ".join(cells + [verdict(r)]) + " |")
    if over:
        lines += ["", "## Per-call cost of the blocks (at most 12 degrees of freedom)", "",
                  f"`_batch` entry points through the ctypes binding (`-O2`), {OVERHEAD_STATES} states per call, "
                  f"the best of {OVERHEAD_CALLS} alternating calls of each variant. The chains up to 12 joints have "
                  "no function beyond one block: their code is unchanged.", "",
                  "| scene | function | whole (ns/state) | blocks (ns/state) | blocks / whole |", "|---|---|---|---|---|"]
        lines += [f"| `{r['scene']}` | {r['function']} | {r['whole_ns']:.0f} | {r['blocks_ns']:.0f} | {r['ratio']:.3f} |"
                  for r in over]
    (HERE / "compile_scale.md").write_text("\n".join(lines) + "\n")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--whole", action="store_true", help="also compile the unsplit sources (slow)")
    parser.add_argument("--overhead", action="store_true", help="also time split against whole functions")
    parser.add_argument("--scenes", default=",".join(SCENES))
    args = parser.parse_args()
    rows, over = [], []
    with tempfile.TemporaryDirectory(prefix="symgen-compile-") as tmp:
        os.environ["SYMGEN_CACHE"] = str(Path(tmp) / "cache")     # the bindings compile into here
        if args.overhead:
            for scene in OVERHEAD_SCENES:
                over += overhead(scene, Path(tmp))
        for scene in filter(None, args.scenes.split(",")):
            row = measure(scene, Path(tmp), args.whole)
            print(row, flush=True)
            rows.append(row)
    write(rows, args.whole, over)


if __name__ == "__main__":
    main()
