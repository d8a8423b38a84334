"""The MJCF reader's allow-list: what changes MuJoCo's dynamics is read with MuJoCo's meaning or
refused with a located :class:`MjcfError`; what does not is accepted and changes nothing. The
numbers MuJoCo produces for the accepted variants are compared in ``test_mjcf_mujoco.py``; here
the expected values are written out from MuJoCo's documented rules."""
from __future__ import annotations

import pathlib
import time

import pytest
import sympy as sp

from symgen.errors import SymgenError
from symgen.io.loading import load
from symgen.io.mjcf import MjcfError, parse_mjcf_text, scene_from_mjcf_model

DATA = pathlib.Path(__file__).parent / "data" / "mjcf"
#: a refused number must be refused at once (the text is judged before any conversion)
FAST = 2.0

ROBOT = """<mujoco model="m">
  {top}
  <worldbody>
    <body name="link">
      <joint name="q"{joint}/>
      <inertial pos="0.1 0 0" mass="1" diaginertia="0.01 0.02 0.02"/>
      {body}
    </body>
    {world}
  </worldbody>
  {bottom}
</mujoco>"""


def robot(top: str = "", joint: str = "", body: str = "", world: str = "", bottom: str = "") -> str:
    return ROBOT.format(top=top, joint=joint, body=body, world=world, bottom=bottom)


def read(text: str):
    return scene_from_mjcf_model(parse_mjcf_text(text, "robot.xml"))


def refusal(text: str) -> MjcfError:
    with pytest.raises(MjcfError) as info:
        read(text)
    return info.value


# ------------------------------------------------------------------ refused: located, typed
@pytest.mark.parametrize("text, element, line, words", [
    (robot(body="<freejoint/>"), "<joint name='q'>", 5, "a free joint must be its body's only joint"),
    (robot(joint=' type="free" damping="1"'), "<joint name='q'>", 5, "damping on a free joint is not read"),
    (robot(world='<replicate count="2"><body name="c"/></replicate>'), "<replicate>", 9, "write the bodies out"),
    (robot(world='<include file="more.xml"/>'), "<include>", 9, "not read from a file"),
    (robot(top='<include file="more.xml"/>'), "<include>", 2, "not read from a file"),
    (robot(body='<attach model="arm" prefix="a"/>'), "<attach>", 7, "write the bodies out"),
    (robot(body='<plugin plugin="mujoco.elasticity.cable"/>'), "<plugin>", 7, "plugin"),
    (robot(top='<extension><plugin plugin="x"/></extension>'), "<extension>", 2, "plugin"),
    (robot(top='<tendon><fixed name="t" stiffness="1"><joint joint="q" coef="1"/></fixed></tendon>'),
     "<fixed name='t'>", 2, "a tendon spring"),
    (robot(top='<tendon><fixed name="t" damping="1"><joint joint="q" coef="1"/></fixed></tendon>'),
     "<fixed name='t'>", 2, "tendon damping"),
    (robot(top='<default><tendon frictionloss="1"/></default><tendon><spatial name="t"><site site="a"/></spatial>'
               '</tendon>'), "<tendon>", 2, "tendon friction loss"),
    (robot(bottom='<equality><joint joint1="q"/></equality>'), "<joint>", 11, "needs joint1 and joint2"),
    (robot(bottom='<equality><tendon tendon1="t"/></equality>'), "<tendon>", 11, "'t' is not a declared, named tendon"),
    (robot(bottom='<equality><flex flex="f"/></equality>'), "<flex>", 11, "couplings of flexes"),
    (robot(bottom='<actuator><damper joint="q" kv="1"/></actuator>'), "<damper>", 11, "opposes the joint's velocity"),
    (robot(bottom='<actuator><muscle joint="q"/></actuator>'), "<muscle>", 11, "own state"),
    (robot(bottom='<actuator><motor/></actuator>'), "<motor>", 11, "needs a transmission"),
    (robot(world='<frame><joint name="k"/></frame>'), "<joint name='k'>", 9, "the world cannot move"),
    (robot(joint=' foo="1"'), "<joint name='q'>", 5, "attribute 'foo' is not read"),
    (robot(body="<foo/>"), "<foo>", 7, "<foo> inside <body> is not an element symgen reads"),
    (robot(joint=' class="missing"'), "<joint>", 5, "default class 'missing' is not declared"),
    (robot(body='<site name="s" fromto="0 0 0 1 0 0"/>'), "<site name='s'>", 7, "fromto needs a site of type"),
])
def test_what_symgen_cannot_model_is_refused_with_element_and_line(text, element, line, words):
    err = refusal(text)
    assert (err.element, err.line) == (element, line) and words in str(err), str(err)
    assert f"robot.xml, line {line}" in str(err)


