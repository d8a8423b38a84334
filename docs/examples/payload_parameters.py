"""One generated model for a UR5 whatever it holds: the payload's ten inertial parameters are the
input p of the generated functions, checked for physical possibility before use."""
import numpy as np

import symgen
from symgen.codegen.parameters import check_parameter_vector, parameterise
from symgen.codegen.runtime import load_generated
from symgen.errors import SceneError
from symgen.io.urdf.examples import ur5


def ur5_holding(mass, com, inertia):
    scene = ur5()
    scene.add_body("payload", mass, com=com, inertia=inertia)
    scene.add_joint("payload_mount", "fixed", "wrist_3_link", "payload", xyz=[0, 0.1, 0])
    return scene


scene = ur5_holding(1.5, [0.01, 0.02, 0.05], [0.01, 0.012, 0.008])
model = symgen.derive(scene)
code = load_generated(model, "numpy", ["inverse_dynamics", "gravity"], parameters=["payload"])
print(code.PARAMETER_NAMES)            # ('payload.mass', 'payload.com_x', ..., 'payload.iyz')

# the robot picks up a heavier box: a new p, the same code
box = np.array([4.0, 0.0, 0.0, 0.08, 0.03, 0.03, 0.02, 0.0, 0.0, 0.0])
chosen_scene, chosen = parameterise(scene, ["payload"])
check_parameter_vector(chosen_scene, chosen, box)
q = np.zeros(6)
held = code.gravity(q, box)

# the same as the model derived with the box declared in the scene
again = symgen.derive(ur5_holding(4.0, [0, 0, 0.08], [0.03, 0.03, 0.02]))
assert np.allclose(held, again.evaluate(q, qd=np.zeros(6)).G, rtol=1e-12, atol=1e-12)

# an impossible payload is refused by name before it reaches the code
try:
    check_parameter_vector(chosen_scene, chosen, np.array([4.0, 0, 0, 0, 0.01, 0.01, 0.05, 0, 0, 0]))
except SceneError as err:
    print(err)                          # body 'payload': rotational inertia violates the triangle inequality ...
