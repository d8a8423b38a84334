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
