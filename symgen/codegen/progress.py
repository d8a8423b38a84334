"""A progress bar for long commands: on stderr, only when stderr is a terminal.

``symgen generate`` at a hundred joints traces for seconds per function; :func:`progress` wraps
the loop over functions in a ``tqdm`` bar that appears only after :data:`DELAY` seconds (a quick
run prints nothing) and only on a terminal, so captured output (tests, pipes, generated files)
never contains it. Without ``tqdm`` installed the loop runs as it is.
"""
from __future__ import annotations

import sys

#: seconds before the bar is drawn
DELAY = 1.0


def progress(items, *, total=None, desc: str = "", stream=None, label=None):
    """``items``, iterated under a progress bar on ``stream`` (stderr) when it is a terminal;
    ``label(item)`` is shown beside the bar (e.g. the function being traced)."""
    stream = sys.stderr if stream is None else stream
    isatty = getattr(stream, "isatty", None)
    if not (isatty and isatty()):
        return items
    try:
        from tqdm import tqdm
    except ImportError:
        return items
    return _labelled(tqdm(items, total=total, desc=desc, file=stream, delay=DELAY, leave=False), label)


def _labelled(bar, label):
    for item in bar:
        if label is not None:
            bar.set_postfix_str(label(item), refresh=False)
        yield item
