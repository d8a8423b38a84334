"""Closed-loop demonstrations of the adaptive controller on the paper's robots.

Each :class:`Demo` names the bodies whose parameters are unknown to the controller, the factor by
which the controller's first estimate of each is wrong (the whole ``P_alpha = (m, m r, I_o)`` is
scaled, so a wrong estimate is still a physical body with the right centre of mass), the task and
the gains. :func:`run_demo` runs it twice -- with adaptation (38) and with the estimates frozen at
their wrong start -- from the same state, on the true plant.

``K_A = k M_q(q_0)``: the velocity error ``e`` of every joint-space mode then decays at about the
same rate ``k`` (1/s), light wrists and heavy bases alike, which keeps the closed loop free of
stiff modes that an explicit integrator would have to resolve.

Bounds: every unknown parameter ``P_k`` lies in ``[P_k - w_k, P_k + w_k]`` with
``w_k = max(|P_k|, floor)`` (a mass in ``[m/10, 2 m]``), which holds every start estimate of a
factor in ``[0.1, 2]``. Update gains ``rho_k = rho w_k^2``: each parameter adapts at the same rate
relative to its own size.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..io.loading import load
from ..model import derive
from .state import StateLayout
from .closed_loop import ClosedLoop, ClosedLoopResult, ControlSettings, check_run, run_closed_loop
from ..control.contact import ContactLaw
from ..control.errors import ControlInputError
from ..control.law import default_parameters
from ..control.parameters import BODY_QUANTITIES, ParameterSet
from ..control.tasks import make_task

#: smallest half-width of a parameter's bounds (kg, kg m, kg m^2): zero entries may still move
BOUND_FLOOR = 0.02


@dataclass(frozen=True)
class Demo:
    """One demonstration: scene, unknown bodies with the factor of their wrong start, task, gains."""

    scene: str
    factors: dict                       # body -> factor of the controller's initial estimate
    amplitude: object = 0.2             # per motion component (m or rad)
    frequency: float = 0.25             # Hz
    task_gain: float = 5.0              # Lambda (1/s)
    gain: float = 10.0                  # K_A = gain * M_q(q0): every joint-space mode decays at ~gain (1/s)
    rho: float = 5.0
    t_end: float = 8.0
    eta_fd: tuple = ()                  # desired constraint force (eta_f components)
    force_gain: float = 0.0             # K_F of eta_fr = eta_fd + K_F int (eta_fd - eta_f)
    contact: dict = field(default_factory=dict)   # viscous/coulomb of the true contact law
    description: str = ""
    motion: dict = field(default_factory=dict)    # replaces the scene's motion coordinates (set_motion)
    rtol: float = 1e-7                  # relative tolerance of the integrator (RK45), atol = rtol / 100


DEMOS = {
    "chain:n=6": Demo("chain:n=6", {"link3": 1.3, "link4": 0.7, "link5": 1.3}, amplitude=0.4, gain=5.0, rho=50.0,
                      description="the benchmark chain tracking a joint-space path, three link masses +-30% off"),
    "arm_on_plane": Demo("arm_on_plane", {"object": 1.5, "link2": 1.3, "link3": 0.7}, amplitude=(0.05, 0.05, 0.3),
                         gain=2.0, task_gain=2.0, rho=500.0,
                         eta_fd=(-20.0, 0.0, 0.0), force_gain=20.0, contact={"viscous": 2.0, "coulomb": 0.5},
                         description="§3.2: the held object slides on the plane along a closed path while "
                                     "pressing on it (eta_fd), object mass and inertia +50%, two links +-30%"),
    "multi_arm:h=2": Demo("multi_arm:h=2", {"object": 1.5, "a1_link3": 1.3, "a2_link3": 0.7},
                          amplitude=(0.02, 0.02, 0.02, 0.05, 0.05, 0.05), eta_fd=(0.0, 10.0, 0.0, 0.0, 0.0, 0.0),
                          gain=10.0, task_gain=5.0, rho=500.0, force_gain=20.0,
                          description="§3.3: two arms carry the object along a path while squeezing it (eta_fd), "
                                      "object +50%, two links +-30%"),
    "five_bar": Demo("five_bar", {"distal1": 1.5, "distal2": 1.5}, amplitude=0.02, gain=2.0, task_gain=2.0,
                     rho=200000.0, motion={"frame": "pin_frame", "components": ["vx", "vy"]},
                     description="planar five-bar whose end effector (the closing pin) tracks a closed path in "
                                 "the plane, both distal links (the payload) +50%"),
    "ur5_on_plane": Demo("ur5_on_plane", {"wrist_3_link": 1.5, "forearm_link": 1.3, "upper_arm_link": 0.7},
                         amplitude=(0.05, 0.05, 0.3), gain=2.0, task_gain=2.0, rho=500.0, eta_fd=(40.0, 0.0, 0.0),
                         force_gain=20.0, contact={"viscous": 2.0, "coulomb": 0.5},
                         description="a real robot (UR5 URDF, extra 'examples'): the tool slides on a plane along a "
                                     "closed path pressing with 40 N, three links' parameters 30-50% off"),
    "stewart": Demo("stewart", {"platform": 1.5}, amplitude=(0.01, 0.01, 0.01, 0.05, 0.05, 0.05), gain=5.0,
                    task_gain=5.0, rho=20.0,
                    description="Stewart platform tracking a platform path, platform (payload) +50%"),
}


def uncertain_parameters(params: ParameterSet, bodies, rho: float) -> ParameterSet:
    """``params`` with every parameter of ``bodies`` uncertain (bounds and gains of the module
    docstring)."""
    spec = {}
    for body in bodies:
        for q in BODY_QUANTITIES:
            name = f"{q}_{body}"
            value = float(params.values[params.index(name)])
            width = max(abs(value), BOUND_FLOOR)
            lower = 0.1 * value if q == "m" else value - width
            spec[name] = (lower, value + width, rho * width * width)
    return params.with_uncertainty(spec)


def wrong_start(params: ParameterSet, factors: dict) -> np.ndarray:
    """The controller's first estimate: each listed body's ``P_alpha`` times its factor."""
    p0 = np.asarray(params.values, float).copy()
    for body, factor in factors.items():
        for q in BODY_QUANTITIES:
            p0[params.index(f"{q}_{body}")] *= factor
    return p0


#: the default run of a scene outside :data:`DEMOS` (:func:`default_demo`): its simulated seconds,
#: the factor of every massive body's first estimate, the force a plane contact presses with (N)
DEFAULT_T_END, DEFAULT_FACTOR, DEFAULT_PRESS = 4.0, 1.3, 40.0
#: the default run's integrator tolerance: adapting every body's ten parameters at once is stiff
#: (a UR10 needs some 4,000 right-hand sides per simulated second at 1e-7, half as many at 1e-5)
DEFAULT_RTOL = 1e-5
#: default excursion of a translation (m), a rotation or a joint (rad)
DEFAULT_AMPLITUDE = {"v": 0.05, "w": 0.3, "joint": 0.2}
#: backends of a closed loop: the dense model per right-hand side, or generated code
BACKENDS = ("dense", "numpy", "c")


def default_demo(spec, model=None) -> Demo:
    """A demonstration of any scene: its own in :data:`DEMOS`, otherwise every massive body's
    parameters :data:`DEFAULT_FACTOR` too large at the start, excursions of
    :data:`DEFAULT_AMPLITUDE` along the motion components, a plane contact pressing with
    :data:`DEFAULT_PRESS` N (the normal component, first of its rows in ``eta_f``, as in
    ``ur5_on_plane``) under integral force feedback, and a viscous and Coulomb contact law on the
    scene's contact forces; :data:`DEFAULT_T_END` simulated seconds at :data:`DEFAULT_RTOL`."""
    if isinstance(spec, str) and spec in DEMOS:
        return DEMOS[spec]
    model = derive(load(spec)) if model is None else model
    motion = model.scene.motion
    amplitude = (tuple(DEFAULT_AMPLITUDE[c[0]] for c in motion.components)      # frame components, then joints
                 + (DEFAULT_AMPLITUDE["joint"],) * len(motion.joints)) if motion.frames else DEFAULT_AMPLITUDE["joint"]
    eta_fd = []
    for con in model.scene.constraints.values():
        eta_fd += [DEFAULT_PRESS if con.kind == "plane_contact" else 0.0] + [0.0] * (len(con.components) - 1)
    eta_fd = tuple(eta_fd) if any(eta_fd) and len(eta_fd) == model.counts.n - model.counts.m else ()
    bodies = {b.name: DEFAULT_FACTOR for b in model.tree.bodies if not b.massless}
    contact = {"viscous": 2.0, "coulomb": 0.5} if model.scene.contact_forces is not None else {}
    words = [f"every massive body's parameters {DEFAULT_FACTOR - 1:.0%} too large at the start"]
    if eta_fd:
        words.append(f"pressing on the plane with {DEFAULT_PRESS:g} N")
    return Demo(model.scene.name if not isinstance(spec, str) else spec, bodies, amplitude=amplitude, gain=2.0,
                task_gain=2.0, rho=500.0, t_end=DEFAULT_T_END, eta_fd=eta_fd, force_gain=20.0 if eta_fd else 0.0,
                contact=contact, rtol=DEFAULT_RTOL, description=f"{model.scene.name}: " + ", ".join(words))


