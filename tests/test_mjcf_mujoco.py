"""The MJCF reader against MuJoCo itself (PyPI ``mujoco``, the independent reference): on the
variants symgen reads (default classes, frames, ``ref``, several sections, ball joints,
``settotalmass``, flags, site and body equalities), the joint-space terms of the tree and the loop
constraints equal MuJoCo's.

Coordinate map. symgen's coordinate of a hinge or slide *is* MuJoCo's ``qpos`` (both equal ``ref``
as drawn, MuJoCo's ``qpos0``: symgen turns the joint origin back by ``ref`` and sets ``q0 = ref``);
a ball joint's rotation is the matrix of MuJoCo's quaternion ``qpos`` (w, x, y, z). symgen's
``qd`` is MuJoCo's ``qvel`` (a ball's three rates: the angular velocity in the body frame in both).
Coordinates are matched by joint name (MuJoCo's ``jnt_dofadr``).

Terms. MuJoCo's mass matrix (``mj_fullM``, armature included) is symgen's ``M_q``; its
``qfrc_bias`` (Coriolis, centrifugal, gravity) is ``C_q qd + G_q - xi`` where ``xi`` is symgen's
friction term (``G_q`` evaluated with ``gravity=False``); its ``qfrc_passive`` (joint damping) is
``-xi`` with friction loss 0 (MuJoCo puts friction loss in its constraint solver). Loops: the rows
of symgen's ``T`` (eq. 6) span the same space as MuJoCo's equality rows of ``efc_J`` (compared as
orthogonal projectors, so the row bases may differ), and MuJoCo's equality residual ``efc_pos``
vanishes on symgen's loop-closed states.
"""
from __future__ import annotations

import copy
import functools
import pathlib

import numpy as np
import pytest

from symgen.closure import random_consistent_states
from symgen.io.mjcf import MjcfError, parse_mjcf_text, scene_from_mjcf_model
from symgen.model import derive
from symgen.math.configuration import Configuration

#: MuJoCo before 3.2.4 ignores euler and axisangle on <inertial>; before 3.3.6 it has no damper and
#: spring flags (one passive flag instead)
mujoco = pytest.importorskip("mujoco", minversion="3.3.6")

DATA = pathlib.Path(__file__).parent / "data" / "mjcf"
#: agreement with MuJoCo, relative to the largest entry of MuJoCo's value
TOL = 1e-10
#: the smallest scale a relative comparison uses (a value of MuJoCo's that is exactly zero)
MIN_SCALE = 1e-6
#: singular values of constraint rows below this (relative) are a rank deficiency
RANK_TOL = 1e-9
STATES = 4
BALL_MOTION = dict(frames={"grip": 1}, components=["vx", "vy", "wx", "wz"])
LOOPS = ["four_bar.xml", "five_bar.xml", "four_bar_sites.xml", "five_bar_sites.xml"]


# ------------------------------------------------------------------ the two sides
def full_mass(m, d) -> np.ndarray:
    """MuJoCo's dense mass matrix (``mj_fullM``: MuJoCo 3 takes ``qM``, MuJoCo 4 the data)."""
    out = np.zeros((m.nv, m.nv))
    if hasattr(d, "qM"):
        mujoco.mj_fullM(m, out, d.qM)
    else:
        mujoco.mj_fullM(m, d, out)
    return out


def quat_matrix(q) -> np.ndarray:
    w, x, y, z = np.asarray(q, float) / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def dof_index(m, names) -> np.ndarray:
    """MuJoCo's dof of each symgen coordinate name (``j`` or ``j.wx``)."""
    out = []
    for name in names:
        joint, _, comp = name.partition(".w")
        out.append(m.jnt_dofadr[m.joint(joint).id] + ("xyz".index(comp) if comp else 0))
    return np.array(out)


def configuration(m, scene, qpos) -> Configuration:
    """symgen's configuration at MuJoCo's ``qpos`` (the coordinate map of the module docstring)."""
    out = {}
    for j in scene.joints.values():
        if j.dof:
            a = m.jnt_qposadr[m.joint(j.name).id]
            out[j.name] = quat_matrix(qpos[a:a + 4]) if j.dof == 3 else float(qpos[a])
    return Configuration(out)


