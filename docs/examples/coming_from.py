"""Coming from Pinocchio / MuJoCo: each difference of conventions, checked on the same robot.

Needs the test extra (pinocchio, mujoco, example-robot-data, yourdfpy)."""
from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin

import symgen
from symgen.io.coordinates import CoordinateMap
from symgen.io.mjcf import scene_from_mjcf
from symgen.io.urdf import scene_from_urdf
from symgen.io.urdf.examples import example_path

DATA = Path(__file__).resolve().parents[2] / "tests" / "data" / "mjcf"
rng = np.random.default_rng(0)

# 1. A continuous joint is (cos, sin) in Pinocchio's q, an angle in symgen; the map converts.
#    Pinocchio's rnea leaves the URDF's <dynamics> friction out: read the file without it to compare.
path = str(Path(example_path("ur5")).parents[2] / "double_pendulum_description/urdf/double_pendulum_continuous.urdf")
scene = scene_from_urdf(path, friction=False)
model = symgen.derive(scene)
pmodel = pin.buildModelFromUrdf(path)
cmap = CoordinateMap.pinocchio(scene, pmodel)
q, v, a = pin.randomConfiguration(pmodel), rng.uniform(-1, 1, pmodel.nv), rng.uniform(-1, 1, pmodel.nv)
assert pmodel.nq == 4 and pmodel.nv == 2                     # two continuous joints: nq = 2 each
config, rates = cmap.to_symgen(q, v)                         # angles atan2(sin, cos), rates by name
_, accel = cmap.to_symgen(q, a)
names = model.coordinate_names()
out = model.evaluate(config, qd=[rates[n] for n in names])
tau = out.M_q @ [accel[n] for n in names] + out.C_q @ out.qd + out.G_q
assert np.allclose(tau, pin.rnea(pmodel, pmodel.createData(), q, v, a)[cmap.velocity_indices(names)],
                   rtol=0, atol=1e-12)
assert np.allclose(cmap.from_symgen(config, rates)[0], q, atol=1e-15)     # and back to (cos, sin)

# 2. A ball joint's quaternion is x y z w in Pinocchio's q and w x y z in MuJoCo's qpos; symgen
#    holds the rotation matrix. The three rates are the angular velocity in the child frame in all.
arm = str(DATA / "ball_arm.xml")
ball_scene = scene_from_mjcf(arm, motion=dict(frames={"grip": 1}, components=["vx", "vy", "wx", "wz"]))
to_mj = CoordinateMap.mujoco(ball_scene, mujoco.MjModel.from_xml_path(arm))
to_pin = CoordinateMap.pinocchio(ball_scene, pin.buildModelFromMJCF(arm))
qpos = np.array(to_mj.neutral)
ball = next(s for s in to_mj.slots if s.form == "quat_wxyz")
qpos[ball.q:ball.q + 4] = np.array([0.8, 0.2, -0.4, 0.4]) / np.linalg.norm([0.8, 0.2, -0.4, 0.4])
config, _ = to_mj.to_symgen(qpos)
q_pin, _ = to_pin.from_symgen(config)
pin_ball = next(s for s in to_pin.slots if s.joint == ball.joint)
assert np.allclose(q_pin[pin_ball.q:pin_ball.q + 4], np.roll(qpos[ball.q:ball.q + 4], -1), atol=1e-15)

# 3. An MJCF hinge's coordinate is MuJoCo's qpos itself, ref included (q0 = ref); MuJoCo's
#    qfrc_bias is C qd + G without the joint damping, which MuJoCo puts in qfrc_passive = -xi.
tree = str(DATA / "defaults_tree.xml")
tree_model = symgen.derive(scene_from_mjcf(tree))
m = mujoco.MjModel.from_xml_path(tree)
d = mujoco.MjData(m)
to_tree = CoordinateMap.mujoco(tree_model.scene, m)
assert np.isclose(tree_model.reference["shoulder"], m.qpos0[m.joint("shoulder").qposadr[0]])   # ref = 15 deg
d.qpos[:], d.qvel[:] = m.qpos0 + rng.uniform(-1, 1, m.nq), rng.uniform(-1, 1, m.nv)
mujoco.mj_forward(m, d)
config, rates = to_tree.to_symgen(d.qpos, d.qvel)
names = tree_model.coordinate_names()
idx = to_tree.velocity_indices(names)
full = tree_model.evaluate(config, qd=[rates[n] for n in names])
xi = tree_model.evaluate(config, qd=[rates[n] for n in names], gravity=False).G_q     # damping alone
dense = np.zeros((m.nv, m.nv))
mujoco.mj_fullM(m, dense, d.qM) if hasattr(d, "qM") else mujoco.mj_fullM(m, d, dense)
assert np.allclose(full.M_q, dense[np.ix_(idx, idx)], atol=1e-12)
assert np.allclose(full.C_q @ full.qd + full.G_q - xi, d.qfrc_bias[idx], atol=1e-12)
assert np.allclose(-xi, d.qfrc_passive[idx], atol=1e-12)
print("Pinocchio and MuJoCo conventions: all checks pass")
