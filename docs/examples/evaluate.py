"""One model, several fields: the same step functions in floats, 50-digit numbers and SymPy."""
import numpy as np

import symgen

model = symgen.derive(symgen.load("four_bar"))        # or a YAML path
print(model.counts.as_dict())
data = model.evaluate(model.reference, V_m=[0.5])     # float, at the scene's q0
print(data.maps.T_S.v.shape, data.M, data.C, data.G)
sym = model.evaluate(model.symbolic_configuration(), qd=model.symbolic_velocity(), field="symbolic")
print(sorted(map(str, sym.M[0, 0].free_symbols)))     # M of (32) in c_j, s_j symbols
dv_m, eta_f = model.forward_dynamics(model.reference, [0.5], tau=[1.0])

mp = model.evaluate(model.reference, V_m=[0.5], field="mp")   # the 50-digit reference field
assert np.allclose(np.asarray(mp.M, dtype=float), data.M, rtol=1e-12, atol=0)
