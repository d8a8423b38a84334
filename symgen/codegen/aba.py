"""Forward dynamics of a tree by the articulated-body algorithm (Featherstone, *Rigid Body Dynamics
Algorithms*, ch. 7), traced on :class:`~symgen.codegen.graph.Node` scalars: ``O(N)`` operations
where the dense route forms ``M_q`` (``O(N^2)``) and factors it (``O(N^3)``).

Body-frame spatial vectors in symgen's order (DESIGN.md): twists ``X = [v; w]``, wrenches
``F = [f; m]``. Across tree joint ``k`` with ``(R, p) = (R_PC, p_PC)`` (the same transforms as
:mod:`symgen.codegen.rnea`), a motion vector of the parent maps to the child as
``w_c = R^T w_p``, ``v_c = R^T (v_p - p x w_p)``, and a wrench of the child to the parent as
``f_p = R f_c``, ``m_p = R m_c + p x (R f_c)``. The joint's motion subspace ``S`` picks entries
(``e3`` prismatic, ``e6`` revolute, ``[0; 1_3]`` spherical, none for a fixed joint).

Three passes (RBDA Table 7.1), with ``I*`` the rotor inertia of eq. (22) added to ``D``:

1. outward: ``v_i = X_i v_p + S qd_i``, ``c_i = v_i x (S qd_i)``, ``I^A_i = I_i``,
   ``p^A_i = v_i x* (I_i v_i)``;
2. inward: ``U = I^A S``, ``D = S^T U + I*``, ``u = tau - S^T p^A``,
   ``I^a = I^A - U D^-1 U^T``, ``p^a = p^A + I^a c + U D^-1 u``, added to the parent through
   ``X^T I^a X`` and ``X^T p^a``;
3. outward: ``a' = X a_p + c``, ``qdd = D^-1 (u - U^T a')``, ``a = a' + S qdd``, from
   ``a_world = [-g; 0]`` (gravity as a base acceleration).

Spatial (not classical) accelerations throughout. A 3x3 ``D`` (spherical joint) is factored as
``L diag(d) L^T`` in scalars. With ``I* = 0`` the rows and columns of ``I^a`` along ``S`` are zero
and ``U D^-1`` is the identity there; both are written in, not computed. A pivot that is the
constant zero (a subtree without mass or rotor inertia) raises :class:`SingularArticulatedInertia`:
the caller keeps the dense route.
"""
from __future__ import annotations

from ..errors import CodegenError
from ..spatial import COMPONENTS
from ..tree import WORLD_INDEX, Tree
from .graph import is_zero
from .rnea import cross, joint_friction, rotate, rotate_t


class SingularArticulatedInertia(CodegenError):
    """An articulated-body pivot ``D_i`` is identically singular (named joint)."""


def _sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def _add(a, b):
    return tuple(x + y for x, y in zip(a, b))


def motion_to_child(r, p, x):
    """``X_i x`` for a motion vector ``x = [v; w]`` of the parent, in the child's axes."""
    v, w = x[:3], x[3:]
    return rotate_t(r, _sub(v, cross(p, w))) + rotate_t(r, w)


def force_to_parent(r, p, f):
    """``X_i^T f`` for a wrench ``f = [f; m]`` of the child, in the parent's axes."""
    rf = rotate(r, f[:3])
    return rf + _add(rotate(r, f[3:]), cross(p, rf))


def cross_motion(x, y):
    """``x x y`` of two twists ``[v; w]``: ``[w x y_v + v x y_w; w x y_w]``."""
    v, w = x[:3], x[3:]
    return _add(cross(w, y[:3]), cross(v, y[3:])) + cross(w, y[3:])


def cross_force(x, f):
    """``x x* f`` of a twist and a wrench: ``[w x f; w x m + v x f]``."""
    v, w = x[:3], x[3:]
    return cross(w, f[:3]) + _add(cross(w, f[3:]), cross(v, f[:3]))


