"""Spatial algebra of the tree recursions, on any scalar: floats, ``Fraction``, mpmath numbers,
SymPy expressions or the code generator's traced nodes.

Vectors are tuples and matrices nested lists, so that a zero of the scene (an axis along z, a
diagonal inertia) is the number ``0`` and folds away entry by entry when the scalars are traced.
Conventions of DESIGN.md: twists ``X = [v; w]``, wrenches ``F = [f; m]``, both in a body's axes at
its frame's origin. Across tree joint ``k`` with ``(R, p) = (R_PC, p_PC)`` a motion vector of the
parent maps to the child as ``w_c = R^T w_p``, ``v_c = R^T (v_p - p x w_p)`` (``^P U_C^T``, the
rows of ``T_S*`` in Section 3.2), and a wrench of the child to the parent as ``f_p = R f_c``,
``m_p = R m_c + p x (R f_c)`` (``^P U_C``, eq. 30).
"""
from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any, Protocol, TypeAlias

from ..math.scalar import Scalar
from ..tree import TreeJoint

#: a 3- or 6-vector
Vector: TypeAlias = tuple[Any, ...]
#: a 3x3 or 6x6 matrix as rows
Matrix: TypeAlias = Sequence[Sequence[Any]]
Rows: TypeAlias = list[list[Any]]
IsZero: TypeAlias = Callable[[Any], bool]
#: ``(R_PC, p_PC)`` of a tree joint
Transform: TypeAlias = tuple[Matrix, Sequence[Any]]


class Labeller(Protocol):
    """What the recursions ask of the code generator's graph: a readable name for a value."""

    def label(self, value: Any, name: str) -> None: ...

ZERO3 = (0, 0, 0)


class FactoredRotation(list[list[Any]]):
    """A rotation ``A B``: its rows (for whatever reads entries) and its two factors, which
    :func:`rotate` and :func:`rotate_t` apply in turn. For a joint placed by a turn about x or y
    through a general angle (a twist) and turning about z, two turns of a plane cost 4
    multiplications and 2 additions each per vector, the product's rows 8 and 5 (and 4 products
    to form them)."""

    def __init__(self, a: Matrix, b: Matrix) -> None:
        super().__init__(matmul3(a, b))
        self.factors = (a, b)


def rotate(r: Matrix, v: Sequence[Any]) -> Vector:
    """``R v``."""
    if isinstance(r, FactoredRotation):
        a, b = r.factors
        return rotate(a, rotate(b, v))
    return tuple(r[i][0] * v[0] + r[i][1] * v[1] + r[i][2] * v[2] for i in range(3))


def rotate_t(r: Matrix, v: Sequence[Any]) -> Vector:
    """``R^T v``."""
    if isinstance(r, FactoredRotation):
        a, b = r.factors
        return rotate_t(b, rotate_t(a, v))
    return tuple(r[0][i] * v[0] + r[1][i] * v[1] + r[2][i] * v[2] for i in range(3))


def matmul3(a: Matrix, b: Matrix) -> Rows:
    """``A B`` of two 3x3 nested lists."""
    return [[a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j] for j in range(3)] for i in range(3)]


def cross(a: Sequence[Any], b: Sequence[Any]) -> Vector:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(row: Sequence[Any], vec: Sequence[Any]) -> Scalar:
    """``sum(row[i] * vec[i])`` folded left to right (zero terms vanish when traced)."""
    total: Any = 0
    for a, b in zip(row, vec):
        total = total + a * b
    return total


def add(a: Sequence[Any], b: Sequence[Any]) -> Vector:
    return tuple(x + y for x, y in zip(a, b))


def sub(a: Sequence[Any], b: Sequence[Any]) -> Vector:
    return tuple(x - y for x, y in zip(a, b))


def scale(k: Scalar, v: Sequence[Any]) -> Vector:
    return tuple(k * x for x in v)


