"""Published operation counts of classical inverse-dynamics formulations, as polynomials in n.

Each :class:`Formula` is a pair of polynomials (multiplications, additions) in the number of
joints ``n`` of an n-joint serial arm, evaluated exactly (:class:`fractions.Fraction`). They are
the figures of the classical comparison the paper quotes (its reference: J.M. Hollerbach, *A
recursive Lagrangian formulation of manipulator dynamics and a comparative study of dynamics
formulation complexity*, IEEE Trans. SMC 10(11):730-736, 1980).

Where each number comes from, and how far it was checked:

* **Uicker/Kahn Lagrange-Euler** and **Luh-Walker-Paul recursive Newton-Euler**: *verified*.
  Both are printed, with the citation to Hollerbach (1980), in Table 1 ("Comparison of
  computational costs for inverse dynamics from various sources") of P. Corke's *Robotics
  Toolbox for MATLAB* manual (section "Manipulator rigid-body dynamics"), found with the search
  tool: multiplications ``32 1/2 n^4 + 86 5/12 n^3 + 171 1/4 n^2 + 53 1/3 n - 128``, additions
  ``25 n^4 + 66 1/3 n^3 + 129 1/2 n^2 + 42 1/3 n - 96``; recursive NE ``150 n - 48`` and
  ``131 n - 48``. That table's n = 6 column reads 66,271 / 51,548 for Lagrange-Euler and
  852 / 738 for recursive NE. The additions and the recursive NE agree with the polynomials;
  the Lagrange-Euler multiplication polynomial gives **67,143** at n = 6, not 66,271 (the source
  is inconsistent with itself there). We evaluate the polynomial, and say so in the tables.
* **Waters**, **Hollerbach's recursive Lagrangian (4x4 and 3x3 matrices)**: *unverified*. The
  coefficients were recalled from Hollerbach (1980), Table I; no searchable copy of that table
  was found, so they are flagged in every table and plot.
* **Featherstone's RNEA** (``93 n - 69`` multiplications, ``81 n - 66`` additions, *Rigid Body
  Dynamics Algorithms*, Springer 2008, Table 10.1): *unverified here*. It is the bound the
  project's benchmark specification states and the code-generation tests already use; the
  search tool did not reach the book's table.

Counting convention of these sources: multiplications include divisions, additions include
subtractions, sine/cosine are not counted -- the same as symgen's ``mul`` / ``add``.
"""
from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction as F

#: the reference of the classical comparison
HOLLERBACH_1980 = ("J.M. Hollerbach, A recursive Lagrangian formulation of manipulator dynamics and a "
                   "comparative study of dynamics formulation complexity, IEEE Trans. SMC 10(11):730-736, 1980")
CORKE_TABLE = ("P. Corke, Robotics Toolbox for MATLAB, manual, Table 1 'Comparison of computational costs "
               "for inverse dynamics from various sources' (reproducing Hollerbach 1980)")
FEATHERSTONE_2008 = "R. Featherstone, Rigid Body Dynamics Algorithms, Springer 2008, Table 10.1"


@dataclass(frozen=True)
class Formula:
    """Operation counts of one published formulation: ``mul(n)``, ``add(n)`` as polynomials.

    ``mul`` and ``add`` are coefficient tuples, highest power first (``(a, b)`` is ``a n + b``).
    """

    key: str
    name: str
    order: str
    mul: tuple
    add: tuple
    source: str
    verified: bool
    note: str = ""

    def counts(self, n: int) -> tuple[F, F]:
        """Exact ``(multiplications, additions)`` at ``n`` joints."""
        return _horner(self.mul, n), _horner(self.add, n)

    def total(self, n: int) -> F:
        m, a = self.counts(n)
        return m + a

    def label(self) -> str:
        return self.name + ("" if self.verified else " (unverified)")


def _horner(coeffs, n) -> F:
    value = F(0)
    for c in coeffs:
        value = value * n + F(c)
    return value


LAGRANGE_EULER = Formula(
    "LE", "Lagrange-Euler (Uicker/Kahn)", "O(n^4)",
    mul=(F(65, 2), F(1037, 12), F(685, 4), F(160, 3), -128),
    add=(25, F(199, 3), F(259, 2), F(127, 3), -96),
    source=f"{HOLLERBACH_1980}; verified in {CORKE_TABLE}", verified=True,
    note="polynomial gives 67,143 mul at n = 6; the source's n = 6 column prints 66,271 (its additions, 51,548, agree)")
WATERS = Formula(
    "Waters", "Lagrangian (Waters)", "O(n^2)",
    mul=(F(425, 4), F(1241, 2), -512), add=(F(247, 3), F(3085, 6), -384),
    source=f"{HOLLERBACH_1980}, Table I (recalled, not found in a searchable copy)", verified=False)
RECURSIVE_LAGRANGE_4 = Formula(
    "RL4", "recursive Lagrangian, 4x4 (Hollerbach)", "O(n)",
    mul=(830, -592), add=(675, -464),
    source=f"{HOLLERBACH_1980}, Table I (recalled, not found in a searchable copy)", verified=False)
RECURSIVE_LAGRANGE_3 = Formula(
    "RL3", "recursive Lagrangian, 3x3 (Hollerbach)", "O(n)",
    mul=(412, -277), add=(320, -201),
    source=f"{HOLLERBACH_1980}, Table I (recalled, not found in a searchable copy)", verified=False)
LUH_WALKER_PAUL = Formula(
    "LWP", "recursive Newton-Euler (Luh-Walker-Paul)", "O(n)",
    mul=(150, -48), add=(131, -48),
    source=f"{HOLLERBACH_1980}; verified in {CORKE_TABLE}", verified=True)
FEATHERSTONE_RNEA = Formula(
    "RNEA", "RNEA (Featherstone)", "O(n)",
    mul=(93, -69), add=(81, -66),
    source=f"{FEATHERSTONE_2008} (the project's benchmark bound; the table itself was not reached by search)",
    verified=False)

#: every formula, in the order of the tables (verified first)
FORMULAS = (LAGRANGE_EULER, LUH_WALKER_PAUL, WATERS, RECURSIVE_LAGRANGE_4, RECURSIVE_LAGRANGE_3,
            FEATHERSTONE_RNEA)
BY_KEY = {f.key: f for f in FORMULAS}
