"""Mass properties across frames and fixed joints (symgen.io.urdf.inertia), against hand derivations
and against Pinocchio's own Inertia algebra."""
import numpy as np
import pytest
import sympy as sp

from symgen.io.urdf.inertia import MassProperties
from symgen.scene.checks import inertia_violation

R = sp.Rational
ROT_Z_90 = sp.Matrix([[0, -1, 0], [1, 0, 0], [0, 0, 1]])


def point(mass, at) -> MassProperties:
    return MassProperties(R(mass), sp.ImmutableMatrix(at), sp.ImmutableMatrix(sp.zeros(3)))


def test_two_point_masses_have_the_dumbbell_inertia():
    # m at (+d, 0, 0) and m at (-d, 0, 0): com 0, I = diag(0, 2 m d^2, 2 m d^2)
    m, d = R(3, 2), R(1, 5)
    both = point(m, [d, 0, 0]) + point(m, [-d, 0, 0])
    assert both.mass == 2 * m and list(both.com) == [0, 0, 0]
    assert both.inertia == sp.diag(0, 2 * m * d**2, 2 * m * d**2)


def test_unequal_masses_put_the_centre_of_mass_at_the_weighted_mean():
    # 1 kg at x = 0 and 3 kg at x = 0.4: com at 0.3; I_yy = 1 * 0.3^2 + 3 * 0.1^2 = 0.12
    both = point(1, [0, 0, 0]) + point(3, [R(2, 5), 0, 0])
    assert list(both.com) == [R(3, 10), 0, 0]
    assert both.inertia == sp.diag(0, R(12, 100), R(12, 100))


def test_a_rod_turned_about_z_swaps_its_x_and_y_moments():
    # a thin rod of mass m, length L along x: I = diag(0, m L^2/12, m L^2/12) about its centre
    m, length = R(2), R(1, 2)
    rod = MassProperties(m, sp.ImmutableMatrix([R(1, 4), 0, 0]),
                         sp.ImmutableMatrix(sp.diag(0, m * length**2 / 12, m * length**2 / 12)))
    turned = rod.transformed(ROT_Z_90, [0, 0, 1])
    assert list(turned.com) == [0, R(1, 4), 1]
    assert turned.inertia == sp.diag(m * length**2 / 12, 0, m * length**2 / 12)


def test_inertia_about_a_point_is_the_parallel_axis_theorem():
    body = MassProperties(R(2), sp.ImmutableMatrix([0, 0, R(1, 2)]), sp.ImmutableMatrix(sp.diag(1, 2, 3)))
    # about the origin: + m (|d|^2 1 - d d^T) with d = (0, 0, 1/2): + 2 * diag(1/4, 1/4, 0)
    assert body.inertia_about([0, 0, 0]) == sp.diag(R(3, 2), R(5, 2), 3)


def test_merging_a_body_with_nothing_changes_nothing():
    body = MassProperties(R(2), sp.ImmutableMatrix([R(1, 3), 0, 0]), sp.ImmutableMatrix(sp.diag(1, 2, 2)))
    assert MassProperties.zero() + body == body


def test_merge_of_rotated_offset_bodies_equals_pinocchio():
    pin = pytest.importorskip("pinocchio", reason="pin is not installed (extra 'oracle')")
    rng = np.random.default_rng(3)
    total_sym, total_pin = MassProperties.zero(), pin.Inertia.Zero()
    for _ in range(3):
        a = sp.Matrix(3, 3, [R(int(v), 7) for v in rng.integers(-7, 8, 9)])
        inertia = a * a.T + sp.eye(3) / 10            # symmetric positive definite, rational
        com = [R(int(v), 10) for v in rng.integers(-5, 6, 3)]
        q = [int(v) for v in rng.integers(-4, 5, 4)]
        n2 = sum(v * v for v in q) or 1
        w, x, y, z = q
        rot = sp.Matrix([[w*w + x*x - y*y - z*z, 2*(x*y - w*z), 2*(x*z + w*y)],
                         [2*(x*y + w*z), w*w - x*x + y*y - z*z, 2*(y*z - w*x)],
                         [2*(x*z - w*y), 2*(y*z + w*x), w*w - x*x - y*y + z*z]]) / n2 if any(q) else sp.eye(3)
        trans = [R(int(v), 5) for v in rng.integers(-5, 6, 3)]
        body = MassProperties(R(int(rng.integers(1, 5))), sp.ImmutableMatrix(com), sp.ImmutableMatrix(inertia))
        total_sym = total_sym + body.transformed(rot, trans)
        placement = pin.SE3(np.array(rot, dtype=float), np.array(trans, dtype=float))
        total_pin = total_pin + placement.act(pin.Inertia(float(body.mass), np.array(com, dtype=float),
                                                          np.array(inertia, dtype=float)))
    assert float(total_sym.mass) == pytest.approx(total_pin.mass, rel=1e-14)
    assert np.allclose(np.array(total_sym.com, dtype=float).ravel(), total_pin.lever, rtol=1e-13, atol=1e-13)
    assert np.allclose(np.array(total_sym.inertia, dtype=float), total_pin.inertia, rtol=1e-13, atol=1e-13)


@pytest.mark.parametrize("diagonal, words, size", [
    ((1, 1, 3), "triangle inequality", 1 / 3),      # (3 - 1 - 1) / 3
    ((1, -1, 1), "not positive semi-definite", 1),  # -(-1) / 1
])
def test_impossible_inertias_are_measured_against_their_largest_moment(diagonal, words, size):
    what, measured, _ = inertia_violation(np.diag(diagonal))
    assert words in what and measured == pytest.approx(size, rel=1e-12)


def test_a_rigid_body_inertia_is_no_violation():
    assert inertia_violation(np.diag([1, 2, 3])) is None and inertia_violation(np.zeros((3, 3))) is None
