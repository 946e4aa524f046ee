"""The solver's answers to every pose, what it raised and printed, its own FK at each ``q``.

A solver with ``solve_batch`` (a user's function in its own process) answers
all poses in one call; any other is called once per pose, its printing counted
by kind (:func:`solve_all`).
"""

from __future__ import annotations

import contextlib
import re
import time
from collections import Counter

import numpy as np

from fkcheck.core.typing import Float
from fkcheck.ik.solver import IkSolver, IkSolverError, validated_solutions
from fkcheck.model.types import Model

__all__ = ["solve_all"]


def solve_all(
    model: Model, solver: IkSolver, targets: Float, q_all: Float
) -> tuple[list[Float], dict[int, str], Float | None, dict[str, int], float]:
    """Every pose's answer, the poses it raised on, its own FK at ``q`` and its printing.

    Returns ``(answers, errors, own_poses, messages, seconds)``; ``errors[-1]``
    is a failure of the whole batch.
    """
    dof = model.dof
    errors: dict[int, str] = {}
    messages: Counter[str] = Counter()
    answers: list[Float] = []
    batch = getattr(solver, "solve_batch", None)
    if callable(batch):  # the user's function: one process of its own for them all
        started = time.perf_counter()
        try:
            answers = [validated_solutions(solver.name, a, dof) for a in batch(targets, q_all)]
        except IkSolverError as exc:
            empty = [np.zeros((0, dof))] * len(targets)
            return empty, {-1: str(exc)}, None, {}, time.perf_counter() - started
        own = getattr(solver, "fk_poses", None)
        return answers, errors, own, {}, time.perf_counter() - started
    batch_context = getattr(solver, "batch", None)  # a library's printing redirected once
    with batch_context() if callable(batch_context) else contextlib.nullcontext():
        spent = _solve_each(solver, targets, dof, answers, errors, messages)
    for line in getattr(solver, "messages", ()) if callable(batch_context) else ():
        messages[_message_kind(line)] += 1
    own_poses = None
    fk = getattr(solver, "fk", None)
    if callable(fk):
        own_poses = np.empty_like(targets)
        for i, q in enumerate(q_all):
            try:
                own_poses[i] = np.asarray(fk(q.copy()), dtype=np.float64)
            except Exception:  # counted as a disagreement: NaN is never within tolerance
                own_poses[i] = np.nan
    return answers, errors, own_poses, dict(messages), spent


def _solve_each(
    solver: IkSolver,
    targets: Float,
    dof: int,
    answers: list[Float],
    errors: dict[int, str],
    messages: Counter[str],
) -> float:
    """Solve the poses one call each into ``answers`` and ``errors``; the seconds spent solving."""
    spent = 0.0
    for i, T in enumerate(targets):
        started = time.perf_counter()
        try:
            answer = solver.solve(T.copy())
        except Exception as exc:  # the solver's failure on this pose: counted, one line each
            spent += time.perf_counter() - started
            errors[i] = f"raised {type(exc).__name__}: {exc}"
            answers.append(np.zeros((0, dof)))
            continue
        spent += time.perf_counter() - started
        try:
            answers.append(validated_solutions(solver.name, answer, dof))
        except IkSolverError as exc:
            errors[i] = exc.problem
            answers.append(np.zeros((0, dof)))
        for line in getattr(solver, "messages", ()):
            messages[_message_kind(line)] += 1
    return spent


def _message_kind(line: str) -> str:
    """A printed line without its numbers: lines of one kind are counted together."""
    words = re.sub(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?", "", line)
    return " ".join(words.split()).rstrip(":")[:200]
