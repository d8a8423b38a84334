"""``symgen complexity``: published formulas, SymPy op counting, the mechanics model of the chain,
the time-limited sweep, the slope check, and the command's tables.

Expected values are written out by hand or computed by independent code (``symgen ops``, a
SymPy ``physics.mechanics`` model compared with symgen's dense model).
"""
from __future__ import annotations

import csv
import json
from fractions import Fraction

import numpy as np
import pytest
import sympy as sp

import symgen.cli
from symgen.codegen.generate import operation_counts
from symgen.complexity import fits, mechanics, sweep as sweep_mod
from symgen.complexity.measure import ERROR, OK, TIMEOUT, Outcome, measure
from symgen.complexity.published import FORMULAS, LAGRANGE_EULER, LUH_WALKER_PAUL
from symgen.complexity.sympy_ops import cse_operation_counts, operation_counts as sympy_ops, sympy_count_ops
from symgen.complexity.tables import poly_text
from symgen.model import derive
from symgen.math.configuration import Configuration

MECHANICS_TOL = 1e-12      # SymPy mechanics vs symgen's dense float model (absolute, entries O(1))
CHAIN_FUNCTIONS = ("inverse_dynamics", "mass_matrix", "forward_dynamics")


def run_cli(monkeypatch, argv) -> int:
    """``symgen.cli.main``, the command line users run (``monkeypatch`` kept for the callers)."""
    from symgen.cli import complexity
    from symgen.cli.commands import COMMAND_MODULES

    assert complexity in COMMAND_MODULES
    return symgen.cli.main(argv)


