"""The cases of the stability suite: stiff problems and extreme scenes, each a state to evaluate
and a short run to integrate.

==========================  ==============================================================
stiff, friction             benchmark chain (n = 3) with viscous friction 1e5 N m s/rad: time
                            constants ~1e-7 s against a 0.05 s run
stiff, contact K            ``arm_on_plane`` whose object is held in the plane by a compliant
                            anchor, ``eta_m = K delta + D d(delta)/dt`` (K = 1e4, 1e6, 1e8,
                            critically damped), ``delta`` = displacement of frame O from its
                            reference pose (x, y, yaw)
extreme, mass ratio         benchmark chain (n = 4), neighbouring links' masses 1e-6 and 1e6 apart
extreme, length             benchmark chain (n = 4) with links 1e-3 m and 1e3 m long
extreme, chain:n=100        the benchmark chain with 100 links
singular, [J_m; J_f]        planar 2R arm, task = tip velocity, elbow almost straight
                            (outstretched): cond [J_m; J_f] = 1e2 .. 1e12; at 1e8 and 1e12 also
                            with forward dynamics by the dense route (``method="dense"``)
singular, dead point        parallelogram four-bar at crank angle theta -> 0 (its dead point):
                            cond [T_u1, T_a1] = 1e4 .. 1e13; refused from 1e8 (the velocity
                            terms lose cond^2 u: symgen.conditioning)
==========================  ==============================================================

Every case says what it expects: ``"accurate"`` (the answer agrees with the 50-digit model to
within what the conditioning allows) or ``"error"`` (a typed error naming the singular matrix
and its condition number).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Callable

import numpy as np

from ..io.builtin import get_scene
from ..codegen.reference import position_vector
from ..model import derive
from ..math.configuration import Configuration
from .scenes import planar_arm, scaled_chain


@dataclass
class Setup:
    """A derived model, the state to evaluate, and the forces of the run."""

    model: object
    config: Configuration
    V_m: np.ndarray
    tau: np.ndarray
    eta_m: Callable | None = None  # (t, q, V_m) -> eta_m, for scenes with contact forces

    @property
    def q(self) -> np.ndarray:
        return position_vector(self.model, self.config)

    def state(self) -> dict:
        """The inputs of the generated functions at ``(config, V_m, tau)``."""
        eta = self.eta_m(0.0, self.q, self.V_m) if self.eta_m else np.zeros(0)
        return dict(q=self.q, V_m=self.V_m, tau=self.tau, eta_m=np.asarray(eta, dtype=float))


@dataclass
class Case:
    """One stability case: ``build()`` gives its :class:`Setup`; ``t_end`` is its run's length."""

    name: str
    kind: str          # "stiff", "extreme" or "singular"
    description: str
    builder: Callable[[], Setup]
    expect: str        # "accurate" or "error"
    t_end: float = 0.05
    slow: bool = False
    reference: str = "mp"   # "mp": the 50-digit dense model; "float": the dense float model
    backend: str | None = None  # forces a backend (chain:n=100: NumPy, so the suite does not wait for cc)
    method: str = "auto"    # forward dynamics' route (generation option): "dense" forms and solves M_mm
    tags: dict = field(default_factory=dict)

    @cached_property
    def setup(self) -> Setup:
        return self.builder()


def _chain_setup(scene, seed: int = 0) -> Setup:
    model = derive(scene)
    rng = np.random.default_rng(seed)
    n = model.counts.n
    config = Configuration({j: float(v) for j, v in zip(scene.joints, rng.uniform(-0.5, 0.5, n))})
    return Setup(model, config, rng.uniform(-0.5, 0.5, n), rng.uniform(-0.1, 0.1, n))


class CompliantAnchor:
    """``eta_m = K delta + D d(delta)/dt`` on frame ``O`` of ``arm_on_plane``: a stiff spring
    holding the object at its reference pose in the plane (``D = 2 sqrt(K)``, critical for a unit
    mass). ``eta_m`` is the force the robot applies to the environment (the joint-space form has
    ``- D_m^T eta_m``), so the robot feels ``-K delta``: a restoring force."""

    def __init__(self, model, stiffness: float):
        from ..simulation.poses import Poses

        self.poses, self.k, self.d = Poses(model), float(stiffness), 2.0 * float(np.sqrt(stiffness))
        rot, pos = self._pose(position_vector(model, model.reference))
        self.p0, self.yaw0 = pos, self._yaw(rot)

    def _pose(self, q):
        rot, pos = self.poses.bodies(q)
        return self.poses.frame(rot, pos, "O")

    @staticmethod
    def _yaw(rot) -> float:
        return float(np.arctan2(rot[1, 0], rot[0, 0]))

    def __call__(self, t, q, v_m) -> np.ndarray:
        rot, pos = self._pose(q)
        planar = rot[:2, :2]                                    # O's x, y axes in the world plane
        delta_xy = planar.T @ (pos - self.p0)[:2]               # in O's axes, like eta_m
        delta_yaw = (self._yaw(rot) - self.yaw0 + np.pi) % (2 * np.pi) - np.pi
        delta = np.array([delta_xy[0], delta_xy[1], delta_yaw])
        return self.k * delta + self.d * np.asarray(v_m, dtype=float)


