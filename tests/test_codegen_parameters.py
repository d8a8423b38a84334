"""Inertial parameters as run-time inputs ``p`` of the generated functions
(:mod:`symgen.codegen.parameters`): with a changed ``p`` the generated code equals the dense model
of the scene re-derived with those values (NumPy and C, an open and a closed chain) and
Pinocchio's RNEA with the changed inertia; with ``p`` at its defaults it equals the folded code;
bad names, lengths and physically impossible vectors are refused by name."""
from __future__ import annotations

import importlib.util
import json
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import symgen
from symgen.cli.commands import main
from symgen.codegen.generate import generate, trace_all
from symgen.codegen.parameters import check_parameter_vector, parameterise
from symgen.codegen.reference import ReferenceState, reference_states
from symgen.codegen.runtime import call_by_name, load_generated
from symgen.errors import CodegenError, SceneError
from symgen.io.urdf.examples import ur5

from .codegen_util import relative_error

_SPEC = importlib.util.spec_from_file_location(
    "parameter_ops", Path(__file__).resolve().parents[1] / "benchmarks" / "parameter_ops.py")
BENCHMARK = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(BENCHMARK)
#: the UR5 holding a payload body (the benchmark's scene)
ur5_with_payload = BENCHMARK.ur5_with_payload

#: generated code with run-time parameters against a dense model re-derived with their values
TOL = 1e-12
#: a wrong parameter vector must miss the reference by far more than TOL
PLANTED = 1e-6
FUNCTIONS = ["inverse_dynamics", "mass_matrix", "forward_dynamics", "gravity", "coriolis_times_v"]
#: the payload's declared values and a different, physically possible, set (mass, com, inertia)
HEAVIER = (3.0, (0.03, -0.01, 0.08), (0.02, 0.03, 0.025, -0.002, 0.001, 0.0))


def flat(values) -> np.ndarray:
    mass, com, inertia = values
    return np.array([mass, *com, *inertia], dtype=float)


def four_bar(values=None):
    scene = symgen.load("four_bar")
    if values is not None:
        mass, com, inertia = values
        old = scene.bodies["coupler"]
        scene.bodies["coupler"] = type(old)("coupler", *_exact(scene, mass, com, inertia))
    return scene


def _exact(scene, mass, com, inertia):
    probe = symgen.Scene("probe")
    body = probe.add_body("b", mass, com=list(com), inertia=list(inertia))
    return body.mass, body.com, body.inertia


#: (name, scene builder, chosen parameters, the other values of them)
CASES = {"ur5_payload": (ur5_with_payload, ["payload"], HEAVIER),
         "four_bar_coupler": (four_bar, ["coupler"], (0.9, (0.12, 0.01, -0.02), (6e-5, 0.006, 0.006, 0.0, 0.0, 1e-5)))}


@pytest.fixture(scope="module", params=sorted(CASES))
def case(request):
    build, chosen, other = CASES[request.param]
    model = symgen.derive(build())
    lowered = trace_all(model, FUNCTIONS, parameters=chosen)
    folded = trace_all(model, FUNCTIONS)
    modules = {t: load_generated(model, t, lowered=lowered) for t in ("numpy", "c")}
    plain = {t: load_generated(model, t, lowered=folded) for t in ("numpy", "c")}
    return request.param, model, symgen.derive(build(other)), flat(other), modules, plain


@pytest.mark.parametrize("target", ["numpy", "c"])
def test_generated_with_p_equals_the_model_rederived_with_those_values(case, target):
    name, _, other_model, p, modules, _ = case
    for state in reference_states(other_model, 2, seed=3):
        ref = ReferenceState(other_model, state, other_model.float_field)
        for fn in FUNCTIONS:
            got = call_by_name(modules[target], fn, {**state, "p": p})
            for g, (out, want) in zip(got, ref.outputs(fn).items(), strict=True):
                assert relative_error(g, want) < TOL, f"{name} {fn} {out}"


@pytest.mark.parametrize("target", ["numpy", "c"])
def test_a_batch_takes_one_p_per_state(case, target):
    """Five states (more than a C lane group), each with its own payload: the batch equals the
    single calls."""
    name, model, _, p, modules, _ = case
    module = modules[target]
    states = reference_states(model, 5, seed=6)
    ps = np.array([module.DEFAULT_PARAMETERS + k / 4 * (p - module.DEFAULT_PARAMETERS) for k in range(5)])
    q, qd, qdd = (np.array([s[k] for s in states]) for k in ("q", "qd", "qdd"))
    batch = module.inverse_dynamics(q, qd, qdd, ps)
    for k, s in enumerate(states):
        assert relative_error(batch[k], module.inverse_dynamics(s["q"], s["qd"], s["qdd"], ps[k])) < TOL, name


