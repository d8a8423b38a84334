"""``symgen check SCENE --against pinocchio``: a URDF scene's model against Pinocchio on the same files.

Prints the worst relative difference of each compared quantity (:mod:`symgen.oracle`) and exits
with status 1 if one exceeds its tolerance. ``--target numpy`` / ``--target c`` also checks the
generated code. Heavy imports happen inside the command, so ``symgen --help`` stays fast.
"""
from __future__ import annotations

import json
import time

from ..codegen.targets import TARGETS
from .args import add_scene, load_scene


def cmd_check(args) -> int:
    from ..model import derive
    from ..oracle.pinocchio_check import check_against_pinocchio

    model = derive(load_scene(args))
    start = time.perf_counter()
    diffs = check_against_pinocchio(model, states=args.states, seed=args.seed, targets=args.target or ())
    elapsed = time.perf_counter() - start
    ok = all(d.passed for d in diffs)
    if args.json:
        print(json.dumps({"scene": model.scene.name, "against": args.against, "passed": ok,
                          "seconds": round(elapsed, 3), "differences": [d.as_dict() for d in diffs]}, indent=1))
        return 0 if ok else 1
    print(f"scene {model.scene.name} against {args.against}, {args.states} random state(s), seed {args.seed}")
    print(f"  {'':4}  {'quantity':<56} {'worst':>10} {'tol.':>7}  compared with")
    for d in diffs:
        print(f"  {'PASS' if d.passed else 'FAIL'}  {d.quantity:<56} {d.worst:>10.2e} {d.tolerance:>7.0e}  {d.against}")
    print(f"{'all agree' if ok else 'SOME DIFFER'} ({elapsed:.1f} s)")
    return 0 if ok else 1


def register(subparsers) -> None:
    p = subparsers.add_parser("check", help="compare a URDF scene's model with Pinocchio on the same URDF files")
    add_scene(p, help="a URDF-based scene: ur5, panda, ur5_on_plane, multi_ur5:h=2, or a YAML with urdf:")
    p.add_argument("--against", choices=("pinocchio",), required=True, help="the reference implementation")
    p.add_argument("--states", type=int, default=20, help="random states (default 20)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--target", action="append", choices=TARGETS,
                   help="also check the generated code of this target (repeatable)")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_check)
