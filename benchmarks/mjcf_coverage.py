"""Which MJCF models of the DeepMind Control Suite symgen loads, and why it refuses the others.

Every ``suite/*.xml`` that the installed ``dm_control`` wheel ships is read by
:func:`symgen.io.mjcf.scene_from_mjcf` (its ``<include>`` files from ``suite/common/``); a file
either loads or raises a :class:`~symgen.errors.SymgenError` naming the element and line. Each
loaded model is then checked against MuJoCo on the same file:

* every body's mass, centre of mass and inertia (MuJoCo's ``body_mass``, ``body_ipos``, and
  ``body_inertia`` turned by ``body_iquat``), here mostly computed from geoms;
* the mass matrix (``mj_fullM``), the bias forces (``qfrc_bias``, less symgen's joint damping and
  springs) and the joint springs (``-qfrc_spring``: symgen's ``G`` at rest without gravity) at
  random states, through the coordinate map (:mod:`symgen.io.coordinates`).

A file refused for its fluid medium (``<option density/viscosity>``) is read again with the reader
option ``fluid="ignore"`` and counted apart (the "reader option" column): its model leaves the fluid
forces out, as MuJoCo's ``mj_fullM`` and ``qfrc_bias`` do, so the same comparison applies.

    python benchmarks/mjcf_coverage.py            # writes benchmarks/mjcf_coverage.md

``tests/test_mjcf_coverage.py`` imports this module and asserts the sets and the agreement.
"""
from __future__ import annotations

import importlib.metadata
import os
import sys
import time
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

SUITE = "dm_control/suite/"
#: random states per loaded model
STATES = 5
SEED = 0
#: agreement with MuJoCo, relative to the largest entry of MuJoCo's value (at least MIN_SCALE)
TOL = 1e-10
MIN_SCALE = 1e-6
#: looser bounds, each with its reason (tests/test_mjcf_meshes.py shows ours are diagonal in MuJoCo's
#: own mesh frames to MuJoCo's threshold, and the dog's centres agree to 1e-13 m)
LOOSER = {
    ("dog.xml", "body inertia"): (1e-7, "MuJoCo's principal axes of a mesh stop its Jacobi iteration at an "
                                        "absolute off-diagonal of 1e-12 (mjuu_eig3), coarse for the small bones"),
    ("dog.xml", "body centre of mass"): (1e-9, "a bone's centre lies 1.5e-6 m from its body frame: the difference, "
                                               "8e-16 m, is divided by the floor 1e-6 m of the scale"),
}


def tolerance(file: str, quantity: str) -> float:
    """The agreement asked of ``quantity`` on ``file``: :data:`TOL`, or its :data:`LOOSER` bound."""
    return LOOSER.get((file, quantity), (TOL, ""))[0]


@dataclass
class Outcome:
    """What one file gave: a scene (its joints and notes) or a refusal, and MuJoCo's comparison."""

    file: str
    joints: int = 0
    dof: int = 0
    notes: list = field(default_factory=list)
    error: BaseException | None = None
    seconds: float = 0.0
    worst: dict = field(default_factory=dict)      # quantity -> worst relative difference
    option: str = ""                               # the reader option it needed ("" for none)

    @property
    def loaded(self) -> bool:
        return self.error is None


def suite_files() -> dict:
    """``{file name: absolute path}`` of every control-suite model the dm_control wheel ships (found
    through the wheel's file list: dm_control itself is not imported)."""
    dist = importlib.metadata.distribution("dm-control")
    files = sorted(str(f) for f in dist.files if str(f).startswith(SUITE) and str(f).count("/") == 2
                   and str(f).endswith(".xml"))
    return {f[len(SUITE):]: str(dist.locate_file(f)) for f in files}


#: the reader option a file refused for its fluid medium is read again with
FLUID_OPTION = {"fluid": "ignore"}


def try_load(name: str, path: str, **options) -> tuple[Outcome, object]:
    """Load one file (``options``: reader options); a :class:`SymgenError` is kept, anything else
    propagates (a bug)."""
    from symgen.errors import SymgenError
    from symgen.io.mjcf import FluidWarning, scene_from_mjcf

    start = time.perf_counter()
    label = ", ".join(f"{k}={v!r}" for k, v in options.items())
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", FluidWarning)       # its text is a note of the scene
            scene = scene_from_mjcf(path, **options)
    except SymgenError as exc:
        return Outcome(name, error=exc, seconds=time.perf_counter() - start, option=label), None
    dof = sum(j.dof for j in scene.joints.values())
    return Outcome(name, sum(1 for j in scene.joints.values() if j.dof), dof, list(scene.notes),
                   seconds=time.perf_counter() - start, option=label), scene