def test_a_planted_wrong_p_misses_the_rederived_model(case):
    name, model, other_model, p, modules, _ = case
    module = modules["numpy"]
    state = reference_states(other_model, 1, seed=3)[0]
    want = ReferenceState(other_model, state, other_model.float_field).outputs("mass_matrix")["M"]
    got, = call_by_name(module, "mass_matrix", {**state, "p": module.DEFAULT_PARAMETERS})
    assert relative_error(got, want) > PLANTED, name


@pytest.mark.parametrize("target", ["numpy", "c"])
def test_generated_with_default_p_equals_the_folded_code(case, target):
    name, model, _, _, modules, plain = case
    defaults = modules[target].DEFAULT_PARAMETERS
    for state in reference_states(model, 2, seed=4):
        for fn in FUNCTIONS:
            got = call_by_name(modules[target], fn, {**state, "p": defaults})
            for g, w in zip(got, call_by_name(plain[target], fn, state), strict=True):
                assert relative_error(g, w) < TOL, f"{name} {fn}"


def test_generated_inverse_dynamics_equals_pinocchio_rnea_with_the_changed_inertia():
    """Pinocchio reads the UR5 from its URDF; the wrist's inertia is replaced there by
    ``pin.Inertia(m, c, I_c)``, independently of symgen's tree frames."""
    pytest.importorskip("pinocchio", reason="pin (Pinocchio) is not installed (extra 'oracle')")
    from symgen.oracle.pinocchio_model import pinocchio_robot

    scene = ur5()
    model = symgen.derive(scene)
    robot = pinocchio_robot(scene)
    module = load_generated(model, "c", ["inverse_dynamics"], parameters=["wrist_3_link"])
    p = np.array([2.0, 0.01, -0.02, 0.03, 0.004, 0.005, 0.006, 0.0005, -0.0003, 0.0002])
    inertia = np.array([[p[4], p[7], p[8]], [p[7], p[5], p[9]], [p[8], p[9], p[6]]])
    robot.model.inertias[robot.joints["wrist_3_joint"]] = robot.pin.Inertia(p[0], p[1:4], inertia)
    idx = robot.v_index(model.coordinate_names())
    for state in reference_states(model, 3, seed=8):
        v, a = np.zeros(robot.model.nv), np.zeros(robot.model.nv)
        v[idx], a[idx] = state["qd"], state["qdd"]
        want = robot.pin.rnea(robot.model, robot.model.createData(), robot.q_vector(state["config"]), v, a)[idx]
        got, = call_by_name(module, "inverse_dynamics", {**state, "p": p})
        assert relative_error(got, want) < TOL
        default, = call_by_name(module, "inverse_dynamics", {**state, "p": module.DEFAULT_PARAMETERS})
        assert relative_error(default, want) > PLANTED


# ------------------------------------------------------------------ files
def test_no_parameters_leave_the_files_unchanged_and_the_request_lists_names_and_defaults():
    model = symgen.derive(four_bar())
    plain = generate(model, "c", ["mass_matrix"])
    same = generate(model, "c", ["mass_matrix"], parameters=[])
    assert plain.files == same.files
    gen = generate(model, "c", ["mass_matrix"], parameters=["coupler.mass", "rocker.com"])
    names = ["coupler.mass", "rocker.com_x", "rocker.com_y", "rocker.com_z"]
    ops = json.loads(gen.files["ops.json"])["parameters"]
    assert ops["names"] == names
    assert ops["defaults"] == [0.6, 0.05, 0.0, 0.0]      # four_bar.yaml: coupler m 0.6, rocker com x 0.05
    header = gen.files["four_bar.h"]
    assert "#define FOUR_BAR_N_PARAMETERS 4" in header
    assert all(f"p[{i}] {n}" in header for i, n in enumerate(names))
    assert "const double *p" in gen.files["four_bar.c"]


def test_cli_payload_writes_parameterised_files(tmp_path, capsys):
    out = tmp_path / "gen"
    assert main(["generate", "four_bar", "--target", "numpy", "--out", str(out), "--functions", "mass_matrix",
                 "--payload", "coupler"]) == 0
    ops = json.loads((out / "ops.json").read_text())
    assert ops["parameters"]["names"][0] == "coupler.mass" and len(ops["parameters"]["names"]) == 10


def test_cli_ops_counts_with_parameters_and_refuses_them_with_fit(capsys):
    assert main(["ops", "four_bar", "--functions", "mass_matrix", "--json", "--payload", "coupler"]) == 0
    assert main(["ops", "--fit", "chain", "--payload", "link1"]) == 2
    assert "--fit counts the family with every constant folded" in capsys.readouterr().err


