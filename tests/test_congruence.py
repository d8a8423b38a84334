"""The congruence ``B^T M_S B`` of eqs. (28)-(32) (:mod:`symgen.steps.subsystem_space`): the
block-by-block product against the dense one, in exact arithmetic, and the mirrored product of
the fields that round against the whole one in 50 digits."""
from __future__ import annotations

import numpy as np
import pytest

from symgen.codegen.reference import pinned_state
from symgen.io.builtin import get_scene
from symgen.math.fields import ExactField, FloatField, MpField, SymbolicField
from symgen.model import derive
from symgen.proofs import random_exact_state
from symgen.steps.subsystem_space import mass_congruence


def _exact_data(spec: str, seed: int = 3):
    model = derive(get_scene(spec))
    cfg, v_m = random_exact_state(model, np.random.default_rng(seed))
    return model.evaluate(cfg, V_m=v_m, field=ExactField(model.tree.parameters))


@pytest.mark.parametrize("spec", ["arm_on_plane", "chain:n=4", "four_bar"])
def test_the_block_product_is_the_dense_product_exactly(spec):
    """``mass_congruence`` skips the zero rows of the joint block (the rotors' inertias: non-zero
    on ``arm_on_plane``, zero on the chain) and each body's zero columns; in rationals it equals
    ``B^T M_S B`` taken with the whole ``n_S x n_S`` matrix, entry for entry."""
    d = _exact_data(spec)
    b = d.B.v
    assert np.array_equal(mass_congruence(d.terms, b), b.T @ d.M_S @ b)
    assert np.array_equal(d.M, b.T @ d.M_S @ b)


def test_which_fields_may_mirror_a_symmetric_product():
    """Only the fields whose arithmetic rounds mirror one triangle; the exact and symbolic fields
    compute both, so the proof of ``M = M^T`` (``symgen prove``) has something to check."""
    assert FloatField().rounds and MpField().rounds
    assert not ExactField().rounds and not SymbolicField().rounds


def test_an_asymmetric_body_block_shows_in_the_exact_mass_matrix():
    """A body block of ``M_S`` made asymmetric (a planted error) makes the exact field's ``M``
    asymmetric, as ``symgen prove`` would report."""
    d = _exact_data("chain:n=4")
    rows = d.terms.blocks[-1]
    d.M_S[rows.start, rows.stop - 1] += 1      # the last body: its rows reach two and three columns
    assert not np.array_equal(d.M, d.M.T)


@pytest.mark.parametrize("spec", ["chain:n=24", "arm_on_plane", "multi_arm:h=2"])
def test_the_mirrored_product_in_50_digits_is_the_whole_one_to_the_last_digits(spec):
    """In the 50-digit field a body's off-diagonal column blocks of ``M`` are mirrored (columns
    split in halves from 16 on: ``chain:n=24`` takes that path); ``M`` is within 1e-45 of the
    whole product, relative to its largest entry, and so symmetric to that digit."""
    model = derive(get_scene(spec))
    s = pinned_state(model)
    fld = MpField(model.tree.parameters)
    d = model.evaluate(s["config"], V_m=s["V_m"], field=fld)
    whole = mass_congruence(d.terms, d.B.v)
    mirrored = d.M
    scale = max(abs(x) for x in whole.ravel())
    assert max(abs(x - y) for x, y in zip(mirrored.ravel(), whole.ravel())) <= 1e-45 * scale
    assert max(abs(x - y) for x, y in zip(mirrored.ravel(), mirrored.T.ravel())) <= 1e-45 * scale
