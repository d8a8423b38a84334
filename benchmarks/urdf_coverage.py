"""Which URDF files of ``example-robot-data`` symgen loads, and why it refuses the others.

Every ``*.urdf`` the installed package ships is read by :func:`symgen.io.urdf.scene_from_urdf` in
one process, once with the default ``inertia="warn"`` and once with ``inertia="repair"``; a file
either loads (joints, URDF warnings, notes) or raises a :class:`~symgen.errors.SymgenError`
naming the element. Pinocchio's own parser is run on each file for comparison, and a handful of
newly loaded robots are cross-checked against Pinocchio (:func:`symgen.oracle.check_against_pinocchio`).

    python benchmarks/urdf_coverage.py            # writes benchmarks/urdf_coverage.md

``tests/test_urdf_coverage.py`` imports this module and asserts the sets.
"""
from __future__ import annotations

import importlib.metadata
import os
import sys
import time
import warnings
from dataclasses import dataclass, field

ROBOTS = "cmeel.prefix/share/example-robot-data/robots/"
#: newly loaded fixed-base robots cross-checked against Pinocchio (warn mode unless CHECK_OPTIONS)
PINOCCHIO_CHECKED = ("bolt_description/robots/bolt.urdf", "go1_description/urdf/go1.urdf",
                     "anymal_b_simple_description/robots/anymal.urdf", "quadruped_description/urdf/quadruped.urdf",
                     "tiago_description/robots/tiago_no_hand.urdf", "centauro_description/urdf/centauro.urdf",
                     "icub_description/robots/icub_reduced.urdf", "romeo_description/urdf/romeo.urdf")
#: the reader options of the checked files that need any (none: a repaired inertia is another robot than
#: the one Pinocchio reads, so files that load only with inertia="repair" cannot be checked this way)
CHECK_OPTIONS: dict = {}


@dataclass
class Outcome:
    """What one file gave: a scene (``joints``, warning classes, notes) or a refusal."""

    file: str
    joints: int = 0
    warned: list = field(default_factory=list)
    notes: list = field(default_factory=list)
    error: BaseException | None = None
    seconds: float = 0.0

    @property
    def loaded(self) -> bool:
        return self.error is None


def example_urdfs() -> dict:
    """``{path below robots/: absolute path}`` of every URDF file of example-robot-data, sorted."""
    dist = importlib.metadata.distribution("example-robot-data")
    files = sorted(str(f) for f in dist.files if str(f).startswith(ROBOTS) and str(f).endswith(".urdf"))
    return {f[len(ROBOTS):]: str(dist.locate_file(f)) for f in files}


def try_load(name: str, path: str, inertia: str = "warn", floating: bool = False, mimic: bool = True) -> Outcome:
    """Load one file; any :class:`SymgenError` is kept, anything else propagates (a bug)."""
    from symgen.errors import SymgenError
    from symgen.io.urdf import scene_from_urdf
    from symgen.io.urdf.physics import UrdfWarning

    start = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            scene = scene_from_urdf(path, inertia=inertia, floating=floating, mimic=mimic)
        except SymgenError as exc:
            return Outcome(name, error=exc, seconds=time.perf_counter() - start)
    warned = sorted({w.category.__name__ for w in caught if issubclass(w.category, UrdfWarning)})
    return Outcome(name, len(scene.joints), warned, list(scene.notes), seconds=time.perf_counter() - start)


def coverage(inertia: str = "warn") -> list[Outcome]:
    return [try_load(name, path, inertia) for name, path in example_urdfs().items()]


def free_body(outcome: Outcome) -> bool:
    """Whether the reader says the file's root is a free body: it has no moving joint (a drone), or
    it loads with a :class:`~symgen.errors.FixedBaseWarning` (a legged robot welded to the world)."""
    return (type(outcome.error).__name__ == "NoMovingJointError" or "FixedBaseWarning" in outcome.warned)


def unknown_mimic(outcome: Outcome) -> bool:
    """Whether the file was refused over a ``<mimic>`` of a joint it lacks (loads with ``mimic=False``)."""
    return outcome.error is not None and "which is not a joint of this robot" in str(outcome.error)


def all_options_coverage(repair: list) -> list[Outcome]:
    """``repair``, with every free-body file loaded again with ``floating=True`` and every file
    whose ``<mimic>`` names a joint it lacks with ``mimic=False``."""
    paths = example_urdfs()
    return [try_load(o.file, paths[o.file], "repair", floating=free_body(o), mimic=not unknown_mimic(o))
            if free_body(o) or unknown_mimic(o) else o for o in repair]


