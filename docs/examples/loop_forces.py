"""Loop forces and the motion of every joint of a passive closed chain."""
import numpy as np

from symgen.io.builtin import get_scene
from symgen.model import derive

model = derive(get_scene("four_bar"))
q, V_m, tau = model.reference, [0.5], [0.1]
print(model.all_coordinate_names())          # ['j1', 'j2', 'j3', 'j4']: scene order, dependent joints included
print(model.joint_rates(q, V_m))             # q̇ of every joint, eq. (10)
print(model.joint_accelerations(q, V_m, tau))  # q̈ of every joint under tau (eq. 11 differentiated)
print(model.constraint_force_names())        # ['closure.fx', 'closure.fy', 'closure.mz']
lam = model.loop_forces(q, V_m, tau)         # forward dynamics; or loop_forces(q, V_m, dV_m=..., eta_f=...)
motion = model.motion(q, V_m, tau)           # all of it from one evaluation: .qd_all .qdd_all .dV_m .eta_f .tau .lam
assert np.allclose(motion.lam, lam, rtol=1e-12, atol=1e-12)
