"""Grouped inertial parameters (:mod:`symgen.dynamics.grouping`): the recursion's joint forces are
exactly those of the bodies as given (exact arithmetic, no tolerance), each revolute link keeps
three structural zeros, and the generated code is cheaper for it.
"""
from __future__ import annotations

import pathlib
from fractions import Fraction

import numpy as np
import pytest

import symgen
from symgen import proofs
from symgen.codegen.generate import operation_counts
from symgen.codegen.trace import force_frames_choice
from symgen.dynamics import _setup, crba, rnea
from symgen.dynamics.grouping import grouped_inertias, origin_inertias
from symgen.kinematics import constants
from symgen.math.fields import ExactField
from symgen.io.urdf.examples import ur5
from symgen.tree import WORLD_INDEX

from .urdf_util import needs_examples

SCENES = ["chain:n=6", "four_bar", "five_bar", "arm_on_plane", "multi_arm:h=2", "stewart", "general_chain:n=7"]


def _exact(model, seed):
    rng = np.random.default_rng(seed)
    cfg, _ = proofs.random_exact_state(model, rng)
    n = model.tree.n_coords
    qd = [Fraction(int(rng.integers(-9, 10)), int(rng.integers(1, 7))) for _ in range(n)]
    qdd = [Fraction(int(rng.integers(-9, 10)), int(rng.integers(1, 7))) for _ in range(n)]
    return cfg, qd, qdd


@pytest.mark.parametrize("spec", SCENES)
def test_grouped_parameters_give_exactly_the_same_joint_forces(spec):
    model = symgen.derive(symgen.load(spec))
    tree = model.tree
    fld = ExactField(tree.parameters)
    for seed in range(2):
        cfg, qd, qdd = _exact(model, seed)
        consts, transforms = _setup(tree, fld, cfg)
        qd, qdd = [fld.const(v) for v in qd], [fld.const(v) for v in qdd]
        plain = rnea.rnea(tree, consts, transforms, qd, qdd, gravity=True)
        grouped = rnea.rnea(tree, consts, transforms, qd, qdd, gravity=True,
                            inertias=grouped_inertias(tree, consts))
        assert plain == grouped


def test_the_arm_moves_mass_and_first_moment_across_offset_joints():
    """The comparison above can fail: on ``arm_on_plane`` links with a mass and a first moment along
    their axis sit at non-zero offsets from their parents, so a dropped transport term (``m p``, the
    parallel axes, the first moment's cross term) would change ``tau``."""
    model = symgen.derive(symgen.load("arm_on_plane"))
    tree = model.tree
    fld = ExactField(tree.parameters)
    consts = constants(tree, fld)
    plain, grouped = origin_inertias(tree, consts), grouped_inertias(tree, consts)
    moved = [j for k, j in enumerate(tree.joints) if j.parent != WORLD_INDEX
             and any(x != 0 for x in consts.joint_trans[k]) and plain[j.child].first_moment[2] != 0]
    assert moved, "no link with a first moment along its axis at an offset from its parent"
    for joint in tree.joints:
        if not (joint.kind.rotates and len(joint.coords) == 1):
            continue
        body = grouped[joint.child]
        assert body.mass == 0 and body.first_moment[2] == 0 and body.inertia[1][1] == 0


@pytest.mark.parametrize("spec, before", [("chain:n=6", 375), ("multi_arm:h=2", 818)])
def test_grouping_cuts_the_inverse_dynamics_count(spec, before):
    """The counts before grouping, as ``symgen ops`` printed them: fewer operations now."""
    ops = operation_counts(symgen.derive(symgen.load(spec)), ["inverse_dynamics"])["inverse_dynamics"]
    assert ops["total"] < before


@needs_examples
def test_grouping_is_kept_only_where_it_pays():
    """The UR5 holding a payload fixed 0.1 m off its wrist: grouped, its recursion costs 457
    operations against 446 about the origins (the payload's part, moved through the wrist's
    rotations, fills sparse parents), and with the origins moved along the joint axes
    (:mod:`symgen.dynamics.origins`) 469 and 449, so the generator keeps the bodies and the tree as
    given there; the bare UR5 costs 354, grouped 307, with the origins moved 377 and grouped so 299, the
    generator's choice."""
    scene = ur5()
    scene.add_body("payload", 1.5, com=[0.01, 0.02, 0.05], inertia=[0.01, 0.012, 0.008, 0.001, 0.0, 0.0005])
    scene.add_joint("payload_mount", "fixed", "wrist_3_link", "payload", xyz=[0, 0.1, 0])
    with_payload, bare = symgen.derive(scene), symgen.derive(ur5())
    assert force_frames_choice(with_payload) == (False, False) and force_frames_choice(bare) == (True, True)
    counts = {name: operation_counts(model, ["inverse_dynamics"])["inverse_dynamics"]["total"]
              for name, model in (("payload", with_payload), ("bare", bare))}
    assert counts == {"payload": 446, "bare": 299}


@pytest.mark.parametrize("spec", ["chain:n=6", "five_bar", "stewart", "data/aba/ball_pendulum.yaml",
                                  "data/aba/prismatic_friction.yaml"])
def test_composite_inertias_give_exactly_the_mass_matrix_of_unit_accelerations(spec):
    """The composite-rigid-body algorithm on the ten parameters about each origin, as given and
    grouped, against the joint forces of a unit acceleration of each coordinate at rest without
    gravity (``M_q e_k``, another algorithm: no composite is formed), in exact arithmetic: revolute,
    prismatic and spherical joints (three columns, not grouped), open and closed trees. (A scene
    whose constant rotations are not exactly orthogonal in rationals, as rounded roll-pitch-yaw
    angles give, differs between the two algorithms at the 1e-19 level there.)"""
    path = pathlib.Path(__file__).parent / spec
    model = symgen.derive(symgen.load(str(path) if path.exists() else spec))
    tree = model.tree
    fld = ExactField(tree.parameters)
    cfg, _, _ = _exact(model, 3)
    consts, transforms = _setup(tree, fld, cfg)
    n = tree.n_coords
    zero = [fld.const(0)] * n
    columns = [rnea.rnea(tree, consts, transforms, zero, [fld.const(int(i == k)) for i in range(n)], gravity=False)
               for k in range(n)]
    want = [[columns[k][i] for k in range(n)] for i in range(n)]
    for inertias in (origin_inertias(tree, consts), grouped_inertias(tree, consts)):
        got = crba.tree_mass_matrix(tree, consts, transforms, inertias)
        assert [[fld.const(x) for x in row] for row in got] == want
