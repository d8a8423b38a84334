"""Typed errors of identification: each names the column, the row or the numbers."""
import numpy as np
import pytest

import symgen
from symgen.cli import main
from symgen.identification.base import base_parameters
from symgen.identification.data import Samples, read_csv, simulated_samples, write_csv
from symgen.identification.errors import (DataColumnError, IdentificationError, NonFiniteSampleError,
                                          TooFewSamplesError)
from symgen.identification.estimate import identify
from symgen.identification.regressor import make_problem
from symgen.identification.states import random_states


@pytest.fixture(scope="module")
def chain():
    model = symgen.derive(symgen.load("chain:n=2"))
    problem = make_problem(model)
    base = base_parameters(problem, count=15)
    samples = simulated_samples(problem, random_states(model, 12, seed=1))
    return problem, base, samples


def _without(samples, column):
    return Samples({k: v for k, v in samples.columns.items() if k != column})


def test_missing_column_is_named(chain):
    problem, base, samples = chain
    with pytest.raises(DataColumnError, match="'qdd_j1'") as err:
        identify(problem, _without(samples, "qdd_j1"), base=base)
    assert err.value.column == "qdd_j1"


def test_non_finite_sample_names_row_and_column(chain):
    problem, base, samples = chain
    cols = {k: v.copy() for k, v in samples.columns.items()}
    cols["tau_j0"][6] = np.nan
    with pytest.raises(NonFiniteSampleError, match=r"row 7, column 'tau_j0'") as err:
        identify(problem, Samples(cols), base=base)
    assert (err.value.row, err.value.column) == (7, "tau_j0")


def test_too_few_samples_states_the_numbers(chain):
    problem, base, samples = chain
    few = Samples({k: v[:3] for k, v in samples.columns.items()})       # 3 samples x 2 rows < 12
    with pytest.raises(TooFewSamplesError, match=r"6 < 12") as err:
        identify(problem, few, base=base)
    assert (err.value.have, err.value.need) == (6, 12)


def test_unexciting_data_is_refused_with_its_rank(chain):
    problem, base, samples = chain
    same = Samples({k: np.repeat(v[:1], 20) for k, v in samples.columns.items()})   # one state, 20 times
    with pytest.raises(TooFewSamplesError, match="rank of the base regressor on these samples: 2 < 12"):
        identify(problem, same, base=base)


def test_partial_constraint_force_columns_name_the_missing_one():
    model = symgen.derive(symgen.load("arm_on_plane"))
    problem = make_problem(model, eta_f_measured=True)
    samples = simulated_samples(problem, random_states(model, 2, seed=1), eta_f=lambda k: np.ones(3))
    with pytest.raises(DataColumnError, match="'eta_f_2'"):
        identify(problem, _without(samples, "eta_f_2"), base=base_parameters(problem, count=20))


def test_too_few_random_states_for_the_base_parameters_are_refused():
    model = symgen.derive(symgen.load("chain:n=2"))
    with pytest.raises(TooFewSamplesError, match=r"20 < 26"):
        base_parameters(make_problem(model), count=10)


def test_bad_csv_cell_names_column_and_row(tmp_path, chain):
    path = tmp_path / "d.csv"
    write_csv(path, chain[2])
    lines = path.read_text().splitlines()
    cells = lines[2].split(",")
    cells[0] = "abc"
    lines[2] = ",".join(cells)
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(DataColumnError, match=r"column 'q_j0': row 2: 'abc' is not a number"):
        read_csv(path)


def test_cli_refuses_out_without_consistent_and_exits_2(tmp_path, chain, capsys):
    path = tmp_path / "d.csv"
    write_csv(path, chain[2])
    assert main(["identify", "chain:n=2", str(path), "--out", str(tmp_path / "s.yaml")]) == 2
    assert "--out needs --consistent" in capsys.readouterr().err
    assert issubclass(TooFewSamplesError, IdentificationError)


def test_cli_missing_column_exits_2_naming_it(tmp_path, chain, capsys):
    path = tmp_path / "d.csv"
    write_csv(path, _without(chain[2], "tau_j1"))
    assert main(["identify", "chain:n=2", str(path), "--states", "10"]) == 2
    assert "column 'tau_j1'" in capsys.readouterr().err


def test_spherical_joints_are_refused_by_name():
    model = symgen.derive(symgen.load("stewart"))
    with pytest.raises(IdentificationError, match="joint 's1': identification supports revolute and prismatic"):
        make_problem(model)
