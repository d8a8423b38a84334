"""The constrained forward-dynamics benchmark reads only the generated function's public signature:
check its header parsing against every built-in's generated C, and its export of the Pinocchio
model (the Stewart platform's legs as five balls)."""
import importlib.util
import pathlib

import pytest

from symgen.io.builtin import get_scene
from symgen.codegen.reference import position_vector
from symgen.model import derive

ROOT = pathlib.Path(__file__).resolve().parent.parent
GENERATED = {"four_bar": "four_bar", "five_bar": "five_bar", "stewart": "stewart", "arm_on_plane": "arm_on_plane",
             "multi_arm:h=2": "multi_arm_h2", "chain:n=6": "chain_n6"}


def _bench():
    spec = importlib.util.spec_from_file_location("constrained_forward", ROOT / "benchmarks" / "constrained_forward.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("scene", sorted(GENERATED))
def test_signature_is_read_from_the_generated_header(scene):
    model = derive(get_scene(scene))
    folder = GENERATED[scene]
    sig = _bench().signature(ROOT / "generated" / folder / "c", folder)
    cf = model.scene.contact_forces
    assert sig["func"] == f"symgen_{folder}_forward_dynamics"
    assert sig["NQ"] == len(position_vector(model, model.reference))
    assert (sig["NM"], sig["NT"]) == (model.counts.m, model.counts.n)
    assert sig["NE"] == (len(cf.components) if cf else 0)
    assert sig["NF"] == model.counts.n - model.counts.m


def test_stewart_model_file_has_five_ball_constraints(tmp_path):
    pytest.importorskip("pinocchio", reason="pin (Pinocchio) is not installed (extra 'oracle')")
    from symgen.oracle.pinocchio_tree import tree_robot

    model = derive(get_scene("stewart"))
    robot = tree_robot(model, drop_massless_spherical_leaves=True)
    rows = _bench().write_model(robot, tmp_path / "stewart.model")
    lines = (tmp_path / "stewart.model").read_text().splitlines()
    assert rows == 15 and lines[0].split() == [str(robot.model.nq), "21", str(robot.model.njoints - 1)]
    assert lines[robot.model.njoints + 4] == "5"         # after joints, armature, damping, coulomb, gravity
    constraint_lines = lines[robot.model.njoints + 5:robot.model.njoints + 10]
    assert [line.split()[0] for line in constraint_lines] == ["3"] * 5


def _floating_bench():
    spec = importlib.util.spec_from_file_location("floating_base", ROOT / "benchmarks" / "floating_base.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_standing_robot_is_exported_on_a_free_flyer_with_one_contact_per_foot(tmp_path):
    pytest.importorskip("pinocchio", reason="pin (Pinocchio) is not installed (extra 'oracle')")
    fb = _floating_bench()
    model = derive(get_scene("solo12_standing"))
    pmodel = fb.free_flyer_model("solo12")
    from symgen.io.coordinates import CoordinateMap

    rows = fb.contact_model_file(model, pmodel, CoordinateMap.pinocchio(model.scene, pmodel), tmp_path / "solo.model")
    lines = (tmp_path / "solo.model").read_text().splitlines()
    assert rows == 12 and lines[1].split()[:2] == ["0", "FF"]
    contacts = lines[pmodel.njoints + 5:pmodel.njoints + 9]
    assert [line.split()[0] for line in contacts] == ["3"] * 4 and lines[-2] == "0 6 0 1 2 3 4 5"


def test_standing_robot_base_acceleration_maps_pinocchios_to_symgens():
    """Pinocchio's constraintDynamics (Python, four CONTACT_3D) at the benchmark's states, mapped by
    base_acceleration, equals Model.forward_dynamics; unmapped (a planted error) it does not."""
    pin = pytest.importorskip("pinocchio", reason="pin (Pinocchio) is not installed (extra 'oracle')")
    import numpy as np

    from symgen.io.coordinates import CoordinateMap

    fb = _floating_bench()
    model = derive(get_scene("solo12_standing"))
    pmodel = fb.free_flyer_model("solo12")
    states = fb.constrained_states(model, CoordinateMap.pinocchio(model.scene, pmodel), 3)
    frames = [pmodel.frames[pmodel.getFrameId(c.frame_a)] for c in model.scene.constraints.values()]
    cmodels = pin.StdVec_RigidConstraintModel([pin.RigidConstraintModel(
        pin.ContactType.CONTACT_3D, pmodel, f.parentJoint, f.placement, pin.ReferenceFrame.LOCAL) for f in frames])
    cdatas = pin.StdVec_RigidConstraintData([c.createData() for c in cmodels])
    data = pmodel.createData()
    pin.initConstraintDynamics(pmodel, data, cmodels, cdatas)
    a_pin = np.array([pin.constraintDynamics(pmodel, data, q, v, u, cmodels, cdatas)[:6]
                      for q, v, u in zip(states["q_pin"], states["v_pin"], states["tau_pin"])])
    want = np.array([model.forward_dynamics(c, v, t)[0] for c, v, t in zip(states["config"], states["V_m"],
                                                                           states["tau"])])
    scale = np.abs(want).max()
    assert np.abs(fb.base_acceleration(model, states, a_pin) - want).max() <= 1e-12 * scale
    assert np.abs(a_pin - want).max() > 1e-3 * scale


def test_derivative_benchmark_reads_every_output_of_the_generated_header(tmp_path):
    """The Jacobian timing places each output matrix of ``forward_dynamics_derivatives`` by the
    sizes in the header: names, order and sizes as the function's outputs."""
    from symgen.codegen.generate import generate

    spec = importlib.util.spec_from_file_location("constrained_derivatives",
                                                  ROOT / "benchmarks" / "constrained_derivatives.py")
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    model = derive(get_scene("five_bar"))
    gen = generate(model, "c", [bench.FUNCTION])
    (tmp_path / f"{gen.module}.h").write_text(gen.files[f"{gen.module}.h"])
    sig = bench.signature(tmp_path, gen.module)
    m, n, nq = model.counts.m, model.counts.n, len(position_vector(model, model.reference))
    assert sig["func"] == f"symgen_{gen.module}_forward_dynamics_derivatives"
    assert (sig["NQ"], sig["NM"], sig["NT"]) == (nq, m, n)
    assert sig["outputs"] == [("ddV_m_dq", m * nq), ("ddV_m_dV_m", m * m), ("ddV_m_dtau", m * n)]
