"""An SDF model (:class:`~symgen.io.sdf.parse.SdfModel`) as a symgen scene, loops included.

SDF, unlike URDF, may describe a graph: a link can be the child of two joints. The reader picks a
**spanning tree** and turns every other joint into a loop-closure constraint of eq. (6):

* Tree joints are taken breadth-first from the root, revolute, prismatic and fixed joints before
  ``ball`` joints, each in file order; a joint whose child is already in the tree closes a loop.
  So a ``ball`` joint closes its loop whenever the loop has another way round (Cassie's four).
* A closing ``ball`` joint becomes a ``ball`` constraint (3 rows: the two links share the joint's
  origin) between the frames ``<joint>_child`` on the child link and ``<joint>_parent`` on the parent
  link, both at the joint frame of the drawn pose; a closing ``fixed`` joint a ``weld`` (6 rows).
  A closing revolute or prismatic joint is refused, and so is a ``ball`` joint in the tree.
* The drawn pose (every link's ``<pose>``) is the reference configuration ``q0 = 0`` of every
  joint, so each closure holds there by construction; the poses are composed in 50-digit arithmetic
  and every placement rounded to the grid ``10**-20`` (:func:`symgen.math.spatial.pose_to_exact`).
* Each moving tree joint's child body has the **joint frame** (at the drawn pose) as its body frame
  (the paper's joint-fixed frames, Step 3); its inertia and frames are expressed there, and every
  link gets a named frame ``<link>`` at its own link frame.
* ``<dynamics>``: ``damping`` and ``friction`` become the joint friction of eq. (22), and
  ``spring_stiffness``/``spring_reference`` a joint spring (potential term of ``G``). On a joint that
  closes a loop they cannot be carried by a constraint: ``closure_dynamics="refuse"`` (default)
  raises :class:`SdfError`, ``"note"`` leaves them out with a note in ``scene.notes``.
* The root link (the one link that is no joint's child) is welded to the world at its pose, or, with
  ``floating=True``, carried by a free joint ``floating_base`` (:mod:`symgen.scene.free_joint`) whose
  ``q0`` is its pose. A joint whose parent is ``world`` fixes the model instead.

Rows of ``T`` that depend on the others on the loop-closure manifold are dropped with a note; ``V_m``
are then the joint rates left once column-pivoted QR of ``T`` (eq. 6) at ``q0`` has picked the
dependent 1-DOF joints (the base's rates always stay in ``V_m``): the ``n_p`` passive rates eq. (10)
eliminates.
"""
from __future__ import annotations

import os
from dataclasses import dataclass

import mpmath
import sympy as sp

from ...errors import SceneError
from ...math.numbers import DPS, mp, mp_matrix, to_exact
from ...math.spatial import pose_to_exact, relative_pose
from ...scene.declaration import WORLD, Scene
from ..urdf.build import scene_name
from ..urdf.overlay import choose_motion_joints
from ..urdf.rotations import SNAP, axis_argument, rotation_from_rpy
from .parse import SDF_BALL, SDF_FIXED, SDF_PRISMATIC, SDF_REVOLUTE, SdfError, SdfJoint, SdfModel, SdfPose, read_sdf

@dataclass(frozen=True)
class SdfSource:
    """Where a scene's robot came from: the SDF file and its model (kept in ``scene.sources``)."""

    source: str | None
    model: str


def sdf_source(scene: Scene) -> SdfSource | None:
    """The SDF model ``scene`` was read from, if any."""
    return next((s for s in scene.sources if isinstance(s, SdfSource)), None)


#: the scene joint kind of each moving SDF joint type
MOVING = {SDF_REVOLUTE: "revolute", SDF_PRISMATIC: "prismatic"}
FLOATING_BASE = "floating_base"
CLOSURE_KINDS = {SDF_BALL: "ball", SDF_FIXED: "weld"}


def _mp_pose(pose: SdfPose, snap: float = SNAP):
    with mpmath.workdps(DPS):
        return mp_matrix(rotation_from_rpy(pose.rpy, snap)), mpmath.matrix([mp(sp.Rational(v)) for v in pose.xyz])


def _compose(a, b):
    with mpmath.workdps(DPS):
        return a[0] * b[0], a[1] + a[0] * b[1]


def spanning_tree(model: SdfModel) -> tuple[str, list[SdfJoint], list[SdfJoint]]:
    """``(root, tree joints in breadth-first order, closing joints)`` (see the module docstring)."""
    has_parent = {j.child for j in model.joints.values()}
    to_world = [j for j in model.joints.values() if j.parent == "world"]
    roots = [WORLD] if to_world else [n for n in model.links if n not in has_parent]
    if len(roots) != 1:
        raise SdfError(f"model {model.name!r}", f"needs one root link (a link no joint has as child), found "
                                                f"{', '.join(roots) or 'none'}", model.source)
    reached, tree = {roots[0]}, []
    ordered = sorted(model.joints.values(), key=lambda j: j.type == SDF_BALL)
    frontier = [roots[0]]
    while frontier:
        nxt = []
        for link in frontier:
            for j in ordered:
                if j.parent == link and j.child not in reached and j not in tree:
                    tree.append(j)
                    reached.add(j.child)
                    nxt.append(j.child)
        frontier = nxt
    missing = [n for n in model.links if n not in reached]
    if missing:
        raise SdfError(f"link {missing[0]!r}", "is not connected to the root by any joint", model.source,
                       model.links[missing[0]].line)
    closing = [j for j in model.joints.values() if j not in tree]
    return roots[0], tree, closing


