"""Data files for ``symgen identify``: whatever the file holds, a typed error naming the file, the
column or the row, or the right samples (a byte-order mark, text columns, blank lines)."""
from __future__ import annotations

import numpy as np
import pytest

import symgen
from symgen.identification.data import (SAMPLE_LIMIT, Samples, check_samples, read_csv, simulated_samples,
                                        write_csv)
from symgen.identification.errors import (DataColumnError, DataFileError, IdentificationError, NonFiniteSampleError,
                                          OptionError, SampleRangeError, TooFewSamplesError)
from symgen.identification.regressor import make_problem
from symgen.identification.states import random_states


@pytest.fixture(scope="module")
def chain():
    model = symgen.derive(symgen.load("chain:n=2"))
    samples = simulated_samples(make_problem(model), random_states(model, 6, seed=2))
    return model, samples


def _text(samples: Samples) -> str:
    names = list(samples.columns)
    lines = [",".join(names)] + [",".join(repr(float(samples.columns[n][k])) for n in names)
                                 for k in range(len(samples))]
    return "\n".join(lines) + "\n"


def test_a_missing_file_is_named(tmp_path):
    with pytest.raises(DataFileError, match=r"data file '.*nothing\.csv': cannot be read: No such file"):
        read_csv(tmp_path / "nothing.csv")


def test_a_folder_is_not_a_data_file(tmp_path):
    with pytest.raises(DataFileError, match="cannot be read"):
        read_csv(tmp_path)


def test_bytes_that_are_not_utf8_are_named(tmp_path, chain):
    path = tmp_path / "latin1.csv"
    path.write_bytes(_text(chain[1]).replace("q_j0", "q_j0\u00e9", 1).encode("latin-1"))
    with pytest.raises(DataFileError, match=r"is not UTF-8 text \(byte 0xe9\)"):
        read_csv(path)


def test_a_byte_order_mark_is_not_part_of_the_first_column(tmp_path, chain):
    path = tmp_path / "bom.csv"
    path.write_bytes(b"\xef\xbb\xbf" + _text(chain[1]).encode("utf-8"))
    samples = read_csv(path)
    assert list(samples.columns)[0] == "q_j0"
    np.testing.assert_array_equal(samples.columns["q_j0"], chain[1].columns["q_j0"])


def test_a_duplicated_column_is_refused_with_both_positions(tmp_path, chain):
    text = _text(chain[1]).replace("q_j1", "q_j0", 1)
    path = tmp_path / "dup.csv"
    path.write_text(text)
    with pytest.raises(DataColumnError, match=r"column 'q_j0': appears twice in the header \(fields 1 and 2\)"):
        read_csv(path)


def test_a_header_only_file_has_no_samples(tmp_path, chain):
    path = tmp_path / "header.csv"
    path.write_text(",".join(chain[1].columns) + "\n")
    with pytest.raises(TooFewSamplesError, match="data rows: 0 < 1 needed; the file holds a header only"):
        check_samples(chain[0], read_csv(path))


def test_a_cell_beyond_the_magnitude_limit_names_row_and_column(chain):
    cols = {k: v.copy() for k, v in chain[1].columns.items()}
    cols["tau_j1"][3] = 1e308
    with pytest.raises(SampleRangeError, match=r"row 4, column 'tau_j1': magnitude 1e\+308 is beyond 1e\+30"):
        check_samples(chain[0], Samples(cols))
    assert SAMPLE_LIMIT == 1e30


def test_an_infinite_cell_is_a_non_finite_sample(tmp_path, chain):
    text = _text(chain[1]).splitlines()
    cells = text[2].split(",")
    cells[-1] = "1e999"
    text[2] = ",".join(cells)
    path = tmp_path / "inf.csv"
    path.write_text("\n".join(text) + "\n")
    with pytest.raises(NonFiniteSampleError, match=r"row 2, column 'tau_j1': non-finite value inf"):
        check_samples(chain[0], read_csv(path))


def test_text_columns_and_blank_lines_are_ignored(tmp_path, chain):
    lines = _text(chain[1]).splitlines()
    lines = ["t,note," + lines[0]] + [f"{k},free text {k}," + line for k, line in enumerate(lines[1:])]
    path = tmp_path / "notes.csv"
    path.write_text("\n".join(lines[:3]) + "\n\n" + "\n".join(lines[3:]) + "\n\n")
    samples = read_csv(path)
    assert set(samples.columns) == set(chain[1].columns) and len(samples) == len(chain[1])


def test_another_robots_data_names_the_foreign_column(tmp_path):
    chain6 = symgen.derive(symgen.load("chain:n=6"))
    four_bar = symgen.derive(symgen.load("four_bar"))
    samples = simulated_samples(make_problem(chain6), random_states(chain6, 2, seed=1))
    with pytest.raises(DataColumnError, match=r"column 'q_j0': names no joint, coordinate or force of scene "
                                              r"'four_bar' \(joints j1, j2, j3, j4; qd: j1\); is this another robot"):
        check_samples(four_bar, samples)


def test_five_bar_data_on_the_four_bar_is_refused():
    five = symgen.derive(symgen.load("five_bar"))
    four = symgen.derive(symgen.load("four_bar"))
    samples = simulated_samples(make_problem(five), random_states(five, 2, seed=1))
    with pytest.raises(DataColumnError, match="scene 'four_bar'"):
        check_samples(four, samples)


def test_constraint_force_columns_on_a_scene_without_them_are_foreign(chain):
    cols = dict(chain[1].columns, eta_f_0=np.zeros(len(chain[1])))
    with pytest.raises(DataColumnError, match="column 'eta_f_0': names no joint"):
        check_samples(chain[0], Samples(cols))


@pytest.mark.parametrize("noise", [np.nan, np.inf, -0.1])
def test_simulated_noise_must_be_finite_and_not_negative(chain, noise):
    model = chain[0]
    with pytest.raises(OptionError, match=r"^noise: "):
        simulated_samples(make_problem(model), random_states(model, 1, seed=1), noise=noise)


def test_written_data_reads_back_exactly(tmp_path, chain):
    path = tmp_path / "d.csv"
    write_csv(path, chain[1])
    back = read_csv(path)
    assert all(np.array_equal(back.columns[k], v) for k, v in chain[1].columns.items())
    assert issubclass(DataFileError, IdentificationError) and issubclass(SampleRangeError, IdentificationError)


def test_a_bad_cell_in_a_later_chunk_names_its_own_row(tmp_path, chain, monkeypatch):
    from symgen.identification import data

    monkeypatch.setattr(data, "READ_CHUNK", 2)
    lines = _text(chain[1]).splitlines()
    cells = lines[5].split(",")
    cells[2] = "fast"
    lines[5] = ",".join(cells)
    path = tmp_path / "bad.csv"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(DataColumnError, match=r"column 'qd_j0': row 5: 'fast' is not a number"):
        read_csv(path)


def test_a_file_with_too_many_rows_is_refused(tmp_path, chain, monkeypatch):
    from symgen.identification import data

    monkeypatch.setattr(data, "READ_CHUNK", 2)
    monkeypatch.setattr(data, "MAX_SAMPLES", 3)
    path = tmp_path / "long.csv"
    path.write_text(_text(chain[1]))
    with pytest.raises(DataFileError, match="more than 3 data rows; decimate the log or split it"):
        read_csv(path)
