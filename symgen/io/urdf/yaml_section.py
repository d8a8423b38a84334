"""The ``urdf:`` section of a scene file: URDF robots plus the constraint overlay.

::

    name: ur5_on_plane
    urdf:
      file: robots/ur5.urdf            # relative to the scene file; or  example: ur5
      q0: {shoulder_lift_joint: -pi/3, elbow_joint: pi/2}
      contact: {frame: tool0}          # tool0 slides on a plane through its pose at q0

    name: two_ur5
    urdf:
      robots:
        - {example: ur5, prefix: a1_}
        - {example: ur5, prefix: a2_, base: {xyz: [1.2, 0, 0], rpy: [0, 0, pi]}}
      hold: {frames: [a1_tool0, a2_tool0], object: {mass: 2, inertia: [0.01, 0.01, 0.01]},
             at: {xyz: [0, 0, 0.1]}}

A robot has ``file`` or ``example``, and optionally ``prefix``, ``base`` (``xyz``, ``rpy`` or
``quat``), ``q0`` and ``lock`` (``{joint: position}``), ``snap``, ``friction``, ``inertia``
(``warn``, ``repair`` or ``strict``) and ``floating`` (``true``: the root on a free joint;
:func:`symgen.io.urdf.add_urdf`). The overlay keys are ``stand`` (``frames``, ``kind``:
``point``/``flat``; :func:`symgen.ground_contacts.stand`), ``contact``
(:func:`~symgen.io.urdf.overlay.add_contact`: ``frame``, ``normal``, ``plane``, ``name``, ``motion``:
``frame``/``joints``/``none``, ``friction_forces``), ``hold``
(:func:`~symgen.io.urdf.overlay.add_hold`: ``frames``, ``object: {name, mass, com, inertia}``,
``at``) and ``close`` (``{name: {type, frames: [A, B], normal, components, place}}``,
:func:`~symgen.io.urdf.overlay.add_closure`). Without constraints, ``V_m`` defaults to all the
robots' joint rates, and with constraints but no motion to the joints chosen by
:func:`~symgen.io.urdf.overlay.choose_motion_joints`. The scene's own ``bodies``, ``joints`` and ``frames`` sections are read after
the robots and before the overlay. Its ``constraints``, ``motion`` and ``contact_forces`` come
last, so they add to or replace what the overlay set.
"""
from __future__ import annotations

import os

from .build import add_urdf, no_moving_joint, urdf_sources
from ...ground_contacts import stand
from .overlay import add_closure, add_contact, add_hold, choose_motion_joints

ROBOT_KEYS = ("file", "example", "prefix", "base", "q0", "lock", "snap", "friction", "inertia", "floating", "mimic")


def _positions(reader, value, element, line) -> dict:
    if value is None:
        return {}
    if not isinstance(value, dict):
        reader.fail(element, f"must be a mapping joint -> position; got {value!r}", line)
    return dict(value)


def _robot(reader, item: dict, element: str, line) -> None:
    """One robot of the section: its file, then :func:`add_urdf` with the options given."""
    chosen = [k for k in ("file", "example") if k in item]
    if len(chosen) != 1:
        reader.fail(element, "give exactly one of file, example", line)
    if "file" in item:
        text = reader.text(item["file"], element, "file", line)
        base_dir = os.path.dirname(reader.source) if reader.source and os.path.isfile(reader.source) else ""
        path = text if os.path.isabs(text) else os.path.join(base_dir, text)
    else:
        from .examples import example_path

        name = reader.text(item["example"], element, "example", line)
        try:
            path = example_path(name)
        except KeyError as exc:
            reader.fail(element, str(exc.args[0]), line)
    base = reader.mapping(item.get("base") or {}, f"{element} base", "urdf_base", line)
    options = dict(prefix=item.get("prefix") or "", q0=_positions(reader, item.get("q0"), element, line),
                   lock=_positions(reader, item.get("lock"), element, line),
                   base_xyz=reader.vector(base.get("xyz"), element, "base xyz", line),
                   base_rpy=reader.vector(base.get("rpy"), element, "base rpy", line),
                   base_quat=reader.vector(base.get("quat"), element, "base quat", line, (4,)))
    if not isinstance(options["prefix"], str):
        reader.fail(element, "prefix must be text", line)
    if item.get("snap") is not None:
        options["snap"] = float(reader.exact(item["snap"], element, "snap", line))
    if item.get("friction") is not None:
        if not isinstance(item["friction"], bool):
            reader.fail(element, "friction must be true or false", line)
        options["friction"] = item["friction"]
    if item.get("inertia") is not None:
        options["inertia"] = reader.text(item["inertia"], element, "inertia", line)
    for flag in ("floating", "mimic"):
        if item.get(flag) is not None:
            if not isinstance(item[flag], bool):
                reader.fail(element, f"{flag} must be true or false", line)
            options[flag] = item[flag]
    reader.call(line, add_urdf, reader.scene, path, **options)


