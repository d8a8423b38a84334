"""Body origins on the joint axes (:mod:`symgen.dynamics.origins`): the named frames and the joint
axes stay where they are, the joint forces and the mass matrix are exactly those of the tree as the
scene gives it (exact arithmetic, no tolerance), and the generator keeps the placement only where
the recursion is cheaper for it.
"""
from __future__ import annotations

import pytest

import symgen
from symgen.codegen.generate import operation_counts
from symgen.codegen.trace import force_frames_choice, force_frames_costs
from symgen.dynamics import _setup, crba, rnea
from symgen.dynamics.algebra import rotate
from symgen.dynamics.grouping import grouped_inertias
from symgen.dynamics.origins import axial_offset, axial_origins
from symgen.math.fields import ExactField
from symgen.tree import WORLD_INDEX

from .test_grouping import _exact
from .urdf_util import needs_examples

SCENES = ["general_chain:n=7", "arm_on_plane", "multi_arm:h=2", "stewart", "five_bar"]


def _world_poses(tree, transforms):
    """Each body's origin and axes (three columns) in the world, composed joint by joint."""
    origin, axes = {WORLD_INDEX: (0, 0, 0)}, {WORLD_INDEX: ((1, 0, 0), (0, 1, 0), (0, 0, 1))}
    for joint, (r, p) in zip(tree.joints, transforms):
        cols = axes[joint.parent]

        def world(v, cols=cols):
            return tuple(sum(v[j] * cols[j][i] for j in range(3)) for i in range(3))
        origin[joint.child] = tuple(o + x for o, x in zip(origin[joint.parent], world(p)))
        axes[joint.child] = tuple(world(rotate(r, e)) for e in ((1, 0, 0), (0, 1, 0), (0, 0, 1)))
    return origin, axes


@pytest.mark.parametrize("spec", SCENES)
def test_moved_origins_give_exactly_the_same_joint_forces_and_mass_matrix(spec):
    model = symgen.derive(symgen.load(spec))
    tree, moved = model.tree, axial_origins(model.tree)
    fld = ExactField(tree.parameters)
    for seed in range(2):
        cfg, qd, qdd = _exact(model, seed)
        qd, qdd = [fld.const(v) for v in qd], [fld.const(v) for v in qdd]
        given, placed = _setup(tree, fld, cfg), _setup(moved, fld, cfg)
        for inertias in (None, grouped_inertias):
            tau = [rnea.rnea(t, c, x, qd, qdd, gravity=True, inertias=inertias and inertias(t, c))
                   for t, (c, x) in ((tree, given), (moved, placed))]
            assert tau[0] == tau[1]
            mass = [crba.tree_mass_matrix(t, c, x, inertias and inertias(t, c))
                    for t, (c, x) in ((tree, given), (moved, placed))]
            assert mass[0] == mass[1]


@pytest.mark.parametrize("spec", ["general_chain:n=7", "arm_on_plane", "multi_arm:h=2"])
def test_the_origins_slide_along_the_axes_and_the_frames_stay_put(spec):
    """In the world, at a configuration: each body's origin slid along its joint's axis by the
    axial part of the joint's given translation, its axes are the same, and every named frame is
    where it was."""
    model = symgen.derive(symgen.load(spec))
    tree, moved = model.tree, axial_origins(model.tree)
    shifts = {j.child: axial_offset(j) for j in tree.joints}
    assert moved is not tree and any(s != 0 for s in shifts.values())
    fld = ExactField(tree.parameters)
    cfg, _, _ = _exact(model, 3)
    (o_given, ax_given), (o_moved, ax_moved) = (_world_poses(t, _setup(t, fld, cfg)[1]) for t in (tree, moved))
    for b, s in shifts.items():
        assert ax_given[b] == ax_moved[b]
        assert o_moved[b] == tuple(o - s * z for o, z in zip(o_given[b], ax_given[b][2]))
    for name, frame in tree.frames.items():
        if frame.body == WORLD_INDEX:
            continue
        b, other = frame.body, moved.frames[name]
        at = [tuple(o[b][i] + sum(t[j] * ax[b][j][i] for j in range(3)) for i in range(3))
              for o, ax, t in ((o_given, ax_given, frame.translation), (o_moved, ax_moved, other.translation))]
        assert at[0] == at[1], name


def test_a_denavit_hartenberg_chain_keeps_two_entries_per_translation():
    """``general_chain:n=7``'s translations ``(a, -sin(alpha) d, cos(alpha) d)`` become
    ``(a, 0, d of the parent)``."""
    tree = symgen.derive(symgen.load("general_chain:n=7")).tree
    moved = axial_origins(tree)
    for k, (given, joint) in enumerate(zip(tree.joints, moved.joints)):
        parent_d = axial_offset(tree.joints[k - 1]) if k else 0
        assert list(joint.translation) == [given.translation[0], 0, parent_d]


def test_a_chain_without_axial_offsets_is_left_as_it_is():
    tree = symgen.derive(symgen.load("chain:n=6")).tree
    assert axial_origins(tree) is tree


def test_the_generator_moves_the_origins_where_the_recursion_is_cheaper():
    """``general_chain:n=7`` (modified Denavit-Hartenberg, three-entry translations): its
    ``inverse_dynamics`` counted 929 operations with the origins as placed (the previous release's
    ``benchmarks/codegen_speed.md``); on the axes, 870. The Stewart platform's are kept as given
    (no cheaper there)."""
    general = symgen.derive(symgen.load("general_chain:n=7"))
    assert force_frames_choice(general) == (True, True)
    ops = operation_counts(general, ["inverse_dynamics", "mass_matrix"])
    assert ops["inverse_dynamics"]["total"] == 870 < 929
    assert ops["mass_matrix"]["total"] < 1184
    assert not force_frames_choice(symgen.derive(symgen.load("stewart")))[0]



def test_the_four_placements_of_the_general_chain_and_the_panda_are_counted():
    """The joint forces' operations as given, grouped, on the axes, and grouped on the axes (the
    figures the guide quotes)."""
    general = symgen.derive(symgen.load("general_chain:n=7"))
    assert force_frames_costs(general) == {(False, False): 1038, (False, True): 929,
                                           (True, False): 979, (True, True): 870}


@needs_examples
def test_the_panda_is_cheapest_grouped_on_the_axes():
    panda = symgen.derive(symgen.load("panda"))
    assert force_frames_costs(panda) == {(False, False): 701, (False, True): 605,
                                         (True, False): 675, (True, True): 588}
    assert force_frames_choice(panda) == (True, True)
