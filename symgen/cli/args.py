"""Argument types shared by the commands."""
from __future__ import annotations

import argparse
import math


def bounded(kind: type, *, low=None, high=None, low_open: bool = False):
    """An argparse ``type`` for an ``int`` or a finite ``float`` in ``[low, high]`` (``low``
    excluded with ``low_open``). A value outside is an :class:`argparse.ArgumentTypeError` whose
    message states the range; argparse prefixes the option's name (``argument --budget: ...``).

    >>> bounded(float, low=0, low_open=True)("2.5")
    2.5
    """
    noun = "an integer" if kind is int else "a finite number"
    above = (f"> {low}" if low_open else f">= {low}") if low is not None else ""
    rule = " and ".join(r for r in (above, f"<= {high}" if high is not None else "") if r)

    def parse(text: str):
        try:
            value = kind(text)
        except (ValueError, OverflowError):
            raise argparse.ArgumentTypeError(f"{text!r} is not {noun}") from None
        if kind is float and not math.isfinite(value):
            raise argparse.ArgumentTypeError(f"{text!r} is not {noun}")
        if (low is not None and (value < low or (low_open and value == low))) or (high is not None and value > high):
            raise argparse.ArgumentTypeError(f"{text} is out of range: give {noun} {rule}")
        return value

    parse.__name__ = kind.__name__
    return parse


def joint_values(text: str) -> dict:
    """``--lock``: ``joint=value,joint=value`` as ``{joint: value text}`` (values as a URDF reader's
    ``lock`` takes them: ``0.5``, ``-pi/2``). A malformed entry is an :class:`argparse.ArgumentTypeError`.

    >>> joint_values("gripper_left_joint=0,elbow=-pi/2")
    {'gripper_left_joint': '0', 'elbow': '-pi/2'}
    """
    out: dict = {}
    for item in text.split(","):
        name, sep, value = (part.strip() for part in item.partition("="))
        if not sep or not name or not value:
            raise argparse.ArgumentTypeError(f"{item.strip()!r} is not joint=value (e.g. --lock finger_joint=0)")
        if name in out:
            raise argparse.ArgumentTypeError(f"joint {name!r} is locked twice")
        out[name] = value
    return out


def add_scene(parser, **kwargs) -> None:
    """The SCENE argument of a command, with ``--lock`` (URDF joints held fixed at a value)."""
    parser.add_argument("scene", **kwargs)
    parser.add_argument("--lock", type=joint_values, metavar="JOINT=VALUE[,...]",
                        help="URDF file: hold these joints fixed at these positions (merged like fixed joints; "
                             "a YAML scene sets lock: in its urdf: section)")
    parser.add_argument("--floating", action="store_true",
                        help="URDF file: put the root link on a free joint (a floating base) instead of welding "
                             "it to the world (a YAML scene sets floating: true in its urdf: section)")
    parser.add_argument("--no-mimic", dest="mimic", action="store_false",
                        help="URDF file: read every <mimic> joint as an independent, actuated joint, as "
                             "Pinocchio's default parse does (a YAML scene sets mimic: false)")
    parser.add_argument("--fluid", choices=("refuse", "ignore"), default=None,
                        help="MJCF file in a fluid medium (<option density/viscosity>): 'ignore' reads the rigid-body "
                             "dynamics without the fluid forces (with a warning); by default it is refused")


def load_scene(args):
    """The scene ``args.scene`` names, its URDF joints locked as ``--lock`` says and its root
    floating with ``--floating``, its ``<mimic>`` elements left out with ``--no-mimic``, an MJCF file's
    fluid as ``--fluid`` says."""
    from ..io.loading import load

    options = {}
    if getattr(args, "lock", None):
        options["lock"] = args.lock
    if getattr(args, "floating", False):
        options["floating"] = True
    if not getattr(args, "mimic", True):
        options["mimic"] = False
    if getattr(args, "fluid", None):
        options["fluid"] = args.fluid
    return load(args.scene, **options)
