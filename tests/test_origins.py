"""Body origins moved along the joint axes (:mod:`symgen.dynamics.origins`): the named frames and the joint
axes stay where they are, the joint forces and the mass matrix are exactly those of the tree as the
scene gives it (exact arithmetic, no tolerance), and the generator keeps the placement only where
the recursion is cheaper for it.
"""
from __future__ import annotations

import pathlib
from fractions import Fraction

import numpy as np
import pytest

import symgen
from symgen.codegen.generate import operation_counts
from symgen.codegen.trace import force_frames_choice, force_frames_costs
from symgen.dynamics import _setup, crba, rnea
from symgen.codegen.dynamics_derivatives import analytic_applies
from symgen.dynamics.aba import articulated_body
from symgen.dynamics.algebra import force_to_parent, rotate
from symgen.dynamics.rnea_derivatives import rnea_derivatives
from symgen.dynamics.grouping import grouped_inertias
from symgen.dynamics.origins import axial_offset, axial_origins
from symgen.math.fields import ExactField
from symgen.tree import WORLD_INDEX

from .test_grouping import _exact
from .urdf_util import needs_examples

SCENES = ["general_chain:n=7", "arm_on_plane", "multi_arm:h=2", "stewart", "data/aba/spherical_arm.yaml"]


def _model(spec):
    path = pathlib.Path(__file__).parent / spec
    return symgen.derive(symgen.load(str(path) if path.exists() else spec))


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


#: its wrist is placed by roll-pitch-yaw angles, whose rotation is rational only to about 1e-17:
#: compared to 1e-12 there, exactly everywhere else
ROUNDED = {"data/aba/spherical_arm.yaml"}
#: massless legs: the spanning tree's articulated inertias are singular (no articulated-body check)
MASSLESS = {"stewart"}


def _same(a, b, exact: bool) -> bool:
    if exact:
        return a == b
    a, b = (np.array([float(x) for x in np.ravel(np.array(v, dtype=object))]) for v in (a, b))
    return bool(np.max(np.abs(a - b)) <= 1e-12 * max(1.0, np.max(np.abs(a))))


@pytest.mark.parametrize("spec", SCENES)
def test_moved_origins_give_the_same_joint_forces_mass_matrix_and_accelerations(spec):
    """Exact arithmetic, the tree as given against the moved one: the joint forces and the mass
    matrix (bodies as given and grouped), the articulated-body accelerations under joint forces and
    a wrench on a named frame (placed on each tree's own frame constants), and the closed-form
    partials of the joint forces where they apply (one-coordinate joints)."""
    model = _model(spec)
    tree, moved = model.tree, axial_origins(model.tree)
    assert moved is not tree
    exact = spec not in ROUNDED
    fld = ExactField(tree.parameters)
    frame = next((name for name, f in tree.frames.items() if f.body != WORLD_INDEX), None)
    rng = np.random.default_rng(11)
    for seed in range(2):
        cfg, qd, qdd = _exact(model, seed)
        qd, qdd = [fld.const(v) for v in qd], [fld.const(v) for v in qdd]
        wrench = tuple(fld.const(Fraction(int(rng.integers(-9, 10)), int(rng.integers(1, 5)))) for _ in range(6))
        trees = [(tree, *_setup(tree, fld, cfg)), (moved, *_setup(moved, fld, cfg))]
        for inertias in (None, grouped_inertias):
            tau = [rnea.rnea(t, c, x, qd, qdd, gravity=True, inertias=inertias and inertias(t, c)) for t, c, x in trees]
            assert _same(*tau, exact)
            mass = [crba.tree_mass_matrix(t, c, x, inertias and inertias(t, c)) for t, c, x in trees]
            assert _same(*mass, exact)
        if spec not in MASSLESS:
            accelerations = []
            for t, c, x in trees:
                r_f, p_f = c.frame[frame] if frame else (None, None)
                wrenches = {t.frames[frame].body: force_to_parent(r_f.tolist(), tuple(p_f), wrench)} if frame else None
                accelerations.append(articulated_body(t, c, x, qd, tau[0], gravity=True, wrenches=wrenches))
            assert _same(*accelerations, exact)
        if analytic_applies(model):
            partials = [rnea_derivatives(t, c, x, qd, qdd, gravity=True) for t, c, x in trees]
            assert _same(partials[0].dtau_dq, partials[1].dtau_dq, exact)
            assert _same(partials[0].dtau_dqd, partials[1].dtau_dqd, exact)


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
    """``general_chain:n=7``'s translations ``(a, -sin(alpha) d, cos(alpha) d)`` (its joint
    rotations ``Rx(alpha)``) become ``(a, 0, d of the parent)``."""
    tree = symgen.derive(symgen.load("general_chain:n=7")).tree
    moved = axial_origins(tree)
    d_parent = 0
    for given, joint in zip(tree.joints, moved.joints):
        (a, y, z), (c, s) = given.translation, (given.rotation[1, 1], given.rotation[2, 1])
        assert (y, z) == (-s * (y * -s + z * c), c * (y * -s + z * c))       # d along Rx(alpha) e3
        assert list(joint.translation) == [a, 0, d_parent]
        d_parent = z * c - y * s


def test_a_chain_without_axial_offsets_is_left_as_it_is():
    tree = symgen.derive(symgen.load("chain:n=6")).tree
    assert axial_origins(tree) is tree


def test_the_generator_moves_the_origins_where_the_recursion_is_cheaper():
    """``general_chain:n=7`` (modified Denavit-Hartenberg, three-entry translations): its
    ``inverse_dynamics`` counted 929 operations and its ``mass_matrix`` 1184 with the origins as
    placed (``benchmarks/codegen_speed.md`` before this change); with them moved, 870 and 1052.
    The Stewart platform's are kept as given (no cheaper there)."""
    general = symgen.derive(symgen.load("general_chain:n=7"))
    assert force_frames_choice(general) == (True, True)
    ops = operation_counts(general, ["inverse_dynamics", "mass_matrix"])
    assert (ops["inverse_dynamics"]["total"], ops["mass_matrix"]["total"]) == (870, 1052)
    assert not force_frames_choice(symgen.derive(symgen.load("stewart")))[0]


def test_the_four_placements_of_the_general_chain_are_counted():
    """The joint forces' operations as given, grouped, with the origins moved, and grouped so (the
    figures the guide quotes)."""
    general = symgen.derive(symgen.load("general_chain:n=7"))
    assert force_frames_costs(general) == {(False, False): 1038, (False, True): 929,
                                           (True, False): 979, (True, True): 870}


@needs_examples
def test_the_panda_is_cheapest_grouped_with_its_origins_moved():
    panda = symgen.derive(symgen.load("panda"))
    assert force_frames_costs(panda) == {(False, False): 701, (False, True): 605,
                                         (True, False): 675, (True, True): 588}
    assert force_frames_choice(panda) == (True, True)
