"""How long ``symgen control SCENE`` takes from the command line: the whole command (load, derive,
trace, compile, two closed-loop runs: adaptive and frozen) under ``/usr/bin/time -v``.

Rows: scenes outside the demonstrations with their default run (a UR10 and a Kinova Jaco 2
pressing on a plane, from the scene files ``docs/examples/ur10_on_plane.yaml`` and
``kinova_on_plane.yaml``) and a demonstration. The wall time depends on
what else the machine runs, so the table also gives the CPU time of the command (user + system)
and the load average when it started. Writes ``control_closed_loop_speed.md`` beside this file.

    python benchmarks/control_closed_loop_speed.py
"""
from __future__ import annotations

import json
import os
import platform
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
#: (label, arguments of ``symgen control``, whether the generated-code cache starts empty)
RUNS = (("ur10_on_plane (default run, empty cache)", ["docs/examples/ur10_on_plane.yaml"], True),
        ("ur10_on_plane (default run)", ["docs/examples/ur10_on_plane.yaml"], False),
        ("kinova_on_plane (default run, empty cache)", ["docs/examples/kinova_on_plane.yaml"], True),
        ("five_bar (demonstration)", ["five_bar"], False))
TARGET_S = 60.0


def _time_field(text: str, name: str) -> str:
    match = re.search(rf"{re.escape(name)}: (.+)", text)
    return match.group(1).strip() if match else ""


def _seconds(clock: str) -> float:
    parts = [float(p) for p in clock.split(":")]
    return sum(p * 60 ** k for k, p in enumerate(reversed(parts)))


def measure(args: list[str], cache: str | None = None) -> dict:
    """One timed command; ``cache`` a folder for ``SYMGEN_CACHE`` (else the user's cache)."""
    symgen = shutil.which("symgen") or str(Path(sys.executable).with_name("symgen"))
    load = os.getloadavg()[0]
    env = dict(os.environ, **({"SYMGEN_CACHE": cache} if cache else {}))
    proc = subprocess.run(["/usr/bin/time", "-v", symgen, "control", *args, "--json"], cwd=ROOT, env=env,
                          capture_output=True, text=True, check=True)
    summary = json.loads(proc.stdout)
    return {"wall": _seconds(_time_field(proc.stderr, "Elapsed (wall clock) time (h:mm:ss or m:ss)")),
            "cpu": float(_time_field(proc.stderr, "User time (seconds)"))
            + float(_time_field(proc.stderr, "System time (seconds)")),
            "rss_mb": float(_time_field(proc.stderr, "Maximum resident set size (kbytes)")) / 1024,
            "load": load, "summary": summary}


def main() -> None:
    from symgen.simulation.closed_loop_generated import pick_backend

    lines = ["# `symgen control`: time of the whole command", "",
             f"Machine: {os.cpu_count()} cores, Python {platform.python_version()}, backend "
             f"`{pick_backend()}` (generated C when a compiler is there). Reproduce with "
             "`python benchmarks/control_closed_loop_speed.py`: each row is "
             "`/usr/bin/time -v symgen control ARGS --json` from the repository root, once. Wall "
             "time includes loading, deriving, tracing and compiling the generated code (once: "
             "the compiled module is cached by content; the first row starts from an empty cache) "
             f"and both closed-loop runs (adaptive and frozen); target: at most {TARGET_S:g} s on a "
             "scene outside the demonstrations. CPU is user + system time of the command; the "
             "machine is shared, so the load average at the start is given.", "",
             "| scene | command | wall (s) | CPU (s) | load at start | RHS calls | max RSS (MB) "
             "| adaptive / frozen task error |",
             "|---|---|---|---|---|---|---|---|"]
    for label, args, cold in RUNS:
        with tempfile.TemporaryDirectory() as empty:
            r = measure(args, empty if cold else None)
        s = r["summary"]
        lines.append(f"| {label} | `symgen control {' '.join(args)}` | {r['wall']:.1f} | {r['cpu']:.1f} | "
                     f"{r['load']:.1f} | {s['rhs_calls']} | {r['rss_mb']:.0f} | {s['ratio']:.2g} |")
        print(lines[-1], flush=True)
    (HERE / "control_closed_loop_speed.md").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