def offset_acceleration(w: Sequence[Any], dw: Sequence[Any], p: Sequence[Any]) -> Vector:
    """``dw x p + w x (w x p) = K p`` with ``K = hat(dw) + w w^T - |w|^2 1`` (entries shared by CSE)."""
    out: list[Any] = []
    for i in range(3):
        j, k = (i + 1) % 3, (i + 2) % 3
        diag = -(w[j] * w[j] + w[k] * w[k])
        # K[i][j] = w_i w_j - dw_k ;  K[i][k] = w_i w_k + dw_j
        out.append(diag * p[i] + (w[i] * w[j] - dw[k]) * p[j] + (w[i] * w[k] + dw[j]) * p[k])
    return tuple(out)


def euler_moment(inertia: Matrix, w: Sequence[Any], dw: Sequence[Any], is_zero: IsZero) -> Vector:
    """``I dw + w x (I w)`` of a symmetric ``I`` (the moment rows of eq. 21 about the body origin),
    expanded per component (``i, j, k`` cyclic)::

        I_ii dw_i + (I_kk - I_jj) w_j w_k + I_ij (dw_j - w_k w_i) + I_ik (dw_k + w_i w_j)
                  + I_jk (w_j^2 - w_k^2)

    The products of ``w`` and the sums with ``dw`` are the entries of ``K`` that
    :func:`offset_acceleration` forms (written the same way, so a traced graph shares them): once
    they are formed, a full inertia costs 15 multiplications and 15 additions (the differences of
    squares included), against 24 and 18 for ``I dw``, ``I w`` and the cross product apart. A structural zero of ``I`` (``is_zero``) drops its term."""
    out: list[Any] = []
    for i in range(3):
        j, k = (i + 1) % 3, (i + 2) % 3
        total: Any = 0
        if not is_zero(inertia[i][i]):
            total = total + inertia[i][i] * dw[i]
        spread = inertia[k][k] - inertia[j][j]
        if not is_zero(spread):
            total = total + spread * (w[j] * w[k])
        if not is_zero(inertia[i][j]):                    # K[k][i] = w_k w_i - dw_j
            total = total - inertia[i][j] * (w[k] * w[i] - dw[j])
        if not is_zero(inertia[i][k]):                    # K[j][i] = w_j w_i + dw_k
            total = total + inertia[i][k] * (w[j] * w[i] + dw[k])
        if not is_zero(inertia[j][k]):
            total = total + inertia[j][k] * (w[j] * w[j] - w[k] * w[k])
        out.append(total)
    return tuple(out)


# ------------------------------------------------------------------ six-vectors
def motion_to_child(r: Matrix, p: Sequence[Any], x: Sequence[Any]) -> Vector:
    """``^P U_C^T x`` for a twist ``x = [v; w]`` of the parent, in the child's axes."""
    v, w = x[:3], x[3:]
    return rotate_t(r, sub(v, cross(p, w))) + rotate_t(r, w)


def force_to_parent(r: Matrix, p: Sequence[Any], f: Sequence[Any]) -> Vector:
    """``^P U_C f`` for a wrench ``f = [f; m]`` of the child, in the parent's axes (eq. 30)."""
    rf = rotate(r, f[:3])
    return rf + add(rotate(r, f[3:]), cross(p, rf))


def cross_motion(x: Sequence[Any], y: Sequence[Any]) -> Vector:
    """``x x y`` of two twists ``[v; w]``: ``[w x y_v + v x y_w; w x y_w]``."""
    v, w = x[:3], x[3:]
    return add(cross(w, y[:3]), cross(v, y[3:])) + cross(w, y[3:])


def cross_force(x: Sequence[Any], f: Sequence[Any]) -> Vector:
    """``x x* f`` of a twist and a wrench: ``[w x f; w x m + v x f]``."""
    v, w = x[:3], x[3:]
    return cross(w, f[:3]) + add(cross(w, f[3:]), cross(v, f[:3]))