def _joint_dynamics(j: SdfJoint) -> dict:
    return dict(viscous=j.damping, coulomb=j.friction, stiffness=j.stiffness, springref=j.springref)


def add_sdf(scene: Scene, sdf, *, floating: bool = False, actuated=None, closure_dynamics: str = "refuse",
            prefix: str = "", snap: float = SNAP) -> dict:
    """Add the model of an SDF file (path, text or :class:`SdfModel`) to ``scene``.

    Args:
        floating: the root link on a free joint ``<prefix>floating_base`` instead of welded.
        actuated: the SDF joints that are actuated (names); ``None``: every moving tree joint.
        closure_dynamics: ``"refuse"`` or ``"note"``: what to do with ``<dynamics>`` on a joint that
            closes a loop (a constraint carries no spring or friction).
        prefix: put in front of every body, joint, frame and constraint name.
        snap: angles within ``snap`` rad of a multiple of pi/2 are taken as exact (as the URDF
            reader's, :mod:`symgen.io.urdf.rotations`); files that write pi/2 as ``1.5708`` need
            ``snap=1e-5`` for their planar loops to be planar.

    Returns:
        ``{"root": body, "joints": {SDF joint: scene joint}, "closures": {SDF joint: constraint},
        "floating": free joint or None}``.
    """
    model = sdf if isinstance(sdf, SdfModel) else read_sdf(sdf)
    if closure_dynamics not in ("refuse", "note"):
        raise SceneError("closure_dynamics", f"must be 'refuse' or 'note', got {closure_dynamics!r}")
    root, tree, closing = spanning_tree(model)
    actuated = set(model.joints if actuated is None else actuated)
    unknown = sorted(actuated - set(model.joints))
    if unknown:
        raise SdfError(f"joint {unknown[0]!r}", f"is named actuated but model {model.name!r} has no such joint",
                       model.source)
    model_pose = _mp_pose(model.pose, snap)
    world_of = {n: _compose(model_pose, _mp_pose(link.pose, snap)) for n, link in model.links.items()}
    body_of: dict[str, str] = {}            # link -> scene body (or world)
    frame_of: dict[str, tuple] = {}         # link -> world pose of its body's frame
    out: dict = {"root": None, "joints": {}, "closures": {}, "floating": None}
    name = lambda n: scene_name(prefix, n)  # noqa: E731
    if root == WORLD:
        body_of[WORLD], frame_of[WORLD] = WORLD, (mpmath.eye(3), mpmath.matrix(3, 1))
    else:
        body_of[root], frame_of[root] = (name(root) if floating else WORLD), world_of[root]
    for j in tree:                          # the layout: every link's body and body frame
        if j.type == SDF_BALL:
            raise SdfError(f"joint {j.name!r}", "is a ball joint in the spanning tree: symgen reads ball joints only "
                                                "where they close a loop", model.source, j.line)
        if j.type == SDF_FIXED:
            body_of[j.child], frame_of[j.child] = body_of[j.parent], frame_of[j.parent]
        else:
            body_of[j.child] = name(j.child)
            frame_of[j.child] = _compose(world_of[j.child], _mp_pose(j.pose, snap))
    masses = _masses(model, body_of, frame_of, world_of, snap)
    if root != WORLD and floating:
        out["floating"] = name(FLOATING_BASE)
        _add_body(scene, model, root, name(root), masses)
        placement = pose_to_exact(world_of[root])
        _scene_call(model, model.links[root].line, f"link {root!r}", scene.add_joint, out["floating"], "free",
                    WORLD, name(root), q0=placement["xyz"] + placement["quat"])
    out["root"] = body_of[root]
    for j in tree:
        if j.type == SDF_FIXED:
            continue
        body, joint_world = body_of[j.child], frame_of[j.child]
        _add_body(scene, model, j.child, body, masses)
        placement = pose_to_exact(relative_pose(frame_of[j.parent], joint_world))
        axis = j.axis
        if j.axis_in_model:
            with mpmath.workdps(DPS):
                r_model = model_pose[0].T * joint_world[0]
                axis = tuple(to_exact(v) for v in r_model.T * mpmath.matrix([mp(sp.Rational(a)) for a in j.axis]))
        _scene_call(model, j.line, f"joint {j.name!r}", scene.add_joint, name(j.name), MOVING[j.type],
                    body_of[j.parent], body, axis=axis_argument(axis), actuated=j.name in actuated, q0=0,
                    **_joint_dynamics(j), **placement)
        scene.joint_limits[name(j.name)] = j.limits
        out["joints"][j.name] = name(j.name)
    for link in model.links:
        if body_of[link] != WORLD and name(link) not in scene.frames:
            _scene_call(model, model.links[link].line, f"link {link!r}", scene.add_frame, name(link), body_of[link],
                        **pose_to_exact(relative_pose(frame_of[link], world_of[link])))
    for j in closing:
        out["closures"][j.name] = _add_closure(scene, model, j, body_of, frame_of, world_of, closure_dynamics, name,
                                                 snap)
    scene.notes.extend(f"SDF model {model.name!r}: {note}" for note in model.notes)
    scene.sources.append(SdfSource(model.source, model.name))
    return out


