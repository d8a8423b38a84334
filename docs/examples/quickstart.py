import symgen

model = symgen.derive(symgen.load("four_bar"))       # a built-in, a YAML/URDF/MJCF path, or a Scene
print(model.counts.as_dict())                         # Steps 1-8: n1a n1u n3a n3u m nc np n
print(model.coordinate_names())                       # the independent rates of eq. (14): ['j1']

data = model.evaluate(model.reference, V_m=[0.5])     # model (32) at q0, in the float field
print(data.M, data.C, data.G)                         # M, C, G in the task space O

dV_m, eta_f = model.forward_dynamics(model.reference, [0.5], tau=[1.0])
lam = model.loop_forces(model.reference, [0.5], [1.0])   # forces in the closing joint, eq. (6) rows
print(dV_m, dict(zip(model.constraint_force_names(), lam)))

assert all(result.passed for result in symgen.prove(model, points=1))   # Remark 2.7, eqs. (18), (21), (27)
