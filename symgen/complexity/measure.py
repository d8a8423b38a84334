"""One measurement in its own subprocess, under a hard wall-clock limit.

:func:`measure` starts ``python -m symgen.complexity.measure TASK_JSON`` in a new session,
reads the JSON line each finished stage prints (:mod:`symgen.complexity.tasks`), and kills the
whole process group (``SIGKILL``) when ``time_limit`` seconds have passed. Stages finished
before the limit keep their results; the stage that was running is reported as ``timeout`` and
the ones after it as ``not_reached``. A crash (non-zero exit) marks the running stage ``error``
with the last line of the child's stderr.

Memory is the child's own peak resident set (``VmHWM``, reset after the imports; ``ru_maxrss``
where ``/proc`` is missing), reported after every stage; the resident set of the ``start`` record
(after imports, before any work) is the baseline, so ``peak - baseline`` is what the measured
work added at its peak.
"""
from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import SymgenError

#: statuses of a stage
OK, TIMEOUT, ERROR, NOT_REACHED = "ok", "timeout", "error", "not_reached"


@dataclass
class Outcome:
    """What one subprocess measurement produced.

    ``stages`` maps each requested stage to ``(status, record)``; ``record`` is the stage's JSON
    record (``seconds``, ``rss_kib`` and its data) for ``ok``, else ``{}``.
    """

    task: dict
    stages: dict = field(default_factory=dict)
    baseline_kib: int | None = None
    wall: float = 0.0
    error: str = ""

    def status(self, stage: str) -> str:
        return self.stages[stage][0]

    def record(self, stage: str) -> dict:
        return self.stages[stage][1]


def measure(task: dict, stages, time_limit: float) -> Outcome:
    """Run ``task`` (with ``stages``, in order) in a subprocess killed after ``time_limit`` s."""
    if time_limit <= 0:
        raise SymgenError(f"--time-limit must be positive, got {time_limit}")
    stages = list(stages)
    task = {**task, "stages": stages}
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [str(_package_root()),
                                                                    os.environ.get("PYTHONPATH")])))
    start = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-m", "symgen.complexity.measure", json.dumps(task)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
                            start_new_session=True)
    timed_out = False
    try:
        out, err = proc.communicate(timeout=time_limit)
    except subprocess.TimeoutExpired:
        timed_out = True
        _kill_group(proc)
        out, err = proc.communicate()
    outcome = Outcome(task, wall=time.perf_counter() - start)
    records = _parse(out)
    if "start" in records:
        outcome.baseline_kib = records["start"]["rss_kib"]
    failed = TIMEOUT if timed_out else ERROR
    if not timed_out and proc.returncode != 0:
        outcome.error = (err.strip().splitlines() or [f"exit status {proc.returncode}"])[-1]
    for name in stages:
        if name in records:
            outcome.stages[name] = (OK, records[name])
        elif failed is not None:
            outcome.stages[name] = (failed, {})
            failed = None
        else:
            outcome.stages[name] = (NOT_REACHED, {})
    return outcome


def _kill_group(proc: subprocess.Popen) -> None:
    """SIGKILL the measuring process and anything it started (its own session)."""
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass


def _parse(out: str) -> dict:
    records = {}
    for line in out.splitlines():
        line = line.strip()
        if line.startswith("{"):
            try:
                rec = json.loads(line)
            except json.JSONDecodeError:   # a line cut by the kill
                continue
            records[rec["stage"]] = rec
    return records


def _package_root() -> Path:
    """The directory holding the ``symgen`` package (so the child imports this very copy)."""
    return Path(__file__).resolve().parents[2]


def _worker(argv) -> int:
    from .tasks import run_task

    if len(argv) != 1:
        print("usage: python -m symgen.complexity.measure TASK_JSON", file=sys.stderr)
        return 2

    def emit(record):
        print(json.dumps(record), flush=True)

    run_task(json.loads(argv[0]), emit)
    return 0


if __name__ == "__main__":
    sys.exit(_worker(sys.argv[1:]))
