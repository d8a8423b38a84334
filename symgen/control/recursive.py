"""The virtual-decomposition controller of Section 4 as generated code: ``control`` (eq. 34) and
``adaptation`` (eq. 38) applied by recursion over the spanning tree, never as ``T_S`` or a dense
``n x p`` regressor (``O(N)`` operations; DESIGN.md section 4).

With ``A = [J_m; J_f]`` (one factorisation, shared with the actual rates)::

    [qd, e]    = A^-1 [[V_m, V_mr - V_m]; [0, 0]]        qd_r = qd + e             (18), (36)
    qdd_r      = A^-1 ([dV_mr; 0] - dA/dt qd_r)          dA/dt along the actual motion
    qd_all     = P qd,   qd_r_all = P qd_r,   qdd_r_all = P qdd_r + dP/dt qd_r      (10)-(11)

Outward pass, per body ``c`` with parent ``p`` across joint ``j`` (``U = ^P U_C``, ``U^T`` the
motion transform into ``c``, ``Z_j`` the joint's motion subspace, ``crm`` the motion cross
product in ``[v; w]`` order), gravity folded into the base (``dX_r`` of the world = ``[-g; 0]``)::

    omega_c = R^T omega_p + Z_w qd_j                              actual angular velocity
    X_r,c   = U^T X_r,p + Z qd_r,j                                eq. (36), rows of T_S
    dX_r,c  = U^T dX_r,p - crm(Z qd_j) (U^T X_r,p) + Z qdd_r,j    d/dt (36) along the motion

per massive body ``F_c = Y_alpha P_alpha`` (eq. 35, :func:`symgen.control.regressor.required_body_force`),
inward pass ``F_p += U F_c``, ``tau_j = Z_j^T F_c + I*_j qdd_r,j + b_j qd_j + c_j sign(qd_j)``
(eqs. 22-23), then ``P^T``; the contact law adds ``D_m^T (b v_c + c sign v_c)`` (eq. 37), and
``J_f^T eta_fr + K_A e`` completes eq. (34). ``adaptation`` runs the same outward pass, plus
``X_e = T_S e`` by a velocity-only pass, and returns ``s_k = Y_k^T e`` for every uncertain
parameter (eq. 38): per body ``Y_alpha^T X_e,alpha`` (:func:`body_signal`), per joint
``[qdd_r, qd, sign qd] e_j``, per contact component ``[v_c, sign v_c] (D_m e)``.

Generation options (:class:`ControlSpec`): which parameters are uncertain (inputs ``P_hat``, in the
order of :func:`symgen.control.law.default_parameters`; the others fold as the scene's values),
the contact law of the known contact parameters, and ``K_A`` folded or an input.
"""
from __future__ import annotations

import fnmatch
from dataclasses import dataclass

from .contact import ContactLaw
from .errors import ControlInputError, UnknownParameterError
from .gains import check_positive_definite, gain_matrix
from .law import check_fully_actuated, default_parameters
from .parameters import BODY_QUANTITIES, parameter_values
from .regressor import required_body_force
from ..dynamics.algebra import add, cross, dot, rotate, rotate_t
from ..errors import CodegenError
from ..tree import WORLD_INDEX

ZERO = (0, 0, 0)
#: ``gain`` value that makes ``K_A`` an ``n x n`` input instead of a folded constant
GAIN_INPUT = "input"


# ------------------------------------------------------------------------- options
@dataclass(frozen=True)
class ControlSpec:
    """The generation-time choices of ``control`` and ``adaptation``.

    ``names``: every parameter of ``P = [P_r; P_m]`` in the order of
    :func:`~symgen.control.law.default_parameters`; ``uncertain``: the positions (in that order)
    that are inputs ``P_hat``; ``gain``: ``K_A`` as an ``n x n`` array (folded) or
    :data:`GAIN_INPUT`; ``contact``: the contact law whose known coefficients fold (``None``
    without contact forces)."""

    names: tuple[str, ...]
    uncertain: tuple[int, ...]
    gain: object
    contact: ContactLaw | None

    @property
    def uncertain_names(self) -> list[str]:
        return [self.names[k] for k in self.uncertain]

    def metadata(self) -> dict:
        """What ``ops.json`` records about the inputs (parameter order and the gain's form)."""
        return {"P_hat": self.uncertain_names,
                "K_A": "input" if isinstance(self.gain, str) else "folded at generation time"}


def _select(names, uncertain) -> tuple[int, ...]:
    """Positions of the uncertain parameters: ``None``/``"all"`` all, ``"none"`` or empty none,
    else names or shell patterns (``m_*``, ``*_link3``), a list or one comma-separated string."""
    if uncertain is None or uncertain == "all":
        return tuple(range(len(names)))
    if isinstance(uncertain, str):
        uncertain = [] if uncertain == "none" else [u.strip() for u in uncertain.split(",") if u.strip()]
    chosen = set()
    for pattern in uncertain:
        hits = [k for k, name in enumerate(names) if fnmatch.fnmatchcase(name, pattern)]
        if not hits:
            raise UnknownParameterError(pattern, "matches no parameter; known: " + ", ".join(names[:12])
                                        + (", ..." if len(names) > 12 else ""))
        chosen.update(hits)
    return tuple(sorted(chosen))


