"""Generate NumPy code for a scene, import it, and call it on a batch of states."""
import numpy as np

import symgen
from symgen.codegen import generate
from symgen.codegen.runtime import load_generated
from symgen.simulation import StateLayout

model = symgen.derive(symgen.load("four_bar"))
files = generate(model, "numpy", ["forward_dynamics"])      # file name -> text, and the op counts
print(sorted(files.files), files.ops["forward_dynamics"]["total"])

gen = load_generated(model, "numpy", ["forward_dynamics"])  # written to $SYMGEN_CACHE and imported
q = StateLayout(model).positions(model.reference)
batch = np.tile(q, (1000, 1))                               # 1000 states in one call
dv_m = gen.forward_dynamics(batch, np.full((1000, 1), 0.5), np.full((1000, 1), 1.0))
reference, _ = model.forward_dynamics(q, [0.5], tau=[1.0])
assert np.allclose(dv_m, reference, rtol=1e-12, atol=0)
