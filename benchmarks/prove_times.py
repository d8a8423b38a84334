"""Wall time of ``symgen prove`` on the built-in scenes, measured in one run.

Writes ``benchmarks/prove_times.md`` and ``benchmarks/prove_times.csv``. The times are for the
exact-arithmetic checks (b)-(e) at ``POINTS`` sampled configurations plus the symbolic body
checks (a); derivation included, interpreter start-up excluded.

    python benchmarks/prove_times.py
"""
import csv
import platform
import time
from pathlib import Path

from symgen.io.builtin import get_scene
from symgen.model import derive
from symgen.proofs import prove

POINTS = 3
SCENES = ["four_bar", "five_bar", "arm_on_plane", "chain:n=6", "chain:n=12", "multi_arm:h=2",
          "stewart", "multi_arm:h=3", "cassie", "space_ur5", "solo12", "solo12_standing", "anymal_standing",
          "talos", "talos_double_support"]
HERE = Path(__file__).parent


def main() -> None:
    rows = []
    for spec in SCENES:
        start = time.perf_counter()
        results = prove(derive(get_scene(spec)), points=POINTS)
        seconds = time.perf_counter() - start
        rows.append({"scene": spec, "passed": all(r.passed for r in results), "seconds": round(seconds, 2)})
        print(f"{spec:<16} {seconds:7.2f} s  {'pass' if rows[-1]['passed'] else 'FAIL'}", flush=True)
    with open(HERE / "prove_times.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=["scene", "passed", "seconds"])
        writer.writeheader()
        writer.writerows(rows)
    lines = [f"# `symgen prove` wall time ({POINTS} exact points)", "",
             f"Measured in one run by `python benchmarks/prove_times.py` on {platform.machine()}, "
             f"Python {platform.python_version()}, {platform.processor() or 'unknown CPU'}.", "",
             "| scene | all properties hold | seconds |", "|---|---|---|"]
    lines += [f"| `{r['scene']}` | {'yes' if r['passed'] else 'NO'} | {r['seconds']} |" for r in rows]
    (HERE / "prove_times.md").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
