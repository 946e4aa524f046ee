"""Timing IK solvers on the same poses: solves per second, and what fkcheck's harness adds.

``fkcheck bench MODEL --ik NAME[,NAME…]``: each solver solves the poses (the
model's check frame pair) of the first :data:`IK_POSES` of the bench's seeded
configurations (:func:`~fkcheck.bench.timing.bench_configurations`). Per solver:

* ``solve``: the solver as ``fkcheck ik`` calls it, a pose at a time (a
  ``module:function`` solver: all poses in its one process, its start included);
  every solution's pose through the in-house FK, the worst distance reported;
* ``library``: for ``ur-analytic-ik``, the library's own call without the
  wrapper (frames, joint zeros, its printing kept off fkcheck's output): the
  wrapper's cost is the difference;
* ``check``: ``fkcheck ik``'s checking of those answers (soundness, completeness,
  branches, its own FK) on the same poses, once: the harness's cost over the solver's.

Every time is the median of ``repeat`` runs after a warm-up
(:func:`~fkcheck.bench.timing.median_seconds`), the check's excepted (it is
run once: it is seconds, not microseconds).
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from fkcheck.bench.machine import machine_info
from fkcheck.bench.timing import bench_configurations, median_seconds
from fkcheck.core.metrics import position_error_m
from fkcheck.core.typing import Float
from fkcheck.ik import check_ik, make_solver
from fkcheck.ik.solver import IkSolver, validated_solutions
from fkcheck.model.sampling import Samples
from fkcheck.model.types import Model

__all__ = ["IK_POSES", "IkBenchResult", "IkTiming", "run_ik_bench"]

#: Poses per solver: enough for a steady time per solve, a few seconds for the check.
IK_POSES = 2000


@dataclass(frozen=True)
class IkTiming:
    """One row: a solver's solve, its library's bare call, or the harness's check.

    Attributes:
        solver: The solver's name.
        part: ``"solve"``, ``"library"`` or ``"check"``.
        n: Poses per run.
        seconds: Median seconds per run of all ``n`` (``None`` if it failed).
        max_position_error_m: Largest distance of a returned solution's pose from
            its target (in-house FK), ``solve`` rows only.
        note: How it was called.
        error: Why it failed.
    """

    solver: str
    part: str
    n: int
    seconds: float | None
    max_position_error_m: float | None = None
    note: str = ""
    error: str = ""

    @property
    def us_per_solve(self) -> float | None:
        """Microseconds per pose."""
        return None if self.seconds is None else self.seconds / self.n * 1e6

    @property
    def solves_per_s(self) -> float | None:
        """Poses per second."""
        return None if not self.seconds else self.n / self.seconds


@dataclass(frozen=True)
class IkBenchResult:
    """Every IK row of one run."""

    model: str
    n: int
    repeat: int
    seed: int
    timings: tuple[IkTiming, ...]
    machine: dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        """Plain data for JSON, each row with its per-solve numbers."""
        return {
            "quantity": "ik",
            "model": self.model,
            "n": self.n,
            "repeat": self.repeat,
            "seed": self.seed,
            "machine": self.machine,
            "timings": [
                {**asdict(t), "us_per_solve": t.us_per_solve, "solves_per_s": t.solves_per_s}
                for t in self.timings
            ],
        }


def run_ik_bench(
    model: Model,
    solvers: Sequence[str],
    n: int,
    repeat: int,
    *,
    seed: int = 0,
    progress: Callable[[str], None] | None = None,
) -> IkBenchResult:
    """Time each solver on the same poses, its library bare where it has one, and the check.

    Raises:
        SolverRefused: A solver name is unknown or does not fit the model.
    """
    count = min(n, IK_POSES)
    q = bench_configurations(model, count, seed)
    frame_from, frame_to = model.check.frame_from, model.check.frame_to
    targets = model.fk(q, frame_from=frame_from, frame_to=frame_to)
    built = [make_solver(spec, model, frame_from, frame_to) for spec in solvers]
    rows: list[IkTiming] = []
    for solver in built:
        if progress is not None:
            progress(solver.name)
        rows.extend(_rows(model, solver, q, targets, repeat, seed))
    return IkBenchResult(
        model=model.name,
        n=count,
        repeat=repeat,
        seed=seed,
        timings=tuple(rows),
        machine=machine_info(),
    )


def _rows(
    model: Model, solver: IkSolver, q: Float, targets: Float, repeat: int, seed: int
) -> list[IkTiming]:
    count = len(q)
    batch = getattr(solver, "solve_batch", None)
    answers: list[Float] = []

    def solve_all() -> None:
        answers.clear()
        if callable(batch):
            answers.extend(batch(targets))
            return
        with session() if callable(session) else contextlib.nullcontext():
            answers.extend(solver.solve(T) for T in targets)

    session = getattr(solver, "batch", None)  # as fkcheck ik calls it
    how = "all poses in one process of its own" if callable(batch) else "one pose a call"
    try:
        seconds = median_seconds(solve_all, repeat)
    except Exception as exc:  # a solver's failure is its row's, one line
        return [IkTiming(solver.name, "solve", count, None, error=f"{type(exc).__name__}: {exc}")]
    worst = 0.0
    for target, answer in zip(targets, answers, strict=True):
        sols = validated_solutions(solver.name, answer, model.dof)
        if len(sols):
            reached = model.fk(
                np.nan_to_num(sols, nan=0.0, posinf=0.0, neginf=0.0),
                frame_from=model.check.frame_from,
                frame_to=model.check.frame_to,
            )
            worst = max(worst, float(position_error_m(reached, target).max()))
    rows = [IkTiming(solver.name, "solve", count, seconds, worst, note=how)]
    library = getattr(solver, "library_call", None)
    if callable(library):
        bare = median_seconds(library(targets), repeat)
        rows.append(
            IkTiming(solver.name, "library", count, bare, note="the library's own call, unwrapped")
        )
    result = check_ik(
        model,
        solver,
        frame_from=model.check.frame_from,
        frame_to=model.check.frame_to,
        samples=count,
        seed=seed,
        configurations=Samples(q=q, origin=("bench",) * count),
    )
    rows.append(
        IkTiming(
            solver.name,
            "check",
            count,
            result.check_s,
            note=f"fkcheck ik's checking of the answers, once ({result.verdict})",
        )
    )
    return rows
