"""Cassie from its SDF file: the four leg loops closed by ball joints become constraints (eq. 6),
and the passive rates they make dependent are eliminated by eq. (10)."""
import symgen
from symgen.io.sdf import scene_from_sdf
from symgen.io.urdf.examples import example_path

model = symgen.derive(symgen.load("cassie"))       # the built-in: Cassie's motors, a free base
counts = model.counts.as_dict()
print(counts)                                       # 28 rates: nc = 10, np = 10, m = 18
assert (counts["nc"], counts["np"], counts["m"]) == (10, 10, 18)

# any SDF file by its path (symgen.load("robot.sdf") with the defaults); this one damps two of its
# loop-closing ball joints, which a constraint cannot carry (closure_dynamics="note" leaves that
# out), and writes pi/2 as 1.5708, which only snap=1e-5 reads as exactly planar foot loops
scene = scene_from_sdf(example_path("cassie"), closure_dynamics="note", snap=1e-5)
print(len(scene.constraints), "loop closures;", scene.notes[0])