def pinocchio_loads(path: str) -> bool:
    import pinocchio as pin

    try:
        pin.buildModelFromUrdf(path)
        return True
    except (RuntimeError, ValueError):
        return False


def pinocchio_check(name: str) -> list:
    """:func:`check_against_pinocchio` of one example (with its :data:`CHECK_OPTIONS`), at 10 random states."""
    import symgen
    from symgen.io.urdf import scene_from_urdf
    from symgen.oracle.pinocchio_check import check_against_pinocchio

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        scene = scene_from_urdf(example_urdfs()[name], **CHECK_OPTIONS.get(name, {}))
    return check_against_pinocchio(symgen.derive(scene), states=10)


def _cell(o: Outcome) -> str:
    if o.loaded:
        warned = ", ".join(w.replace("Warning", "") for w in o.warned)
        return f"loads: {o.joints} joints" + (f"; warns {warned}" if warned else "") + \
            (f"; {len(o.notes)} notes" if o.notes else "")
    text = str(o.error).split(" (/")[0].replace("|", "/")
    return f"**{type(o.error).__name__}** {text[:230]}{'...' if len(text) > 230 else ''}"


def report(warn: list, repair: list, options: list, pin: dict, checks: dict) -> str:
    n = len(warn)
    version = importlib.metadata.version("example-robot-data")
    lines = [f"# URDF coverage: example-robot-data {version}", "",
             "Written by `python benchmarks/urdf_coverage.py`; asserted by `tests/test_urdf_coverage.py`.", "",
             f"- files: {n}; Pinocchio's `buildModelFromUrdf` loads {sum(pin.values())}",
             f"- symgen, `inertia=\"warn\"` (default): **{sum(o.loaded for o in warn)}** load, "
             f"{sum(not o.loaded for o in warn)} refused",
             f"- symgen, `inertia=\"repair\"`: **{sum(o.loaded for o in repair)}** load, "
             f"{sum(not o.loaded for o in repair)} refused",
             f"- symgen, `inertia=\"repair\"`, `floating=True` for the {sum(free_body(o) for o in repair)} "
             "files whose root is a free body (no moving joint, or a `FixedBaseWarning`) and `mimic=False` for "
             f"the {sum(unknown_mimic(o) for o in repair)} whose `<mimic>` names a joint the file lacks: "
             f"**{sum(o.loaded for o in options)}** load, {sum(not o.loaded for o in options)} refused",
             "- a joint that moves no mass (with the joints that mimic it) is locked like a fixed joint, with a "
             "`MasslessJointWarning` (Romeo's hands)",
             "- every refusal is a `SymgenError` naming the element (link, joint or robot)",
             "- \"warn\" keeps inertias within 1e-6 of their largest principal moment of a rigid body's "
             "(none of the files of version 6.0.0 is in that band: their violations on moving links are 0.18 % "
             "to 200 %); "
             "\"repair\" replaces every violating inertia by the nearest consistent one", "",
             "## Pinocchio cross-check of newly loaded robots (10 random states, relative error)", "",
             "| file | quantity | worst | tolerance | passed |", "|---|---|---|---|---|"]
    for name, diffs in checks.items():
        lines += [f"| {name} | {d.quantity} | {d.worst:.1e} | {d.tolerance:.0e} | {d.passed} |" for d in diffs]
    lines += ["", "## Every file", "", "| file | Pinocchio | symgen (warn) | symgen (repair) | symgen (all options) |",
              "|---|---|---|---|---|"]
    for w, r, f in zip(warn, repair, options):
        lines.append(f"| {w.file} | {'loads' if pin[w.file] else 'refuses'} | {_cell(w)} | "
                     f"{'same' if _cell(r) == _cell(w) else _cell(r)} | {'same' if f is r else _cell(f)} |")
    return "\n".join(lines) + "\n"


def main() -> None:
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    warn, repair = coverage("warn"), coverage("repair")
    options = all_options_coverage(repair)
    pin = {name: pinocchio_loads(path) for name, path in example_urdfs().items()}
    checks = {name: pinocchio_check(name) for name in PINOCCHIO_CHECKED}
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "urdf_coverage.md")
    with open(out, "w") as fh:
        fh.write(report(warn, repair, options, pin, checks))
    print(f"warn: {sum(o.loaded for o in warn)} of {len(warn)} load; repair: {sum(o.loaded for o in repair)}; "
          f"all options: {sum(o.loaded for o in options)}; "
          f"written {out}")


if __name__ == "__main__":
    main()
