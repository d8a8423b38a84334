"""Solo12 standing on its four feet: the torques that hold it still, and the ground's forces."""
import numpy as np

from symgen import derive, load

model = derive(load("solo12_standing"))
config, rest = model.reference, np.zeros(model.counts.m)
eta_f = np.zeros(model.counts.n - model.counts.m)       # no internal squeeze between the feet

# the joint torques for dV_m = 0 (the base stays still) ...
tau = model.inverse_dynamics(config, rest, rest, eta_f)
# ... under which no joint moves
assert np.abs(model.joint_accelerations(config, rest, tau)).max() < 1e-12

# the ground's force on each foot, world axes: together they carry the robot's weight
forces = model.constraint_wrenches(config, rest, tau, axes="world")
total = sum(wrench[:3] for wrench in forces.values())
mass = sum(model.scene.value_of(body.mass) for body in model.scene.bodies.values())
assert np.allclose(total, [0, 0, 9.81 * mass], atol=1e-9)
for name, wrench in forces.items():
    print(f"{name}: f = {np.round(wrench[:3], 3)} N")
