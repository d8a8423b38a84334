"""SVG plots of benchmark tables, for the documentation (``docs/figures/``).

* ``dead_point.svg``: from ``benchmarks/dead_point.md`` (second table), the error of every answer
  of the dense model, the generated NumPy and the generated C against ``max(cond W, cond A)``, per
  built-in with loops, with the bound ``cond^2 u`` and the refusal limits;
* ``forward_ops.svg``: from ``benchmarks/forward_ops.md``, the operation count of the generated
  ``forward_dynamics`` (articulated-body route) against N with Featherstone's count.

Byte-deterministic: the SVG writer's ids come from a fixed salt, no date is written and the text
stays text. ``tests/test_plots.py`` regenerates both and compares bytes.

    python benchmarks/plots.py [OUT_DIR]       # default docs/figures
"""
from __future__ import annotations

import pathlib
import re
import sys

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent
U = 2.0 ** -53
DOORS = {"dense": "o", "NumPy": "s", "C": "x"}


def _rows(path: pathlib.Path, column: str) -> list[dict]:
    """The rows of the first markdown table of ``path`` whose header has ``column``."""
    lines = path.read_text(encoding="utf-8").splitlines()
    for i, line in enumerate(lines):
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if line.startswith("|") and column in cells:
            out = []
            for row in lines[i + 2:]:
                if not row.startswith("|"):
                    break
                out.append(dict(zip(cells, (c.strip() for c in row.strip().strip("|").split("|")))))
            return out
    raise ValueError(f"{path}: no table with a column {column!r}")


def _pyplot():
    import matplotlib

    matplotlib.use("svg")
    import matplotlib.pyplot as plt

    plt.rcParams.update({"svg.hashsalt": "symgen", "svg.fonttype": "none", "font.size": 9})
    return plt


def dead_point(out: pathlib.Path) -> pathlib.Path:
    plt = _pyplot()
    rows = _rows(HERE / "dead_point.md", "max(cond)^2 u")
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for k, scene in enumerate(scenes):
        for door, marker in DOORS.items():
            pts = [(max(float(r["cond W"]), float(r["cond A"])), float(r[door])) for r in rows
                   if r["scene"] == scene and re.fullmatch(r"[0-9.e+-]+", r[door])]
            if pts:
                ax.loglog(*zip(*pts), marker, color=f"C{k}", mfc="none", ms=5,
                          label=f"{scene}, {door}")
    conds = [10.0 ** e for e in range(1, 16)]
    ax.loglog(conds, [c * c * U for c in conds], "k--", lw=1, label="bound cond² u")
    ax.axvline(1e8, color="grey", lw=1)
    ax.text(1.2e8, 1e-15, "refused above\n10⁸", fontsize=8, color="grey")
    ax.set_xlabel("max(cond W, cond A) at the rounded input")
    ax.set_ylabel("relative error of dV_m vs 50 digits")
    ax.set_ylim(1e-17, 10)
    ax.legend(fontsize=6, ncol=2, loc="upper left")
    ax.set_title("Answers near a singular loop, and where symgen refuses")
    return _save(fig, out / "dead_point.svg")


def forward_ops(out: pathlib.Path) -> pathlib.Path:
    plt = _pyplot()
    rows = _rows(HERE / "forward_ops.md", "RBDA total")
    n = [int(r["N"]) for r in rows]
    fig, ax = plt.subplots(figsize=(6.4, 3.8))
    ax.plot(n, [int(r["total"]) for r in rows], "o-", label="generated forward_dynamics (mul + add)")
    ax.plot(n, [int(r["RBDA total"]) for r in rows], "s--", mfc="none", label="RBDA Table 10.1 (mul + add)")
    ax.set_xlabel("N (links of chain:n=N)")
    ax.set_ylabel("operations")
    ax.legend()
    ax.set_title("Forward dynamics by the articulated-body recursion: linear in N")
    return _save(fig, out / "forward_ops.svg")


def _save(fig, path: pathlib.Path) -> pathlib.Path:
    fig.tight_layout()
    fig.savefig(path, format="svg", metadata={"Date": None, "Creator": None})
    import matplotlib.pyplot as plt

    plt.close(fig)
    return path


def main(argv=None) -> int:
    args = sys.argv[1:] if argv is None else argv
    out = pathlib.Path(args[0]) if args else ROOT / "docs" / "figures"
    out.mkdir(parents=True, exist_ok=True)
    for make in (dead_point, forward_ops):
        print(make(out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