def stiff_friction() -> Setup:
    return _chain_setup(scaled_chain(3, viscous=100_000, name="chain_n3_viscous"))


def stiff_contact(stiffness: float) -> Callable[[], Setup]:
    def build() -> Setup:
        model = derive(get_scene("arm_on_plane"))
        anchor = CompliantAnchor(model, stiffness)
        return Setup(model, model.reference, np.array([0.05, -0.02, 0.1]), np.zeros(model.counts.n), anchor)
    return build


def mass_ratio(ratio: float) -> Callable[[], Setup]:
    return lambda: _chain_setup(scaled_chain(4, mass_ratio=ratio, name="chain_n4_mass_ratio"))


def link_length(length: float) -> Callable[[], Setup]:
    return lambda: _chain_setup(scaled_chain(4, length=length, name="chain_n4_length"))


def long_chain() -> Setup:
    return _chain_setup(get_scene("chain:n=100"))


def outstretched(condition: float) -> Callable[[], Setup]:
    """Planar arm with ``cond [J_m; J_f] ~ 5 / q2`` (measured: 5.0 / q2 for small q2)."""
    def build() -> Setup:
        model = derive(planar_arm())
        config = Configuration({"j1": 0.3, "j2": 5.0 / condition})
        return Setup(model, config, np.array([0.05, 0.02]), np.array([0.1, -0.05]))
    return build


def dead_point(condition: float) -> Callable[[], Setup]:
    """Parallelogram four-bar at crank angle ``theta``: the closed configuration is exactly
    ``(theta, -theta, theta - pi, pi - theta)``; ``cond [T_u1, T_a1] ~ 21.6 / theta``."""
    def build() -> Setup:
        model = derive(get_scene("four_bar"))
        theta = 21.6 / condition
        config = Configuration({"j1": theta, "j2": -theta, "j3": theta - np.pi, "j4": np.pi - theta})
        return Setup(model, config, np.array([0.01]), np.array([0.01]))
    return build


def all_cases() -> list[Case]:
    """The suite, in report order."""
    cases = [Case("stiff_friction", "stiff", "chain n=3, viscous friction 1e5 N m s/rad", stiff_friction,
                  "accurate")]
    for k in (1e4, 1e6, 1e8):
        cases.append(Case(f"stiff_contact_K{k:.0e}", "stiff",
                          f"arm_on_plane, compliant anchor eta_m = K delta + D delta', K = {k:.0e}",
                          stiff_contact(k), "accurate", t_end=0.02))
    for r in (1e-6, 1e6):
        cases.append(Case(f"mass_ratio_{r:.0e}", "extreme", f"chain n=4, neighbour mass ratio {r:.0e}",
                          mass_ratio(r), "accurate"))
    for length in (1e-3, 1e3):
        cases.append(Case(f"length_{length:.0e}", "extreme", f"chain n=4, link length {length:g} m",
                          link_length(length), "accurate"))
    cases.append(Case("chain_n100", "extreme", "benchmark chain, 100 links", long_chain, "accurate",
                      t_end=0.01, slow=True, reference="float", backend="numpy"))
    for c in (1e2, 1e4, 1e6, 1e8, 1e12):
        # the articulated-body route solves with A only and never forms M_mm: accurate up to cond A = 1e12
        cases.append(Case(f"outstretched_{c:.0e}", "singular", f"planar 2R arm, cond [J_m; J_f] ~ {c:.0e}",
                          outstretched(c), "accurate", t_end=0.01))
    for c in (1e8, 1e12):
        # the dense route: M_mm = A^-T M_q A^-1 has about 0.1 cond(A)^2, beyond 1e12 the generated solve refuses it
        cases.append(Case(f"outstretched_dense_{c:.0e}", "singular", f"planar 2R arm, cond [J_m; J_f] ~ {c:.0e}, "
                          "forward dynamics by the dense route", outstretched(c), "error", t_end=0.01, method="dense"))
    for c in (1e4, 1e6, 1e9, 1e10, 1e13):
        # the velocity terms lose cond(W)^2 u: refused above symgen.conditioning.MAX_LOOP_CONDITION (the
        # generated code holds its pivot-ratio estimate, which runs below the 2-norm condition, to MAX_LOOP_ESTIMATE)
        cases.append(Case(f"dead_point_{c:.0e}", "singular", f"four-bar near its dead point, "
                          f"cond [T_u1, T_a1] ~ {c:.0e}", dead_point(c), "accurate" if c <= 1e6 else "error",
                          t_end=0.01))
    return cases


def get_case(name: str) -> Case:
    from ..errors import SymgenError

    for case in all_cases():
        if case.name == name:
            return case
    raise SymgenError(f"unknown stability case {name!r}; choose from {', '.join(c.name for c in all_cases())}")