def read_csv(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


# ----------------------------------------------------------------------------- published formulas
def test_published_formulas_at_six_joints():
    """Hand evaluation: LWP 150*6-48 = 852, 131*6-48 = 738; Lagrange-Euler additions
    25*1296 + 199/3*216 + 259/2*36 + 127/3*6 - 96 = 51548 (the source's n = 6 value), its
    multiplications 42120 + 18666 + 6165 + 320 - 128 = 67143 (the source prints 66,271)."""
    assert LUH_WALKER_PAUL.counts(6) == (852, 738)
    assert LAGRANGE_EULER.counts(6) == (67143, 51548)
    assert LAGRANGE_EULER.counts(1) == (Fraction(65, 2) + Fraction(1037, 12) + Fraction(685, 4) + Fraction(160, 3) - 128,
                                        25 + Fraction(199, 3) + Fraction(259, 2) + Fraction(127, 3) - 96)


def test_unverified_formulas_are_labelled():
    for f in FORMULAS:
        assert ("unverified" in f.label()) == (not f.verified)
        assert ("Corke" in f.source) == f.verified


def test_poly_text_mixed_fractions():
    assert poly_text(LAGRANGE_EULER.mul) == "32 1/2 n^4 + 86 5/12 n^3 + 171 1/4 n^2 + 53 1/3 n - 128"
    assert poly_text((150, -48)) == "150 n - 48"


# ----------------------------------------------------------------------------- counting SymPy expressions
X, Y, Z = sp.symbols("x y z")


@pytest.mark.parametrize("expr, mul, div, add, trig", [
    (X * Y + Z, 1, 0, 1, 0),
    (X - Y, 0, 0, 1, 0),                           # subtraction is an addition, the sign is free
    (-X * Y, 1, 0, 0, 0),                          # negation free
    (sp.Rational(3, 10) * X, 1, 0, 0, 0),          # a constant is a literal, not a division
    (X / Y, 1, 1, 0, 0),                           # one division (mul includes div)
    (1 / (X * Y), 2, 1, 0, 0),                     # x*y, then 1/(.)
    (2 * X / (Y * Z), 3, 1, 0, 0),                 # 2*x, y*z, then the division
    (X**3, 2, 0, 0, 0),
    (sp.sin(X)**2 + sp.cos(X)**2, 2, 0, 1, 2),
    (X * Y + sp.sin(X * Y), 2, 0, 1, 1),           # a repeated subexpression counts each time
])
def test_sympy_ops_hand_counts(expr, mul, div, add, trig):
    got = sympy_ops([expr])
    assert (got["mul"], got["div"], got["add"], got["trig"]) == (mul, div, add, trig)
    assert got["total"] == mul + add


def test_sympy_count_ops_differs_from_our_convention():
    """count_ops counts the constant 3/10 as a DIV and the negation: x*(-3/10) -> MUL, DIV, NEG."""
    expr = -sp.Rational(3, 10) * X
    assert sympy_count_ops([expr]) == 3
    assert sympy_ops([expr])["total"] == 1


def test_cse_counts_shared_subexpression_once():
    a, b, c = sp.symbols("a b c")
    counts, replacements = cse_operation_counts([a * b + c, sp.sin(a * b)])
    assert replacements == 1
    assert (counts["mul"], counts["add"], counts["trig"]) == (1, 1, 1)


def test_time_functions_must_be_replaced():
    q = sp.Function("q")(sp.Symbol("t"))
    with pytest.raises(ValueError, match="plain symbol"):
        sympy_ops([q * X])


# ----------------------------------------------------------------------------- the mechanics model
@pytest.mark.parametrize("method", mechanics.METHODS)
def test_mechanics_chain_equals_symgen_model(method):
    """Kane's and Lagrange's ``M qdd = forcing`` of the rebuilt chain equal symgen's dense model:
    ``M = M_q`` and ``forcing = -(C_q qd + G_q)`` at seeded random states (n = 3)."""
    n = 3
    M, forcing = mechanics.EQUATIONS[method](n)
    model = derive(symgen.load(f"chain:n={n}"))
    rng = np.random.default_rng(505)
    for _ in range(2):
        q, qd = rng.uniform(-3, 3, n), rng.uniform(-2, 2, n)
        data = model.evaluate(Configuration({f"j{i}": q[i] for i in range(n)}), qd=qd)
        m_val, f_val = mechanics.evaluate(M, forcing, q, qd)
        assert np.max(np.abs(m_val - data.M_q)) <= MECHANICS_TOL
        assert np.max(np.abs(f_val + data.C_q @ data.qd + data.G_q)) <= MECHANICS_TOL


# ----------------------------------------------------------------------------- the slope check
def test_inverse_dynamics_slope_constant_within_five_percent():
    """Local slopes of inverse_dynamics's total between consecutive N in 8..64 stay within 5 % of
    the least-squares slope."""
    sizes = fits.SLOPE_CHECK_SIZES
    totals = [operation_counts(derive(symgen.load(f"chain:n={n}")), ["inverse_dynamics"])["inverse_dynamics"]["total"]
              for n in sizes]
    check = fits.slope_constancy(sizes, totals)
    assert check.passed, check.describe()


def test_slope_check_fails_on_quadratic_and_on_a_kink():
    sizes = fits.SLOPE_CHECK_SIZES
    assert not fits.slope_constancy(sizes, [n * n / 2 + 80 * n for n in sizes]).passed
    kinked = [82 * n - 118 + (0 if n < 32 else 9 * (n - 32)) for n in sizes]   # slope 82 -> 91 (+11 %)
    assert not fits.slope_constancy(sizes, kinked).passed
    assert fits.slope_constancy(sizes, [82 * n - 118 for n in sizes]).max_deviation == pytest.approx(0, abs=1e-9)


def test_growth_exponent_of_power_laws():
    ns = [4, 8, 16, 32]
    assert fits.growth_exponent(ns, [3 * n**4 for n in ns]) == pytest.approx(4)
    assert fits.growth_exponent(ns, [70 * n for n in ns]) == pytest.approx(1)


# ----------------------------------------------------------------------------- the sweep (no subprocesses)
def test_sweep_skips_a_stage_after_it_exceeded(monkeypatch):
    """cse times out at N = 2: at N = 3 derive and raw still run, cse is not attempted and is
    shown as over the limit, like the timeout itself."""
    calls = []

    def fake_measure(task, stages, time_limit):
        calls.append((task["n"], tuple(stages)))
        out = Outcome(task)
        for st in stages:
            rec = {"stage": st, "seconds": 0.1, "rss_kib": 1, "ops": {"total": 1}}
            out.stages[st] = (TIMEOUT, {}) if (st == "cse" and task["n"] >= 2) else (OK, rec)
        out.baseline_kib = 0
        return out

    monkeypatch.setattr(sweep_mod, "measure", fake_measure)
    sw = sweep_mod.run_sweep("chain", [1, 2, 3], ["kane"], 5.0)
    assert calls == [(1, ("derive", "raw", "cse")), (2, ("derive", "raw", "cse")), (3, ("derive", "raw"))]
    assert sw.status("kane", 3, "cse") == sweep_mod.SKIPPED
    assert [sw.display("kane", n, "cse") for n in (1, 2, 3)] == ["ok", "limit", "limit"]
    assert sw.display("kane", 3, "raw") == "ok"


def test_measure_reports_a_crash_with_its_message():
    out = measure({"method": "symgen", "spec": "chain:n=0", "function": "inverse_dynamics"}, ["derive", "ops"], 60)
    assert out.status("derive") == ERROR and "chain:n=0" in out.error


# ----------------------------------------------------------------------------- the command
@pytest.mark.slow   # ~15 s: 12 measuring subprocesses
def test_command_small_chain_tables_match_symgen_ops(tmp_path, monkeypatch, capsys):
    """N = 1, 2, 4: every table row is there, and this formulation's counts are those of
    ``symgen ops chain:n=N --json``."""
    out = tmp_path / "cx"
    assert run_cli(monkeypatch, ["complexity", "--family", "chain", "--sizes", "1,2,4,8", "--max-dof", "4",
                                 "--time-limit", "60", "--methods", "symgen,kane", "--out", str(out)]) == 0
    capsys.readouterr()
    for name in ("chain.md", "chain.csv", "chain_ops.png", "chain_time.png"):
        assert (out / name).stat().st_size > 0, name
    rows = read_csv(out / "chain.csv")
    measured = {(r["method"], int(r["size"]), r["stage"]): r for r in rows}
    assert sorted({int(r["size"]) for r in rows}) == [1, 2, 4]       # --max-dof 4 cut N = 8
    for n in (1, 2, 4):
        assert run_cli(monkeypatch, ["ops", f"chain:n={n}", "--json"]) == 0
        want = json.loads(capsys.readouterr().out)["functions"]
        for fn in CHAIN_FUNCTIONS:
            row = measured[(f"symgen:{fn}", n, "ops")]
            assert row["status"] == "ok"
            for key in ("mul", "add", "total", "solve_flops"):
                assert int(row[key]) == want[fn][key], (n, fn, key)
        for stage in ("derive", "raw", "cse"):
            assert measured[("kane", n, stage)]["status"] == "ok"
        assert float(measured[("published:LWP", n, "formula")]["total"]) == 281 * n - 96
    md = (out / "chain.md").read_text()
    header = "| N | inverse_dynamics | mass_matrix | forward_dynamics | FD: LU flops | Kane raw | Kane cse |"
    assert header in md
    id4 = measured[("symgen:inverse_dynamics", 4, "ops")]["total"]
    assert f"| 4 | {id4} |" in md
    assert "Lagrange-Euler [H80]" in md and "(unverified)" in md


def test_command_tiny_limit_shows_limit_and_skips(tmp_path, monkeypatch, capsys):
    out = tmp_path / "cx"
    assert run_cli(monkeypatch, ["complexity", "--max-dof", "2", "--time-limit", "0.01", "--methods", "symgen,kane",
                                 "--out", str(out), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert {r["status"] for r in report["results"]} == {"limit"}
    md = (out / "chain.md").read_text()
    assert "| 2 | > 0.01 s | > 0.01 s | > 0.01 s | > 0.01 s | > 0.01 s | > 0.01 s |" in md
    assert {r["status"] for r in read_csv(out / "chain.csv") if not r["method"].startswith("published")} == {"limit"}


def test_command_multi_arm_per_arm_cost(tmp_path, monkeypatch, capsys):
    """multi_arm:h=1,2: the per-arm difference of inverse_dynamics equals symgen's own counts."""
    out = tmp_path / "cx"
    assert run_cli(monkeypatch, ["complexity", "--family", "multi_arm", "--sizes", "1,2", "--time-limit", "60",
                                 "--out", str(out)]) == 0
    totals = [operation_counts(derive(symgen.load(f"multi_arm:h={h}")), ["inverse_dynamics"])["inverse_dynamics"]
              ["total"] for h in (1, 2)]
    md = (out / "multi_arm.md").read_text()
    assert f"| {totals[0]} |  |" in md and f"| {totals[1]} | {totals[1] - totals[0]} |" in md
    assert (out / "multi_arm_ops.png").stat().st_size > 0


@pytest.mark.parametrize("argv, message", [
    (["--sizes", "0"], "not a positive integer"),
    (["--methods", "symgen,newton"], "unknown method"),
    (["--family", "multi_arm", "--methods", "kane"], "only measured on the chain"),
    (["--time-limit", "0"], "must be positive"),
])
def test_command_rejects_bad_input(tmp_path, monkeypatch, capsys, argv, message):
    assert run_cli(monkeypatch, ["complexity", *argv, "--out", str(tmp_path / "x")]) == 2
    assert message in capsys.readouterr().err
