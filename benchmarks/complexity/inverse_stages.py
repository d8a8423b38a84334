"""Where the operations of a generated ``inverse_dynamics`` go, stage by stage (printed, no table).

Traces ``inverse_dynamics`` of a scene the way :meth:`symgen.codegen.builder.Builder.joint_space_forces`
does, for both routes of eq. (10) (``P`` formed, and by solves with ``W``), marks the graph between
the stages -- positions, the loop-closure rows ``T`` (eq. 6), the factorisation of ``W`` (eq. 9),
``P``, the rates (eq. 10), the accelerations with ``dP/dt qd`` (eq. 11), the recursive Newton-Euler
passes, the projection ``P^T`` -- and counts each stage's live operations (a node shared by two
stages counts in the first that made it; the sum is the function's ``total``).

    python benchmarks/complexity/inverse_stages.py stewart
"""
from __future__ import annotations

import contextlib
import sys

import symgen
from symgen.codegen.builder import Builder, has_gravity
from symgen.codegen.trace import rates_by_solve
from symgen.dynamics.rnea import rnea


def stages(model, by_solve: bool) -> list[tuple[str, dict]]:
    """``[(stage, counts)]`` of ``inverse_dynamics`` traced by one route of eq. (10)."""
    with (rates_by_solve() if by_solve else contextlib.nullcontext()):
        b = Builder(model)
        g, t = b.g, b.t
        t.use_null_space_rows()
        marks = [("positions and joint transforms", 0)]
        qd, qdd = b.arg("qd", b.n, ""), b.arg("qdd", b.n, "")
        if model.partition.u1:
            marks.append(("loop-closure rows T (eq. 6)", len(g.nodes)))
            t.closure
            marks.append(("factors of W (eq. 9)", len(g.nodes)))
            t.blocks
            if not t.by_solve:
                marks.append(("P (eq. 10)", len(g.nodes)))
                t.rates
        marks.append(("rates qd_all (eq. 10)", len(g.nodes)))
        qd_all = t.complete_rates(qd)
        marks.append(("accelerations with dP/dt qd (eq. 11)", len(g.nodes)))
        qdd_all = t.accelerations_of_rates(qdd, qd_all)
        marks.append(("recursive Newton-Euler", len(g.nodes)))
        tau = rnea(t.tree, t.consts, t.transforms, qd_all, qdd_all, gravity=has_gravity(model), graph=g)
        marks.append(("projection P^T", len(g.nodes)))
        out = t.project(tau)
        marks.append(("", len(g.nodes)))
    alive = g.live([out])
    return [(name, g.count([a and lo <= i < hi for i, a in enumerate(alive)]))
            for (name, lo), (_, hi) in zip(marks, marks[1:])]


def main(spec: str) -> None:
    model = symgen.derive(symgen.load(spec))
    for by_solve in ([False, True] if model.partition.u1 else [False]):
        rows = stages(model, by_solve)
        print(f"{spec} inverse_dynamics, eq. (10) {'by solves with W' if by_solve else 'through P'}:")
        for name, c in rows:
            print(f"  {name:38s} mul {c['mul']:5d}  add {c['add']:5d}  total {c['total']:5d}")
        print(f"  {'total':38s} {sum(c['total'] for _, c in rows):29d}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "stewart")