def demo_model(demo: Demo, scene=None):
    """The model of ``demo``'s scene (``scene`` if given, else ``load(demo.scene)``), with the
    demonstration's motion coordinates."""
    scene = load(demo.scene) if scene is None else scene
    if demo.motion:
        scene.motion = None
        scene.set_motion(**demo.motion)
    return derive(scene)


def setup(demo: Demo, *, adapt: bool = True, exact: bool = False, backend: str = "dense", model=None):
    """``(loop, x0)`` for ``demo``: with ``exact`` the estimates start at the true values;
    ``backend`` one of :data:`BACKENDS` (:class:`ClosedLoop` on the dense model, or
    :class:`~symgen.simulation.closed_loop_generated.GeneratedClosedLoop`); ``model`` the
    :func:`demo_model` when the caller has it."""
    if backend not in BACKENDS:
        raise ControlInputError(f"backend {backend!r}: choose from {', '.join(BACKENDS)}")
    model = demo_model(demo) if model is None else model
    contact = ContactLaw.for_scene(model.scene, **demo.contact) if model.scene.contact_forces else None
    params = uncertain_parameters(default_parameters(model, contact), demo.factors, demo.rho)
    p0 = np.asarray(params.values, float) if exact else wrong_start(params, demo.factors)
    layout = StateLayout(model)
    x0 = layout.initial_state(V_m=np.zeros(model.counts.m))
    config = layout.configuration(x0[:layout.nq])
    data = model.evaluate(config, V_m=np.zeros(model.counts.m))
    task = make_task(model, config, data, amplitude=demo.amplitude, frequency=demo.frequency, gain=demo.task_gain)
    settings = ControlSettings(gain=demo.gain * np.asarray(data.M_q, float), force_gain=demo.force_gain,
                               eta_fd=np.asarray(demo.eta_fd, float) if demo.eta_fd else None, adapt=adapt)
    if backend == "dense":
        return ClosedLoop(model, params, p0, task, settings, contact), x0
    from .closed_loop_generated import GeneratedClosedLoop

    return GeneratedClosedLoop(model, params, p0, task, settings, contact, backend=backend), x0