@pytest.mark.parametrize("text, element, line, words", [
    (robot(joint=' springdamper="0.1 0"'), "<joint name='q'>", 5, "both numbers must be positive"),
    (robot(joint=' type="ball" springdamper="0.1 1"'), "<joint name='q'>", 5, "springdamper on a ball joint"),
    (robot(top='<compiler boundmass="0.1"/>'), "<compiler>", 2, "raises smaller masses"),
    (robot(top='<compiler boundinertia="0.1"/>'), "<compiler>", 2, "raises smaller inertias"),
    (robot(top='<option density="1.2"/>'), "<option>", 2, "fluid forces"),
    (robot(top='<option viscosity="0.1"/>'), "<option>", 2, "fluid forces"),
    (robot(bottom='<actuator><motor joint="q" armature="0.1"/></actuator>'), "<motor>", 11, "armature"),
    (robot(bottom='<actuator><motor joint="q" damping="0.1"/></actuator>'), "<motor>", 11, "damping"),
    (robot(top='<default><motor damping="0.1"/></default>', bottom='<actuator><motor joint="q"/></actuator>'),
     "<motor>", 2, "damping"),
])
def test_values_that_change_the_dynamics_are_refused(text, element, line, words):
    err = refusal(text)
    assert (err.element, err.line) == (element, line) and words in str(err), str(err)


def test_body_gravcomp_and_mocap_are_refused():
    gravcomp = robot().replace('<body name="link">', '<body name="link" gravcomp="1">')
    assert "gravity compensation" in str(refusal(gravcomp))
    assert "mocap" in str(refusal(robot().replace('<body name="link">', '<body name="link" mocap="true">')))


NO_INERTIAL = '<inertial pos="0.1 0 0" mass="1" diaginertia="0.01 0.02 0.02"/>'


@pytest.mark.parametrize("geom, words", [
    ('<geom type="mesh" mesh="m"/>', "mesh 'm' is not declared in <asset>"),
    ('<geom type="box" mesh="m"/>', "fitted to the mesh by MuJoCo"),
    ('<geom type="hfield" hfield="h"/>', "a hfield geom"),
    ('<geom type="box" size="0.1 0.1"/>', "needs 3 positive numbers"),
    ('<geom type="capsule" size="0.1 -0.2"/>', "must be positive"),
    ('<geom type="sphere" size="0.1" fromto="0 0 0 0 0 1"/>', "fromto is not read for a sphere"),
    ('<geom type="capsule" size="0.1" fromto="0 0 1 0 0 1"/>', "the two points must differ"),
    ('<geom size="0.1" shellinertia="true"/>', "shellinertia"),
    ('<geom size="0.1" density="-1"/>', "density must not be negative"),
    ('<geom size="0.1" mass="-1"/>', "mass must not be negative"),
])
def test_geoms_whose_inertia_symgen_does_not_compute_are_refused_by_name(geom, words):
    err = refusal(robot(body=geom).replace(NO_INERTIAL, ""))
    assert err.element.startswith("<geom") and err.line == 7 and words in str(err), str(err)


def test_a_mesh_geom_is_accepted_beside_an_explicit_inertial():
    assert read(robot(body='<geom type="mesh" mesh="m"/>')).bodies["link"].mass == 1