def body_inertia(consts, b):
    """The 6x6 spatial inertia of body ``b`` about its frame's origin, ``[[m 1, -hat(m c)],
    [hat(m c), I_c + m (|c|^2 1 - c c^T)]]`` (nested lists; symmetric entries share one node)."""
    m, c, ic = consts.mass[b], consts.com[b], consts.inertia[b]
    mc = tuple(m * x for x in c)
    mcc = mc[0] * c[0] + mc[1] * c[1] + mc[2] * c[2]
    out = [[0] * 6 for _ in range(6)]
    for i in range(3):
        out[i][i] = m
        for j in range(i, 3):
            out[3 + i][3 + j] = out[3 + j][3 + i] = ic[i][j] - mc[i] * c[j] + (mcc if i == j else 0)
    hat = ((0, -mc[2], mc[1]), (mc[2], 0, -mc[0]), (-mc[1], mc[0], 0))
    for i in range(3):
        for j in range(3):
            out[i][3 + j] = out[3 + j][i] = -hat[i][j]
    return out


def _apply_inertia(inertia, x):
    return tuple(_dot(inertia[i], x) for i in range(6))


def _dot(row, vec):
    total = 0
    for a, b in zip(row, vec):
        total = total + a * b
    return total


def _rotate_block(r, block, symmetric):
    """``R B R^T`` of a 3x3 block (upper triangle computed when ``symmetric``)."""
    t = [[_dot(r[i], (block[0][j], block[1][j], block[2][j])) for j in range(3)] for i in range(3)]
    out = [[None] * 3 for _ in range(3)]
    for i in range(3):
        for j in range(i if symmetric else 0, 3):
            out[i][j] = _dot(t[i], r[j])
            if symmetric:
                out[j][i] = out[i][j]
    return out


def _hat_times(p, m):
    """``hat(p) M`` for a 3x3 ``M``."""
    cols = [cross(p, (m[0][j], m[1][j], m[2][j])) for j in range(3)]
    return [[cols[j][i] for j in range(3)] for i in range(3)]


def inertia_to_parent(r, p, ia):
    """``X_i^T I X_i``: a symmetric 6x6 of the child's axes in the parent's. With the rotated
    blocks ``A, B, C`` (``f = A v + B w``): ``A_p = A``, ``B_p = B - A hat(p)``,
    ``C_p = C + hat(p) B + (hat(p) B)^T - hat(p) A hat(p)``."""
    blk = lambda i0, j0: [[ia[i0 + i][j0 + j] for j in range(3)] for i in range(3)]  # noqa: E731
    a = _rotate_block(r, blk(0, 0), True)
    b = _rotate_block(r, blk(0, 3), False)
    c = _rotate_block(r, blk(3, 3), True)
    a_hat = [[-x for x in row] for row in _hat_times(p, a)]          # A hat(p) = -(hat(p) A)^T, A sym
    a_hat = [[a_hat[j][i] for j in range(3)] for i in range(3)]
    b_p = [[b[i][j] - a_hat[i][j] for j in range(3)] for i in range(3)]
    hb = _hat_times(p, b)
    hah = _hat_times(p, a_hat)
    out = [[None] * 6 for _ in range(6)]
    for i in range(3):
        for j in range(3):
            out[i][3 + j] = out[3 + j][i] = b_p[i][j]
        for j in range(i, 3):
            out[i][j] = out[j][i] = a[i][j]
            out[3 + i][3 + j] = out[3 + j][3 + i] = c[i][j] + hb[i][j] + hb[j][i] - hah[i][j]
    return out


class _Pivot:
    """``D = L diag(d) L^T`` of a symmetric 1x1 or 3x3 pivot, written out in scalars."""

    def __init__(self, d, name):
        k = len(d)
        self.k = k
        self.low = [[0] * k for _ in range(k)]
        self.inv = [None] * k
        unscaled = [[None] * k for _ in range(k)]          # L diag(d), column by column
        for j in range(k):
            for i in range(j, k):
                unscaled[i][j] = d[i][j] - _dot(self.low[i][:j], unscaled[j][:j])
            if is_zero(unscaled[j][j]):
                raise SingularArticulatedInertia(f"joint {name!r}: its articulated inertia D is singular "
                                                 "(the subtree has no mass or rotor inertia along the joint)")
            self.inv[j] = 1 / unscaled[j][j]
            for i in range(j + 1, k):
                self.low[i][j] = unscaled[i][j] * self.inv[j]

    def solve(self, rhs):
        k = self.k
        y = list(rhs)
        for i in range(k):
            for s in range(i):
                y[i] = y[i] - self.low[i][s] * y[s]
        y = [y[i] * self.inv[i] for i in range(k)]
        for i in reversed(range(k)):
            for s in range(i + 1, k):
                y[i] = y[i] - self.low[s][i] * y[s]
        return y


