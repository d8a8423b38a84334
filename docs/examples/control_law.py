"""Section 4's control law (34) and adaptation signal (38) at one state of the arm on a plane.

With the true parameters and the required motion equal to the actual one (V_mr = V_m), the law is
the inverse dynamics of model (32): property (f) of ``symgen prove``, checked here in floats.
"""
import numpy as np

import symgen
from symgen.control import law

model = symgen.derive(symgen.load("arm_on_plane"))
v_m, dv_m, eta_f = [0.1, -0.2, 0.05], [0.3, 0.0, -0.1], [20.0, 0.0, 0.0]
data = model.evaluate(model.reference, V_m=v_m)              # any field: float, exact, symbolic, mp
params = law.default_parameters(model)                       # P_r: names, values, bounds, gains
p_hat = np.array(params.values, dtype=float)                 # the estimates (here: the true values)
out = law.control(model, data, params, p_hat, v_m, dv_m, eta_fr=eta_f, gain=5.0)
print(out.tau, out.s.shape, out.Y.shape)                     # (34), (38), and Y = [T_S^T Y_r, Y_m]
tau = model.inverse_dynamics(model.reference, v_m, dv_m, eta_f=eta_f)
assert np.allclose(out.tau, tau, rtol=1e-9, atol=1e-9)