def test_weld_torquescale_zero_and_half_site_equalities_are_refused():
    sites = dict(body='<site name="s"/>', world='<site name="w"/>')
    assert "torquescale" in str(refusal(robot(**sites, bottom='<equality><weld site1="s" site2="w" torquescale="0"/>'
                                                             '</equality>')))
    assert "not both" in str(refusal(robot(**sites, bottom='<equality><connect site1="s" body1="link" anchor="0 0 0"/>'
                                                           '</equality>')))


def test_a_document_type_declaration_is_refused():
    text = '<!DOCTYPE mujoco [<!ENTITY m "1">]>\n' + robot().replace('mass="1"', 'mass="&m;"')
    assert "document type declaration" in str(refusal(text))


# ------------------------------------------------------------------ numbers
@pytest.mark.parametrize("value, words", [
    ("1e99999999", "exponent 99999999 has more than 3 digits"),
    ("9" * 5000, "5000 digits in a row"),
    ("1e31", "outside the range"),
    ("pi", "is not a finite decimal number"),
    ("1/3", "is not a finite decimal number"),
    ("nan", "is not a finite decimal number"),
    ("inf", "is not a finite decimal number"),
    ("0x10", "is not a finite decimal number"),
])
def test_numbers_are_plain_decimals_within_the_shared_limits(value, words):
    start = time.perf_counter()
    err = refusal(robot().replace('mass="1"', f'mass="{value}"'))
    assert time.perf_counter() - start < FAST
    assert err.element == "<inertial>" and err.line == 6 and words in str(err), str(err)


def test_a_direction_whose_components_differ_beyond_the_bound_is_refused_at_once():
    start = time.perf_counter()
    err = refusal(robot(joint=' type="slide" axis="1e308 1 1"'))
    assert time.perf_counter() - start < FAST and "differ in magnitude by more than a factor 1e30" in str(err)


def test_decimal_forms_are_read_exactly():
    scene = read(robot(joint=' damping="+.5" armature="5." frictionloss="-2.5e-3"').replace("frictionloss=\"-2.5e-3\"",
                                                                                             'frictionloss="2.5e-3"'))
    q = scene.joints["q"]
    assert (q.viscous, q.rotor_inertia, q.coulomb) == (sp.Rational(1, 2), 5, sp.Rational(1, 400))


def test_a_non_ascii_model_name_is_accepted_as_an_identifier():
    assert read(robot().replace('model="m"', 'model="robôt ñ"')).name == "rob_t__"
    assert read(robot().replace('model="m"', 'model="ロボット"')).name == "mjcf_robot"
    assert read(robot().replace('model="m"', f'model="{"a" * 100}"')).name == "a" * 64


# ------------------------------------------------------------------ read with MuJoCo's meaning
def test_default_classes_resolve_as_mujoco():
    """main, childclass on a body (inherited by its subtree), class= on an element, a class
    inheriting from another: values from tests/data/mjcf/defaults_tree.xml, resolved by hand."""
    j = load(str(DATA / "defaults_tree.xml")).joints
    half = sp.sqrt(2) / 2
    expected = {   # type, axis, rotor inertia (armature), viscous (damping)
        "shoulder": ("revolute", [0, 1, 0], sp.Rational(1, 100), sp.Rational(1, 20)),
        "extend": ("prismatic", [1, 0, 0], sp.Rational(1, 100), sp.Rational(1, 5)),
        "extend2": ("prismatic", [0, half, half], sp.Rational(3, 10), sp.Rational(1, 5)),
        "elbow": ("revolute", [0, 0, 1], sp.Rational(1, 100), sp.Rational(1, 20)),
        "swing": ("revolute", [1, 0, 0], sp.Rational(1, 100), sp.Rational(1, 20)),
    }
    assert {n: (x.type, list(x.axis), x.rotor_inertia, x.viscous) for n, x in j.items()} == expected


def test_a_site_class_orientation_gives_way_to_the_sites_own():
    text = robot(top='<default><site pos="1 2 3" euler="0 0 90"/></default>',
                 body='<site name="a"/><site name="b" quat="1 0 0 0"/>')
    frames = read(text).frames
    assert frames["a"].pose.rotation == sp.ImmutableMatrix([[0, -1, 0], [1, 0, 0], [0, 0, 1]])
    assert frames["b"].pose.rotation == sp.eye(3)
    assert list(frames["b"].pose.translation) == [1, 2, 3]