def _label(graph, values, prefix):
    if graph is not None:
        for comp, v in zip(("vx", "vy", "vz", "wx", "wy", "wz"), values):
            graph.label(v, f"{prefix}_{comp}")


def articulated_body(tree: Tree, consts, transforms, qd_all, tau_all, *, gravity: bool, wrenches=None,
                     graph=None):
    """``qdd_all`` (one per tree coordinate) of ``M_q qdd + c(q, qd) + g(q) + sum J_b^T F_b = tau_all``
    by the three passes of the module docstring; ``wrenches`` maps a body to a wrench ``F_b`` in its
    axes at its origin (added to ``p^A``); ``tau_all`` already carries the joint friction."""
    zero6 = (0,) * 6
    base = tuple(-x for x in consts.gravity) + (0, 0, 0) if gravity else zero6
    nb = len(tree.bodies)
    vel, bias_acc = [None] * nb, [None] * nb
    ia = [None] * nb
    pa = [zero6] * nb
    for k, joint in enumerate(tree.joints):           # pass 1
        r, p = transforms[k]
        b = joint.child
        v = zero6 if joint.parent == WORLD_INDEX else motion_to_child(r, p, vel[joint.parent])
        sq = [0] * 6
        for col, coord in zip(subspace_columns(joint), joint.coords):
            sq[col] = qd_all[coord]
        v = _add(v, tuple(sq))
        vel[b] = v
        bias_acc[b] = cross_motion(v, tuple(sq))
        _label(graph, v, f"V_{tree.bodies[b].name}")
        body = tree.bodies[b]
        if body.massless:
            ia[b] = [[0] * 6 for _ in range(6)]
        else:
            ia[b] = body_inertia(consts, b)
            pa[b] = cross_force(v, _apply_inertia(ia[b], v))
        if wrenches and b in wrenches:
            pa[b] = _add(pa[b], wrenches[b])
    pivots, gains, drive = [None] * len(tree.joints), [None] * len(tree.joints), [None] * len(tree.joints)
    for k in reversed(range(len(tree.joints))):       # pass 2
        joint = tree.joints[k]
        b = joint.child
        cols = subspace_columns(joint)
        big, bias = ia[b], pa[b]
        rotor = consts.rotor[k]
        pivot = _Pivot([[big[i][j] + (rotor if i == j else 0) for j in cols] for i in cols], joint.name)
        u = [tau_all[coord] - bias[col] for col, coord in zip(cols, joint.coords)]
        exact = is_zero(rotor)                          # U D^-1 = 1 on the joint's rows
        w = []
        for i in range(6):
            if exact and i in cols:
                w.append([1 if cols[s] == i else 0 for s in range(len(cols))])
            else:
                w.append(pivot.solve([big[i][j] for j in cols]) if cols else [])
        pivots[k], gains[k], drive[k] = pivot, w, u
        if joint.parent == WORLD_INDEX:
            continue
        art = [[None] * 6 for _ in range(6)]
        for i in range(6):
            for j in range(i, 6):
                if exact and (i in cols or j in cols):
                    value = 0
                else:
                    value = big[i][j] - _dot(w[i], [big[j][c] for c in cols])
                art[i][j] = art[j][i] = value
        c = bias_acc[b]
        pa_b = [bias[i] + _dot(art[i], c) + _dot(w[i], u) for i in range(6)]
        if exact:                                       # p^a = tau along S
            for col, coord in zip(cols, joint.coords):
                pa_b[col] = tau_all[coord]
        r, p = transforms[k]
        par = joint.parent
        ia[par] = [[x + y for x, y in zip(rp, rc)] for rp, rc in zip(ia[par], inertia_to_parent(r, p, art))]
        pa[par] = _add(pa[par], force_to_parent(r, p, tuple(pa_b)))
    qdd_all = [0] * tree.n_coords
    acc = [None] * nb
    for k, joint in enumerate(tree.joints):           # pass 3
        r, p = transforms[k]
        b = joint.child
        ap = base if joint.parent == WORLD_INDEX else acc[joint.parent]
        a = _add(motion_to_child(r, p, ap), bias_acc[b])
        cols = subspace_columns(joint)
        if cols:
            w, u, pivot = gains[k], drive[k], pivots[k]
            if pivot.k == 1:
                qdd = [u[0] * pivot.inv[0] - _dot([w[i][0] for i in range(6)], a)]
            else:
                qdd = pivot.solve([u[s] - _dot([ia[b][i][cols[s]] for i in range(6)], a) for s in range(len(cols))])
            a = list(a)
            for col, coord, value in zip(cols, joint.coords, qdd):
                qdd_all[coord] = value
                a[col] = a[col] + value
                if graph is not None:
                    graph.label(value, f"qdd_{tree.coordinates[coord].label.replace('.', '_')}")
            a = tuple(a)
        acc[b] = a
    return qdd_all


