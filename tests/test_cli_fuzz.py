"""A small seeded sample of the command-line fuzzer (``tests/fuzz_cli.py``): every mutated
command line ends in a parser refusal or a status 0/1/2 with a one-line error, within the time
bound. ``python benchmarks/fuzz_cli.py`` runs thousands (``benchmarks/fuzz_cli.md``)."""
from __future__ import annotations

import random

import pytest

from .fuzz_cli import TEMPLATES, make_files, mutate_argv, run_cli_case

#: seeds of the CI sample (the benchmark runs seeds 0 .. N-1)
SAMPLE = range(40)


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    return make_files(tmp_path_factory.mktemp("fuzz-files"))


def test_every_template_is_a_valid_command_line(files, tmp_path):
    """Before mutation each template runs with status 0: the fuzzer starts from lines that work."""
    for k, template in enumerate(TEMPLATES):
        argv = [t.replace("{S}", "chain:n=2").replace("{OUT}", f"out{k}") for t in template]
        argv = [files.get(t[1:-1], t) if t.startswith("{") else t for t in argv]
        outcome, finding = run_cli_case(argv, tmp_path)
        assert (outcome, finding) == ("status 0", None), argv


@pytest.mark.parametrize("seed", SAMPLE)
def test_a_mutated_command_line_is_refused_or_answered_cleanly(files, tmp_path, seed):
    argv = mutate_argv(random.Random(seed), files)
    outcome, finding = run_cli_case(argv, tmp_path)
    assert finding is None, (argv, outcome, finding)


def test_the_mutations_are_seeded(files):
    assert mutate_argv(random.Random(7), files) == mutate_argv(random.Random(7), files)
