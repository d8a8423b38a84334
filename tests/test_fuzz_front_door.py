"""Fuzzing the front door: mutated scene files and URDFs (``tests/fuzz_inputs.py``) either load,
derive and generate code that compiles with strict flags and imports, or are refused with a
:class:`~symgen.errors.SymgenError` -- never another exception, never a hang.

The CI share is a few hundred cases (``max_examples``); ``benchmarks/fuzz_front_door.py`` runs
tens of thousands with the same mutators, and the ``slow`` test below 1,500.
"""
import shutil

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from .fuzz_inputs import check_generated, mutate_urdf, mutate_yaml, run_case

needs_cc = pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler")
#: hypothesis settings of the CI share: no deadline per example (the time bound is
#: fuzz_inputs.CASE_BOUND, enforced by a timer), no example database
CI = dict(deadline=None, database=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])


@pytest.fixture(scope="module")
def compiled():
    return set()


def check(kind, text, folder, compiled):
    outcome, generated = run_case(kind, text)
    if generated is not None:
        check_generated(generated, folder, compiled)
    return outcome


@needs_cc
@settings(max_examples=200, **CI)
@given(rng=st.randoms(use_true_random=False))
def test_mutated_scene_files_are_accepted_whole_or_refused_typed(rng, tmp_path_factory, compiled):
    check("yaml", mutate_yaml(rng), tmp_path_factory.mktemp("fuzz_yaml"), compiled)


@needs_cc
@settings(max_examples=150, **CI)
@given(rng=st.randoms(use_true_random=False))
def test_mutated_urdfs_are_accepted_whole_or_refused_typed(rng, tmp_path_factory, compiled):
    check("urdf", mutate_urdf(rng), tmp_path_factory.mktemp("fuzz_urdf"), compiled)


@pytest.mark.extended     # a minute of the suite's budget: the two tests above run 350 mutations on every CI run
@needs_cc
@settings(max_examples=1500, **CI)
@given(kind=st.sampled_from(["yaml", "urdf"]), rng=st.randoms(use_true_random=False))
def test_many_more_mutations_are_accepted_whole_or_refused_typed(kind, rng, tmp_path_factory, compiled):
    text = mutate_yaml(rng) if kind == "yaml" else mutate_urdf(rng)
    check(kind, text, tmp_path_factory.mktemp("fuzz_many"), compiled)
