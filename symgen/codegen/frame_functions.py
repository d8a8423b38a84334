"""The generated functions of frame kinematics, centre of mass and centroidal momentum
(:mod:`symgen.frame_kinematics`: conventions), each traced by running the model layer's
field-generic functions on traced nodes:

=========================  ==================================================================
``frame_pose``             ``q -> (R, p)``: the named frame's axes and origin in the world
``frame_jacobian``         ``q -> J`` (6 x n): ``[v; w] = J qd``, in ``axes``
``frame_drift``            ``(q, qd) -> a``: ``J̇ qd``, the classical acceleration at ``qdd = 0``
``center_of_mass``         ``q -> c``, world axes
``com_jacobian``           ``q -> J_c`` (3 x n): ``dc/dt = J_c qd``
``centroidal_momentum``    ``(q, qd) -> h``: ``[linear; angular about c]``, world axes
=========================  ==================================================================

``qd`` are the independent rates of eq. (14), as ``inverse_dynamics`` takes them; the frame
functions take the options ``frame`` (required) and ``axes`` (``local`` or ``world_aligned``).
Each function carries its dense reference, the :class:`~symgen.model.Model` method of the same
name in the reference's field (the C test program's 50 digits included).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import partial

import numpy as np

from .. import frame_kinematics as fk
from ..errors import CodegenError
from .builder import Builder, Function
from .derivatives import differentiate
from .dynamics_derivatives import check_supported
from .node_product import node_matmul
from .field_configuration import field_configuration
from .tangent import coordinate_columns, q_directions


@dataclass
class FrameFunction(Function):
    """A traced function with its options (``metadata``, in ``ops.json``) and its reference:
    ``reference(state, field=...)`` gives the outputs from the Model's methods."""

    metadata: dict = field(default_factory=dict)
    reference_inputs: object = None
    reference: object = None


def _frame(model, frame, axes) -> dict:
    if frame is None:
        known = ", ".join(sorted(model.tree.frames)) or "none"
        raise CodegenError(f"the frame functions need a frame: option frame (symgen generate --frame NAME); "
                           f"the scene's frames: {known}")
    fk.check_frame(model.tree, frame, CodegenError)
    fk.check_axes(axes, CodegenError)
    return {"frame": frame, "axes": axes}


def _reference(model, method, with_qd, state, field="float", **options):
    """The outputs of generated function ``method`` at ``state`` from the Model's method of the
    same name, in ``field``."""
    fld = model.field_of(field)
    args = (field_configuration(model, state["q"], fld),) + ((state["qd"],) if with_qd else ())
    args += (options["frame"],) if "frame" in options else ()
    kwargs = {"axes": options["axes"]} if "axes" in options else {}
    if method in ("frame_pose", "center_of_mass"):
        out = getattr(model, method)(*args, field=fld, **kwargs)
    else:
        out = getattr(model, method)(*args, field=fld, check_closure=False, **kwargs)
    return {"R": out[0], "p": out[1]} if method == "frame_pose" else {_OUTPUT[method]: out}


_OUTPUT = {"frame_jacobian": "J", "frame_drift": "a", "center_of_mass": "c", "com_jacobian": "J_c",
           "centroidal_momentum": "h"}


def _finish(model, b: Builder, name: str, doc: str, outputs, options: dict, with_qd: bool) -> FrameFunction:
    fn = b.finish(name, doc, outputs)
    return FrameFunction(**vars(fn), metadata=dict(options),
                         reference=partial(_reference, model, name, with_qd, **options))


def _frame_pose(model, frame=None) -> Function:
    options = _frame(model, frame, "local")
    b = Builder(model)
    r, p = b.t.kinematics().frame_pose(frame)
    return _finish(model, b, "frame_pose", f"Pose of frame {frame!r}: its axes R_W_F and origin p_W_F in the world.",
                   [("R", r.v, "rotation R_W_F (3 x 3)"), ("p", p.v, "origin p_W_F (3)")],
                   {"frame": options["frame"]}, False)


def _frame_jacobian(model, frame=None, axes="local") -> Function:
    options = _frame(model, frame, axes)
    b = Builder(model)
    rows = fk.frame_jacobian_all(b.t.kinematics(), frame, axes)
    jac = node_matmul(rows, b.t.p_full())
    return _finish(model, b, "frame_jacobian", f"Jacobian of frame {frame!r} in {axes} axes: [v; w] = J qd, "
                   "v the velocity of its origin, qd the independent rates (eq. 14).",
                   [("J", jac, "frame Jacobian (6 x n)")], options, False)


def _frame_drift(model, frame=None, axes="local") -> Function:
    options = _frame(model, frame, axes)
    b = Builder(model)
    qd = b.arg("qd", b.n, "independent joint rates (eq. 14)")
    qd_all = b.t.complete_rates(qd)
    bias, _ = b.t.rate_bias(qd_all)
    out = fk.frame_drift(b.t.kinematics(qd_all), frame, qd_all, bias, axes)
    return _finish(model, b, "frame_drift", f"J-dot qd of frame {frame!r} in {axes} axes: the classical "
                   "acceleration [a; dw] of its origin at qdd = 0 (eq. 11 differentiated inside).",
                   [("a", list(out), "classical acceleration at qdd = 0 (6)")], options, True)


