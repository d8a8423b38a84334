"""A derived model is a constant description: it cannot be changed, and later edits of the scene
it came from do not reach it."""
import dataclasses

import pytest

import symgen


def test_model_attributes_cannot_be_reassigned():
    model = symgen.derive(symgen.load("four_bar"))
    with pytest.raises(dataclasses.FrozenInstanceError):
        model.counts = None


def test_editing_the_scene_after_derive_leaves_the_model_unchanged():
    scene = symgen.load("four_bar")
    model = symgen.derive(scene)
    before = model.evaluate(model.reference, V_m=[0.5]).M.copy()
    scene.bodies["crank"] = dataclasses.replace(scene.bodies["crank"], mass=scene.bodies["crank"].mass * 10)
    assert (model.evaluate(model.reference, V_m=[0.5]).M == before).all()
    assert symgen.derive(scene).evaluate(model.reference, V_m=[0.5]).M[0, 0] != before[0, 0]