# ------------------------------------------------------------------ refusals
@pytest.mark.parametrize("request_, named", [(["gripper"], "'gripper'"), (["coupler.mas"], "'mas'"),
                                             ([""], "''"), ([3], "3")])
def test_an_unknown_body_or_parameter_is_refused_by_name(request_, named):
    model = symgen.derive(four_bar())
    with pytest.raises(CodegenError, match=named):
        trace_all(model, ["mass_matrix"], parameters=request_)


@pytest.mark.parametrize("function", ["inverse_dynamics_derivatives", "control"])
def test_derivative_and_controller_functions_refuse_parameters(function):
    model = symgen.derive(four_bar())
    with pytest.raises(CodegenError, match=function):
        trace_all(model, [function], {"gain": 2.0} if function == "control" else None, parameters=["coupler"])


def load_scene(value):
    """The four-bar whose coupler's mass is the declared parameter ``m_load``."""
    scene = four_bar()
    m_load = scene.add_parameter("m_load", value)
    old = scene.bodies["coupler"]
    scene.bodies["coupler"] = type(old)("coupler", m_load, old.com, old.inertia)
    return scene


def test_a_declared_scene_parameter_becomes_an_input_and_is_checked_in_its_body():
    model = symgen.derive(load_scene(0.6))
    module = load_generated(model, "numpy", ["inverse_dynamics"], parameters=["m_load"])
    assert module.PARAMETER_NAMES == ("m_load",) and list(module.DEFAULT_PARAMETERS) == [0.6]
    heavier = symgen.derive(load_scene(1.1))
    for state in reference_states(heavier, 2, seed=5):
        want = ReferenceState(heavier, state, heavier.float_field).outputs("inverse_dynamics")["tau"]
        got, = call_by_name(module, "inverse_dynamics", {**state, "p": np.array([1.1])})
        assert relative_error(got, want) < TOL
    scene, chosen = parameterise(model.scene, ["m_load"])
    with pytest.raises(SceneError, match="coupler.*negative"):
        check_parameter_vector(scene, chosen, [-0.5])


@pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler on this machine")
def test_the_standalone_c_test_program_passes_with_parameters(tmp_path):
    gen = generate(symgen.derive(four_bar()), "c", parameters=["coupler"])
    for name, text in gen.files.items():
        (tmp_path / name).write_text(text)
    exe = tmp_path / "check"
    subprocess.run(["cc", "-std=c99", "-O2", "-Wall", "-Wextra", "-pedantic", "-Werror", "-o", str(exe),
                    str(tmp_path / "test_four_bar.c"), str(tmp_path / "four_bar.c"), "-lm"], check=True)
    run = subprocess.run([str(exe)], capture_output=True, text=True)
    assert run.returncode == 0 and run.stdout.strip().endswith("ok"), run.stdout


@pytest.mark.parametrize("target", ["numpy", "c"])
def test_a_parameter_array_of_the_wrong_length_is_refused_by_the_generated_module(target):
    model = symgen.derive(four_bar())
    module = load_generated(model, target, ["mass_matrix"], parameters=["coupler.mass"])
    state = reference_states(model, 1)[0]
    with pytest.raises(ValueError, match="p"):
        module.mass_matrix(state["q"], np.array([0.6, 0.1]))


@pytest.mark.parametrize("values, complaint", [
    ((-1.0, (0, 0, 0), (0.01, 0.01, 0.01, 0, 0, 0)), "negative"),
    ((1.0, (0, 0, 0), (0.01, 0.01, 0.05, 0, 0, 0)), "triangle"),
    ((1.0, (0, 0, 0), (0.01, 0.01, 0.01, 0.02, 0, 0)), "semi-definite|triangle|eigen")])
def test_a_physically_impossible_parameter_vector_is_refused_naming_the_body(values, complaint):
    scene, chosen = parameterise(ur5_with_payload(), ["payload"])
    with pytest.raises(SceneError, match="payload") as err:
        check_parameter_vector(scene, chosen, flat(values))
    assert err.match(complaint)


def test_a_possible_parameter_vector_passes_and_a_wrong_length_is_refused():
    scene, chosen = parameterise(ur5_with_payload(), ["payload"])
    assert np.array_equal(check_parameter_vector(scene, chosen, flat(HEAVIER)), flat(HEAVIER))
    with pytest.raises(SceneError, match="payload.mass"):
        check_parameter_vector(scene, chosen, flat(HEAVIER)[:4])