def _center_of_mass(model) -> Function:
    fk.total_mass(model.tree)
    b = Builder(model)
    c = fk.center_of_mass(b.t.field, b.t.kinematics())
    return _finish(model, b, "center_of_mass", "Centre of mass in world axes.",
                   [("c", list(c), "centre of mass (3)")], {}, False)


def _com_jacobian(model) -> Function:
    fk.total_mass(model.tree)
    b = Builder(model)
    rows = fk.com_jacobian_all(b.t.field, b.t.kinematics())
    return _finish(model, b, "com_jacobian", "Jacobian of the centre of mass in world axes: dc/dt = J_c qd.",
                   [("J_c", node_matmul(rows, b.t.p_full()), "centre-of-mass Jacobian (3 x n)")], {}, False)


def _centroidal_momentum(model) -> Function:
    fk.total_mass(model.tree)
    b = Builder(model)
    qd = b.arg("qd", b.n, "independent joint rates (eq. 14)")
    qd_all = b.t.complete_rates(qd)
    h = fk.centroidal_momentum(b.t.field, b.t.kinematics(), b.t.transforms, qd_all)
    return _finish(model, b, "centroidal_momentum", "Centroidal momentum in world axes: linear, then angular "
                   "about the centre of mass.", [("h", list(h), "momentum [linear; angular] (6)")], {}, True)


def _centroidal_momentum_derivatives(model) -> Function:
    """``(dh_dq, A_G)``: ``centroidal_momentum`` traced, then differentiated in its own graph
    (:func:`~symgen.codegen.derivatives.differentiate`); ``dh_dq`` along the independent
    coordinates through ``P`` of eq. (10), as ``inverse_dynamics_derivatives``
    (:mod:`symgen.codegen.dynamics_derivatives`; a spherical joint's three columns its rotation
    turned in the child frame, :mod:`symgen.codegen.tangent`), and ``A_G = dh/dqd``, the
    centroidal momentum matrix (``h`` is linear in ``qd``)."""
    check_supported(model, "centroidal_momentum_derivatives")
    fk.total_mass(model.tree)
    b = Builder(model)
    qd = b.arg("qd", b.n, "independent joint rates (eq. 14)")
    h = fk.centroidal_momentum(b.t.field, b.t.kinematics(), b.t.transforms, b.t.complete_rates(qd))
    columns, seeds, nq = q_directions(b)
    jac = differentiate(b.g, list(h), columns + list(qd), seeds=seeds)
    d_q_all = jac[:, coordinate_columns(model)]
    p = b.t.p_full()
    dh_dq = node_matmul(d_q_all, p)
    if dh_dq is None:
        dh_dq = d_q_all @ p
    fn = b.finish("centroidal_momentum_derivatives", "Jacobians of the centroidal momentum h: dh/dq along the "
                  "independent coordinates (through P of eq. (10) on a closed chain; a spherical joint turned in "
                  "its child frame, R exp(hat(delta))) and A_G = dh/dqd, the centroidal momentum matrix.",
                  [("dh_dq", dh_dq, "d h / dq along the independent coordinates (6 x n)"),
                   ("A_G", jac[:, nq:], "d h / dqd, the centroidal momentum matrix (6 x n)")])
    return FrameFunction(**vars(fn), reference=partial(_momentum_derivatives_reference, model))


def _momentum_derivatives_reference(model, state, field="float"):
    """``A_G`` column by column from the Model's ``centroidal_momentum`` (linear in ``qd``, so
    exact), and ``dh_dq`` by central differences of it at 50 digits (step ``1e-20``), the loops
    re-closed at that precision for every step on a closed chain."""
    from ..closure import refine_closure
    from ..dynamics_jacobians import moved_position
    from ..math.configuration import Configuration
    from ..math.fields import MpField
    from .reference_derivatives import field_positions

    fld = model.field_of(field)
    mp = fld if isinstance(fld, MpField) else MpField(model.tree.parameters)
    base = refine_closure(model, field_positions(model, state["q"], mp), mp)
    qd = [mp.const(v) for v in state["qd"]]
    n = model.counts.n
    eye = [[mp.one if i == k else mp.zero for i in range(n)] for k in range(n)]
    a_g = np.array([model.centroidal_momentum(Configuration(base), e, field=mp, check_closure=False)
                    for e in eye], dtype=object).T
    step = mp.const(10) ** -20
    cols = []
    for coord in model.partition.independent:
        c = model.tree.coordinates[coord]
        direction = (c.joint, None if c.kind.is_one_dof else c.component)
        ends = [refine_closure(model, moved_position(base, direction, s * step, mp), mp) for s in (1, -1)]
        hp, hm = (model.centroidal_momentum(Configuration(e), qd, field=mp, check_closure=False) for e in ends)
        cols.append((hp - hm) / (2 * step))
    out = {"dh_dq": np.array(cols, dtype=object).T, "A_G": a_g}
    if fld is mp:
        return out
    return {k: mp.to_float(v) for k, v in out.items()}