def test_frames_and_a_second_worldbody_place_their_bodies():
    """slide_link sits in a <frame pos="0.3 0 0" euler="0 90 0"> (eulerseq zyx: a quarter turn about
    y) and its slide has ref 0.05 along x, which the quarter turn sends to -z: the joint origin is
    (0.3, 0, 0) - 0.05 (0, 0, -1). 'pendulum' is in a second <worldbody>."""
    scene = load(str(DATA / "defaults_tree.xml"))
    extend = scene.joints["extend"]
    assert list(extend.origin.translation) == [sp.Rational(3, 10), 0, sp.Rational(1, 20)]
    assert extend.origin.rotation == sp.ImmutableMatrix([[0, 0, 1], [0, 1, 0], [-1, 0, 0]])
    assert scene.joints["swing"].parent == "world" and list(scene.joints["swing"].origin.translation) == [1, 0, 0]


def test_hinge_and_slide_ref_are_the_reference_positions():
    """MuJoCo's qpos0 is ref (degrees here): symgen's q is MuJoCo's qpos, q0 = ref."""
    joints = load(str(DATA / "defaults_tree.xml")).joints
    assert (joints["shoulder"].q0, joints["extend"].q0) == (sp.pi / 12, sp.Rational(1, 20))


def test_all_option_and_compiler_sections_apply_the_last_value_winning():
    text = robot(top='<compiler angle="radian"/><option gravity="0 0 -1" timestep="0.01"/>'
                     '<option gravity="0 -2 0"/><compiler eulerseq="zyx"/>').replace(
        '<body name="link">', '<body name="link" euler="0 0 1.5707963267948966">')
    scene = read(text)
    assert list(scene.gravity) == [0, -2, 0]
    # euler "0 0 a" in zyx order is a turn about x, in radians: compiler sections apply file-wide
    assert scene.joints["q"].origin.rotation == sp.ImmutableMatrix([[1, 0, 0], [0, 0, -1], [0, 1, 0]])


@pytest.mark.parametrize("flag, check", [
    ('gravity="disable"', lambda s: list(s.gravity) == [0, 0, 0]),
    ('damper="disable"', lambda s: s.joints["q"].viscous == 0),
    ('frictionloss="disable"', lambda s: s.joints["q"].coulomb == 0),
    ('passive="disable"', lambda s: s.joints["q"].viscous == 0 and s.joints["q"].coulomb != 0),
])
def test_flags_are_read(flag, check):
    scene = read(robot(top=f"<option><flag {flag}/></option>", joint=' damping="0.5" frictionloss="0.2"'))
    assert check(scene)


def test_neutral_values_are_accepted():
    scene = read(robot(joint=' stiffness="0" springref="2" springdamper="0 0"').replace(
        '<body name="link">', '<body name="link" gravcomp="0" mocap="false">'))
    assert scene.joints["q"].type == "revolute"
    spring_off = read(robot(top='<option><flag spring="disable"/></option>', joint=' stiffness="3"'))
    assert spring_off.joints["q"].type == "revolute" and spring_off.joints["q"].stiffness == 0


def test_a_joint_spring_is_read_from_a_default_class_with_springref_in_the_angle_unit():
    import sympy as sp

    joint = read(robot(top='<default>\n<joint stiffness="2" springref="45"/></default>')).joints["q"]
    assert (joint.stiffness, joint.springref) == (2, sp.pi / 4)


def test_settotalmass_scales_every_mass_and_inertia():
    two = robot(top='<compiler settotalmass="6"/>', body='<body name="tip" pos="0.2 0 0"><joint name="r"/>'
                                                          '<inertial pos="0 0 0" mass="2" diaginertia="1 1 1"/></body>')
    bodies = read(two).bodies      # masses 1 and 2 scaled by 6 / 3
    assert (bodies["link"].mass, bodies["tip"].mass) == (2, 4)
    assert bodies["link"].inertia == sp.ImmutableMatrix(sp.diag(sp.Rational(2, 100), sp.Rational(4, 100),
                                                                 sp.Rational(4, 100)))