def _scene_call(model: SdfModel, line, element: str, call, *args, **kwargs):
    """A Scene declaration; its :class:`SceneError` names the SDF element and line."""
    try:
        return call(*args, **kwargs)
    except SdfError:
        raise
    except SceneError as exc:
        raise SdfError(exc.element, f"{exc.message} (from SDF {element})", model.source, line) from None


def _add_body(scene: Scene, model: SdfModel, link: str, body: str, masses: dict) -> None:
    """The body of ``link`` with the summed mass properties of the links it carries."""
    from ..urdf.inertia import MassProperties

    props = masses.get(body, MassProperties.zero())
    _scene_call(model, model.links[link].line, f"link {link!r}", scene.add_body, body, **props.scene_arguments())


def _masses(model: SdfModel, body_of: dict, frame_of: dict, world_of: dict, snap: float) -> dict:
    """Every link's inertial in its body's frame, summed per body (links merged by fixed joints)."""
    from ...math.spatial import exact_quat
    from ..urdf.inertia import MassProperties

    total: dict = {}
    for n, link in model.links.items():
        body = body_of[n]
        if body == WORLD or link.inertial is None:
            continue
        inertial_world = _compose(world_of[n], _mp_pose(link.inertial_pose, snap))
        exact = pose_to_exact(relative_pose(frame_of[n], inertial_world))
        props = link.inertial.transformed(exact_quat(*[sp.Rational(v) for v in exact["quat"]]),
                                          [sp.Rational(v) for v in exact["xyz"]])
        total[body] = total.get(body, MassProperties.zero()) + props
    return total


def _add_closure(scene: Scene, model: SdfModel, j: SdfJoint, body_of, frame_of, world_of, closure_dynamics, name,
                 snap: float):
    """The constraint closing the loop of joint ``j``: frames at the joint on both links."""
    if j.type not in CLOSURE_KINDS:
        raise SdfError(f"joint {j.name!r}", f"is a {j.type} joint closing a loop (link {j.child!r} already has a "
                                            "parent joint); symgen closes loops with ball and fixed joints only",
                       model.source, j.line)
    dyn = {k: v for k, v in _joint_dynamics(j).items() if v != 0}
    if dyn:
        what = ", ".join(f"{k}={v}" for k, v in dyn.items())
        if closure_dynamics == "refuse":
            raise SdfError(f"joint {j.name!r}", f"closes a loop as a constraint, which carries no <dynamics> "
                                                f"({what}); pass closure_dynamics='note' to leave it out",
                           model.source, j.line)
        scene.notes.append(f"SDF joint {j.name!r} closes a loop: its <dynamics> ({what}) is left out")
    joint_world = _compose(world_of[j.child], _mp_pose(j.pose, snap))
    frames = []
    for end, link in (("child", j.child), ("parent", j.parent)):
        frame = name(f"{j.name}_{end}")
        _scene_call(model, j.line, f"joint {j.name!r}", scene.add_frame, frame, body_of[link],
                    **pose_to_exact(relative_pose(frame_of[link], joint_world)))
        frames.append(frame)
    _scene_call(model, j.line, f"joint {j.name!r}", scene.add_constraint, name(j.name), CLOSURE_KINDS[j.type],
                *frames)
    return name(j.name)


def scene_from_sdf(path, *, name: str | None = None, validate: bool = True, **options) -> Scene:
    """A :class:`~symgen.scene.Scene` of one SDF model; ``options`` are those of :func:`add_sdf`.

    Constraint rows that depend on the others on the loop-closure manifold (a ``ball`` closing a
    planar loop: its translation normal to the plane) are dropped with a note
    (:func:`symgen.vanishing_rows.drop_vanishing_rows`), so ``T`` has full row rank; ``V_m`` is
    then chosen by :func:`symgen.io.urdf.overlay.choose_motion_joints` (the free base kept whole).

    Raises:
        SdfError: anything in the file that symgen cannot model, named with its line.
    """
    from ...vanishing_rows import drop_vanishing_rows

    model = path if isinstance(path, SdfModel) else read_sdf(path)
    scene = Scene(name or scene_name("", model.name),
                  description=f"SDF model {model.name!r} from {os.path.basename(model.source or 'text')}")
    out = add_sdf(scene, model, **options)
    if not out["joints"]:
        raise SdfError(f"model {model.name!r}", "has no moving joint: nothing to model", model.source)
    scene = drop_vanishing_rows(scene)
    scene.set_motion(joints=choose_motion_joints(scene, keep_free_joints=True))
    if validate:
        scene.validate()
    return scene