def load_with_option(name: str, path: str) -> tuple[Outcome, object]:
    """:func:`try_load`, and again with :data:`FLUID_OPTION` when the refusal is for the fluid (then
    its outcome, loaded or refused for something else)."""
    outcome, scene = try_load(name, path)
    if scene is None and "fluid='ignore'" in str(outcome.error):
        return try_load(name, path, **FLUID_OPTION)     # loaded, or refused for what remains
    return outcome, scene


def _relative(ours, theirs) -> float:
    ours, theirs = np.asarray(ours, float), np.asarray(theirs, float)
    if not theirs.size:
        return 0.0
    return float(np.max(np.abs(ours - theirs))) / max(float(np.max(np.abs(theirs))), MIN_SCALE)


def mass_properties_check(path: str, **options) -> dict:
    """Worst relative differences of every body's mass, centre of mass and inertia (body frame)
    between symgen's reading of ``path`` and MuJoCo's compiled model."""
    import mujoco

    from symgen.io.mjcf import FluidWarning, parse_mjcf
    from symgen.io.mjcf.records import element_name
    from symgen.math.configuration import quaternion_rotation

    m = mujoco.MjModel.from_xml_path(path)
    worst = {"body mass": 0.0, "body centre of mass": 0.0, "body inertia": 0.0}
    ids = {element_name(m.body(i).name): i for i in range(m.nbody)}   # 'pinch site' is read as pinch_site
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", FluidWarning)           # the loaded scene's note says it
        bodies = parse_mjcf(path, **options).bodies
    for b in bodies:
        bid = ids[b.name]
        mass = float(b.inertial.mass) if b.inertial else 0.0
        com = np.array(b.inertial.pos, dtype=float).ravel() if b.inertial else np.zeros(3)
        inertia = np.array(b.inertial.inertia, dtype=float) if b.inertial else np.zeros((3, 3))
        rot = quaternion_rotation(m.body_iquat[bid])
        theirs = rot @ np.diag(m.body_inertia[bid]) @ rot.T
        worst["body mass"] = max(worst["body mass"], _relative(mass, m.body_mass[bid]))
        if mass:
            worst["body centre of mass"] = max(worst["body centre of mass"], _relative(com, m.body_ipos[bid]))
            worst["body inertia"] = max(worst["body inertia"], _relative(inertia, theirs))
    return worst


def dynamics_check(path: str, scene, states: int = STATES, seed: int = SEED) -> dict:
    """Worst relative differences of the mass matrix and the bias forces between symgen's model of
    ``scene`` and MuJoCo on ``path``, at ``states`` random states mapped by the coordinate map."""
    import mujoco

    from symgen.io.coordinates import CoordinateMap
    from symgen.model import derive

    model = derive(scene)
    m = mujoco.MjModel.from_xml_path(path)
    d = mujoco.MjData(m)
    cmap = CoordinateMap.mujoco(scene, m)
    rng = np.random.default_rng(seed)
    worst = {"mass matrix": 0.0, "bias forces": 0.0, "joint springs": 0.0}
    names = model.coordinate_names()
    idx = cmap.velocity_indices(names)
    close, p_map = _coupling_map(scene, m, cmap, idx)
    for _ in range(states):
        qpos = close(m.qpos0 + rng.uniform(-1.0, 1.0, m.nq))
        qvel = p_map @ rng.uniform(-1.0, 1.0, len(names))
        d.qpos[:], d.qvel[:] = qpos, qvel
        mujoco.mj_forward(m, d)
        config, rates = cmap.to_symgen(qpos, qvel)
        qd = [rates[n] for n in names]
        full = model.evaluate(config, qd=qd)
        xi = model.evaluate(config, qd=qd, gravity=False).G_q          # damping and springs: qfrc_passive
        springs = model.evaluate(config, qd=[0.0] * len(qd), gravity=False).G_q
        dense = np.zeros((m.nv, m.nv))
        mujoco.mj_fullM(m, dense, d.qM) if hasattr(d, "qM") else mujoco.mj_fullM(m, d, dense)
        worst["mass matrix"] = max(worst["mass matrix"], _relative(full.M_q, p_map.T @ dense @ p_map))
        worst["bias forces"] = max(worst["bias forces"],
                                   _relative(np.asarray(full.C_q @ full.qd + full.G_q - xi, float).ravel(),
                                             p_map.T @ d.qfrc_bias))
        worst["joint springs"] = max(worst["joint springs"],
                                     _relative(np.asarray(springs, float).ravel(), -p_map.T @ d.qfrc_spring))
    return worst