def run_demo(demo: Demo | str, *, t_end: float | None = None, samples: int = 161,
             rtol: float | None = None, backend: str | None = None, model=None) -> dict[str, ClosedLoopResult]:
    """The demonstration with adaptation and with frozen estimates: ``{"adaptive", "frozen"}``.
    ``t_end`` (default the demonstration's) and ``samples`` are checked before anything runs
    (:func:`~symgen.simulation.closed_loop.check_run`); ``backend`` (default: generated C when a
    compiler is there, else NumPy) and ``model`` (default :func:`demo_model`) as in :func:`setup`."""
    if backend is None:
        from .closed_loop_generated import pick_backend

        backend = pick_backend()
    if isinstance(demo, str):
        if demo not in DEMOS:
            raise ControlInputError(f"no demonstration for {demo!r}; choose from {', '.join(DEMOS)}")
        demo = DEMOS[demo]
    t_end = demo.t_end if t_end is None else t_end
    rtol = demo.rtol if rtol is None else rtol
    check_run(t_end, samples)
    if not (isinstance(rtol, (int, float)) and 1e-14 <= rtol <= 1e-2):
        raise ControlInputError(f"rtol = {rtol!r}: give a relative tolerance >= 1e-14 and <= 1e-2")
    out, model = {}, demo_model(demo) if model is None else model
    for label, adapt in (("adaptive", True), ("frozen", False)):
        loop, x0 = setup(demo, adapt=adapt, backend=backend, model=model)
        out[label] = run_closed_loop(loop, x0, t_end, samples=samples, rtol=rtol, atol=rtol * 1e-2,
                                     method="RK45", label=f"{label} run")
    return out
