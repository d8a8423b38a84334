"""Small dense solves in line or by the library LU: speed per call and accuracy over the workspace.

Up to 16 x 16, symgen eliminates a matrix in line (static pivot order, run-time pivot check,
``symgen/codegen/sparse_lu.py``) whenever that costs no more flops than the dense LU; before, only
when it cost at most half (``sparse_lu.SMALL = 0`` restores that rule, which is what this script
does for the *library* columns). The scenes whose solves this changes are the arms' 6 x 6 tool
Jacobians and object block (``multi_arm``) and the Stewart platform's 6 x 6 ``[J_m; J_f]``.

For each scene and function:

* **ns/state**: the generated C ``_batch`` entry point through the ctypes binding (its own
  ``-O2``), 1000 loop-closed states per call, the best of 40 alternating calls of each variant;
* **error**: the worst and 99th-percentile relative error (``max |diff| / max(1, max |want|)``)
  of the generated NumPy against the dense float model (``symgen.codegen.reference``, library
  solves), at ``STATES`` random loop-closed states drawn around ``q0`` with the given spread
  (radians or metres per joint coordinate).

Writes ``small_dense_solves.md`` and ``.csv`` beside this file.

    python benchmarks/small_dense_solves.py
"""
from __future__ import annotations

import contextlib
import csv
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE))
from ctypes_variants import best_ns_per_state, load_variant, state_batch  # noqa: E402

import symgen  # noqa: E402
from symgen.codegen import sparse_lu  # noqa: E402
from symgen.codegen.generate import generate, trace_all  # noqa: E402
from symgen.codegen.reference import reference_outputs, reference_states  # noqa: E402
from symgen.codegen.runtime import call_by_name, load_generated  # noqa: E402

CASES = [("multi_arm:h=2", "forward_dynamics", (0.3, 1.0)), ("multi_arm:h=2", "mass_matrix", (0.3,)),
         ("multi_arm:h=3", "forward_dynamics", (0.3,)), ("stewart", "forward_dynamics", (0.3,))]
STATES = 200
CALL_STATES, CALLS = 1000, 40
FIELDS = ["scene", "function", "spread", "ns_in_line", "ns_library", "ratio", "err_max_in_line", "err_max_library",
          "err_p99_in_line", "err_p99_library"]


@contextlib.contextmanager
def library_small_solves():
    """The earlier rule: in line only at half the dense flops, whatever the size."""
    saved = sparse_lu.SMALL
    sparse_lu.SMALL = 0
    try:
        yield
    finally:
        sparse_lu.SMALL = saved


def lowered(model, fn, variant):
    with library_small_solves() if variant == "library" else contextlib.nullcontext():
        return trace_all(model, [fn])


def per_call(model, fn, low, work: Path) -> dict:
    modules = {v: load_variant(generate(model, "c", lowered=lw), work, f"{model.scene.name}_{fn}_{v}")
               for v, lw in low.items()}
    return best_ns_per_state(modules, fn, state_batch(model, CALL_STATES), CALLS)


def errors(model, fn, low, spread) -> dict:
    modules = {v: load_generated(model, "numpy", [fn], lowered=lw) for v, lw in low.items()}
    errs = {v: [] for v in modules}
    for s in reference_states(model, STATES, seed=5, spread=spread):
        want = list(reference_outputs(model, fn, s).values())
        for v, module in modules.items():
            got = call_by_name(module, fn, s)
            errs[v].append(max(np.abs(a - b).max() / max(1.0, np.abs(b).max()) for a, b in zip(got, want)))
    return {v: (max(e), float(np.percentile(e, 99))) for v, e in errs.items()}


def main() -> None:
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for spec, fn, spreads in CASES:
            model = symgen.derive(symgen.load(spec))
            low = {"in_line": lowered(model, fn, "in_line"), "library": lowered(model, fn, "library")}
            ns = per_call(model, fn, low, Path(tmp))
            for spread in spreads:
                err = errors(model, fn, low, spread)
                rows.append(dict(scene=spec, function=fn, spread=spread, ns_in_line=f"{ns['in_line']:.0f}",
                                 ns_library=f"{ns['library']:.0f}", ratio=f"{ns['in_line'] / ns['library']:.2f}",
                                 err_max_in_line=f"{err['in_line'][0]:.1e}", err_max_library=f"{err['library'][0]:.1e}",
                                 err_p99_in_line=f"{err['in_line'][1]:.1e}", err_p99_library=f"{err['library'][1]:.1e}"))
                print(rows[-1], flush=True)
    with open(HERE / "small_dense_solves.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=FIELDS)
        writer.writeheader()
        writer.writerows(rows)
    doc = __doc__.split("\n\n")
    lines = ["# Small dense solves: in line or by the library LU", "", " ".join(doc[1].split()).replace("``", "`"), "",
             f"Reproduce with `python benchmarks/small_dense_solves.py`; {STATES} states per spread, "
             f"{CALL_STATES} states per timed call.", "",
             "| " + " | ".join(FIELDS) + " |", "|" + "---|" * len(FIELDS)]
    lines += ["| " + " | ".join(f"`{r[k]}`" if k == "scene" else str(r[k]) for k in FIELDS) + " |" for r in rows]
    (HERE / "small_dense_solves.md").write_text("\n".join(lines) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