def _coupling_map(scene, m, cmap, idx):
    """``(close, P)`` for a scene whose constraints are joint couplings ``q_j + sum c_i q_i = b``
    (``c_j = 1``, ``j`` dependent): ``close(qpos)`` sets each dependent joint's qpos from the others,
    and MuJoCo's ``qvel = P V_m`` (``P`` constant, so ``P^T qfrc`` is the reduced force, eq. 14:
    ``M_q = P^T M P``, and the bias needs no ``dP/dt`` term). Without couplings ``P`` selects."""
    p_map = np.zeros((m.nv, len(idx)))
    p_map[idx, np.arange(len(idx))] = 1.0
    couplings = [c for c in scene.constraints.values() if c.is_coupling]
    assert len(couplings) == len(scene.constraints), "frame constraints are not compared here"
    for c in couplings:
        (dep, one), others = c.terms[0], c.terms[1:]
        assert one == 1
        row = cmap.velocity_indices([dep])[0]
        for joint, coef in others:
            p_map[row] -= float(coef) * p_map[cmap.velocity_indices([joint])[0]]

    def close(qpos):
        qpos = qpos.copy()
        for c in couplings:
            (dep, _), others = c.terms[0], c.terms[1:]
            qpos[m.joint(dep).qposadr[0]] = float(c.offset) - sum(
                float(coef) * qpos[m.joint(j).qposadr[0]] for j, coef in others)
        return qpos

    return close, p_map


def coverage(check: bool = True) -> list[Outcome]:
    """Every suite file's outcome; ``check``: compare the loaded ones with MuJoCo."""
    out = []
    for name, path in suite_files().items():
        outcome, scene = load_with_option(name, path)
        if scene is not None and check:
            options = FLUID_OPTION if outcome.option else {}
            outcome.worst = {**mass_properties_check(path, **options), **dynamics_check(path, scene)}
        out.append(outcome)
    return out


def reason(outcome: Outcome) -> str:
    """The refusal in one line: the element, and the message without the file's path."""
    err = outcome.error
    text = str(err).split(" (/")[0].split(" (" + os.sep)[0]
    line = f", line {err.line}" if getattr(err, "line", None) else ""
    return f"{text}{line}"


def markdown(outcomes: list[Outcome], seconds: float) -> str:
    loaded = [o for o in outcomes if o.loaded]
    version = importlib.metadata.version("dm-control")
    mj = importlib.metadata.version("mujoco")
    lines = [
        "# MJCF coverage: the DeepMind Control Suite",
        "",
        f"Every model of `dm_control/suite/*.xml` (dm_control {version}), read by `symgen.io.mjcf.scene_from_mjcf`, "
        f"and each loaded one compared with MuJoCo {mj} on the same file ({STATES} random states, seed {SEED}; "
        "differences relative to MuJoCo's largest entry). Written by `python benchmarks/mjcf_coverage.py` "
        f"in {seconds:.0f} s.",
        "",
        f"**{len(loaded)} of {len(outcomes)} load** ({sum(not o.option for o in loaded)} as they are, "
        f"{sum(bool(o.option) for o in loaded)} with the reader option `fluid='ignore'`, which leaves the fluid "
        f"forces out); {len(outcomes) - len(loaded)} are refused, each with a typed error naming the element.",
        "",
        f"Every difference is within {TOL:.0e}, except "
        + "; ".join(f"{q} of {f} (within {t:.0e}: {why})" for (f, q), (t, why) in LOOSER.items()) + ".",
        "",
        "## Loaded",
        "",
        "| model | reader option | moving joints | DOF | body mass | centre of mass | inertia | mass matrix "
        "| bias forces | joint springs |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for o in loaded:
        w = o.worst
        lines.append(f"| {o.file} | {f'`{o.option}`' if o.option else ''} | {o.joints} | {o.dof} | " + " | ".join(
            f"{w.get(k, float('nan')):.1e}" for k in ("body mass", "body centre of mass", "body inertia",
                                                     "mass matrix", "bias forces", "joint springs")) + " |")
    lines += ["", "## Refused", "", "| model | reader option | typed error |", "|---|---|---|"]
    for o in outcomes:
        if not o.loaded:
            lines.append(f"| {o.file} | {f'`{o.option}`' if o.option else ''} | `{type(o.error).__name__}`: "
                         f"{reason(o).replace('|', '/')} |")
    lines += ["", "## Notes of the loaded models", ""]
    for o in loaded:
        for note in o.notes:
            lines.append(f"- {o.file}: {note}")
    return "\n".join(lines) + "\n"


def main() -> int:
    start = time.perf_counter()
    outcomes = coverage()
    text = markdown(outcomes, time.perf_counter() - start)
    out = Path(__file__).with_suffix(".md")
    out.write_text(text)
    print(text)
    bad = [o.file for o in outcomes if o.loaded and any(v > tolerance(o.file, k) for k, v in o.worst.items())]
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
