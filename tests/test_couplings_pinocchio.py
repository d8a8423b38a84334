"""URDF ``<mimic>`` joints read as joint couplings, checked against an independent KKT solve built
from Pinocchio's ``crba`` and ``nonLinearEffects`` (Pinocchio's own parser treats the mimicking
joints as free joints; the coupling rows ``[.., 1, .., -a, ..]`` are written here by hand from the
file's numbers)."""
from __future__ import annotations

import numpy as np
import pytest

pin = pytest.importorskip("pinocchio", reason="pin (Pinocchio) is not installed (extra 'oracle')")

from symgen.closure import random_consistent_states  # noqa: E402
from symgen.io.coordinates import CoordinateMap  # noqa: E402
from symgen.io.urdf import scene_from_urdf  # noqa: E402
from symgen.io.urdf.examples import example_path  # noqa: E402
from symgen.model import derive  # noqa: E402
from symgen.oracle.pinocchio_model import pinocchio_robot  # noqa: E402

RTOL = 1e-9
STATES = 5


def baxter_path() -> str:
    import importlib.metadata

    dist = importlib.metadata.distribution("example-robot-data")
    return str(next(dist.locate_file(f) for f in dist.files if str(f).endswith("baxter_description/urdf/baxter.urdf")))


#: file -> {mimicking joint: (leader, multiplier)}, read off the URDF text by hand
ROBOTS = {
    "panda": (lambda: example_path("panda"), {"panda_finger_joint2": ("panda_finger_joint1", 1.0)}),
    "baxter": (baxter_path, {"l_gripper_r_finger_joint": ("l_gripper_l_finger_joint", -1.0),
                             "r_gripper_r_finger_joint": ("r_gripper_l_finger_joint", -1.0)}),
}


def kkt_reference(robot, cmap, names, config, qd_all, force_all, couplings):
    """``[M, -T^T; T, 0] [qdd; lam] = [f - h; 0]`` in Pinocchio's coordinates (``T`` constant, so
    no ``dT/dt qd`` term), mapped back to symgen's order: ``(qdd_all, lam)``."""
    model, data = robot.model, robot.model.createData()
    q, v = cmap.from_symgen(config, dict(zip(names, qd_all)))
    mass = pin.crba(model, data, q)
    mass = np.triu(mass) + np.triu(mass, 1).T
    bias = pin.nonLinearEffects(model, data, q, v)
    index = cmap.velocity_indices(names)
    f = np.zeros(model.nv)
    f[index] = force_all
    t = np.zeros((len(couplings), model.nv))
    for row, (joint, (leader, ratio)) in enumerate(couplings.items()):
        t[row, index[names.index(joint)]] = 1.0
        t[row, index[names.index(leader)]] = -ratio
    nc = len(couplings)
    kkt = np.block([[mass, -t.T], [t, np.zeros((nc, nc))]])
    sol = np.linalg.solve(kkt, np.concatenate([f - bias, np.zeros(nc)]))
    return sol[:model.nv][index], sol[model.nv:]


@pytest.mark.parametrize("robot_name", sorted(ROBOTS))
def test_mimic_dynamics_match_a_pinocchio_kkt_solve(robot_name):
    path, couplings = ROBOTS[robot_name]
    scene = scene_from_urdf(path(), friction=False)
    assert {c.terms[0][0]: (c.terms[1][0], -float(c.terms[1][1])) for c in scene.constraints.values()} == couplings
    assert all(not scene.joints[j].actuated for j in couplings)
    couplings = {c.terms[0][0]: couplings[c.terms[0][0]] for c in scene.constraints.values()}  # lam's order
    model = derive(scene)
    assert (model.counts.nc, model.counts.np) == (len(couplings), len(couplings))
    robot = pinocchio_robot(scene)
    cmap = CoordinateMap.pinocchio(scene, robot.model)
    names = model.all_coordinate_names()
    rng = np.random.default_rng(7)
    for config, v_m in random_consistent_states(model, STATES, seed=11, spread=0.2):
        tau = rng.uniform(-2, 2, model.counts.n)
        out = model.motion(config, v_m, tau=tau)
        force_all = np.zeros(len(names))
        force_all[list(model.partition.independent)] = tau
        qdd_ref, lam_ref = kkt_reference(robot, cmap, names, config, out.qd_all, force_all, couplings)
        scale = np.max(np.abs(qdd_ref))
        assert np.max(np.abs(out.qdd_all - qdd_ref)) <= RTOL * scale
        assert np.max(np.abs(out.lam - lam_ref)) <= RTOL * max(np.max(np.abs(lam_ref)), 1e-3)


def test_the_kkt_check_catches_a_wrong_multiplier():
    """The planted error: Panda's coupling read with multiplier -1 instead of 1 misses the reference."""
    path, couplings = ROBOTS["panda"]
    scene = scene_from_urdf(path(), friction=False)
    model = derive(scene)
    robot = pinocchio_robot(scene)
    cmap = CoordinateMap.pinocchio(scene, robot.model)
    names = model.all_coordinate_names()
    config, v_m = random_consistent_states(model, 1, seed=11, spread=0.2)[0]
    tau = np.full(model.counts.n, 0.5)
    out = model.motion(config, v_m, tau=tau)
    force_all = np.zeros(len(names))
    force_all[list(model.partition.independent)] = tau
    wrong = {"panda_finger_joint2": ("panda_finger_joint1", -1.0)}
    qdd_ref, _ = kkt_reference(robot, cmap, names, config, out.qd_all, force_all, wrong)
    assert np.max(np.abs(out.qdd_all - qdd_ref)) > 1e-3 * np.max(np.abs(qdd_ref))


def test_symgen_check_compares_a_mimic_robot_with_pinocchio():
    """``symgen check`` (:func:`symgen.oracle.check_against_pinocchio`) takes the coupling rows too."""
    from symgen.oracle import check_against_pinocchio

    differences = check_against_pinocchio(derive(scene_from_urdf(example_path("panda"), friction=False)), states=5)
    assert any("lam" in d.quantity for d in differences)
    assert all(d.passed for d in differences), [d.as_dict() for d in differences if not d.passed]