def test_inactive_or_disabled_equalities_are_no_constraints_with_a_note():
    sites = dict(body='<site name="s" pos="0.3 0 0"/>', world='<site name="w" pos="0.3 0 0"/>')
    inactive = read(robot(**sites, bottom='<equality><connect site1="s" site2="w" active="false"/></equality>'))
    assert not inactive.constraints and "inactive" in inactive.notes[0]
    by_class = read(robot(**sites, top='<default><equality active="false"/></default>',
                          bottom='<equality><connect site1="s" site2="w"/></equality>'))
    assert not by_class.constraints
    disabled = read(robot(**sites, top='<option><flag equality="disable"/></option>',
                          bottom='<equality><connect site1="s" site2="w"/></equality>'))
    assert not disabled.constraints and "disabled" in disabled.notes[0]


def test_site_based_equalities_constrain_the_sites():
    """A site connect holds the sites' origins together (rows vx vy vz, vz vanishing in the plane);
    a site weld their whole frames (vz wx wy vanishing)."""
    four = load(str(DATA / "four_bar_sites.xml")).constraints["closure"]
    five = load(str(DATA / "five_bar_sites.xml")).constraints["closure"]
    assert (four.frame_a, four.frame_b, four.components) == ("rocker_tip", "ground_D", ("vx", "vy"))
    assert (five.frame_a, five.frame_b, five.components) == ("stub_end", "distal2_end", ("vx", "vy", "wz"))


def test_a_weld_relpose_away_from_the_drawn_pose_leaves_the_loop_open():
    """relpose is body2's pose in body1 (MuJoCo): here not the drawn one, so the loop is open at q0."""
    text = (DATA / "five_bar.xml").read_text().replace('<weld name="closure" body1="stub" body2="distal2"/>',
                                                       '<weld name="closure" body1="stub" body2="distal2" '
                                                       'relpose="0 0 0 1 0 0 0"/>')
    start = time.perf_counter()
    with pytest.raises(MjcfError, match="violated by 0.2") as info:
        scene_from_mjcf_model(parse_mjcf_text(text))
    assert info.value.line == 35 and time.perf_counter() - start < FAST


def test_what_does_not_change_the_dynamics_is_accepted_and_changes_nothing():
    plain = read(robot(bottom='<actuator><motor joint="q"/></actuator>'))
    busy = read(robot(
        top='<size memory="1M"/><statistic extent="2"/><visual><global fovy="30"/></visual>'
            '<asset><texture name="t" type="2d" builtin="flat" width="8" height="8"/></asset>'
            '<custom><numeric name="n" data="1"/></custom><option timestep="0.01" integrator="RK4">'
            '<flag contact="disable" warmstart="disable"/></option>',
        joint=' range="-1 1" limited="true" group="2" solreflimit="0.02 1"',
        body='<geom type="capsule" size="0.02 0.1" rgba="1 0 0 1"/><camera name="c"/><light name="l"/>',
        world='<geom type="plane" size="1 1 0.1"/>',
        bottom='<contact><exclude body1="world" body2="link"/></contact><sensor><jointpos joint="q"/></sensor>'
               '<keyframe><key qpos="0.3"/></keyframe><actuator><position joint="q" kp="10" ctrlrange="-1 1"/>'
               '</actuator>'))
    assert busy.joints == plain.joints and busy.bodies == plain.bodies and busy.gravity == plain.gravity


def test_a_ball_joint_tree_takes_every_rate_or_the_callers_motion_coordinates():
    text = (DATA / "ball_arm.xml").read_text()
    assert {"ball.wx", "ball.wy", "ball.wz"} <= set(read(text).motion.joints)
    scene = scene_from_mjcf_model(parse_mjcf_text(text), motion=dict(frames={"grip": 1},
                                                                     components=["vx", "vy", "wx", "wz"]))
    assert scene.joints["ball"].type == "spherical" and scene.motion.frames == (("grip", 1),)


