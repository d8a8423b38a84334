"""``symgen accuracy SCENE``: the printed table, the markdown and CSV files, and bad input."""
from __future__ import annotations

import csv
import json
import re

import pytest

from symgen.accuracy import AccuracyError
from symgen.accuracy.table import BACKENDS, check_request
from symgen.cli import main
from symgen.codegen.catalogue import FUNCTIONS

#: generated NumPy and C against the 50-digit reference on four_bar
GENERATED_TOL = 1e-12
ROW = re.compile(r"^(?P<function>\w+)\s+(?P<backend>numpy|c|lambdify|dense float)\s+(?P<rest>.*)$")


def table_rows(text: str) -> dict[tuple[str, str], list[str]]:
    rows = {}
    for line in text.splitlines():
        m = ROW.match(line)
        if m and m["function"] in FUNCTIONS:
            rows[m["function"], m["backend"]] = m["rest"].split()
    return rows


def test_four_bar_table_and_files(tmp_path, capsys):
    status = main(["accuracy", "four_bar", "--states", "3", "--out", str(tmp_path)])
    printed = capsys.readouterr().out
    assert status == 0
    assert "max(|ref|_inf, 0.01)" in printed and "mpmath at 50 digits" in printed
    rows = table_rows(printed)
    assert {f for f, _ in rows} == set(FUNCTIONS)
    for function in FUNCTIONS:
        for backend in ("numpy", "c"):
            max_err, median_err = (float(v) for v in rows[function, backend][:2])
            assert 0 <= median_err <= max_err < GENERATED_TOL, (function, backend)
        assert (function, "lambdify") in rows            # a number or "n/a: <reason>", never missing
    md = (tmp_path / "accuracy_four_bar.md").read_text()
    assert md.count("| `") == len(FUNCTIONS) * len(BACKENDS)
    with open(tmp_path / "accuracy_four_bar.csv", newline="") as fh:
        records = list(csv.DictReader(fh))
    assert len(records) == len(FUNCTIONS) * len(BACKENDS)
    for r in records:
        if r["backend"] in ("numpy", "c"):
            assert 0 <= float(r["max_rel_error"]) < GENERATED_TOL and float(r["seconds_per_call"]) > 0


def test_json_and_lambdify_reason(capsys):
    """--json gives the same rows; a skipped lambdify column says why instead of disappearing."""
    status = main(["accuracy", "chain:n=2", "--states", "2", "--functions", "mass_matrix,gravity", "--json",
                   "--lambdify-timeout", "0"])
    report = json.loads(capsys.readouterr().out)
    assert status == 0 and report["states"] == 2 and report["dps"] == 50
    by = {(r["function"], r["backend"]): r for r in report["rows"]}
    assert set(by) == {(f, b) for f in ("mass_matrix", "gravity") for b in BACKENDS}
    assert by["gravity", "lambdify"]["note"].startswith("n/a: disabled")
    assert by["gravity", "lambdify"]["max_error"] is None
    assert 0 <= by["mass_matrix", "c"]["max_error"] < GENERATED_TOL


@pytest.mark.parametrize("argv, needle", [
    (["--functions", "no_such_function"], "no_such_function"),
    (["--states", "0"], "--states"),
    (["--dps", "19"], "dps must be an integer >= 20"),
    (["--floor", "0"], "--floor"),
])
def test_bad_input_exits_2_with_a_message(argv, needle, capsys):
    assert main(["accuracy", "four_bar", *argv]) == 2
    err = capsys.readouterr().err
    assert err.startswith("symgen: error:") and needle in err


def test_check_request_is_typed():
    with pytest.raises(AccuracyError):
        check_request(3, 50, ["mass_matrix", "bogus"])
    assert check_request(1, 20, None) == [f for f in FUNCTIONS]


def test_lambdify_column_names_the_refused_inverse(capsys):
    """chain:n=7 needs a 7x7 symbolic inverse, which the symbolic field refuses (limit 6)."""
    assert main(["accuracy", "chain:n=7", "--states", "1", "--functions", "mass_matrix", "--seed", "3"]) == 0
    rows = table_rows(capsys.readouterr().out)
    cell = " ".join(rows["mass_matrix", "lambdify"])
    assert cell.startswith("n/a: symbolic inverse of the 7x7 [J_m; J_f] (eq. 18) refused (limit 6)")
    assert float(rows["mass_matrix", "numpy"][0]) < GENERATED_TOL
