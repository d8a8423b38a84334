"""Gain matrices of eq. (34): normalisation and the symmetric positive definite check."""
from fractions import Fraction

import mpmath
import numpy as np
import pytest

from symgen.control.errors import ControlInputError, GainMatrixError
from symgen.control.gains import check_positive_definite, gain_matrix, ldlt_pivots


def test_scalar_gain_is_a_multiple_of_the_identity():
    np.testing.assert_array_equal(gain_matrix(2.5, 3), 2.5 * np.eye(3))


def test_vector_gain_is_diagonal():
    np.testing.assert_array_equal(gain_matrix([1, 2, 3], 3), np.diag([1.0, 2.0, 3.0]))


def test_fraction_gains_stay_exact():
    k = gain_matrix(Fraction(1, 3), 2)
    assert k[0, 0] == Fraction(1, 3) and k[0, 1] == 0 and isinstance(k[0, 1], Fraction)


def test_wrong_gain_shape_is_a_typed_error():
    with pytest.raises(ControlInputError, match="K_A"):
        gain_matrix(np.ones((2, 3)), 2, "K_A")


def test_float_spd_gain_passes():
    a = np.array([[2.0, 1.0], [1.0, 2.0]])
    assert check_positive_definite(a, "K_A") is not None


def test_indefinite_float_gain_names_itself_and_its_smallest_eigenvalue():
    """[[1, 2], [2, 1]] has eigenvalues 3 and -1."""
    with pytest.raises(GainMatrixError, match="K_A.*smallest eigenvalue -1") as info:
        check_positive_definite(np.array([[1.0, 2.0], [2.0, 1.0]]), "K_A")
    assert info.value.gain == "K_A" and info.value.smallest_eigenvalue == pytest.approx(-1.0)


def test_semidefinite_gain_is_rejected():
    with pytest.raises(GainMatrixError, match="smallest eigenvalue 0"):
        check_positive_definite(np.diag([1.0, 0.0]), "Lambda")


def test_asymmetric_gain_is_rejected():
    with pytest.raises(GainMatrixError, match="not symmetric"):
        check_positive_definite(np.array([[2.0, 1.0], [0.0, 2.0]]), "K_A")


def test_non_finite_gain_is_rejected():
    with pytest.raises(GainMatrixError, match="not finite"):
        check_positive_definite(np.array([[np.inf]]), "K_A")


def test_exact_ldlt_pivots_are_the_ratios_of_leading_minors():
    """[[4, 2], [2, 3]]: minors 4 and 8, pivots 4 and 8/4 = 2."""
    k = np.array([[Fraction(4), Fraction(2)], [Fraction(2), Fraction(3)]], dtype=object)
    assert ldlt_pivots(k) == [4, 2]


def test_exact_gain_that_is_barely_definite_passes():
    """[[1, 1], [1, 1 + 1e-30]] is positive definite; in floats its second pivot rounds to 0."""
    eps = Fraction(1, 10**30)
    k = np.array([[Fraction(1), Fraction(1)], [Fraction(1), 1 + eps]], dtype=object)
    assert check_positive_definite(k, "K_A") is k


def test_exact_gain_that_is_barely_indefinite_is_rejected():
    eps = Fraction(1, 10**30)
    k = np.array([[Fraction(1), Fraction(1)], [Fraction(1), 1 - eps]], dtype=object)
    with pytest.raises(GainMatrixError, match="K_A.*not positive definite"):
        check_positive_definite(k, "K_A")


def test_exact_asymmetric_gain_is_rejected():
    k = np.array([[Fraction(2), Fraction(1)], [Fraction(1, 2), Fraction(2)]], dtype=object)
    with pytest.raises(GainMatrixError, match="not symmetric"):
        check_positive_definite(k, "K_A")


def test_mpmath_gain_is_checked_by_ldlt():
    k = np.array([[mpmath.mpf(2), mpmath.mpf(1)], [mpmath.mpf(1), mpmath.mpf(2)]], dtype=object)
    assert check_positive_definite(k, "K_A") is k


def test_non_square_gain_is_a_typed_error():
    with pytest.raises(ControlInputError):
        check_positive_definite(np.ones((2, 3)), "K_A")