def random_qpos(m, rng) -> np.ndarray:
    qpos = m.qpos0.copy()
    for jid in range(m.njnt):
        a = m.jnt_qposadr[jid]
        if m.jnt_type[jid] == mujoco.mjtJoint.mjJNT_BALL:
            q = rng.normal(size=4)
            qpos[a:a + 4] = q / np.linalg.norm(q)
        else:
            qpos[a] += rng.uniform(-1.0, 1.0)
    return qpos


def mujoco_at(text: str, qpos, qvel):
    m = mujoco.MjModel.from_xml_string(text)
    m.opt.jacobian = mujoco.mjtJacobian.mjJAC_DENSE
    d = mujoco.MjData(m)
    d.qpos[:], d.qvel[:] = qpos, qvel
    mujoco.mj_forward(m, d)
    return m, d


def assert_close(ours, theirs, what: str) -> None:
    err = float(np.max(np.abs(np.asarray(ours) - np.asarray(theirs)))) if np.size(theirs) else 0.0
    scale = max(float(np.max(np.abs(theirs))) if np.size(theirs) else 0.0, MIN_SCALE)
    assert err <= TOL * scale, f"{what}: symgen and MuJoCo differ by {err:.3g} (scale {scale:.3g})"


@functools.lru_cache(maxsize=None)
def text_of(name: str) -> str:
    return (DATA / name).read_text()


@functools.lru_cache(maxsize=None)
def scene_of(text: str, ball: bool = False):
    return scene_from_mjcf_model(parse_mjcf_text(text), motion=BALL_MOTION if ball else None)


@functools.lru_cache(maxsize=None)
def model_of(text: str, tree_only: bool = False, ball: bool = False):
    scene = copy.deepcopy(scene_of(text, ball))
    if tree_only:       # the same bodies and joints without the loop closures: MuJoCo's M and bias
        scene.constraints.clear()
        scene.set_motion(joints=[j.name for j in scene.joints.values() if j.dof])
    return derive(scene)


def compare_tree(text: str, model, seed: int) -> None:
    rng = np.random.default_rng(seed)
    m = mujoco.MjModel.from_xml_string(text)
    idx = dof_index(m, model.coordinate_names())
    for _ in range(STATES):
        qpos, qvel = random_qpos(m, rng), rng.uniform(-1.0, 1.0, m.nv)
        m, d = mujoco_at(text, qpos, qvel)
        config = configuration(m, model.scene, qpos)
        full = model.evaluate(config, qd=qvel[idx])
        xi = model.evaluate(config, qd=qvel[idx], gravity=False).G_q
        assert_close(full.M_q, full_mass(m, d)[np.ix_(idx, idx)], "mass matrix")
        assert_close(full.C_q @ full.qd + full.G_q - xi, d.qfrc_bias[idx], "bias forces")
        assert_close(-xi, d.qfrc_passive[idx], "joint damping")


# ------------------------------------------------------------------ trees
def _variant(extra: str, where: str = "<mujoco model=\"defaults_tree\">") -> str:
    return text_of("defaults_tree.xml").replace(where, where + extra)


TREES = {
    "defaults_frames_ref": lambda: text_of("defaults_tree.xml"),
    "settotalmass": lambda: _variant('<compiler settotalmass="7.5"/>'),
    "gravity_disabled": lambda: _variant('<option><flag gravity="disable"/></option>'),
    "dampers_disabled": lambda: _variant('<option><flag damper="disable"/></option>'),
    "springs_disabled": lambda: _variant('<option><flag spring="disable"/></option>').replace(
        '<joint damping="0.05"', '<joint stiffness="3" damping="0.05"'),
    "springs_in_degrees": lambda: text_of("defaults_tree.xml").replace(
        '<joint damping="0.05"', '<joint stiffness="3" springref="20" damping="0.05"'),
    "joint_and_site_in_a_frame": lambda: text_of("defaults_tree.xml").replace(
        '<joint name="elbow" class="wrist"/>', '<frame pos="0.01 0.02 0" euler="0 30 0"><joint name="elbow" '
                                               'class="wrist"/><site name="s" pos="0.1 0 0"/></frame>'),
    "radian_XYZ": lambda: _variant('<compiler angle="radian" eulerseq="XYZ"/>').replace(
        'euler="10 20 30"', 'euler="0.1 0.2 0.3"').replace('euler="0 90 0"', 'euler="0 1.5707963267948966 0"'),
}