def body_inertia(mass: Scalar, com: Sequence[Any], inertia: Matrix) -> Rows:
    """The 6x6 spatial inertia ``M_alpha`` of eq. (21) about the body frame's origin,
    ``[[m 1, -hat(m c)], [hat(m c), I_c + m (|c|^2 1 - c c^T)]]`` (nested lists; symmetric entries
    share one value) from the mass, the centre of mass ``c`` and ``I_c`` about it."""
    m, c, ic = mass, com, inertia
    mc = tuple(m * x for x in c)
    mcc = mc[0] * c[0] + mc[1] * c[1] + mc[2] * c[2]
    out: Rows = [[0] * 6 for _ in range(6)]
    for i in range(3):
        out[i][i] = m
        for j in range(i, 3):
            out[3 + i][3 + j] = out[3 + j][3 + i] = ic[i][j] - mc[i] * c[j] + (mcc if i == j else 0)
    hat = ((0, -mc[2], mc[1]), (mc[2], 0, -mc[0]), (-mc[1], mc[0], 0))
    for i in range(3):
        for j in range(3):
            out[i][3 + j] = out[3 + j][i] = -hat[i][j]
    return out


def apply_inertia(inertia: Matrix, x: Sequence[Any]) -> Vector:
    """``I x`` of a 6x6 inertia and a twist."""
    return tuple(dot(inertia[i], x) for i in range(6))


def _rotate_block(r: Matrix, block: Matrix, symmetric: bool) -> Rows:
    """``R B R^T`` of a 3x3 block (upper triangle computed when ``symmetric``)."""
    t = [[dot(r[i], (block[0][j], block[1][j], block[2][j])) for j in range(3)] for i in range(3)]
    out: Rows = [[None] * 3 for _ in range(3)]
    for i in range(3):
        for j in range(i if symmetric else 0, 3):
            out[i][j] = dot(t[i], r[j])
            if symmetric:
                out[j][i] = out[i][j]
    return out


def _hat_times(p: Sequence[Any], m: Matrix) -> Rows:
    """``hat(p) M`` for a 3x3 ``M``."""
    cols = [cross(p, (m[0][j], m[1][j], m[2][j])) for j in range(3)]
    return [[cols[j][i] for j in range(3)] for i in range(3)]


def inertia_to_parent(r: Matrix, p: Sequence[Any], ia: Matrix) -> Rows:
    """``^P U_C I ^P U_C^T``: a symmetric 6x6 of the child's axes in the parent's. With the
    rotated blocks ``A, B, C`` (``f = A v + B w``): ``A_p = A``, ``B_p = B - A hat(p)``,
    ``C_p = C + hat(p) B + (hat(p) B)^T - hat(p) A hat(p)``."""
    def blk(i0: int, j0: int) -> Rows:
        return [[ia[i0 + i][j0 + j] for j in range(3)] for i in range(3)]

    a = _rotate_block(r, blk(0, 0), True)
    b = _rotate_block(r, blk(0, 3), False)
    c = _rotate_block(r, blk(3, 3), True)
    a_hat = [[-x for x in row] for row in _hat_times(p, a)]          # A hat(p) = -(hat(p) A)^T, A sym
    a_hat = [[a_hat[j][i] for j in range(3)] for i in range(3)]
    b_p = [[b[i][j] - a_hat[i][j] for j in range(3)] for i in range(3)]
    hb = _hat_times(p, b)
    hah = _hat_times(p, a_hat)
    out: Rows = [[None] * 6 for _ in range(6)]
    for i in range(3):
        for j in range(3):
            out[i][3 + j] = out[3 + j][i] = b_p[i][j]
        for j in range(i, 3):
            out[i][j] = out[j][i] = a[i][j]
            out[3 + i][3 + j] = out[3 + j][3 + i] = c[i][j] + hb[i][j] + hb[j][i] - hah[i][j]
    return out


def subspace_columns(joint: TreeJoint) -> list[int]:
    """Entries of ``[v; w]`` that the joint's motion subspace ``Z_j`` selects, one per coordinate."""
    sub_ = joint.kind.subspace
    return [next(i for i in range(6) if sub_[i][col]) for col in range(joint.kind.dof)]


def joint_twist(joint: TreeJoint, qd_all: Sequence[Any]) -> Vector:
    """``Z_j qd_j``: the twist ``[v; w]`` a joint adds to its child, in the child's axes (the
    joint's column of ``T_S*``, Section 3.2); entries the subspace does not select are ``0``."""
    sq: list[Any] = [0] * 6
    for col, coord in zip(subspace_columns(joint), joint.coords):
        sq[col] = qd_all[coord]
    return tuple(sq)