def control_spec(model, uncertain=None, gain=1.0, contact: ContactLaw | None = None) -> ControlSpec:
    """Validate the options: a fully actuated scene (eq. 15), known parameter names, a symmetric
    positive definite ``K_A`` (or :data:`GAIN_INPUT`); the contact law defaults to zero
    coefficients on the scene's contact components (typed errors of :mod:`symgen.control.errors`)."""
    check_fully_actuated(model)
    if contact is None and model.scene.contact_forces is not None:
        contact = ContactLaw.for_scene(model.scene)
    elif contact is not None and model.scene.contact_forces is None:
        raise ControlInputError(f"scene {model.scene.name!r} declares no contact forces (eta_m); "
                                "give no contact law")
    names = default_parameters(model, contact).names
    n = model.counts.n
    if isinstance(gain, str):
        if gain != GAIN_INPUT:
            raise ControlInputError(f"gain 'K_A': {gain!r} is neither a number, a matrix nor {GAIN_INPUT!r}")
        k_a = GAIN_INPUT
    else:
        k_a = gain_matrix(gain, n, "K_A")
        check_positive_definite(k_a, "K_A")
    return ControlSpec(names, _select(names, uncertain), k_a, contact)


def _known_values(tracer, spec: ControlSpec) -> dict:
    """``{name: constant node}`` of every parameter with the scene's values (exact where rational)."""
    fld = tracer.field
    out = {f"{q}_{owner}": v for owner, q, v in parameter_values(tracer.tree, fld)}
    if spec.contact is not None:
        out.update({p.name: fld.const(p.value) for p in spec.contact.parameters()})
    return out


def parameter_nodes(tracer, spec: ControlSpec, p_hat) -> dict:
    """``{name: node}``: the inputs ``p_hat`` for the uncertain parameters, constants otherwise."""
    values = _known_values(tracer, spec)
    missing = set(spec.names) - set(values)
    if missing:
        raise CodegenError(f"parameters {sorted(missing)} have no value in the tree")
    for k, node in zip(spec.uncertain, p_hat):
        values[spec.names[k]] = node
    return values


# ------------------------------------------------------------------------- recursion
def _transport(r, p, v, w):
    """``U^T [v; w]``: a twist of the parent frame in the child frame (``R = R_PC``, ``p = p_PC``)."""
    return rotate_t(r, add(v, cross(w, p))), rotate_t(r, w)


def _sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


@dataclass
class BodyMotion:
    """Per body: actual angular velocity, required twist (36) and its derivative, body axes."""

    omega: tuple
    v_r: tuple
    w_r: tuple
    dv_r: tuple
    dw_r: tuple


def required_motion(tracer, qd_all, qd_r_all, qdd_r_all, gravity) -> list:
    """The outward pass of the module docstring: a :class:`BodyMotion` per body (``None`` for
    bodies the tree does not reach). ``gravity`` is the world's gravity vector (3) or zeros."""
    tree, g = tracer.tree, tracer.g
    out = [None] * len(tree.bodies)
    base = BodyMotion(ZERO, ZERO, ZERO, tuple(-x for x in gravity), ZERO)
    for k, joint in enumerate(tree.joints):
        r, p = tracer.transforms[k]
        par = base if joint.parent == WORLD_INDEX else out[joint.parent]
        kind = joint.kind
        rates, rates_r, acc_r = ([vec[c] for c in joint.coords] for vec in (qd_all, qd_r_all, qdd_r_all))
        yv, yw = _transport(r, p, par.v_r, par.w_r)
        dv, dw = _transport(r, p, par.dv_r, par.dw_r)
        jv, jw = kind.linear(rates), kind.angular(rates)
        dv = add(_sub(dv, add(cross(jw, yv), cross(jv, yw))), kind.linear(acc_r))
        dw = add(_sub(dw, cross(jw, yw)), kind.angular(acc_r))
        motion = BodyMotion(add(rotate_t(r, par.omega), jw), add(yv, kind.linear(rates_r)),
                            add(yw, kind.angular(rates_r)), dv, dw)
        name = tree.bodies[joint.child].name
        for label, vec in (("w", motion.omega), ("vr", motion.v_r), ("wr", motion.w_r), ("dvr", motion.dv_r),
                           ("dwr", motion.dw_r)):
            for comp, v in zip("xyz", vec):
                g.label(v, f"{label}_{name}_{comp}")
        out[joint.child] = motion
    return out