@pytest.mark.parametrize("variant", list(TREES))
def test_tree_mass_matrix_bias_and_damping_equal_mujocos(variant):
    text = TREES[variant]()
    compare_tree(text, model_of(text), seed=1)


def test_ball_joint_terms_equal_mujocos():
    text = text_of("ball_arm.xml")
    compare_tree(text, model_of(text, ball=True), seed=2)


@pytest.mark.parametrize("name", LOOPS)
def test_the_tree_of_a_loop_model_equals_mujocos(name):
    compare_tree(text_of(name), model_of(text_of(name), tree_only=True), seed=3)


def test_reference_positions_are_mujocos_qpos0():
    text = text_of("defaults_tree.xml")
    model = model_of(text)
    m = mujoco.MjModel.from_xml_string(text)
    q0 = configuration(m, model.scene, m.qpos0)
    assert all(abs(model.reference[name] - q0[name]) <= TOL for name in q0.positions)


# ------------------------------------------------------------------ loops
def projector(rows: np.ndarray) -> tuple[np.ndarray, int]:
    """The orthogonal projector onto the row space of ``rows``, and its rank."""
    _, s, vt = np.linalg.svd(rows)
    rank = int(np.sum(s > RANK_TOL * max(float(s[0]) if s.size else 0.0, 1e-300)))
    return vt[:rank].T @ vt[:rank], rank


def _mujoco_pose(text: str, body: str) -> tuple[np.ndarray, np.ndarray]:
    m = mujoco.MjModel.from_xml_string(text)
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    return d.xmat[m.body(body).id].reshape(3, 3), d.xpos[m.body(body).id]


def _five_bar(equality: str, actuators: str = "") -> str:
    text = text_of("five_bar.xml").replace('<weld name="closure" body1="stub" body2="distal2"/>', equality)
    return text.replace('<motor joint="j2"/>', '<motor joint="j2"/>' + actuators)


def _relpose_weld() -> str:
    """A body weld with an anchor (in body2) and an explicit relpose: the pose of distal2's anchor
    frame in the stub as MuJoCo itself places the bodies at qpos0."""
    base, anchor = text_of("five_bar.xml"), np.array([0.05, 0.01, 0.0])
    (r1, p1), (r2, p2) = _mujoco_pose(base, "stub"), _mujoco_pose(base, "distal2")
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, (r1.T @ r2).ravel())
    relpose = " ".join(repr(float(v)) for v in np.concatenate([r1.T @ (p2 + r2 @ anchor - p1), quat]))
    return _five_bar(f'<weld name="closure" body1="stub" body2="distal2" anchor="0.05 0.01 0" relpose="{relpose}"/>')


LOOP_VARIANTS = {
    **{name: lambda name=name: text_of(name) for name in LOOPS},
    "body_weld_anchor_relpose": _relpose_weld,
    "body_weld_reversed_anchor": lambda: _five_bar('<weld name="closure" body1="distal2" body2="stub" '
                                                   'anchor="0.02 0.01 0"/>'),
    "body_connect_two_moving_bodies": lambda: _five_bar('<connect name="closure" body1="stub" body2="distal2" '
                                                        'anchor="0.01 0.003 0"/>', '<motor joint="j4"/>'),
}


