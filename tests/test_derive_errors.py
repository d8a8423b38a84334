"""Bad scenes that only the derivation can detect give typed errors naming the element."""
import pytest

from symgen.io.builtin import get_scene
from symgen.errors import ConstraintError, SingularConfigurationError, SymbolicTooLargeError
from symgen.model import derive
from symgen.scene import Scene


def planar_two_link(elbow_q0: float) -> Scene:
    s = Scene("two_link")
    s.add_body("upper", mass=1, com=[0.5, 0, 0], inertia=[0.01, 0.02, 0.03])
    s.add_body("fore", mass=1, com=[0.5, 0, 0], inertia=[0.01, 0.02, 0.03])
    s.add_joint("shoulder", "revolute", "world", "upper", actuated=True, q0=0.4)
    s.add_joint("elbow", "revolute", "upper", "fore", xyz=[1, 0, 0], actuated=True, q0=elbow_q0)
    s.add_frame("tip", "fore", xyz=[1, 0, 0])
    s.set_motion(frame="tip", components=["vx", "vy"])
    return s


def four_bar(closure_kind: str = "planar_weld", rocker_q0: float = 2.0 * 3.141592653589793 / 3) -> Scene:
    """Parallelogram, crank at 60 degrees; ``rocker_q0`` wrong -> the loop is open."""
    import math
    a, d, th = 0.2, 0.5, math.pi / 3
    s = Scene("fb")
    for name, length in (("crank", a), ("coupler", d), ("rocker", a)):
        s.add_body(name, mass=1, com=[length / 2, 0, 0], inertia=[0.001, 0.01, 0.01])
    s.add_body("pin", mass=0)
    s.add_joint("j1", "revolute", "world", "crank", actuated=True, q0=th)
    s.add_joint("j2", "revolute", "crank", "coupler", xyz=[a, 0, 0], q0=-th)
    s.add_joint("j3", "revolute", "coupler", "rocker", xyz=[d, 0, 0], q0=th + math.pi if rocker_q0 is None else rocker_q0)
    s.add_joint("j4", "revolute", "rocker", "pin", xyz=[a, 0, 0], q0=-th - math.pi)
    s.add_frame("pin_frame", "pin")
    s.add_frame("ground_pin", "world", xyz=[d, 0, 0])
    s.add_constraint("closure", closure_kind, "pin_frame", "ground_pin")
    s.set_motion(joints=["j1"])
    return s


def test_a_consistent_parallelogram_derives():
    assert derive(four_bar(rocker_q0=None)).counts.np == 3


def test_singular_task_map_at_the_reference_configuration_reports_the_condition_number():
    assert derive(planar_two_link(0.7)).counts.n == 2
    with pytest.raises(SingularConfigurationError) as err:
        derive(planar_two_link(0.0))          # arm stretched out: the tip Jacobian is singular
    assert "[J_m; J_f]" in str(err.value) and "reference configuration" in str(err.value)
    assert err.value.condition > 1e10


def test_an_open_loop_at_the_reference_configuration_names_the_constraint():
    with pytest.raises(ConstraintError, match="constraint 'closure'.*violated"):
        derive(four_bar(rocker_q0=2.5))


def test_redundant_constraints_name_the_constraint():
    """A ball closure on a planar loop: its out-of-plane row vz is already enforced by the
    parallel axes, so T loses rank."""
    with pytest.raises(ConstraintError, match="constraint 'closure'") as err:
        derive(four_bar(closure_kind="ball", rocker_q0=None))
    assert "redundant" in str(err.value)


def test_more_constraints_than_joint_coordinates_is_refused():
    with pytest.raises(ConstraintError, match=r"constraints \(closure\).*6 constraint equations but only 4"):
        derive(four_bar(closure_kind="weld", rocker_q0=None))


def test_symbolic_inverse_of_a_large_matrix_is_refused_with_a_typed_error():
    model = derive(get_scene("stewart"))
    with pytest.raises(SymbolicTooLargeError, match="30x30"):
        model.evaluate(model.symbolic_configuration(), field="symbolic")


def test_bad_runtime_state_gets_a_typed_error_naming_the_joint_or_argument():
    from symgen.errors import StateError
    from symgen.math.configuration import Configuration

    model = derive(get_scene("stewart"))
    partial = Configuration({k: v for k, v in model.reference.positions.items() if k != "p3"})
    with pytest.raises(StateError, match="joint 'p3'"):
        model.evaluate(partial)
    broken = Configuration({**model.reference.positions, "s2": 0.3})
    with pytest.raises(StateError, match="joint 's2'.*3x3"):
        model.evaluate(broken)
    with pytest.raises(StateError, match=r"V_m must have shape \(6,\)"):
        model.evaluate(model.reference, V_m=[0.0] * 5)
    with pytest.raises(StateError, match=r"tau must have shape \(6,\)"):
        model.forward_dynamics(model.reference, [0.0] * 6, tau=[1.0] * 7)


def test_a_passive_joint_whose_column_of_T_is_rounding_noise_is_a_free_passive_coordinate():
    """arm_on_plane's base joint turns about the plane's normal, so the contact does not constrain
    it: its column of T is rounding noise (1e-17), judged against the whole of T (Step 4's rank),
    and made passive it becomes an independent unactuated coordinate (q_u2), with n_p = 0."""
    import dataclasses

    import symgen

    scene = symgen.load("arm_on_plane")
    scene.joints["j1"] = dataclasses.replace(scene.joints["j1"], actuated=False)
    model = symgen.derive(scene)
    assert model.counts.np == 0 and model.counts.n1u == 1
    assert [model.tree.coordinates[c].joint for c in model.partition.u2] == ["j1"]


@pytest.mark.parametrize("spatial, planar, words", [("weld", "planar_weld", "no motion is left"),
                                                     ("point", "planar_point", "linearly dependent")])
def test_a_spatial_closure_of_a_planar_loop_names_the_planar_kind(spatial, planar, words):
    """The four-bar closed by a weld (6 rows, m < 0) or a point (3 rows, one vanishing): the error
    says which planar kind closes the same joint."""
    import pathlib

    import symgen
    from symgen.errors import ConstraintError
    from symgen.io.scene_yaml import load_scene

    text = (pathlib.Path(symgen.__file__).parent / "io" / "scenes" / "four_bar.yaml").read_text()
    assert "type: planar_weld" in text
    with pytest.raises(ConstraintError, match=f"{words}.*use {planar} instead of {spatial}"):
        symgen.derive(load_scene(text.replace("type: planar_weld", f"type: {spatial}")))
