"""The three forms a state takes: a Configuration, a mapping, a flat array in scene order."""
import numpy as np

import symgen
from symgen.simulation import StateLayout

model = symgen.derive(symgen.load("four_bar"))
q = StateLayout(model).positions(model.reference)       # flat, scene order: j1, j2, j3, j4
positions = dict(model.reference.positions)             # {"j1": 1.047..., "j2": ...}
dv_flat, _ = model.forward_dynamics(q, [0.5], tau=[1.0])
dv_map, _ = model.forward_dynamics(positions, [0.5], tau=[1.0])   # the same dV_m
assert np.array_equal(dv_flat, dv_map)

try:
    model.forward_dynamics({"j1": 0.3}, [0.5], tau=[1.0])         # a joint missing
except symgen.StateError as exc:
    print("refused:", exc)