@pytest.mark.parametrize("variant", list(LOOP_VARIANTS))
def test_loop_rows_span_mujocos_equality_rows_and_close_its_residual(variant):
    text = LOOP_VARIANTS[variant]()
    model = model_of(text)
    m = mujoco.MjModel.from_xml_string(text)
    idx = dof_index(m, model.all_coordinate_names())
    states = [(model.reference, None)] + list(random_consistent_states(model, STATES, seed=4, spread=0.5))
    for config, _ in states:
        qpos = m.qpos0.copy()
        for name in model.all_coordinate_names():
            qpos[m.jnt_qposadr[m.joint(name).id]] = config[name]
        m, d = mujoco_at(text, qpos, np.zeros(m.nv))
        rows = d.efc_type[:d.nefc] == mujoco.mjtConstraint.mjCNSTR_EQUALITY
        jac = np.asarray(d.efc_J).reshape(-1)[:d.nefc * m.nv].reshape(d.nefc, m.nv)[rows][:, idx]
        ours, rank = projector(np.asarray(model.evaluate(config).maps.T.v, float))
        theirs, their_rank = projector(jac)
        assert rank == their_rank and rows.any()
        assert_close(ours, theirs, "projector onto the constraint rows")
        assert np.max(np.abs(d.efc_pos[:d.nefc][rows])) <= TOL, "MuJoCo's loop is open on symgen's closed state"


# ------------------------------------------------------------------ orientations
ORIENTATION_BODIES = [
    'quat="2 0.5 -1 0.25"', 'euler="10 -20 200"', 'axisangle="1 2 -2 33"', 'xyaxes="1 1 0 -2 1 0.5"',
    'zaxis="0 1 1"', 'zaxis="0 0 -3"', 'zaxis="1 -2 3"', 'euler="45 30 60"',
]


@pytest.mark.parametrize("eulerseq", ["xyz", "XYZ", "zyx", "ZXz"])
def test_orientations_equal_mujocos(eulerseq):
    """Each orientation form, read in the file's conventions, is MuJoCo's rotation (body_quat)
    within the 1e-12 of an exact rotation snapped from a float one."""
    bodies = "".join(f'<body name="b{k}" pos="{k} 0 0" {o}><frame euler="0 0 {15 * k}"><body name="c{k}" {o}/>'
                     f'</frame></body>' for k, o in enumerate(ORIENTATION_BODIES))
    text = f'<mujoco><compiler eulerseq="{eulerseq}"/><worldbody>{bodies}</worldbody></mujoco>'
    m = mujoco.MjModel.from_xml_string(text)
    for b in parse_mjcf_text(text).bodies:
        assert np.max(np.abs(np.array(b.rot, dtype=float) - quat_matrix(m.body(b.name).quat))) <= 1e-11, b.name
        assert np.max(np.abs(np.array(b.pos, dtype=float).ravel() - m.body(b.name).pos)) <= 1e-15, b.name


# ------------------------------------------------------------------ what MuJoCo refuses
MASS_CASES = {    # the content of a body with a hinge
    "rigid body": '<inertial pos="0 0 0" mass="1" diaginertia="1 1 1"/>',
    "tiny mass": '<inertial pos="0 0 0" mass="1e-16" diaginertia="1 1 1"/>',
    "small mass": '<inertial pos="0 0 0" mass="1e-14" diaginertia="1 1 1"/>',
    "rod": '<inertial pos="0 0 0" mass="1" diaginertia="1 1 0"/>',
    "point mass": '<inertial pos="0.2 0 0" mass="1" diaginertia="0 0 0"/>',
    "no inertial": "",
    "massless, a massive body welded to it": '<body name="w" pos="1 0 0"><inertial pos="0 0 0" mass="1" '
                                             'diaginertia="1 1 1"/></body>',
    "massless, a massive body moving on it": '<body name="w" pos="1 0 0"><joint name="k"/><inertial pos="0 0 0" '
                                             'mass="1" diaginertia="1 1 1"/></body>',
    "rod and disk welded": '<inertial pos="0 0 0" mass="1" diaginertia="1 1 0"/><body name="w"><inertial '
                           'pos="0 0 0" mass="1" diaginertia="0 0 1"/></body>',
}


@pytest.mark.parametrize("case", list(MASS_CASES))
def test_moving_bodies_are_refused_for_lack_of_mass_exactly_when_mujoco_refuses_them(case):
    text = f'<mujoco><worldbody><body name="b"><joint name="j"/>{MASS_CASES[case]}</body></worldbody></mujoco>'
    try:
        mujoco.MjModel.from_xml_string(text)
        mujoco_refuses = False
    except ValueError:
        mujoco_refuses = True
    try:
        parse_mjcf_text(text)
        symgen_refuses = False
    except MjcfError:
        symgen_refuses = True
    assert symgen_refuses == mujoco_refuses