def velocity_pass(tracer, rates_all) -> list:
    """``T_S``'s body rows applied to ``rates_all`` (eq. 25): ``(v, w)`` per body, body axes."""
    tree = tracer.tree
    out = [None] * len(tree.bodies)
    for k, joint in enumerate(tree.joints):
        r, p = tracer.transforms[k]
        v, w = (ZERO, ZERO) if joint.parent == WORLD_INDEX else out[joint.parent]
        v, w = _transport(r, p, v, w)
        rates = [rates_all[c] for c in joint.coords]
        out[joint.child] = (add(v, joint.kind.linear(rates)), add(w, joint.kind.angular(rates)))
    return out


def unit(w, g):
    """``w / |w|``, ``0`` at ``w = 0`` (as :func:`symgen.control.regressor.Y_3i`), branch-free:
    the denominator ``|w| + (1 - sign |w|)`` is ``|w|`` exactly when ``|w| > 0`` and 1 at 0."""
    norm = g.func("sqrt", dot(w, w))
    den = norm + (1 - g.func("sign", norm))
    return tuple(x / den for x in w)


def _body_params(values, name):
    return [values[f"{q}_{name}"] for q in BODY_QUANTITIES]


def _joint_terms(tracer, joint, values, qd_all, qdd_r_all) -> list:
    """``I* qdd_r + b qd + c sign(qd)`` (eq. 22) or ``b w + c w/|w|`` (eq. 23) per coordinate."""
    if not joint.coords:
        return []
    get = (lambda q: values[f"{q}_{joint.name}"])
    rates = [qd_all[c] for c in joint.coords]
    if joint.kind.dof == 1:
        return [get("Ir") * qdd_r_all[joint.coords[0]] + get("b") * rates[0]
                + get("c") * tracer.field.sign(rates[0])]
    u = unit(rates, tracer.g)
    return [get("b") * x + get("c") * y for x, y in zip(rates, u)]


def regressor_torque(tracer, values, qd_all, qd_r_all, qdd_r_all, motion) -> list:
    """``T_S^T Y_r P_r`` on the independent coordinates: body forces ``Y_alpha P_alpha`` (35),
    inward pass, joint terms (22)-(23), then ``P^T``."""
    tree, fld = tracer.tree, tracer.field
    nb = len(tree.bodies)
    force, moment = [ZERO] * nb, [ZERO] * nb
    for b, body in enumerate(tree.bodies):
        if not body.massless and motion[b] is not None:
            mo = motion[b]
            f = required_body_force(_body_params(values, body.name), mo.omega, mo.v_r + mo.w_r, mo.dv_r + mo.dw_r,
                                    ZERO, fld)
            force[b], moment[b] = tuple(f[:3]), tuple(f[3:])
    tau = [0] * tree.n_coords
    for k in reversed(range(len(tree.joints))):
        joint = tree.joints[k]
        c = joint.child
        terms = _joint_terms(tracer, joint, values, qd_all, qdd_r_all)
        for coord, z, t in zip(joint.coords, joint.kind.transmitted(force[c], moment[c]), terms):
            tau[coord] = z + t
            tracer.g.label(tau[coord], f"tau_{tree.coordinates[coord].label.replace('.', '_')}")
        if joint.parent != WORLD_INDEX:
            r, p = tracer.transforms[k]
            rf = rotate(r, force[c])
            force[joint.parent] = add(force[joint.parent], rf)
            moment[joint.parent] = add(moment[joint.parent], add(rotate(r, moment[c]), cross(p, rf)))
    return tracer.project(tau)


def _lsym(x, y):
    """``L(x)^T y`` (6) with ``I_o x = L(x) [Ixx, Iyy, Izz, Ixy, Ixz, Iyz]``: ``y^T I_o x`` per entry."""
    return (x[0] * y[0], x[1] * y[1], x[2] * y[2], x[0] * y[1] + x[1] * y[0], x[0] * y[2] + x[2] * y[0],
            x[1] * y[2] + x[2] * y[1])


def body_signal(mo: BodyMotion, xv, xw) -> tuple:
    """``Y_alpha^T [xv; xw]`` (10) for :func:`symgen.control.regressor.Y_alpha` without forming it
    (gravity already in ``dv_r``)::

        u = dv_r + omega x v_r,    z = dw_r + omega x w_r
        s_m = u . xv
        s_h = xv x dw_r + w_r x (omega x xv) + u x xw
        s_I = L(z)^T xw + L(w_r)^T (xw x omega)
    """
    u = add(mo.dv_r, cross(mo.omega, mo.v_r))
    z = add(mo.dw_r, cross(mo.omega, mo.w_r))
    s_h = add(add(cross(xv, mo.dw_r), cross(mo.w_r, cross(mo.omega, xv))), cross(u, xw))
    s_i = tuple(a + b for a, b in zip(_lsym(z, xw), _lsym(mo.w_r, cross(xw, mo.omega))))
    return (dot(u, xv),) + s_h + s_i
