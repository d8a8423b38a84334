"""The tour's four-bar declared in Python: the same scene as the YAML file and the built-in."""
import symgen
from symgen import Scene

scene = Scene(name="four_bar")
scene.add_body("crank", "0.2", com=("0.05", 0, 0), inertia=("1/75000", "13/75000", "13/75000"))
scene.add_body("coupler", "0.6", com=("0.15", 0, 0), inertia=("4.0e-05", "0.00452", "0.00452"))
scene.add_body("rocker", "0.2", com=("0.05", 0, 0), inertia=("1/75000", "13/75000", "13/75000"))
scene.add_body("pin", 0)                                  # massless frame carrier that closes the loop
scene.add_joint("j1", "revolute", "world", "crank", axis="z", actuated=True, q0="pi/3")
scene.add_joint("j2", "revolute", "crank", "coupler", xyz=("0.1", 0, 0), q0="-pi/3")
scene.add_joint("j3", "revolute", "coupler", "rocker", xyz=("0.3", 0, 0), q0="-2*pi/3")
scene.add_joint("j4", "revolute", "rocker", "pin", xyz=("0.1", 0, 0), q0="2*pi/3")
scene.add_frame("pin_frame", "pin")
scene.add_frame("ground_pin", "world", xyz=("0.3", 0, 0))
scene.add_constraint("closure", "planar_weld", "pin_frame", "ground_pin", normal="z")
scene.set_motion(joints=["j1"])

builtin = symgen.load("four_bar")
for part in ("bodies", "joints", "frames", "constraints", "motion", "gravity"):
    assert getattr(scene, part) == getattr(builtin, part), part
print(symgen.derive(scene).counts.as_dict())