def read_robots(reader, value, line):
    """Add the robots of ``urdf:`` to ``reader.scene``; return the function that adds the overlay."""
    item = reader.mapping(value, "urdf", "urdf", line)
    if "robots" in item:
        stray = [k for k in ROBOT_KEYS if k in item]
        if stray:
            reader.fail("urdf", f"{', '.join(stray)} belong inside each entry of robots", line)
        robots = item["robots"]
        if not isinstance(robots, list) or not robots:
            reader.fail("urdf", "robots must be a non-empty list of {file|example, ...}", line)
        for i, robot in enumerate(robots, 1):
            element = f"urdf robot {i}"
            _robot(reader, reader.mapping(robot, element, "urdf_robot", line), element, line)
    else:
        _robot(reader, item, "urdf", line)
    return lambda: _overlay(reader, item, line)


def _overlay(reader, item: dict, line) -> None:
    scene = reader.scene
    if item.get("contact") is not None:
        c = reader.mapping(item["contact"], "urdf contact", "urdf_contact", line)
        motion = c.get("motion", "frame")
        reader.call(line, add_contact, scene, reader.text(c["frame"], "urdf contact", "frame", line),
                    plane=c.get("plane", "plane"), name=c.get("name", "contact"), normal=c.get("normal", "z"),
                    motion=None if motion == "none" else motion, friction_forces=c.get("friction_forces", True))
    if item.get("hold") is not None:
        h = reader.mapping(item["hold"], "urdf hold", "urdf_hold", line)
        obj = reader.mapping(h["object"], "urdf hold object", "urdf_object", line)
        at = reader.mapping(h.get("at") or {}, "urdf hold at", "urdf_base", line)
        reader.call(line, add_hold, scene, reader.names(h["frames"], "urdf hold", "frames", line),
                    mass=obj["mass"], com=obj.get("com") or [0, 0, 0], inertia=obj.get("inertia") or [0, 0, 0],
                    name=obj.get("name", "object"), at_xyz=at.get("xyz"), at_rpy=at.get("rpy"),
                    at_quat=at.get("quat"))
    if item.get("stand") is not None:
        st = reader.mapping(item["stand"], "urdf stand", "urdf_stand", line)
        reader.call(line, stand, scene, reader.names(st["frames"], "urdf stand", "frames", line),
                    reader.text(st.get("kind", "point"), "urdf stand", "kind", line))
    closures = item.get("close") or {}
    if not isinstance(closures, dict):
        reader.fail("urdf close", "must be a mapping name -> {type, frames}", line)
    for name, value in closures.items():
        element = f"constraint {name!r}"
        c = reader.mapping(value, element, "urdf_close", line)
        frames = reader.names(c["frames"], element, "frames", line)
        if len(frames) != 2:
            reader.fail(element, "close needs two frames", line)
        reader.call(line, add_closure, scene, name, c["type"], *frames, normal=c.get("normal", "z"),
                    components=c.get("components"), place=c.get("place", True))
    if scene.motion is None and scene.constraints:   # e.g. after close: joints chosen by QR at q0
        reader.call(line, lambda: scene.set_motion(joints=choose_motion_joints(scene)))
    elif scene.motion is None:
        joints = [j for src in urdf_sources(scene) for j in ([src.floating] if src.floating else [])
                  + src.leading_joints]
        if not joints and not scene.joints:
            reader.call(line, _raise, no_moving_joint(urdf_sources(scene)[0].robot))
        reader.call(line, scene.set_motion, joints=joints)


def _raise(error: Exception) -> None:
    raise error


__all__ = ["read_robots"]