def subspace_columns(joint) -> list[int]:
    """Entries of ``[v; w]`` that the joint's motion subspace ``S`` selects, one per coordinate."""
    sub = joint.kind.subspace
    return [next(i for i in range(6) if sub[i][col]) for col in range(joint.kind.dof)]


def applies(model) -> bool:
    """The recursion replaces the dense route for a tree (``n_c = 0``) whose every coordinate is
    independent (``P`` a permutation, eq. 10) and whose task rows are all motion rows (``n = m``)."""
    c = model.counts
    return c.nc == 0 and c.n == c.m == model.tree.n_coords == len(set(model.partition.independent))


def motion_coordinates(model):
    """With motion given on joints, the tree coordinate of each entry of ``V_m`` (``J_m`` is then a
    constant selection, eq. 17, and ``V_m``, ``dV_m`` are rates and accelerations of those
    coordinates); ``None`` for motion on frames."""
    joints = model.scene.motion.joints
    if not joints:
        return None
    by_name = {j.name: j for j in model.tree.joints}
    return [by_name[name].coords[0] for name in joints]


def contact_wrenches(tracer, eta_m) -> dict:
    """``D_m^T eta_m`` (eq. 16) as a wrench on the contact frame's body: ``S^T eta_m`` in the frame's
    axes at its origin, moved to the body's origin (``J_F^T W = J_b^T (^b U_F W)``)."""
    cf = tracer.model.scene.contact_forces
    frame = tracer.tree.frames[cf.frame]
    if frame.body == WORLD_INDEX:
        return {}
    wrench = [0] * 6
    for name, value in zip(cf.components, eta_m):
        wrench[COMPONENTS.index(name)] = value
    r_f, p_f = tracer.consts.frame[cf.frame]
    return {frame.body: force_to_parent(r_f.tolist(), tuple(p_f), tuple(wrench))}


def tree_forward(tracer, v_m, tau, eta_m, *, task_rates, gravity: bool, friction: bool):
    """``(dV_m, qd_all, qdd_all)`` of model (32) for a tree: ``qd_all`` from ``V_m`` (directly for
    motion on joints, else ``task_rates(V_m) -> (A, qd_all)``, a solve with ``A = J_m``); the joint
    forces ``tau`` (independent order) less the joint friction ``xi`` (eqs. 22-23), with the contact
    wrench of ``eta_m`` (or ``None``), drive the recursion; ``dV_m = J_m qdd + dJ_m/dt qd`` (eq. 17)."""
    t = tracer
    tree, independent = t.tree, t.part.independent
    coords = motion_coordinates(t.model)
    if coords is not None:
        task, qd_all = None, [0] * tree.n_coords
        for coord, value in zip(coords, v_m):
            qd_all[coord] = value
    else:
        task, qd_all = task_rates(v_m)
    tau_all = [0] * tree.n_coords
    for j, coord in enumerate(independent):
        tau_all[coord] = tau[j]
    if friction:
        for k, joint in enumerate(tree.joints):
            if joint.kind.position_is_rotation and not is_zero(t.consts.coulomb[k]):
                raise CodegenError(f"joint {joint.name!r}: Coulomb friction on a spherical joint "
                                   "is not supported by the code generator")
        xi = joint_friction(tree, t.consts, qd_all, t.field.sign, t.g)
        tau_all = [x - y for x, y in zip(tau_all, xi)]
    wrenches = contact_wrenches(t, eta_m) if eta_m is not None else None
    qdd_all = articulated_body(tree, t.consts, t.transforms, qd_all, tau_all, gravity=gravity,
                               wrenches=wrenches, graph=t.g)
    if task is None:
        return [qdd_all[c] for c in coords], qd_all, qdd_all
    qdd = [qdd_all[c] for c in independent]
    bias, kin = t.rate_bias(qd_all)
    rows = t.task_bias(qd_all, bias, kin)
    return [_dot(task[i], qdd) + rows[i] for i in range(t.m)], qd_all, qdd_all