def test_every_refusal_is_a_symgen_error():
    assert issubclass(MjcfError, SymgenError)


def test_a_tendon_without_passive_force_is_accepted_with_a_note_and_its_actuator_marks_no_joint():
    scene = read(robot(top='<tendon><fixed name="t" range="0 1"><joint joint="q" coef="1"/></fixed></tendon>',
                       bottom='<actuator><motor tendon="t"/></actuator>'))
    assert not scene.joints["q"].actuated and scene.motion.joints == ("q",)
    assert any("tendon <fixed name='t'>" in n and "length limits" in n for n in scene.notes)
    assert any("drives tendon 't', not one joint" in n for n in scene.notes)


def test_jointinparent_drives_its_hinge_as_joint_does():
    assert read(robot(bottom='<actuator><motor jointinparent="q"/></actuator>')).joints["q"].actuated




def test_body_and_site_names_with_spaces_are_read_as_identifiers_and_others_are_refused():
    """The control suite names a body 'pinch site': spaces, dots and hyphens read as '_' (as the
    URDF reader names links); a quote or a parenthesis, which could reach generated code, is
    still a typed error naming the element."""
    scene = read(robot(body='<body name="pinch site" pos="0.2 0 0"><site name="tip-1.a"/>'
                            '<inertial pos="0 0 0" mass="0.1" diaginertia="1e-3 1e-3 1e-3"/></body>'))
    assert "pinch_site" in scene.bodies and "tip_1_a" in scene.frames
    error = refusal(robot(body='<body name="a(b)" pos="0.2 0 0"><inertial pos="0 0 0" mass="0.1" '
                               'diaginertia="1e-3 1e-3 1e-3"/></body>'))
    assert "a(b)" in error.element and "identifiers" in str(error)


def test_a_tree_with_a_joint_coupling_and_too_few_actuators_moves_by_every_uncoupled_joint():
    """Without one actuator per motion DOF, a tree whose only constraints are couplings takes every
    joint but each coupling's first joint as V_m (that joint's rate is given by eq. 10)."""
    text = robot(body='<body name="b2" pos="0.2 0 0"><joint name="q2"/><joint name="q3" axis="0 1 0"/>'
                      '<inertial pos="0.1 0 0" mass="1" diaginertia="0.01 0.02 0.02"/></body>',
                 bottom='<equality><joint joint1="q2" joint2="q" polycoef="0 2 0 0 0"/></equality>')
    scene = read(text)
    assert [c.terms[0][0] for c in scene.constraints.values()] == ["q2"]
    assert scene.motion.joints == ("q", "q3") and "coupling" in " ".join(scene.notes)


def test_a_fluid_medium_is_read_without_its_forces_only_by_option_from_load_and_the_cli(tmp_path):
    import argparse
    import warnings

    from symgen.cli.args import add_scene, load_scene
    from symgen.io.mjcf import FluidWarning

    path = tmp_path / "robot.xml"
    path.write_text(robot(top='<option density="1.2" viscosity="0.1"/>'))
    err = refusal(path.read_text())
    assert err.element == "<option>" and "fluid='ignore'" in str(err) and err.line == 2
    with pytest.raises(SymgenError, match="density"):
        load(str(path))
    with pytest.warns(FluidWarning):
        scene = load(str(path), fluid="ignore")
    assert any("density=6/5 viscosity=1/10" in n for n in scene.notes), scene.notes
    with pytest.raises(SymgenError, match="apply to URDF files only"):
        load(str(path), lock={"q": "0"})
    parser = argparse.ArgumentParser()
    add_scene(parser)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", FluidWarning)
        assert load_scene(parser.parse_args([str(path), "--fluid", "ignore"])).bodies["link"].mass == 1
    with pytest.raises(SymgenError, match="density"):
        load_scene(parser.parse_args([str(path)]))
    # without a medium the option changes nothing and warns nothing
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        plain = tmp_path / "plain.xml"
        plain.write_text(robot())
        assert not any("fluid" in n for n in load(str(plain), fluid="ignore").notes)
