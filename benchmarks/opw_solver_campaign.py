"""Soundness and completeness of the ``opw`` IK solver on the bundled OPW arms (a campaign).

For seeded configurations q within the limits, the pose is the in-house table FK; the
solver gets the pose only. Sound: each solution's table FK is the pose (worst position
and rotation error reported). Complete: q itself (modulo 2π) is among the solutions.
Then the same at the wrist singularity (θ5 = 0 exactly), where θ4 and θ6 share one
angle: a solution with q's θ1, θ2, θ3, θ5 counts as q's branch.

    python benchmarks/opw_solver_campaign.py [--arms kr6r700sixx irb2400 puma560]
        [--n 20000] [--singular 2000] [--seed 0] [--api inverse reach]
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from fkcheck.core.metrics import position_error_m, rotation_error_rad
from fkcheck.ik.opw_solver import APIS, make_opw_solver
from fkcheck.model.read import load_model

#: q is "among the solutions" when every joint is this close, modulo 2π.
SAME_Q_RAD = 1e-9
#: At θ5 = 0 the branch is q's when θ1, θ2, θ3, θ5 are this close.
SAME_BRANCH_RAD = 1e-6


def _apart(solutions: np.ndarray, q: np.ndarray) -> np.ndarray:
    diff = np.remainder(solutions - q + math.pi, 2 * math.pi) - math.pi
    return np.abs(diff).max(axis=1) if len(solutions) else np.array([np.inf])


def campaign(name: str, api: str, n: int, singular: int, seed: int) -> None:
    model = load_model(name)
    solver = make_opw_solver(model, api)  # type: ignore[arg-type]
    rng = np.random.default_rng(seed)
    lo, hi = model.limits[:, 0], model.limits[:, 1]
    q_all = lo + rng.random((n, 6)) * (hi - lo)
    worst_m = worst_rad = fk_gap = 0.0
    missed = 0
    counts: dict[int, int] = {}
    for q in q_all:
        pose = model.fk(q)
        solutions = solver.solve(pose)
        counts[len(solutions)] = counts.get(len(solutions), 0) + 1
        if len(solutions):
            reached = model.fk(solutions)
            worst_m = max(worst_m, float(position_error_m(reached, pose[None]).max()))
            worst_rad = max(worst_rad, float(rotation_error_rad(reached, pose[None]).max()))
        missed += int(_apart(solutions, q).min() > SAME_Q_RAD)
        fk_gap = max(fk_gap, float(np.abs(solver.fk(q) - pose).max()))
    print(
        f"{name} [{solver.name}] random: {n} poses, worst solution {worst_m:.2g} m "
        f"{worst_rad:.2g} rad, q missed {missed}, solution counts {dict(sorted(counts.items()))}, "
        f"solver FK vs table {fk_gap:.2g}"
    )
    q_sing = lo + rng.random((singular, 6)) * (hi - lo)
    q_sing[:, 4] = 0.0
    arm = [0, 1, 2, 4]
    exact = shared = dropped = 0
    worst_rad = 0.0
    for q in q_sing:
        pose = model.fk(q)
        solutions = solver.solve(pose)
        if len(solutions):
            worst_rad = max(
                worst_rad, float(rotation_error_rad(model.fk(solutions), pose[None]).max())
            )
        if _apart(solutions, q).min() <= SAME_Q_RAD:
            exact += 1
        elif len(solutions) and _apart(solutions[:, arm], q[arm]).min() <= SAME_BRANCH_RAD:
            shared += 1
        else:
            dropped += 1
    print(
        f"{name} [{solver.name}] θ5 = 0: {singular} poses, q itself {exact}, q's branch "
        f"(θ4/θ6 shared otherwise) {shared}, q's branch missing {dropped}; worst solution "
        f"{worst_rad:.2g} rad"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--arms", nargs="+", default=["kr6r700sixx", "irb2400", "puma560"])
    parser.add_argument("--api", nargs="+", default=list(APIS), choices=APIS)
    parser.add_argument("--n", type=int, default=20_000)
    parser.add_argument("--singular", type=int, default=2_000)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    for name in args.arms:
        for api in args.api:
            campaign(name, api, args.n, args.singular, args.seed)


if __name__ == "__main__":
    main()
