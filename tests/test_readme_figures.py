"""Every figure the README and the documentation quote from a benchmark table is checked against
the row it cites.

Each quoted figure is declared once below, next to its source: a :class:`Figure` is a snippet of
the README or of a page under ``docs/`` with ``{name}`` placeholders, and each placeholder names a
source value -- a :class:`Cell` of a benchmark CSV or markdown table (file, row selector, column,
format), a number in a table file's prose (:class:`Prose`), or a key of a JSON file
(:class:`Json`). The test renders the snippet with the values the tables hold *now* and asks that
the text contain it (whitespace and line breaks do not matter). So a regenerated table with other
numbers fails here until the text quotes the new ones; the last tests show that a changed figure
is caught. Whole tables are not copied: the docs' benchmark pages include the files themselves
(``tests/test_docs_build.py`` checks that every table has its page).

The ``codegen_speed`` figures are checked as they are on this branch.
"""
from __future__ import annotations

import csv
import io
import json
import re
import shutil
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: the pages that quote figures: the README and the documentation (the benchmark pages under
#: docs/benchmarks only include the tables, and so quote nothing themselves)
PAGES = [ROOT / "README.md"] + sorted(p for p in (ROOT / "docs").rglob("*.md")
                                      if "benchmarks" not in p.relative_to(ROOT / "docs").parts)
TEXT = "\n\n".join(p.read_text(encoding="utf-8") for p in PAGES)


# ---------------------------------------------------------------------------------------------
# Reading the benchmark files


def number(text: str) -> float:
    """A table cell as a number: backticks, ``+``, ``%``, ``×``, thousands separators dropped."""
    cleaned = re.sub(r"[`+%×,\s]", "", str(text))
    return float(cleaned)


def normalise(text: str) -> str:
    """Whitespace collapsed, backticks dropped, spaces between digits (``1 144``) removed, dashes unified."""
    text = str(text).replace("`", "").replace("–", "-").replace("−", "-")
    text = re.sub(r"(?<=\d) (?=\d{3}\b)", "", text)
    return re.sub(r"\s+", " ", text).strip()


def _unique(names: list[str]) -> list[str]:
    """Repeated header names get ``#2``, ``#3``, ... (``add``, ``add#2``)."""
    seen: dict[str, int] = {}
    out = []
    for name in names:
        seen[name] = seen.get(name, 0) + 1
        out.append(name if seen[name] == 1 else f"{name}#{seen[name]}")
    return out


def md_tables(text: str) -> list[list[dict]]:
    """Every pipe table of a markdown text, as lists of ``{header: cell}`` (cells stripped)."""
    tables, lines = [], text.splitlines()
    i = 0
    while i < len(lines) - 1:
        if lines[i].startswith("|") and re.fullmatch(r"\|(\s*:?-+:?\s*\|)+", lines[i + 1].strip()):
            header = _unique([c.strip() for c in lines[i].strip().strip("|").split("|")])
            rows, i = [], i + 2
            while i < len(lines) and lines[i].startswith("|"):
                cells = [c.strip() for c in lines[i].strip().strip("|").split("|")]
                rows.append(dict(zip(header, cells)))
                i += 1
            tables.append(rows)
        else:
            i += 1
    return tables


def read_rows(root: Path, path: str, table: str | None = None) -> list[dict]:
    """The rows of a CSV, or of the markdown table of ``path`` whose header has the column ``table``
    (the first table when ``None``)."""
    text = (root / path).read_text(encoding="utf-8")
    if path.endswith(".csv"):
        return list(csv.DictReader(io.StringIO(text)))
    tables = [t for t in md_tables(text) if t and (table is None or table in t[0])]
    assert tables, f"{path}: no table with a column {table!r}"
    return tables[0]


def _matches(row: dict, where: dict) -> bool:
    for key, want in where.items():
        have = normalise(row.get(key, ""))
        if isinstance(want, tuple):
            if have not in {normalise(w) for w in want}:
                return False
        elif have != normalise(want):
            return False
    return True


Format = str | Callable[[float], str] | None


def render(value, fmt: Format) -> str:
    """``fmt``: ``None`` keeps the cell's text; a format spec (``".2f"``) or a function of the number."""
    if fmt is None:
        return str(value)
    value = number(value) if isinstance(value, str) else value
    return fmt(value) if callable(fmt) else format(value, fmt)


@dataclass(frozen=True)
class Cell:
    """One value of a benchmark table: the rows ``where`` selects, the ``column`` (a name, or a
    function of the row), then ``agg`` (``None``: exactly one row; ``max``, ``min``, ``sum``;
    ``same``: every selected row holds the same value)."""

    path: str
    column: str | Callable[[dict], float]
    where: dict = field(default_factory=dict)
    fmt: Format = None
    agg: str | None = None
    table: str | None = None

    def text(self, root: Path) -> str:
        rows = [r for r in read_rows(root, self.path, self.table) if _matches(r, self.where)]
        assert rows, f"{self.path}: no row where {self.where}"
        values = [self.column(r) if callable(self.column) else r[self.column] for r in rows]
        if self.agg is None:
            assert len(values) == 1, f"{self.path}: {len(values)} rows where {self.where}; name one"
            return render(values[0], self.fmt)
        if self.agg == "same":
            assert len({normalise(v) for v in values}) == 1, f"{self.path}: rows differ: {values}"
            return render(values[0], self.fmt)
        nums = [number(v) if isinstance(v, str) else v for v in values]
        return render({"max": max, "min": min, "sum": sum}[self.agg](nums), self.fmt)


@dataclass(frozen=True)
class Prose:
    """A number in a benchmark file's text, found by a regular expression with one group."""

    path: str
    pattern: str
    fmt: Format = None

    def text(self, root: Path) -> str:
        found = re.findall(self.pattern, (root / self.path).read_text(encoding="utf-8"))
        assert len(found) == 1, f"{self.path}: {len(found)} matches of {self.pattern!r}"
        return render(found[0], self.fmt)


@dataclass(frozen=True)
class Json:
    """A top-level value of a JSON file."""

    path: str
    key: str
    fmt: Format = None

    def text(self, root: Path) -> str:
        return render(json.loads((root / self.path).read_text(encoding="utf-8"))[self.key], self.fmt)


@dataclass(frozen=True)
class Computed:
    """A value computed from the rows of one table (e.g. a fit over its rows), then formatted."""

    path: str
    compute: Callable[[list[dict]], float]
    fmt: Format = None
    table: str | None = None

    def text(self, root: Path) -> str:
        return render(self.compute(read_rows(root, self.path, self.table)), self.fmt)


class Figure:
    """A snippet of the README or the docs with ``{name}`` placeholders, each bound to a source value."""

    def __init__(self, snippet: str, **sources):
        self.snippet, self.sources = snippet, sources
        names = set(re.findall(r"\{(\w+)\}", snippet))
        assert names == set(sources), f"placeholders {names} against sources {set(sources)}"

    def __repr__(self) -> str:
        return f"Figure({self.snippet[:60]!r})"

    def expected(self, root: Path) -> str:
        values = {k: src.text(root) for k, src in self.sources.items()}
        return re.sub(r"\{(\w+)\}", lambda m: values[m.group(1)], self.snippet)

    def problems(self, readme: str, root: Path = ROOT) -> list[str]:
        """Empty when the text quotes the table; else what the text says against the table."""
        text, want = normalise(readme), normalise(self.expected(root))
        if want in text:
            return []
        parts = re.split(r"\{\w+\}", normalise(self.snippet))
        pattern = r"(.{1,40}?)".join(re.escape(p) for p in parts)
        found = re.search(pattern, text)
        said = found.group(0) if found else "(snippet not found)"
        return [f"the text says: {said!r}\n  the tables say: {want!r}"]


# ---------------------------------------------------------------------------------------------
# The figures: the quoting snippet and the row it quotes, declared together

CODEGEN = "benchmarks/codegen_speed.csv"


def _settled_ratios(rows: list[dict]) -> list[float]:
    """The generated Jacobian's wall ratios on the stability suite's stiff cases (which settle
    within their run), the swinging chain left out."""
    return [number(r["wall_ratio"]) for r in rows
            if r["jacobian"] == "generated" and r["case"] != "swinging_stiff_joint"]


def codegen(scene: str, quantity: str, fmt: Format = None) -> Cell:
    return Cell(CODEGEN, "value", dict(table="runtime", scene=scene, quantity=quantity), fmt)


def per_second(ns: float) -> str:
    """States per second from ns per state, as ``8.20e+06``."""
    return f"{1e9 / ns:.2e}"


def pinocchio_rnea(scene: str) -> Cell:
    """The fastest of Pinocchio's three C++ ``rnea`` builds (header templates by g++ and by clang++,
    precompiled library)."""
    return Cell(CODEGEN, "value", dict(table="runtime", scene=scene, quantity=("header_ns", "clang_ns", "lib_ns")),
                ".0f", agg="min")


def _published_count(rows, scene: str) -> float:
    """The published RNEA count (mul + add) at a scene's DOF (codegen_speed.csv rows)."""
    value = {r["quantity"]: r["value"] for r in rows if r["table"] == "runtime" and r["scene"] == scene}
    return float(value["rnea_mul"]) + float(value["rnea_add"])


def _published_share(rows, scene: str) -> float:
    """A scene's ``inverse_dynamics`` operations over the published RNEA count (codegen_speed.csv rows)."""
    value = {r["quantity"]: r["value"] for r in rows if r["table"] == "runtime" and r["scene"] == scene}
    return float(value["total"]) / _published_count(rows, scene)


def states_per_s(ns: float) -> str:
    """NumPy states per second from ns per state, written as ``1.30e6``."""
    mantissa, exponent = f"{1e9 / ns:.2e}".split("e")
    return f"{mantissa}e{int(exponent)}"


NONFINITE = "benchmarks/nonfinite_check.md"
LANES = "benchmarks/batch_lanes.md"
SINGLE = "benchmarks/single_call.md"
PINBASE = "benchmarks/pinocchio_baseline.csv"
PROVE = "benchmarks/prove_times.csv"
CONTROL = "benchmarks/control/summary.csv"
CONTROL_SPEED = "benchmarks/control_speed.md"
CONTROL_COMMAND = "benchmarks/control_closed_loop_speed.md"
SLOTINE = "benchmarks/slotine_li.md"
CHAIN = "benchmarks/complexity/chain.md"
SIM = "benchmarks/simulation"
CLOSED = "benchmarks/complexity/closed_chains.csv"


def closed(scene: str, function: str, column: str = "total_with_solves") -> Cell:
    """A cell of the closed-chain op-count table, written with thousands separators."""
    return Cell(CLOSED, column, dict(scene=scene, function=function), lambda v: f"{v:,.0f}")

def _chain_totals(rows: list[dict]) -> dict[int, int]:
    """``N -> inverse_dynamics total`` over the rows of the chain's op-count table."""
    return {int(r["N"]): int(r["inverse_dynamics"]) for r in rows}


def _chain_fit(rows: list[dict]):
    """The straight-line fit of ``symgen ops --fit chain`` (its N = 2..64), on the table's totals."""
    from symgen.codegen.linearity import FAMILIES, fit_line

    totals = _chain_totals(rows)
    sizes = FAMILIES["chain"][1]
    return fit_line(sizes, [totals[n] for n in sizes])


IDENT = "benchmarks/identification.md"
#: the closed chains of the identification benchmark
CLOSED_IDENT = ("`five_bar`", "`arm_on_plane`", "`arm_on_plane (eta_f measured)`")


def _gap(row: dict) -> tuple[float, float]:
    """``(kept, dropped)`` of a rank-gap cell ``kept / dropped``."""
    kept, dropped = row["rank gap (kept / dropped)"].split("/")
    return float(kept), float(dropped)
DEAD = "benchmarks/dead_point.md"
URDF_COVERAGE = "benchmarks/urdf_coverage.md"
MJCF_COVERAGE = "benchmarks/mjcf_coverage.md"
FLOATING = "benchmarks/floating_base.csv"
FLOATING_GROUND = "benchmarks/floating_base_constrained.csv"
SPACE = "benchmarks/space_momentum.csv"


CONSTRAINED = "benchmarks/constrained_forward.csv"


def constrained(scene: str) -> Cell:
    """symgen's generated C over the fastest Pinocchio route, as the README writes it."""
    return Cell(CONSTRAINED, "ratio_symgen_over_best", dict(scene=scene), ".2f")


FORWARD = "benchmarks/forward_speed.md"
DERIV = "benchmarks/derivative_ops.csv"
DERIV_SPEED = "benchmarks/derivative_speed.csv"
CLOSED_FORM = "benchmarks/closed_form_products.csv"
BLOCKS = "benchmarks/block_size.csv"
ORDER = "benchmarks/statement_order.csv"
CONSTRAINED_DERIV = "benchmarks/constrained_derivatives.csv"
INV_DERIV = "benchmarks/derivative_sweeps.csv"
DERIV_SWEEPS_FWD = "benchmarks/derivative_sweeps_forward.csv"
FRAMES = "benchmarks/frame_ops.csv"
FORWARD_OPS = "benchmarks/forward_ops.md"
PARAMS = "benchmarks/parameter_ops.csv"
FUZZ_CLI = "benchmarks/fuzz_cli.md"


def forward_ops_row(n: int) -> "Figure":
    """A row of the code-generation guide's table of forward_dynamics counts (articulated-body route)."""
    cell = lambda column: Cell(FORWARD_OPS, column, dict(N=str(n)), table="RBDA mul")  # noqa: E731
    return Figure(f"| {n} | {{mul}} | {{add}} | {{total}} | {{lu}} | {{rm}} + {{ra}} = {{rt}} |",
                  mul=cell("mul"), add=cell("add"), total=cell("total"), lu=cell("LU flops"),
                  rm=cell("RBDA mul"), ra=cell("RBDA add"), rt=cell("RBDA total"))


def forward_fit(count: str, column: str) -> Cell:
    return Cell(FORWARD_OPS, column, dict(count=count), table="slope (per link)")


def forward(scene: str, column: str, fmt: Format = None) -> Cell:
    return Cell(FORWARD, column, dict(scene=f"`{scene}`"), fmt, table="ABA C (ns/call)")


COMPILE = "benchmarks/compile_scale.csv"
MASS = "benchmarks/complexity/mass_matrix.csv"
SMALL_DENSE = "benchmarks/small_dense_solves.csv"


def small_dense(scene: str, function: str, spread: str, column: str) -> Cell:
    """A cell of the small-dense-solves table (in line against the library LU)."""
    return Cell(SMALL_DENSE, column, dict(scene=scene, function=function, spread=spread))


def mass_ops(scene: str, route: str, fmt: Format = None) -> Cell:
    """Operations of ``M_q`` by one route (``composite``, ``columns``) in the mass-matrix table."""
    return Cell(MASS, route, dict(scene=scene), fmt)


def compiled(scene: str, column: str, fmt: Format = ".3g") -> Cell:
    return Cell(COMPILE, column, dict(scene=scene), fmt)


FIGURES = [
    Figure("runs at {solo}× Pinocchio's `rnea` on Solo12 and {talos}× on Talos",
           solo=Cell(FLOATING, "ratio", dict(scene="solo12"), ".3g"),
           talos=Cell(FLOATING, "ratio", dict(scene="talos"), ".3g")),
    Figure("takes {solo}× the time of Pinocchio's faster constrained route on Solo12 (four point feet), {anymal}× on "
           "ANYmal and {talos}× on Talos (two flat soles)",
           solo=Cell(FLOATING_GROUND, "ratio", dict(scene="solo12_standing"), ".2f"),
           anymal=Cell(FLOATING_GROUND, "ratio", dict(scene="anymal_standing"), ".2f"),
           talos=Cell(FLOATING_GROUND, "ratio", dict(scene="talos_double_support"), ".2f")),
    Figure("forward dynamics of Solo12 on four point feet takes {solo}× the time of Pinocchio's faster constrained "
           "route (`constraintDynamics`), ANYmal {anymal}× and Talos on its two soles {talos}×",
           solo=Cell(FLOATING_GROUND, "ratio", dict(scene="solo12_standing"), ".2f"),
           anymal=Cell(FLOATING_GROUND, "ratio", dict(scene="anymal_standing"), ".2f"),
           talos=Cell(FLOATING_GROUND, "ratio", dict(scene="talos_double_support"), ".2f")),
    Figure("`space_ur5`'s momentum drifts by {drift} over 10 s ({s} s of simulation; {old} at `rtol = atol = 1e-13`; "
           "{tight} at `atol = 1e-16`)",
           drift=Cell(SPACE, "drift", dict(rtol="2.3e-14", atol="1e-14"), ".1e"),
           s=Cell(SPACE, "seconds", dict(rtol="2.3e-14", atol="1e-14"), ".0f"),
           old=Cell(SPACE, "drift", dict(rtol="1e-13", atol="1e-13"), ".1e"),
           tight=Cell(SPACE, "drift", dict(rtol="2.3e-14", atol="1e-16"), ".1e")),
    Figure("Talos on two feet takes {derive} s to derive and {generate} s to generate",
           derive=Cell(FLOATING, "derive_s", dict(scene="talos_double_support"), ".2g"),
           generate=Cell(FLOATING, "generate_s", dict(scene="talos_double_support"), ".3g")),
    Figure("every default function as C and {compile} s to compile it",
           compile=Cell(FLOATING, "compile_s", dict(scene="talos_double_support"), ".3g")),
    Figure("`inverse_dynamics` is now\nthe arithmetic of {ops} operations", ops=Cell(FLOATING, "id_ops", dict(scene="talos"))),
    Figure("{loaded} of {total} models load, and each",
           loaded=Prose(MJCF_COVERAGE, r"\*\*(\d+) of \d+ load\*\*"),
           total=Prose(MJCF_COVERAGE, r"\*\*\d+ of (\d+) load\*\*")),
    Figure("{loaded} of {total} with `\"warn\"`, {repair} with `\"repair\"`",
           loaded=Prose(URDF_COVERAGE, r'`inertia="warn"` \(default\): \*\*(\d+)\*\* load'),
           total=Prose(URDF_COVERAGE, r"- files: (\d+);"),
           repair=Prose(URDF_COVERAGE, r'`inertia="repair"`: \*\*(\d+)\*\* load')),
    Figure("and {free} with `\"repair\"`, `floating=True`",
           free=Prose(URDF_COVERAGE, r'`floating=True` for the \d+ files whose root is a free body[^*]*\*\*(\d+)\*\* load')),
    *[forward_ops_row(n) for n in (6, 12, 32, 64)],
    # the identification guide: its prose figures, from benchmarks/identification.md
    Figure("scene measured: kept ≥ {kept}, dropped ≤ {dropped}",
           kept=Computed(IDENT, lambda rows: min(_gap(r)[0] for r in rows), ".1e", table="rank gap (kept / dropped)"),
           dropped=Computed(IDENT, lambda rows: max(_gap(r)[1] for r in rows), ".1e",
                            table="rank gap (kept / dropped)")),
    Figure("The optimiser ran for at most {s} s. On the closed chains it stopped after {lo} to {hi} evaluations",
           s=Prose(IDENT, r"stopped after \d+ evaluations or (\d+) s"),
           lo=Cell(IDENT, "evaluations", dict(scene=CLOSED_IDENT), agg="min", fmt="g", table="evaluations"),
           hi=Cell(IDENT, "evaluations", dict(scene=CLOSED_IDENT), agg="max", fmt="g", table="evaluations")),
    Figure("(over {lo} to {hi} parameters)",
           lo=Cell(IDENT, "base", agg="min", fmt="g", table="base"), hi=Cell(IDENT, "base", agg="max", fmt="g",
                                                                             table="base")),
    Figure("With zero noise every scene is recovered to {e} or better",
           e=Cell(IDENT, "noise 0 rms", agg="max", fmt=lambda v: f"{float(f'{v:.0e}'):.0e}", table="noise 0 rms")),
    Figure("condition number ~{c}, so some base parameters are barely determined",
           c=Cell(IDENT, "cond(W_b) optimised", dict(scene="`arm_on_plane`"), ".0e", table="evaluations")),
    Figure("at every noise level the errors stay within {k} of them",
           k=Computed(IDENT, lambda rows: max(float(x) for r in rows if r["scene"] == "`arm_on_plane`"
                                              for x in re.findall(r"\(([0-9.]+)\)", " ".join(r.values()))),
                      ".1f", table="noise 0 rms")),
    Figure("Measuring `eta_f` gives 6 rows and a condition number of about {c}",
           c=Cell(IDENT, "cond(W_b) random", dict(scene="`arm_on_plane (eta_f measured)`"), ".0e",
                  table="evaluations")),
    Figure("the fit is `total = {ts} N − {ti}` (R² = {tr}): mul `{ms} N − {mi}`, add `{as_} N − {ai}`",
           ts=forward_fit("total", "slope (per link)"), ti=Cell(FORWARD_OPS, lambda r: -float(r["intercept"]),
                                                               dict(count="total"), ".1f", table="slope (per link)"),
           tr=forward_fit("total", "R^2"), ms=forward_fit("mul", "slope (per link)"),
           mi=Cell(FORWARD_OPS, lambda r: -float(r["intercept"]), dict(count="mul"), ".1f", table="slope (per link)"),
           as_=forward_fit("add", "slope (per link)"),
           ai=Cell(FORWARD_OPS, lambda r: -float(r["intercept"]), dict(count="add"), ".1f", table="slope (per link)")),
    Figure("From N = 4 on, one more link costs {lo} to {hi} operations",
           lo=Prose(FORWARD_OPS, r"costs ([0-9.]+) to"), hi=Prose(FORWARD_OPS, r"to ([0-9.]+) operations")),
    Figure("the rounding alone costs {e7} at `cond W` = {c7} and {e9} at {c9}",
           e7=Cell(DEAD, "relative error from rounding q", dict(t="1e-06")),
           c7=Cell(DEAD, "cond(W) (2-norm)", dict(t="1e-06")),
           e9=Cell(DEAD, "relative error from rounding q", dict(t="1e-08")),
           c9=Cell(DEAD, "cond(W) (2-norm)", dict(t="1e-08"))),
    Figure("`W` stays near {w} while `cond A` grows like `1/t`, and so does the error: {e} from the dense model at "
           "`cond A` = {a}",
           w=Cell(DEAD, "cond W", dict(scene="multi_arm:h=2", t="1e-06"), table="scene"),
           e=Cell(DEAD, "dense", dict(scene="multi_arm:h=2", t="1e-06"), table="scene"),
           a=Cell(DEAD, "cond A", dict(scene="multi_arm:h=2", t="1e-06"), table="scene")),
    Figure("by up to {r} times on these sweeps (the Stewart platform)",
           r=Cell(DEAD, "condition / estimate", dict(scene="stewart"), table="condition / estimate")),
    Figure("(for example {e} from the dense Stewart model at `cond W` = {c})",
           e=Cell(DEAD, "dense", dict(scene="stewart", t="1e-06"), table="scene"),
           c=Cell(DEAD, "cond W", dict(scene="stewart", t="1e-06"), table="scene")),
    # README: the headline figures
    Figure("the generated `inverse_dynamics` costs `{a} N − {b}` operations; at N = 6 its C takes {r}× the time "
           "of Pinocchio's C++ `rnea`",
           a=Computed(CHAIN, lambda rows: _chain_fit(rows).slope, ".2f", table="Kane cse"),
           b=Computed(CHAIN, lambda rows: -_chain_fit(rows).intercept, ".1f", table="Kane cse"),
           r=codegen("chain:n=6", "c_over_pin", ".3f")),
    Figure("({c} ns per call, Pinocchio {pin} ns) ([codegen_speed](benchmarks/codegen_speed.md)). The baseline is the fastest "
           "Pinocchio built here: its templates compiled by clang++ run `rnea` in {clang} ns, by g++ in {gcc} ns",
           c=codegen("chain:n=6", "c_ns", ".0f"), pin=pinocchio_rnea("chain:n=6"),
           clang=codegen("chain:n=6", "clang_ns", ".0f"), gcc=codegen("chain:n=6", "header_ns", ".0f")),
    Figure("on `general_chain:n=7` (general geometry and inertia, nothing to fold) the generated C takes {r}× "
           "Pinocchio's time in {ops} operations, {share} of the best published RNEA count, and its derivatives "
           "{d}× `computeRNEADerivatives`",
           r=codegen("general_chain:n=7", "c_over_pin", ".3f"), ops=codegen("general_chain:n=7", "total"),
           share=Computed(CODEGEN, lambda rows: _published_share(rows, "general_chain:n=7"), ".2f"),
           d=Cell(DERIV_SPEED, "ratio", dict(scene="general_chain:n=7", function="inverse_dynamics_derivatives"), ".2f")),
    Figure("There inverse_dynamics takes {ops} operations at N = 7, {share} of the published {pub}, and the Panda "
           "(perpendicular axes, full inertias) {panda}, {pshare}",
           ops=codegen("general_chain:n=7", "total"),
           share=Computed(CODEGEN, lambda rows: _published_share(rows, "general_chain:n=7"), ".2f"),
           pub=Computed(CODEGEN, lambda rows: _published_count(rows, "general_chain:n=7"), ".0f"),
           panda=codegen("panda", "total"),
           pshare=Computed(CODEGEN, lambda rows: _published_share(rows, "panda"), ".2f")),
    # Pinocchio's own benchmark method against our harness (benchmarks/pinocchio_baseline)
    Figure("compiled by clang++, that program gives {lib} ns per call; header-only with our flags, {native} ns; "
           "our harness's clang++ build, {ours} ns",
           lib=Cell(PINBASE, "median_ns", dict(program="timings method", build="clang++ lib", algorithm="rnea",
                                               states="100000 random states", clock="wall")),
           native=Cell(PINBASE, "median_ns", dict(program="timings method", build="clang++ native", algorithm="rnea",
                                                  states="100000 random states", clock="wall")),
           ours=Cell(PINBASE, "median_ns", dict(program="rnea_timing.cpp", build="clang", algorithm="rnea"))),
    Figure("scales to {scaled} ns at this machine's clock; the fastest `rnea` measured here, {best} ns, is {gap}× that",
           scaled=Prose("benchmarks/pinocchio_baseline.md", r"GHz is (\d+) ns on this machine"),
           best=Prose("benchmarks/pinocchio_baseline.md", r"minimum\) takes (\d+) ns"),
           gap=Prose("benchmarks/pinocchio_baseline.md", r"ns, ([\d.]+)x the clock-scaled")),
    Figure("clang++ builds the fastest `rnea` on this machine, {clang} ns against {gcc} ns by g++ at N = 6",
           clang=codegen("chain:n=6", "clang_ns", ".0f"), gcc=codegen("chain:n=6", "header_ns", ".0f")),
    Figure("The generated C takes {four}× (`four_bar`), {stewart}× (`stewart`) and {arms}× (`multi_arm:h=2`) the "
           "time of the faster of Pinocchio's `constraintDynamics` and a KKT solve",
           four=constrained("four_bar"), stewart=constrained("stewart"), arms=constrained("multi_arm:h=2")),
    Figure("{r6}× Pinocchio's `aba` at N = 6 (the joint-space route) and {r}× at N = 64 (the articulated-body "
           "recursion)", r6=forward("chain:n=6", "kept / Pin."), r=forward("chain:n=64", "ABA / Pin.")),
    Figure("`symgen prove` takes at most {small} s on the planar loops and the arm on a plane",
           small=Cell(PROVE, "seconds", dict(scene=("four_bar", "five_bar", "arm_on_plane")), ".2f", "max")),
    # Code generation at scale: compile and generation (benchmarks/compile_scale)
    Figure("With blocks, `cc -O2` takes {cc35} s and {mb35} MB on `chain:n=35`, against {w35} s and {wmb35} MB for "
           "the whole functions.",
           cc35=compiled("chain:n=35", "cc_wall_s"), mb35=compiled("chain:n=35", "cc_mb"),
           w35=compiled("chain:n=35", "whole_wall_s"), wmb35=compiled("chain:n=35", "whole_mb")),
    Figure("`chain:n=100` compiles in {cc100} s and {mb100} MB (its whole source is not tried)",
           cc100=compiled("chain:n=100", "cc_wall_s"), mb100=compiled("chain:n=100", "cc_mb", ".3g")),
    Figure("the C of every function of `chain:n=100` takes {cc100} s to compile",
           cc100=compiled("chain:n=100", "cc_wall_s")),
    Figure("generate ({g35} s and {g100} s, of which about {g6} s is starting Python",
           g35=compiled("chain:n=35", "gen_s"), g100=compiled("chain:n=100", "gen_s"),
           g6=compiled("chain:n=6", "gen_s", ".1f")),
    Figure("Per call, the blocks cost {lo} to {hi} times the whole functions",
           lo=Cell("benchmarks/compile_scale.md", "blocks / whole", fmt=".3f", agg="min", table="blocks / whole"),
           hi=Cell("benchmarks/compile_scale.md", "blocks / whole", fmt=".3f", agg="max", table="blocks / whole")),
    # Code generation: the mass matrix by composite inertias (benchmarks/complexity/mass_matrix)
    Figure("on `chain:n=35` the composite route has {c35} operations against {r35}",
           c35=mass_ops("chain:n=35", "composite", lambda v: f"{v:,.0f}"),
           r35=mass_ops("chain:n=35", "columns", lambda v: f"{v:,.0f}")),
    Figure("the four-bar keeps the columns, {cols} against {comp}",
           cols=mass_ops("four_bar", "columns", ".0f"), comp=mass_ops("four_bar", "composite", ".0f")),
    Figure("{c64} operations at N = 64, where one recursion per column took {r64}",
           c64=mass_ops("chain:n=64", "composite", lambda v: f"{v:,.0f}"),
           r64=mass_ops("chain:n=64", "columns", lambda v: f"{v:,.0f}")),
    # Code generation: small dense solves in line (benchmarks/small_dense_solves)
    Figure("`multi_arm:h=2` `forward_dynamics` takes {ns} ns per state against {lib} ({r}×), Stewart's {rs}×",
           ns=small_dense("multi_arm:h=2", "forward_dynamics", "0.3", "ns_in_line"),
           lib=small_dense("multi_arm:h=2", "forward_dynamics", "0.3", "ns_library"),
           r=small_dense("multi_arm:h=2", "forward_dynamics", "0.3", "ratio"),
           rs=small_dense("stewart", "forward_dynamics", "0.3", "ratio")),
    Figure("library LU (worst {a} against {b} on `multi_arm:h=2`)",
           a=small_dense("multi_arm:h=2", "forward_dynamics", "0.3", "err_max_in_line"),
           b=small_dense("multi_arm:h=2", "forward_dynamics", "0.3", "err_max_library")),
    Figure("(99th percentile {p} against {pl}, worst {w} against {wl})",
           p=small_dense("multi_arm:h=2", "forward_dynamics", "1.0", "err_p99_in_line"),
           pl=small_dense("multi_arm:h=2", "forward_dynamics", "1.0", "err_p99_library"),
           w=small_dense("multi_arm:h=2", "forward_dynamics", "1.0", "err_max_in_line"),
           wl=small_dense("multi_arm:h=2", "forward_dynamics", "1.0", "err_max_library")),
    # Code generation: the articulated-body route against Pinocchio's aba
    Figure("The generated C takes {r6}× Pinocchio's `aba` time at N = 6 ({c6} ns against {p6} ns) and {r64}× "
           "at N = 64 ({c64} ns against {p64} ns)",
           r6=forward("chain:n=6", "ABA / Pin."), c6=forward("chain:n=6", "ABA C (ns/call)"),
           p6=forward("chain:n=6", "Pin. aba clang (ns/call)"), r64=forward("chain:n=64", "ABA / Pin."),
           c64=forward("chain:n=64", "ABA C (ns/call)"), p64=forward("chain:n=64", "Pin. aba clang (ns/call)")),
    Figure("the g++ build takes {g6} ns at N = 6", g6=forward("chain:n=6", "Pin. aba header (ns/call)")),
    Figure("`chain:n=6`'s inverse dynamics {c6}× the time of the default build and Talos's {talos}×",
           c6=Cell("benchmarks/trig_inline.csv", "wide_vector", dict(scene="chain:n=6", build="clang"), ".2f"),
           talos=Cell("benchmarks/trig_inline.csv", "wide_vector", dict(scene="talos", build="clang"), ".2f")),
    Figure("In clang's build the inverse dynamics takes {one}× the time it takes with them one at a time on "
           "chain:n=6 and {libm}× the time with the C library's",
           one=Cell("benchmarks/trig_inline.csv", "vector_scalar", dict(scene="chain:n=6", build="clang"), ".2f"),
           libm=Cell("benchmarks/trig_inline.csv", "ratio", dict(scene="chain:n=6", build="clang"), ".2f")),
    Figure("is {r32}× Pinocchio at N = 32 and {r64}× at N = 64", r32=forward("chain:n=32", "dense / Pin."),
           r64=forward("chain:n=64", "dense / Pin.")),
    Figure("At N = 6 the operation counts keep the joint-space route ({joint} against {dense} dense and {aba} "
           "articulated-body), which ran at {ns} ns, {r}×",
           joint=forward("chain:n=6", "ops joint-space"), dense=forward("chain:n=6", "ops dense"),
           aba=forward("chain:n=6", "ops ABA"), ns=forward("chain:n=6", "joint-space C (ns/call)"),
           r=forward("chain:n=6", "joint-space / Pin.")),
    # Pinocchio twins: constrained forward dynamics against Pinocchio's C++
    Figure("the generated C takes {four}× (`four_bar`), {five}× (`five_bar`), {arm}× (`arm_on_plane`) and "
           "{stewart}× (`stewart`",
           four=constrained("four_bar"), five=constrained("five_bar"), arm=constrained("arm_on_plane"),
           stewart=constrained("stewart")),
    Figure("**Two arms holding one object** (`multi_arm:h=2`): {ratio}×", ratio=constrained("multi_arm:h=2")),
    Figure("(`chain:n=6`, `chain:n=64`, open): {n6}× and {n64}× Pinocchio's `aba`",
           n6=constrained("chain:n=6"), n64=constrained("chain:n=64")),
    # Code generation: what the straight-line solves buy
    Figure("Stewart `inverse_dynamics`: {base} for the baseline, which factors a 30 × 30 LU, and {now} with these "
           "routes, with no library call",
           base=closed("stewart", "inverse_dynamics", "baseline_total_with_solves"),
           now=closed("stewart", "inverse_dynamics")),
    Figure("Stewart `forward_dynamics`: {base} for the baseline, {now} with these routes",
           base=closed("stewart", "forward_dynamics", "baseline_total_with_solves"),
           now=closed("stewart", "forward_dynamics")),
    Figure("four-bar `inverse_dynamics`: {base} for the baseline, {now} with these routes",
           base=closed("four_bar", "inverse_dynamics", "baseline_total_with_solves"),
           now=closed("four_bar", "inverse_dynamics")),
    Figure("`arm_on_plane` `forward_dynamics`: {base} for the baseline, {now} with these routes",
           base=closed("arm_on_plane", "forward_dynamics", "baseline_total_with_solves"),
           now=closed("arm_on_plane", "forward_dynamics")),
    # Built-in scenes: `symgen prove` times
    Figure("at most {small} s for the planar loops and the arm on a plane, about {stewart} s for the "
           "Stewart platform, and about {h3} s for `multi_arm:h=3`",
           small=Cell(PROVE, "seconds", dict(scene=("four_bar", "five_bar", "arm_on_plane")), ".2f", "max"),
           stewart=Cell(PROVE, "seconds", dict(scene="stewart"), ".0f"),
           h3=Cell(PROVE, "seconds", dict(scene="multi_arm:h=3"), ".0f")),
    # How it is checked: fuzzing
    Figure("`benchmarks/fuzz_cli.py` ran {cases} in {seconds} s with {findings} findings: every case is a parser "
           "refusal or a status 0, 1 or 2 with one error line, none longer than the {bound} s bound, the slowest "
           "{slowest} s",
           cases=Prose(FUZZ_CLI, r"\n(\d+) cases \(seeds"), seconds=Prose(FUZZ_CLI, r"in (\d+) s\. Time bound"),
           findings=Prose(FUZZ_CLI, r"or a hang\): (\d+)\."), bound=Prose(FUZZ_CLI, r"Time bound per case: (\d+) s"),
           slowest=Prose(FUZZ_CLI, r"slowest case ([0-9.]+) s")),
    Figure("`benchmarks/fuzz_front_door.py` ran {cases})",
           cases=Cell("benchmarks/fuzz_front_door.md", "cases", fmt=".0f", agg="sum")),
    # Code generation: linear growth of inverse_dynamics
    Figure("The fit is `total = {a} N − {b}` with R² = {r2}, and `total(64)/total(32) = {ratio}`",
           a=Computed(CHAIN, lambda rows: _chain_fit(rows).slope, ".2f", table="Kane cse"),
           b=Computed(CHAIN, lambda rows: -_chain_fit(rows).intercept, ".1f", table="Kane cse"),
           r2=Computed(CHAIN, lambda rows: _chain_fit(rows).r2, ".6f", table="Kane cse"),
           ratio=Computed(CHAIN, lambda rows: _chain_totals(rows)[64] / _chain_totals(rows)[32], ".3f",
                          table="Kane cse")),
    Figure("For `multi_arm:h=H` (H = 1…8) it is `{a} H + {b}` with R² = {r2}.",
           a=Prose("benchmarks/complexity/multi_arm.md", r"- inverse_dynamics total: ([\d.]+) H", ".0f"),
           b=Prose("benchmarks/complexity/multi_arm.md", r"- inverse_dynamics total: [\d.]+ H \+([\d.]+)", ".0f"),
           r2=Prose("benchmarks/complexity/multi_arm.md", r"- inverse_dynamics total: [\d.]+ H \+[\d.]+ \(R\^2 = ([\d.]+)\)")),
    # Code generation: lanes across states and single calls from Python
    Figure("`chain:n=6` inverse dynamics through the `_batch` path at {rate} states/s on one core, {r}× the "
           "scalar batch ([batch_lanes](benchmarks/batch_lanes.md)); one UR10 inverse dynamics from Python "
           "through the CPython extension in {ext} ns, {er}× the time of `pinocchio.rnea`",
           rate=Cell(LANES, "lanes (states/s)", dict(scene="chain:n=6", function="inverse_dynamics")),
           r=Cell(LANES, "scalar / lanes", dict(scene="chain:n=6", function="inverse_dynamics"), ".2f"),
           ext=Cell(SINGLE, "min (ns)", {"call": "symgen, CPython extension (`ur10_ext.inverse_dynamics`)"}),
           er=Cell(SINGLE, "/ rnea (median of rounds)",
                   {"call": "symgen, CPython extension (`ur10_ext.inverse_dynamics`)"}, ".3f")),
    Figure("`chain:n=6` inverse dynamics {lane} ns per state against {scalar} for the scalar batch, {r}×, "
           "{rate} states/s; forward dynamics {fr}×. At `chain:n=64`, with 512 states per call ({kib} KB",
           lane=Cell(LANES, "lanes (ns/state)", dict(scene="chain:n=6", function="inverse_dynamics")),
           scalar=Cell(LANES, "scalar batch (ns/state)", dict(scene="chain:n=6", function="inverse_dynamics")),
           r=Cell(LANES, "scalar / lanes", dict(scene="chain:n=6", function="inverse_dynamics"), ".2f"),
           rate=Cell(LANES, "lanes (states/s)", dict(scene="chain:n=6", function="inverse_dynamics")),
           fr=Cell(LANES, "scalar / lanes", dict(scene="chain:n=6", function="forward_dynamics"), ".2f"),
           kib=Cell(LANES, lambda r: number(r["data (KiB)"]) / number(r["states per call"]),
                    dict(scene="chain:n=64", function="inverse_dynamics", **{"states per call": "512"}), ".0f")),
    Figure("core's 2 MB second-level cache), {r64}× for the inverse dynamics and {f64}× for the forward "
           "dynamics; with 4096 states per call ({kib} MB) {r64b}× and {f64b}×.",
           r64=Cell(LANES, "scalar / lanes", dict(scene="chain:n=64", function="inverse_dynamics",
                                                   **{"states per call": "512"}), ".2f"),
           f64=Cell(LANES, "scalar / lanes", dict(scene="chain:n=64", function="forward_dynamics",
                                                   **{"states per call": "512"}), ".2f"),
           kib=Cell(LANES, lambda r: number(r["data (KiB)"]) / 1024,
                    dict(scene="chain:n=64", function="inverse_dynamics", **{"states per call": "4096"}), ".0f"),
           r64b=Cell(LANES, "scalar / lanes", dict(scene="chain:n=64", function="inverse_dynamics",
                                                    **{"states per call": "4096"}), ".2f"),
           f64b=Cell(LANES, "scalar / lanes", dict(scene="chain:n=64", function="forward_dynamics",
                                                    **{"states per call": "4096"}), ".2f")),
    Figure("there the lanes take {big} ns per state against {small} at 512 states",
           big=Cell(LANES, "lanes (ns/state)", dict(scene="chain:n=64", function="inverse_dynamics",
                                                    **{"states per call": "4096"})),
           small=Cell(LANES, "lanes (ns/state)", dict(scene="chain:n=64", function="inverse_dynamics",
                                                      **{"states per call": "512"}))),
    Figure("A plain copy of the same inputs moves {copy} GB/s (bytes read plus bytes written), the lanes read and "
           "write theirs at {rate} GB/s",
           copy=Cell(LANES, "memmove (GB/s)", dict(scene="chain:n=64", function="inverse_dynamics",
                                                   **{"states per call": "4096"})),
           rate=Cell(LANES, "lanes data rate (GB/s)", dict(scene="chain:n=64", function="inverse_dynamics",
                                                           **{"states per call": "4096"}))),
    Figure("timed in the same rounds, take {a}× the 8 lanes' time on `chain:n=6`'s inverse dynamics, {b}× on "
           "`chain:n=64`'s forward\ndynamics in cache and {c}× on the streamed `chain:n=64` inverse dynamics",
           a=Cell(LANES, "4 lanes / lanes", dict(scene="chain:n=6", function="inverse_dynamics"), ".2f"),
           b=Cell(LANES, "4 lanes / lanes", dict(scene="chain:n=64", function="forward_dynamics",
                                                  **{"states per call": "512"}), ".2f"),
           c=Cell(LANES, "4 lanes / lanes", dict(scene="chain:n=64", function="inverse_dynamics",
                                                  **{"states per call": "4096"}), ".2f")),
    Figure("The lanes add to the source's compile time ({lanes} s against {scalar} s",
           lanes=Cell(LANES, lambda r: number(r["compile lanes / scalar (s)"].split("/")[0]),
                      dict(scene="chain:n=64", function="inverse_dynamics", **{"states per call": "512"}), ".1f"),
           scalar=Cell(LANES, lambda r: number(r["compile lanes / scalar (s)"].split("/")[1]),
                       dict(scene="chain:n=64", function="inverse_dynamics", **{"states per call": "512"}), ".1f")),
    Figure("Its last run: {ext} ns per call through the extension, {pin} ns for `pinocchio.rnea` ({er}×), and "
           "{ct} ns through the ctypes binding",
           ext=Cell(SINGLE, "min (ns)", {"call": "symgen, CPython extension (`ur10_ext.inverse_dynamics`)"}),
           pin=Cell(SINGLE, "min (ns)", {"call": "Pinocchio `pinocchio.rnea(model, data, q, v, a)`"}),
           er=Cell(SINGLE, "/ rnea (median of rounds)",
                   {"call": "symgen, CPython extension (`ur10_ext.inverse_dynamics`)"}, ".3f"),
           ct=Cell(SINGLE, "min (ns)", {"call": "symgen, ctypes binding (`ur10_ctypes.inverse_dynamics`)"})),
    # Code generation: cost of the finiteness checks
    Figure("The check costs {ns} ns ({cost}) on the cheapest C function measured (`chain:n=6` inverse dynamics, "
           "{plain} ns unchecked), at most {numpy1} of a one-state NumPy call, and at most {batch} batched",
           ns=Cell(NONFINITE, lambda r: number(r["C checked (ns)"]) - number(r["C plain (ns)"]),
                   dict(scene="chain:n=6", function="inverse_dynamics"), ".1f"),
           cost=Cell(NONFINITE, "C cost", dict(scene="chain:n=6", function="inverse_dynamics")),
           plain=Cell(NONFINITE, "C plain (ns)", dict(scene="chain:n=6", function="inverse_dynamics")),
           numpy1=Cell(NONFINITE, "NumPy 1 cost", fmt=lambda v: f"+{v:.1f}%", agg="max"),
           batch=Cell(NONFINITE, "NumPy 1000 cost", fmt=lambda v: f"+{v:.1f}%", agg="max")),
    # Code generation: per-call times, batch throughput (benchmarks/codegen_speed)
    Figure("for the benchmark chain `chain:n=6`: the generated C in {r}× Pinocchio's `rnea` time ({c} ns against "
           "{pin} ns), and {r64}× at `chain:n=64`; the compiled batch path (the ctypes binding's `_batch` call) "
           "{ct} ns/state, {cts} states/s; the NumPy module {np4} / {np5} states/s at 10⁴ / 10⁵ states per call "
           "with the default allocator. For `ur5`: {ur}× ({uc} ns against {upin} ns), {ucts} states/s through "
           "ctypes, {unp4} / {unp5} states/s in NumPy",
           r=codegen("chain:n=6", "c_over_pin", ".3f"), c=codegen("chain:n=6", "c_ns", ".0f"),
           pin=pinocchio_rnea("chain:n=6"), r64=codegen("chain:n=64", "c_over_pin", ".3f"),
           ct=codegen("chain:n=6", "ctypes_ns", ".0f"), cts=codegen("chain:n=6", "ctypes_ns", per_second),
           np4=codegen("chain:n=6", "numpy_ns", per_second), np5=codegen("chain:n=6", "numpy_big_ns", per_second),
           ur=codegen("ur5", "c_over_pin", ".3f"), uc=codegen("ur5", "c_ns", ".0f"), upin=pinocchio_rnea("ur5"),
           ucts=codegen("ur5", "ctypes_ns", per_second), unp4=codegen("ur5", "numpy_ns", per_second),
           unp5=codegen("ur5", "numpy_big_ns", per_second)),
    Figure("In-process generation of all functions, without start-up, takes {g35} s on `chain:n=35` and {g100} s "
           "on `chain:n=100`",
           g35=Cell(CODEGEN, "value", dict(table="generation", scene="chain:n=35", quantity="seconds_all_functions"),
                    ".2f"),
           g100=Cell(CODEGEN, "value", dict(table="generation", scene="chain:n=100", quantity="seconds_all_functions"),
                     ".2f")),
    Figure("the generated C takes {ur5}× and {panda}× the time of Pinocchio's C++ `rnea`",
           ur5=codegen("ur5", "c_over_pin", ".2f"), panda=codegen("panda", "c_over_pin", ".2f")),
    # Code generation: one pass for M, C and G
    Figure("It costs {stewart}× the three separate functions on the Stewart platform, {arm}× on the arm on a plane "
           "and {chain}× on `chain:n=6`",
           **{k: Cell("benchmarks/dynamics_terms.csv", "ratio", dict(scene=s), ".2f")
              for k, s in (("stewart", "stewart"), ("arm", "arm_on_plane"), ("chain", "chain:n=6"))}),
    # Code generation: frames, centre of mass and momentum
    Figure("on the UR5, with `tool0`, `frame_jacobian` costs {jacw} operations world-aligned ({jac} in the frame's "
           "axes), `frame_drift` {driftw} ({drift}), `com_jacobian` {com}, `centroidal_momentum` {h} and "
           "`centroidal_momentum_derivatives` {hd}, against {inv} for `inverse_dynamics`",
           **{k: Cell(FRAMES, col, dict(scene="ur5")) for k, col in (
               ("jac", "frame_jacobian"), ("jacw", "frame_jacobian_world"), ("drift", "frame_drift"),
               ("driftw", "frame_drift_world"), ("com", "com_jacobian"), ("h", "centroidal_momentum"),
               ("hd", "centroidal_momentum_derivatives"), ("inv", "inverse_dynamics"))}),
    Figure("On `chain:n=32`, `frame_jacobian` costs {jacw} ({jac}), `frame_drift` {driftw}, `com_jacobian` {com} and "
           "`centroidal_momentum` {h}, against {inv} for `inverse_dynamics`; the forward-mode derivatives grow "
           "faster, {hd}",
           **{k: Cell(FRAMES, col, dict(scene="chain:n=32")) for k, col in (
               ("jac", "frame_jacobian"), ("jacw", "frame_jacobian_world"), ("driftw", "frame_drift_world"),
               ("com", "com_jacobian"), ("h", "centroidal_momentum"), ("hd", "centroidal_momentum_derivatives"),
               ("inv", "inverse_dynamics"))}),
    # Code generation: parameters at run time
    Figure("on the UR5 with a payload, `inverse_dynamics` costs {ip} operations with the payload's ten parameters "
           "in `p` against {if_} folded, `mass_matrix` {mp} against {mf} and `forward_dynamics` {fp} against {ff}; "
           "on `chain:n=6` with all {n} parameters in `p`, `inverse_dynamics` costs {cp} against {cf} ({cr}×) and "
           "`forward_dynamics` {dp} against {df}",
           **{f"{k}{tag}": Cell(PARAMS, col, dict(scene=s, function=f))
              for k, s, f in (("i", "ur5 + payload", "inverse_dynamics"), ("m", "ur5 + payload", "mass_matrix"),
                              ("f", "ur5 + payload", "forward_dynamics"), ("c", "chain:n=6", "inverse_dynamics"),
                              ("d", "chain:n=6", "forward_dynamics"))
              for tag, col in (("p", "parameterised"), ("f" if k != "i" else "f_", "folded"))},
           n=Cell(PARAMS, "parameters", dict(scene="chain:n=6"), agg="same"),
           cr=Cell(PARAMS, "ratio", dict(scene="chain:n=6", function="inverse_dynamics"))),
    # Code generation: the Jacobians of forward dynamics
    Figure("`chain:n=6` costs {d6} operations against {p6} for `forward_dynamics` ({r6}×), the four-bar {d4} "
           "against {p4}, `arm_on_plane` {da} against {pa} and `multi_arm:h=2` {dm} against {pm} ({rm}×)",
           **{f"{k}{tag}": Cell(DERIV, col, dict(scene=s), agg="same") for tag, s in (("6", "chain:n=6"), ("4", "four_bar"),
                                                                          ("a", "arm_on_plane"), ("m", "multi_arm:h=2"))
              for k, col in (("d", "derivatives"), ("p", "primal"))
              if f"{k}{tag}" in ("d6", "p6", "d4", "p4", "da", "pa", "dm", "pm")},
           r6=Cell(DERIV, "ratio", dict(scene="chain:n=6"), ".2f", "same"), rm=Cell(DERIV, "ratio", dict(scene="multi_arm:h=2"), ".2f")),
    # Code generation: derivatives against Pinocchio's (spherical and free joints section)
    Figure("the generated C takes {ci}× the time of `computeRNEADerivatives` on `chain:n=6`, {ui}× on the UR5 and "
           "{pi}× on the Panda; `forward_dynamics_derivatives` {cf}×, {uf}× and {pf}× that of `computeABADerivatives`",
           **{f"{tag}{f[0]}": Cell(DERIV_SPEED, "ratio", dict(scene=s, function=f"{f}_dynamics_derivatives"), ".2f")
              for tag, s in (("c", "chain:n=6"), ("u", "ur5"), ("p", "panda")) for f in ("inverse", "forward")}),
    Figure("the generated C `forward_dynamics_derivatives` takes {st}× its time on `stewart` and {ma}× on "
           "`multi_arm:h=2`",
           st=Cell(CONSTRAINED_DERIV, "ratio", dict(scene="stewart"), ".2f"),
           ma=Cell(CONSTRAINED_DERIV, "ratio", dict(scene="multi_arm:h=2"), ".2f")),
    Figure("not on the two arms, whose {ops}-operation Jacobian",
           ops=Cell(DERIV, "derivatives", dict(scene="multi_arm:h=2"), ".0f")),
    Figure("on `general_chain:n=7` the generated C takes {gi}× `computeRNEADerivatives` and {gf}× "
           "`computeABADerivatives`, in {oi} and {of} operations",
           **{f"{k}{f[0]}": Cell(DERIV_SPEED, col, dict(scene="general_chain:n=7", function=f"{f}_dynamics_derivatives"), fmt)
              for f in ("inverse", "forward") for k, col, fmt in (("g", "ratio", ".2f"), ("o", "ops", ".0f"))}),
    Figure("On `chain:n=32` it is met for both: {ri}× `computeRNEADerivatives` (0.455×, 0.47×, 0.44×, 0.44×, 0.50×\n"
           "and 0.48× in the six previous runs) and {rf}× `computeABADerivatives` (0.458× and 0.54× in the two previous runs; the\n"
           "forward derivatives by the joint-space route with its mass matrix in the library's symmetric factor, above). From\n"
           "`chain:n=6` to `chain:n=32` the generated inverse derivatives grow from {o6} to {o32} operations\n"
           "plus {f32} flops of library products, and their time from {c6} to {c32} ns, while Pinocchio's grows\n"
           "from {p6} to {p32} ns",
           ri=Cell(DERIV_SPEED, "ratio", dict(scene="chain:n=32", function="inverse_dynamics_derivatives"), ".3f"),
           rf=Cell(DERIV_SPEED, "ratio", dict(scene="chain:n=32", function="forward_dynamics_derivatives"), ".3f"),
           f32=Cell(DERIV_SPEED, "library_flops", dict(scene="chain:n=32", function="inverse_dynamics_derivatives"), ".0f"),
           **{f"{k}{tag}": Cell(DERIV_SPEED, col, dict(scene=f"chain:n={tag}", function="inverse_dynamics_derivatives"), ".0f")
              for tag in ("6", "32") for k, col in (("o", "ops"), ("c", "c_ns"), ("p", "pin_clang++_ns"))}),
    Figure("{rf}× ({cf} against {pf}) in this run, with\nthe factor's last columns and the inverse's mirror as they are now",
           rf=Cell(DERIV_SPEED, "ratio", dict(scene="chain:n=32", function="forward_dynamics_derivatives"), ".3f"),
           cf=Cell(DERIV_SPEED, "c_ns", dict(scene="chain:n=32", function="forward_dynamics_derivatives"), ".0f"),
           pf=Cell(DERIV_SPEED, "pin_ns", dict(scene="chain:n=32", function="forward_dynamics_derivatives"), ".0f")),
    # Code generation: the closed form's entries as library products
    Figure("as straight-line dot products the same function takes {d32}\noperations, hundreds of kilobytes of code "
           "that stream from the second-level cache on every call,\nand more time ({n32} "
           "against {l32} ns",
           d32=Cell(CLOSED_FORM, "dots_ops", dict(scene="chain:n=32"), ".0f"),
           n32=Cell(CLOSED_FORM, "dots_ns", dict(scene="chain:n=32"), ".0f"),
           l32=Cell(CLOSED_FORM, "products_ns", dict(scene="chain:n=32"), ".0f")),
    Figure("{r12}× the dot products' time at {p12} pairs (`chain:n=12`), {r16}× at {p16} (`chain:n=16`), {r24}× at "
           "{p24} and {r32}× at {p32} (`chain:n=32`), but {rg}× on `general_chain:n=7` ({pg} pairs). The products "
           "also win at {p10} pairs (`chain:n=10`: {r10}×), not at {p8} (`chain:n=8`: {r8}×)",
           **{f"{k}{tag}": Cell(CLOSED_FORM, col, dict(scene=s), fmt) for tag, s in
              (("8", "chain:n=8"), ("10", "chain:n=10"), ("12", "chain:n=12"), ("16", "chain:n=16"),
               ("24", "chain:n=24"), ("32", "chain:n=32"), ("g", "general_chain:n=7"))
              for k, col, fmt in (("r", "ratio", ".2f"), ("p", "pairs", ".0f"))}),
    Figure("(`chain:n=10`'s closed form would count {o10} operations and {f10} flops against the reverse sweep's "
           "{rev10}), so it would go to the reverse sweep, which no benchmark times against either; from 78 pairs the "
           "closed form with its products costs fewer ({o12} operations and {f12} flops against {rev12} on "
           "`chain:n=12`)",
           **{f"{k}{tag}": Cell(CLOSED_FORM, col, dict(scene=f"chain:n={tag}"), ".0f")
              for tag in ("10", "12") for k, col in (("o", "products_ops"), ("f", "products_flops"))},
           **{f"rev{tag}": Cell(INV_DERIV, "reverse", dict(scene=f"chain:n={tag}"), ".0f") for tag in ("10", "12")}),
    # Code generation: forward dynamics, the route kept by its count against the other's time
    Figure("as in this run at N = 12: {js} ns for the joint-space route kept by its {ojs} operations against {ab} ns "
           "for the recursion's {oab}",
           js=forward("chain:n=12", "joint-space C (ns/call)"), ab=forward("chain:n=12", "ABA C (ns/call)"),
           ojs=forward("chain:n=12", "ops joint-space"), oab=forward("chain:n=12", "ops ABA")),
    Figure("reads {c}× ({f}× here)", c=constrained("chain:n=64"), f=forward("chain:n=64", "ABA / Pin.")),
    # Code generation: the block size of long functions
    Figure("`general_chain:n=7`'s inverse-dynamics Jacobians take {kw} KB whole, {k5} KB in blocks of 5000 and "
           "{k1} KB in blocks of 1000, and {tw}, {t5} and {t1} ns per call",
           **{f"{k}{tag}": Cell(BLOCKS, col, dict(scene="general_chain:n=7", function="inverse_dynamics_derivatives",
                                                  variant=v, compiler="clang"), fmt)
              for tag, v in (("w", "whole"), ("5", "blocks of 5000"), ("1", "blocks of 1000"))
              for k, col, fmt in (("k", "code_kb", ".1f"), ("t", "ns", ".0f"))}),
    Figure("the Panda's forward Jacobians take {kw} KB whole and run fastest so ({tw} ns), {k1} KB and {t1} ns in "
           "blocks of 1000",
           **{f"{k}{tag}": Cell(BLOCKS, col, dict(scene="panda", function="forward_dynamics_derivatives",
                                                  variant=v, compiler="clang"), fmt)
              for tag, v in (("w", "whole"), ("1", "blocks of 1000"))
              for k, col, fmt in (("k", "code_kb", ".1f"), ("t", "ns", ".0f"))}),
    Figure("their machine code goes from {kt} KB with {st} instructions on the stack to {kf} KB and {sf}, and the "
           "call from {nt} to {nf} ns ({rf}× the traced order's time; {rc}× built by cc)",
           **{f"{k}{tag}": Cell(ORDER, col, dict(scene="panda", function="inverse_dynamics_derivatives",
                                                 order=order, build="clang fused"), fmt)
              for tag, order in (("t", "traced"), ("f", "first use"))
              for k, col, fmt in (("k", "code_kb", ".1f"), ("s", "stack_refs", ".0f"), ("n", "ns", ".0f"))},
           rf=Cell(ORDER, "vs_traced", dict(scene="panda", function="inverse_dynamics_derivatives",
                                            order="first use", build="clang fused"), ".2f"),
           rc=Cell(ORDER, "vs_traced", dict(scene="panda", function="inverse_dynamics_derivatives",
                                            order="first use", build="cc fused"), ".2f")),
    # Code generation: the two sweeps of inverse_dynamics_derivatives
    Figure("forward / reverse, `chain:n=6` {f6} / {r6} operations against {p6} for `inverse_dynamics`; {f3} / {r3} "
           "at `n = 3`, {f12} / {r12} at `n = 12`; {f4} / {r4} on the four-bar; the UR5 {fu} / {ru}; the Panda "
           "{fp} / {rp} against {pp}",
           **{f"{k}{tag}": Cell(INV_DERIV, col, dict(scene=s)) for tag, s in
              (("6", "chain:n=6"), ("3", "chain:n=3"), ("12", "chain:n=12"), ("4", "four_bar"), ("u", "ur5"),
               ("p", "panda")) for k, col in (("f", "forward"), ("r", "reverse"))},
           p6=Cell(INV_DERIV, "primal", dict(scene="chain:n=6")), pp=Cell(INV_DERIV, "primal", dict(scene="panda"))),
    Figure("on `chain:n=6` the reverse sweep stays cheaper ({r6} against {a6} operations), on `general_chain:n=7` the "
           "closed form is kept ({ag} against {rg}), and on the chain its advantage grows with `n` (from `n = 12` its "
           "count includes the flops of the library products below): {a12} against {r12} "
           "at `n = 12`, {a24} against {r24} at `n = 24`, {a32} against {r32} at `n = 32`",
           **{f"{k}{tag}": Cell(INV_DERIV, col, dict(scene=s)) for tag, s in
              (("6", "chain:n=6"), ("g", "general_chain:n=7"), ("12", "chain:n=12"), ("24", "chain:n=24"),
               ("32", "chain:n=32")) for k, col in (("a", "analytic"), ("r", "reverse"))}),
    Figure("`chain:n=32`'s articulated-body route ({ab} operations) would be kept over the joint-space one ({js} "
           "operations in straight line and {fl} flops in the library's loops",
           ab=Cell(DERIV, "fewest", dict(scene="chain:n=32")), js=Cell(DERIV, "straight", dict(scene="chain:n=32")),
           fl=Cell(DERIV, "flops", dict(scene="chain:n=32"))),
    Figure("the Panda's `implicit-dense-reverse` costs {pr} operations against {pd} for `implicit-dense`, "
           "`chain:n=6` {cr} against {cd}; on `arm_on_plane` the forward sweep is the cheaper ({ad} against {ar}), and the\n"
           "route kept there is `{ak}` ({ao})",
           **{f"{tag}{k}": Cell(DERIV_SWEEPS_FWD, col, dict(scene=s)) for tag, s in
              (("p", "panda"), ("c", "chain:n=6"), ("a", "arm_on_plane")) for k, col in (("d", "forward"), ("r", "reverse"))},
           ak=Cell(DERIV_SWEEPS_FWD, "kept", dict(scene="arm_on_plane")),
           ao=Cell(DERIV_SWEEPS_FWD, "best", dict(scene="arm_on_plane"))),
    Figure("four- and five-bar, and `{ak}` on the arm on a plane and `{mk}` on the two arms (on `multi_arm:h=2`\n"
           "{dm} operations against {ir} for `implicit-dense-reverse` and {jr} for\n`implicit-joint-space-reverse`",
           dm=Cell(DERIV, "derivatives", dict(scene="multi_arm:h=2")),
           **{k: Cell(DERIV, "route", dict(scene=sc)) for k, sc in (("ak", "arm_on_plane"), ("mk", "multi_arm:h=2"))},
           **{k: Prose("benchmarks/derivative_ops.md", rf"\| multi_arm:h=2 \|.*{r} (\d+)")
              for k, r in (("ir", "implicit-dense-reverse"), ("jr", "implicit-joint-space-reverse"))}),
    Figure("On the chain the count of the route with the fewest operations fits `{fit}` (R^2 = {r2}) over N = 2…32",
           fit=Prose("benchmarks/derivative_ops.md", r"over N = [\d, ]+: ([^(]+?) \(R"),
           r2=Prose("benchmarks/derivative_ops.md", r"R\^2 = ([\d.]+)\)")),
    # Simulation: the Jacobian of stiff runs
    Figure("on `stiff_contact_K1e+06` Radau takes {rg} right-hand sides against {rf}, BDF {bg} against {bf}",
           **{k: Cell("benchmarks/stiff_jacobian.csv", "rhs_calls", dict(case="stiff_contact_K1e+06", method=m, jacobian=j))
              for k, m, j in (("rg", "Radau", "generated"), ("rf", "Radau", "finite-difference"),
                              ("bg", "BDF", "generated"), ("bf", "BDF", "finite-difference"))}),
    Figure("the wall time is the same within this host's noise ({lo}–{hi}× the finite differences' time",
           lo=Computed("benchmarks/stiff_jacobian.csv", lambda rows: min(_settled_ratios(rows)), ".2f"),
           hi=Computed("benchmarks/stiff_jacobian.csv", lambda rows: max(_settled_ratios(rows)), ".2f")),
    Figure("There Radau asks for {rj} Jacobians and BDF for {bj}; with the generated one Radau takes {rg} "
           "right-hand sides against {rf} and {rw}× the wall time, BDF {bg} against {bf} and {bw}×",
           rj=Cell("benchmarks/stiff_jacobian.csv", "jacobian_calls",
                   dict(case="swinging_stiff_joint", method="Radau", jacobian="generated")),
           bj=Cell("benchmarks/stiff_jacobian.csv", "jacobian_calls",
                   dict(case="swinging_stiff_joint", method="BDF", jacobian="generated")),
           rw=Cell("benchmarks/stiff_jacobian.csv", "wall_ratio",
                   dict(case="swinging_stiff_joint", method="Radau", jacobian="generated"), ".2f"),
           bw=Cell("benchmarks/stiff_jacobian.csv", "wall_ratio",
                   dict(case="swinging_stiff_joint", method="BDF", jacobian="generated"), ".2f"),
           **{k: Cell("benchmarks/stiff_jacobian.csv", "rhs_calls", dict(case="swinging_stiff_joint", method=m, jacobian=j))
              for k, m, j in (("rg", "Radau", "generated"), ("rf", "Radau", "finite-difference"),
                              ("bg", "BDF", "generated"), ("bf", "BDF", "finite-difference"))}),
    # Simulation: the stability suite
    Figure("The outstretched arm is accurate up to `cond [J_m; J_f]` = 1e12 (error {err} against 50 digits)",
           err=Cell("benchmarks/stability/stability.md", "error vs 50 digits", dict(case="outstretched_1e+12"),
                    table="EOM residual")),
    # Simulation: one right-hand side
    Figure("costs {lo}–{hi}× the two separate calls",
           lo=Cell("benchmarks/simulation_rhs.md", "ratio", fmt=".2f", agg="min"),
           hi=Cell("benchmarks/simulation_rhs.md", "ratio", fmt=".2f", agg="max")),
    # Simulation: the work-precision reference
    Figure("For the four-bar they differ by {diff}.",
           diff=Json(f"{SIM}/four_bar/work_precision.json", "reference_difference", ".2g")),
    # Adaptive control: demonstrations
    Figure("Adaptation ends with {worst} (stewart) to {best} (multi_arm:h=2) of the frozen controller's task error",
           worst=Cell(CONTROL, "ratio", dict(scene="stewart"), lambda v: f"1/{1 / v:,.0f}"),
           best=Cell(CONTROL, "ratio", dict(scene="multi_arm:h=2"), lambda v: f"1/{1 / v:,.0f}")),
    Figure("presses with its desired 20 N to within {force} N",
           force=Cell(CONTROL, "final_force_error_adaptive", dict(scene="arm_on_plane"), ".2g")),
    Figure("on `arm_on_plane` with more ({adaptive} N against {frozen} N",
           adaptive=Cell(CONTROL, "final_force_error_adaptive", dict(scene="arm_on_plane"), ".2g"),
           frozen=Cell(CONTROL, "final_force_error_frozen", dict(scene="arm_on_plane"), ".2g")),
    Figure("default run takes {cold} s on the UR10 from an empty cache (deriving, tracing and compiling "
           "included; {warm} s with the compiled module cached) and {kinova} s on the Jaco",
           warm=Cell(CONTROL_COMMAND, "wall (s)", dict(scene="ur10_on_plane (default run)")),
           cold=Cell(CONTROL_COMMAND, "wall (s)", dict(scene="ur10_on_plane (default run, empty cache)")),
           kinova=Cell(CONTROL_COMMAND, "wall (s)", dict(scene="kinova_on_plane (default run, empty cache)"))),
    # Adaptive control: the generated controller's cost
    Figure("the controller adds {lo} to {hi} operations per arm",
           lo=Cell(CONTROL_SPEED, "increment#2", dict(H=("2", "3", "4", "5", "6")), ".0f", agg="min",
                   table="control - task_inverse_dynamics"),
           hi=Cell(CONTROL_SPEED, "increment#2", dict(H=("2", "3", "4", "5", "6")), ".0f", agg="max",
                   table="control - task_inverse_dynamics")),
    Figure("all 78 parameters uncertain: {ns} ns per call, {id}× generated `inverse_dynamics` and {pin}× "
           "Pinocchio's C++ `rnea`; - none uncertain: {none} ns",
           ns=Cell(CONTROL_SPEED, "ns/call", dict(function="control, all uncertain")),
           id=Cell(CONTROL_SPEED, "/ inverse_dynamics", dict(function="control, all uncertain")),
           pin=Cell(CONTROL_SPEED, "/ Pinocchio rnea", dict(function="control, all uncertain")),
           none=Cell(CONTROL_SPEED, "ns/call", dict(function="control, none uncertain"))),
    # Adaptive control: the Slotine-Li baseline
    Figure("adaptive against frozen task error {s_a} / {s_f} (symgen) and {b_a} / {b_f} (Slotine–Li)",
           s_a=Cell(SLOTINE, "task error, adaptive", dict(controller="symgen Section 4 (dense reference, on symgen's plant)")),
           s_f=Cell(SLOTINE, "task error, frozen", dict(controller="symgen Section 4 (dense reference, on symgen's plant)")),
           b_a=Cell(SLOTINE, "task error, adaptive", dict(controller="Slotine-Li (Pinocchio regressor, on Pinocchio's aba)")),
           b_f=Cell(SLOTINE, "task error, frozen", dict(controller="Slotine-Li (Pinocchio regressor, on Pinocchio's aba)"))),
    Figure("the classical regressor and law take {classic} µs, symgen's generated NumPy `control` {numpy} µs and its "
           "C `control` {c} µs (mostly the ctypes call; from C, {from_c} µs)",
           classic=Cell(SLOTINE, "us per call", dict(implementation=(
               "Slotine-Li, classical regressor (60 columns from 61 models: Pinocchio's C++ crba, Coriolis matrix, "
               "gravity via Python)")), ".0f", table="us per call"),
           numpy=Cell(SLOTINE, "us per call", dict(implementation="symgen generated NumPy control"), ".0f",
                      table="us per call"),
           c=Cell(SLOTINE, "us per call", dict(implementation="symgen generated C control (ctypes call)"), ".0f",
                  table="us per call"),
           from_c=Cell(CONTROL_SPEED, "ns/call", dict(function="control, all uncertain"), lambda v: f"{v / 1000:.1f}")),
    # Complexity
    Figure("`inverse_dynamics` = {a} N − {b} operations (R² = {r2})",
           a=Cell(CHAIN, "slope a (ops/DOF)", dict(series="inverse_dynamics"), table="slope a (ops/DOF)"),
           b=Cell(CHAIN, "intercept b", dict(series="inverse_dynamics"), lambda v: f"{-v:g}", table="slope a (ops/DOF)"),
           r2=Cell(CHAIN, "R^2", dict(series="inverse_dynamics"), table="slope a (ops/DOF)")),
    Figure("Its local slope over N = 8…64 stays within {dev} % of the fit",
           dev=Prose(CHAIN, r"largest deviation ([\d.]+) %", ".1f")),
    Figure("At N = 6 this formulation needs {ops} operations, {ratio}× their {lwp}",
           ops=Prose(CHAIN, r"inverse_dynamics (\d+) / \d+ = "), ratio=Prose(CHAIN, r"inverse_dynamics \d+ / \d+ = ([\d.]+)"),
           lwp=Prose(CHAIN, r"inverse_dynamics \d+ / (\d+) = ")),
    Figure("Kane after `cse` grows as N^{p}",
           p=Cell(CHAIN, "exponent p", dict(series="Kane cse"), table="slope a (ops/DOF)")),
    Figure("Each extra arm adds exactly {a} operations to `inverse_dynamics` ({a} H + {b} for H = 1…8)",
           a=Prose("benchmarks/complexity/multi_arm.md", r"- inverse_dynamics total: ([\d.]+) H", ".0f"),
           b=Prose("benchmarks/complexity/multi_arm.md", r"- inverse_dynamics total: [\d.]+ H \+([\d.]+)", ".0f")),
]


#: benchmark files the text links to, each of which must back at least one declared figure
LINKED = {"benchmarks/trig_inline.md": "benchmarks/trig_inline.csv", FRAMES.replace(".csv", ".md"): FRAMES, PARAMS.replace(".csv", ".md"): PARAMS, "benchmarks/control_closed_loop_speed.md": CONTROL_COMMAND, "benchmarks/floating_base.md": FLOATING, "benchmarks/floating_base_constrained.md": FLOATING_GROUND, "benchmarks/space_momentum.md": SPACE, "benchmarks/derivative_ops.md": DERIV, "benchmarks/derivative_speed.md": DERIV_SPEED, "benchmarks/closed_form_products.md": CLOSED_FORM, "benchmarks/block_size.md": BLOCKS, "benchmarks/statement_order.md": ORDER, "benchmarks/constrained_derivatives.md": CONSTRAINED_DERIV, "benchmarks/derivative_sweeps.md": INV_DERIV, "benchmarks/stiff_jacobian.md": "benchmarks/stiff_jacobian.csv", "benchmarks/codegen_speed.md": CODEGEN, "benchmarks/prove_times.md": PROVE, "benchmarks/dead_point.md": DEAD, "benchmarks/urdf_coverage.md": URDF_COVERAGE,
          MJCF_COVERAGE: MJCF_COVERAGE,
          "benchmarks/nonfinite_check.md": NONFINITE, "benchmarks/dynamics_terms.md": "benchmarks/dynamics_terms.csv",
          "benchmarks/simulation_rhs.md": "benchmarks/simulation_rhs.md",
          "benchmarks/fuzz_front_door.md": "benchmarks/fuzz_front_door.md", FUZZ_CLI: FUZZ_CLI,
          "benchmarks/stability/stability.md": "benchmarks/stability/stability.md",
          "benchmarks/control/summary.md": CONTROL, "benchmarks/control_speed.md": CONTROL_SPEED,
          "benchmarks/slotine_li.md": SLOTINE, "benchmarks/complexity/multi_arm.md": "benchmarks/complexity/multi_arm.md",
          "benchmarks/simulation/four_bar/work_precision.md": f"{SIM}/four_bar/work_precision.json",
          "benchmarks/complexity/closed_chains.md": CLOSED, CHAIN: CHAIN,
          "benchmarks/constrained_forward.md": CONSTRAINED, FORWARD: FORWARD, FORWARD_OPS: FORWARD_OPS, IDENT: IDENT,
          "benchmarks/compile_scale.md": COMPILE, "benchmarks/complexity/mass_matrix.md": MASS,
          "benchmarks/small_dense_solves.md": SMALL_DENSE, LANES: LANES, SINGLE: SINGLE,
          "benchmarks/pinocchio_baseline.md": PINBASE}
#: benchmark files the text links to for their descriptions, not for figures
#: (identification.md: the guide points at its three tables, which its benchmark page includes;
#: simulation/summary.md: the simulation page includes it whole)
DESCRIPTIONS = {"benchmarks/simulation/README.md", f"{SIM}/summary.md"}


# ---------------------------------------------------------------------------------------------
# The tests


@pytest.mark.parametrize("figure", FIGURES, ids=lambda f: normalise(f.snippet)[:50])
def test_the_text_quotes_the_row_it_cites(figure):
    assert not figure.problems(TEXT), "\n".join(figure.problems(TEXT))


def _sources(item: Figure) -> set[str]:
    return {src.path for src in item.sources.values()}


def _linked(text: str) -> set[str]:
    """Benchmark files the text links to: ``benchmarks/x.md`` in the README, ``../benchmarks/x.md``
    (the page that includes it) in the docs, or written as code."""
    return (set(re.findall(r"\]\((?:\.\./)*(benchmarks/[^)]+\.md)\)", text))
            | set(re.findall(r"`(benchmarks/[^`]+\.md)`", text)))


def test_every_linked_benchmark_backs_a_declared_figure():
    linked = _linked(TEXT)
    declared = set().union(*(_sources(x) for x in FIGURES))
    unknown = sorted(p for p in linked if p not in LINKED and p not in DESCRIPTIONS and (ROOT / p).exists())
    assert not unknown, f"the text links {unknown}: declare their figures here (or add them to LINKED)"
    missing = sorted(p for p in linked if p in LINKED and LINKED[p] not in declared)
    assert not missing, f"no declared figure from {missing}"


def test_the_readme_quotes_its_headline_figures():
    """The README's figures are among the declared ones (each checked above against its row)."""
    readme = normalise((ROOT / "README.md").read_text(encoding="utf-8"))
    quoted = [f for f in FIGURES if normalise(f.expected(ROOT)) in readme]
    assert len(quoted) >= 4, [f.snippet for f in quoted]


# --- the check catches what it should


def _figure(words: str) -> Figure:
    """The declared figure whose snippet contains ``words``."""
    (found,) = [f for f in FIGURES if words in f.snippet]
    return found


def test_a_changed_figure_fails():
    """The known misquote (another row's figures -- the UR5's, or the Panda's when a run gives the
    UR5 and the chain the same rounded time -- quoted for the chain) is caught, and so is any
    figure of the list changed by one digit."""
    chain_c = codegen("chain:n=6", "c_ns", ".0f").text(ROOT)
    other_c = next(c for c in (codegen(s, "c_ns", ".0f").text(ROOT) for s in ("ur5", "panda", "chain:n=12"))
                 if c != chain_c)
    misquote = TEXT.replace(f"({chain_c} ns against", f"({other_c} ns against", 1)
    assert misquote != TEXT
    problems = _figure("for the benchmark chain `chain:n=6`").problems(misquote)
    assert problems and f"({other_c} ns" in problems[0] and f"({chain_c} ns" in problems[0]
    for figure in FIGURES:
        if figure.problems(TEXT):
            continue                                  # already failing: reported by the test above
        quoted = normalise(figure.expected(ROOT))
        value = next(iter(figure.sources.values())).text(ROOT)
        text = normalise(TEXT)
        broken = text.replace(quoted, quoted.replace(value, _bump(value), 1))
        assert broken != text, figure
        assert figure.problems(broken), f"a changed figure passes: {figure}"


def _bump(text: str) -> str:
    """The first digit of ``text`` changed."""
    return re.sub(r"\d", lambda m: str((int(m.group(0)) + 1) % 10), text, count=1)


def _bump_cell(path: Path, where: dict, column: str, table: str | None = None) -> None:
    """Rewrite one cell of a CSV or markdown table file: its first digit changed (``_bump``)."""
    text = path.read_text(encoding="utf-8")
    if path.suffix == ".csv":
        rows = list(csv.DictReader(io.StringIO(text)))
        (row,) = [r for r in rows if _matches(r, where)]
        row[column] = _bump(row[column])
        buf = io.StringIO()
        writer = csv.DictWriter(buf, fieldnames=list(rows[0]), lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
        path.write_text(buf.getvalue(), encoding="utf-8")
        return
    lines, header = text.splitlines(), None
    for i, line in enumerate(lines):
        cells = [c.strip() for c in line.strip().strip("|").split("|")] if line.startswith("|") else None
        if cells is None:
            header = None
        elif header is None:
            header = _unique(cells) if (table is None or table in cells) else []
        elif header and not set(line) <= set("|-: ") and _matches(dict(zip(header, cells)), where):
            cells[header.index(column)] = _bump(cells[header.index(column)])
            lines[i] = "| " + " | ".join(cells) + " |"
            path.write_text("\n".join(lines) + "\n", encoding="utf-8")
            return
    raise AssertionError(f"{path}: no row {where}")


def test_a_regenerated_table_with_other_numbers_fails(tmp_path):
    """Copies of the benchmark files with one number changed: the unchanged text fails against them."""
    for rel in {CODEGEN, NONFINITE}:
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(ROOT / rel, tmp_path / rel)
    chain_figure = _figure("for the benchmark chain `chain:n=6`")
    assert not chain_figure.problems(TEXT, tmp_path)
    _bump_cell(tmp_path / CODEGEN, dict(table="runtime", scene="chain:n=6", quantity="c_ns"), "value")
    assert chain_figure.problems(TEXT, tmp_path)
    _bump_cell(tmp_path / NONFINITE, dict(scene="chain:n=6", function="inverse_dynamics"), "C checked (ns)")
    assert _figure("The check costs").problems(TEXT, tmp_path)


def test_the_readers():
    tables = md_tables("x\n| a | b | a |\n|---|---|---|\n| 1 | `2` | 3 |\n\n| c |\n|:--|\n| 4 |\n")
    assert tables == [[{"a": "1", "b": "`2`", "a#2": "3"}], [{"c": "4"}]]
    assert number("+6.7%") == 6.7 and number("1 005 970 187") == 1005970187 and number("0.19×") == 0.19
    assert normalise("1 144 (+216)\n  a–b") == "1144 (+216) a-b"
    assert states_per_s(769.3853) == "1.30e6" and states_per_s(3109.2) == "3.22e5"
