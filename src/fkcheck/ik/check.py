"""The IK check: every solution right, none missing, no garbage at singularities.

For each configuration ``q`` of :func:`~fkcheck.ik.poses.ik_configurations`,
``T = from_T_to(q)`` with the in-house FK (:meth:`Model.fk
<fkcheck.model.types.Model.fk>`), the solver's answers for ``T``, and:

* **soundness** — every returned solution reproduces ``T`` through the table's
  FK within the model's tolerances (``[check] tol_pos`` / ``tol_rot``, or
  ``fkcheck ik --tol-pos/--tol-rot``); one that does not is a *wrong solution*;
* **completeness** — ``q`` itself is among the sound solutions, joint by joint
  within :data:`SAME_CONFIGURATION_RAD` (revolute joints modulo 2π); a pose where
  it is not is *missed*, named by ``q``'s branch (:mod:`fkcheck.ik.branches`).
  Not for an arm of more than six joints, whose poses have a continuum of
  configurations (:attr:`IkResult.completeness_checked`);
* **singular poses** — where the Jacobian's smallest singular value is below
  :data:`SINGULAR_SIGMA` the pose has a continuum of solutions or merged
  branches: no answer is required ("none" is a stated answer), but what is
  returned must be sound;
* **garbage** — a NaN or inf anywhere in an answer is a failure, singular or not;
* **the solver's own FK**, when it has one (``fk(q)``), against the table's at
  every ``q``: an IK consistent with a wrong forward model passes its own
  round trip and fails here.

The result says, for a failing solver, which poses, which branches and whether
its own FK or its inversion is wrong (:attr:`IkResult.explanation`).
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import re
import time
from collections import Counter
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from fkcheck.core.metrics import position_error_m, rotation_error_rad
from fkcheck.core.typing import Float
from fkcheck.ik.branches import branch_names, branch_values, classifiable
from fkcheck.ik.poses import ik_configurations
from fkcheck.ik.solver import IkSolver, IkSolverError, validated_solutions
from fkcheck.model.sampling import Samples
from fkcheck.model.types import Model

__all__ = [
    "SAME_CONFIGURATION_RAD",
    "SINGULAR_SIGMA",
    "WORST_CASES",
    "IkCase",
    "IkResult",
    "check_ik",
]

#: Two configurations are the same when every joint agrees within this (radians,
#: revolute joints modulo 2π; metres for a prismatic one). An analytic solver's
#: round-off is about 1e-12 rad away from singularities; distinct branches differ
#: by far more (a wrist flip by π in θ4 and θ6). A pose error ε becomes a joint
#: error of at most ε/σ_min, so above :data:`SINGULAR_SIGMA` round-off stays below this.
SAME_CONFIGURATION_RAD = 1e-6
#: A pose whose Jacobian (at the ``to`` frame, m/rad and rad/rad) has a smallest
#: singular value below this is singular: 1e-16 round-off over σ_min = 1e-9 is
#: 1e-7 rad, still below :data:`SAME_CONFIGURATION_RAD`; closer, a solver's
#: answer for the ill-conditioned joints is legitimately anywhere in a continuum.
SINGULAR_SIGMA = 1e-9
#: Worst cases kept in the result (the largest errors first, missed poses after).
WORST_CASES = 10


@dataclass(frozen=True)
class IkCase:
    """One failing pose, with what the solver returned.

    Attributes:
        kind: ``"wrong"`` (a returned solution does not reproduce the pose),
            ``"missed"`` (``q`` is not among the solutions), ``"garbage"`` (NaN or
            inf), ``"raised"`` (the solver raised) or ``"own-fk"`` (its FK
            disagrees with the table at ``q``).
        index: The configuration's index in the check's set.
        origin: Where it came from (``random``, ``near-wrist``, ``pose:home``…).
        q: The configuration the pose came from, radians / metres.
        branch: ``q``'s branch (``""`` for an arm branches are not named for).
        returned: Every solution returned for the pose.
        returned_branches: Their branches.
        solution: The offending solution (``kind == "wrong"``), else ``None``.
        position_error_m: How far it (or the solver's FK) puts the ``to`` frame, metres.
        rotation_error_rad: And how far turned, radians.
        explanation: What is wrong, in words.
    """

    kind: str
    index: int
    origin: str
    q: tuple[float, ...]
    branch: str
    returned: tuple[tuple[float, ...], ...]
    returned_branches: tuple[str, ...]
    solution: tuple[float, ...] | None
    position_error_m: float
    rotation_error_rad: float
    explanation: str


@dataclass(frozen=True)
class IkResult:
    """An IK check's outcome.

    Attributes:
        model: The model's name.
        solver: The solver's name.
        method: What computes its answers.
        frame_from: The frame the solver's pose is expressed in.
        frame_to: The frame whose pose it inverts.
        tol_pos_m: Soundness tolerance, metres.
        tol_rot_rad: Soundness tolerance, radians.
        seed: The samples' seed.
        samples: Random samples asked for.
        poses: Configurations checked.
        singular_poses: Of them, singular (:data:`SINGULAR_SIGMA`).
        solutions: Solutions returned in all.
        counts: How many poses got each number of solutions.
        wrong_solutions: Returned solutions that do not reproduce their pose.
        missed: Regular poses whose configuration is not among the solutions.
        garbage: Poses whose answer holds NaN or inf.
        raised: Poses the solver raised on.
        own_fk: Whether the solver's own FK was checked.
        own_fk_disagreements: Configurations where it disagrees with the table.
        missed_by_branch: Missed poses by their configuration's branch.
        wrong_by_branch: Wrong solutions by their own branch.
        worst: Up to :data:`WORST_CASES` failing poses.
        explanation: What a failing solver gets wrong, a line each.
        solve_s: Time spent in the solver, seconds.
        check_s: Time spent checking its answers, seconds.
        messages: Lines the solver printed (a library's warnings), with a count.
        error: A failure of the whole run (a function's process died), or ``""``.
        completeness_checked: ``False`` for an arm of more than six joints: a pose
            has a continuum of configurations, no finite answer holds them all.
    """

    model: str
    solver: str
    method: str
    frame_from: str
    frame_to: str
    tol_pos_m: float
    tol_rot_rad: float
    seed: int
    samples: int
    poses: int
    singular_poses: int
    solutions: int
    counts: dict[int, int]
    wrong_solutions: int
    missed: int
    garbage: int
    raised: int
    own_fk: bool
    own_fk_disagreements: int
    missed_by_branch: dict[str, int]
    wrong_by_branch: dict[str, int]
    worst: tuple[IkCase, ...]
    explanation: tuple[str, ...]
    solve_s: float
    check_s: float
    messages: dict[str, int] = field(default_factory=dict)
    error: str = ""
    completeness_checked: bool = True

    @property
    def passed(self) -> bool:
        """Sound, complete, no garbage, no raise, own FK (if any) agreeing, no error."""
        return not (
            self.error
            or self.wrong_solutions
            or self.missed
            or self.garbage
            or self.raised
            or self.own_fk_disagreements
        )

    @property
    def verdict(self) -> str:
        """``"pass"`` or ``"fail"``."""
        return "pass" if self.passed else "fail"


def check_ik(
    model: Model,
    solver: IkSolver,
    *,
    frame_from: str,
    frame_to: str,
    samples: int,
    seed: int,
    tol_pos_m: float | None = None,
    tol_rot_rad: float | None = None,
    configurations: Samples | None = None,
) -> IkResult:
    """Check ``solver`` against the table's FK on seeded and singular configurations.

    Args:
        model: The model (its FK is the truth).
        solver: The solver, built for ``model`` and the frame pair.
        frame_from: The frame the solver's pose is expressed in.
        frame_to: The frame whose pose it inverts.
        samples: Random samples besides the structured ones.
        seed: Their seed.
        tol_pos_m: Soundness tolerance (default: the model's ``[check]``).
        tol_rot_rad: Likewise, radians.
        configurations: Check these instead (``fkcheck bench --ik`` times the
            check on the bench's configurations); ``samples`` and ``seed`` are then
            only reported.

    Returns:
        The result; a solver that fails as a whole (a function's process dies)
        gives a failing result with :attr:`IkResult.error`.
    """
    tol_pos = model.check.tol_pos_m if tol_pos_m is None else tol_pos_m
    tol_rot = model.check.tol_rot_rad if tol_rot_rad is None else tol_rot_rad
    configs = ik_configurations(model, samples, seed) if configurations is None else configurations
    q_all = configs.q
    targets = model.fk(q_all, frame_from=frame_from, frame_to=frame_to)
    sigma = np.linalg.svd(model.jacobian(q_all, frame=frame_to), compute_uv=False)[:, -1]
    singular = sigma < SINGULAR_SIGMA

    answers, errors, own_poses, messages, solve_s = _solve_all(model, solver, targets, q_all)
    started = time.perf_counter()
    named = classifiable(model)
    branches = branch_names(branch_values(model, q_all)) if named else [""] * len(q_all)
    sols = _judge_solutions(
        model, answers, q_all, targets, (frame_from, frame_to), (tol_pos, tol_rot), named=named
    )
    sizes, owner, bad = sols.sizes, sols.owner, sols.bad
    garbage_pose = np.zeros(len(q_all), dtype=bool)
    np.logical_or.at(garbage_pose, owner, ~sols.finite)
    raised_pose = np.zeros(len(q_all), dtype=bool)
    raised_pose[[i for i in errors if i >= 0]] = True
    # A run that failed as a whole has no answers to judge: its error says so, not a count.
    # A redundant arm's pose has a continuum of configurations: completeness is not checked.
    complete = model.dof <= 6
    missed_pose = ~sols.found & ~singular & ~raised_pose & (-1 not in errors) & complete
    own_pos = own_rot = np.zeros(len(q_all))
    own_err = np.zeros(len(q_all), dtype=bool)
    if own_poses is not None:
        own_pos = position_error_m(own_poses, targets)
        own_rot = rotation_error_rad(own_poses, targets)
        own_err = ~((own_pos <= tol_pos) & (own_rot <= tol_rot))  # NaN disagrees

    cases: list[IkCase] = []
    missed_by: Counter[str] = Counter(branches[i] for i in np.flatnonzero(missed_pose))
    wrong_by: Counter[str] = Counter(sols.names[k] for k in np.flatnonzero(bad))
    failing = raised_pose | garbage_pose | missed_pose | own_err
    failing[owner[bad]] = True
    for i in np.flatnonzero(failing).tolist():
        base = dict(index=i, origin=configs.origin[i], q=_row(q_all[i]), branch=branches[i])
        cases.extend(
            _pose_cases(
                i,
                base,
                sols,
                raised=errors[i] if raised_pose[i] else None,
                garbage=bool(garbage_pose[i]),
                missed=bool(missed_pose[i]),
                own=(float(own_pos[i]), float(own_rot[i])) if own_err[i] else None,
                solver=solver,
                model=model,
                target=targets[i],
                tol=(tol_pos, tol_rot),
            )
        )
    counts = Counter(sizes[~raised_pose].tolist())
    wrong = int(bad.sum())
    missed = int(missed_pose.sum())
    garbage = int(garbage_pose.sum())
    raised = int(raised_pose.sum())
    solutions = int(sizes.sum())
    own_bad = int(own_err.sum()) if own_poses is not None else 0
    check_s = time.perf_counter() - started
    result = IkResult(
        model=model.name,
        solver=solver.name,
        method=str(getattr(solver, "method", "")),
        frame_from=frame_from,
        frame_to=frame_to,
        tol_pos_m=tol_pos,
        tol_rot_rad=tol_rot,
        seed=seed,
        samples=samples,
        poses=len(q_all),
        singular_poses=int(singular.sum()),
        solutions=solutions,
        counts=dict(sorted(counts.items())),
        wrong_solutions=wrong,
        missed=missed,
        garbage=garbage,
        raised=raised,
        own_fk=own_poses is not None,
        own_fk_disagreements=own_bad,
        missed_by_branch=dict(missed_by.most_common()),
        wrong_by_branch=dict(wrong_by.most_common()),
        worst=tuple(_worst(cases)),
        explanation=(),
        solve_s=solve_s,
        check_s=check_s,
        messages=messages,
        completeness_checked=complete,
        error=errors.get(-1, ""),
    )
    return _explained(result, cases)


@dataclass(frozen=True)
class _Solutions:
    """Every solution of every pose, judged at once (a row per solution, unless said).

    Attributes:
        sizes: How many solutions each pose got (a row per pose).
        owner: The pose each solution answers.
        start: Pose ``i``'s solutions are rows ``start[i]:start[i + 1]`` (a row per pose, and one).
        flat: The solutions.
        finite: Whether it holds no NaN or inf.
        pos: How far it puts the ``to`` frame from its pose, metres.
        rot: And how far turned, radians.
        bad: Finite, and beyond either tolerance: a wrong solution.
        delta: It minus its pose's ``q``, revolute joints wrapped to (-π, π].
        gap: The largest ``|delta|``.
        names: Its branch (``""`` for an arm branches are not named for).
        found: Whether the pose's ``q`` is among its sound solutions (a row per pose).
    """

    sizes: NDArray[np.int64]
    owner: NDArray[np.int64]
    start: NDArray[np.int64]
    flat: Float
    finite: NDArray[np.bool_]
    pos: Float
    rot: Float
    bad: NDArray[np.bool_]
    delta: Float
    gap: Float
    names: list[str]
    found: NDArray[np.bool_]


def _judge_solutions(
    model: Model,
    answers: list[Float],
    q_all: Float,
    targets: Float,
    frames: tuple[str, str],
    tol: tuple[float, float],
    *,
    named: bool,
) -> _Solutions:
    """Judge every solution of every pose at once.

    The check costs a few batched FKs, not a Python loop of small ones (the
    per-pose loop of :func:`check_ik` visits failures only).
    """
    frame_from, frame_to = frames
    tol_pos, tol_rot = tol
    revolute = np.array([j.type == "revolute" for j in model.joints])
    sizes = np.array([len(a) for a in answers], dtype=np.int64)
    owner = np.repeat(np.arange(len(q_all)), sizes)
    flat = np.concatenate(answers) if len(owner) else np.zeros((0, model.dof))
    finite: NDArray[np.bool_] = np.asarray(np.isfinite(flat).all(axis=1))
    safe = np.where(finite[:, None], flat, 0.0)
    reached = model.fk(safe, frame_from=frame_from, frame_to=frame_to)
    pos = position_error_m(reached, targets[owner])
    rot = rotation_error_rad(reached, targets[owner])
    bad: NDArray[np.bool_] = finite & ((pos > tol_pos) | (rot > tol_rot))
    delta = safe - q_all[owner]
    delta[:, revolute] = np.angle(np.exp(1j * delta[:, revolute]))
    gap = np.abs(delta).max(axis=1, initial=0.0)
    same = finite & ~bad & (gap <= SAME_CONFIGURATION_RAD)
    found = np.zeros(len(q_all), dtype=bool)
    np.logical_or.at(found, owner, same)
    names = branch_names(branch_values(model, safe)) if named and len(owner) else [""] * len(owner)
    start = np.concatenate([[0], np.cumsum(sizes)])
    return _Solutions(sizes, owner, start, flat, finite, pos, rot, bad, delta, gap, names, found)


def _pose_cases(
    i: int,
    base: dict[str, Any],
    s: _Solutions,
    *,
    raised: str | None,
    garbage: bool,
    missed: bool,
    own: tuple[float, float] | None,
    solver: IkSolver,
    model: Model,
    target: Float,
    tol: tuple[float, float],
) -> list[IkCase]:
    """The failing cases of pose ``i``, in the order raised, garbage, wrong, missed, own-fk.

    Args:
        i: The pose.
        base: Its :class:`IkCase` fields ``index``, ``origin``, ``q`` and ``branch``.
        s: Every solution, judged.
        raised: What the solver raised on it, or ``None``.
        garbage: Whether a solution holds NaN or inf.
        missed: Whether its configuration is missing.
        own: The solver's own FK's position and rotation error at ``q`` when it
            disagrees with the table, else ``None``.
        solver: The solver (its own FK tells a wrong solution's cause).
        model: The model.
        target: The pose.
        tol: The soundness tolerances, metres and radians.
    """
    if raised is not None:
        return [_case("raised", base, (), (), None, math.inf, math.inf, raised)]
    cases: list[IkCase] = []
    rows = slice(s.start[i], s.start[i + 1])
    sols = s.flat[rows]
    returned = tuple(n for n, ok in zip(s.names[rows], s.finite[rows], strict=True) if ok)
    if garbage:
        cases.append(
            _case("garbage", base, sols, (), None, math.inf, math.inf,
                  f"{int((~s.finite[rows]).sum())} of its {len(sols)} solutions hold NaN or inf")
        )  # fmt: skip
    good = np.flatnonzero(s.finite[rows])
    for k in np.flatnonzero(s.bad[rows]).tolist():
        own_at = _own_pose(solver, i, s.finite[rows], int(np.searchsorted(good, k)), sols[k])
        cases.append(
            _case("wrong", base, sols, returned, sols[k], float(s.pos[rows][k]),
                  float(s.rot[rows][k]), _why_wrong(own_at, target, *tol))
        )  # fmt: skip
    if missed:
        why = _why_missed(model, s, rows, base["branch"], returned, own_disagrees=own is not None)
        cases.append(_case("missed", base, sols, returned, None, 0.0, 0.0, why))
    if own is not None:
        cases.append(
            _case("own-fk", base, sols, returned, None, *own,
                  "the solver's own FK disagrees with the table at q")
        )  # fmt: skip
    return cases


def _why_missed(
    model: Model,
    s: _Solutions,
    rows: slice,
    branch: str,
    returned: tuple[str, ...],
    *,
    own_disagrees: bool,
) -> str:
    """Why a pose missed its configuration: what it got, how near the nearest right one came."""
    why = f"missed {branch or 'the configuration'}; returned {len(s.flat[rows])}"
    if returned:
        why += f" ({'; '.join(sorted(set(returned)))})"
    right = np.flatnonzero(s.finite[rows] & ~s.bad[rows])
    if len(right):  # how near the nearest right one came: a snapped singularity?
        nearest = right[np.argmin(s.gap[rows][right])]
        joint = int(np.argmax(np.abs(s.delta[rows][nearest])))
        why += (
            f"; the nearest right solution is {s.gap[rows][nearest]:.2g} rad from it "
            f"(joint {joint + 1}, {model.joints[joint].name})"
        )
    if own_disagrees:
        why += "; its own FK disagrees with the table here: it solves another arm"
    return why


def _row(q: Float) -> tuple[float, ...]:
    return tuple(float(v) for v in q)


def _case(
    kind: str,
    base: dict[str, Any],
    sols: Any,
    returned_branches: tuple[str, ...],
    solution: Float | None,
    pos: float,
    rot: float,
    why: str,
) -> IkCase:
    return IkCase(
        kind=kind,
        returned=tuple(_row(s) for s in sols),
        returned_branches=returned_branches,
        solution=None if solution is None else _row(solution),
        position_error_m=pos,
        rotation_error_rad=rot,
        explanation=why,
        **base,
    )


def _own_pose(
    solver: IkSolver, index: int, finite: Any, k: int, solution: Float
) -> Float | str | None:
    """The solver's own FK at the ``k``-th finite solution of pose ``index``.

    ``None`` without an own FK; the text of its failure if it raised.
    """
    precomputed = getattr(solver, "fk_at_solutions", None)
    if precomputed is not None:  # the user's function: computed in its own process
        poses: Float = precomputed[index][finite][k]
        return poses
    fk = getattr(solver, "fk", None)
    if not callable(fk):
        return None
    try:
        own: Float = np.asarray(fk(solution.copy()), dtype=np.float64)
    except Exception as exc:  # the solver's own fk, in a diagnosis: one line
        return f"raised {type(exc).__name__}: {exc}"
    return own


def _why_wrong(own: Float | str | None, target: Float, tol_pos: float, tol_rot: float) -> str:
    """Whether a wrong solution is the solver's FK's fault or its inversion's."""
    if own is None:
        return (
            "it does not reproduce the pose (the solver has no fk to tell its FK from its "
            "inversion)"
        )
    if isinstance(own, str):
        return f"it does not reproduce the pose; its fk {own}"
    if np.shape(own) == (4, 4) and (
        float(position_error_m(own, target)) <= tol_pos
        and float(rotation_error_rad(own, target)) <= tol_rot
    ):
        return (
            "its own FK maps this solution to the pose: the inversion is consistent, "
            "the solver's forward model disagrees with the table"
        )
    return (
        "its inversion is wrong: the solution reproduces the pose neither by the table nor by "
        "its own FK"
    )


def _solve_all(
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


def _worst(cases: list[IkCase]) -> list[IkCase]:
    """Up to :data:`WORST_CASES`, one per pose and kind: one of each kind first, then by error."""
    order = sorted(cases, key=lambda c: (-c.position_error_m, -c.rotation_error_rad))
    seen: set[tuple[str, int]] = set()
    unique: list[IkCase] = []
    for case in order:
        if (case.kind, case.index) not in seen:
            seen.add((case.kind, case.index))
            unique.append(case)
    order = unique
    picked: list[IkCase] = []
    for kind in ("raised", "garbage", "own-fk", "wrong", "missed"):
        first = next((c for c in order if c.kind == kind), None)
        if first is not None:
            picked.append(first)
    for case in order:
        if len(picked) >= WORST_CASES:
            break
        if case not in picked:
            picked.append(case)
    return picked


def _explained(result: IkResult, cases: list[IkCase]) -> IkResult:
    """The result with its explanation: which poses, which branches, FK or inversion."""
    lines: list[str] = []
    if result.error:
        lines.append(f"the solver failed as a whole: {result.error}")
    if result.own_fk_disagreements:
        worst = max((c for c in cases if c.kind == "own-fk"), key=lambda c: c.position_error_m)
        lines.append(
            f"its own FK disagrees with the table at {result.own_fk_disagreements} of "
            f"{result.poses} configurations (worst {worst.position_error_m:.3g} m, "
            f"{worst.rotation_error_rad:.3g} rad): it models another arm"
        )
    if result.wrong_solutions:
        lines.extend(_wrong_lines(result, cases))
    if result.missed:
        lines.append(_missed_line(result, cases))
    if result.garbage:
        lines.append(f"{result.garbage} poses answered with NaN or inf")
    if result.raised:
        first = next(c for c in cases if c.kind == "raised")
        lines.append(f"it raised on {result.raised} poses (first: {first.explanation})")
    return dataclasses.replace(result, explanation=tuple(lines))


def _wrong_lines(result: IkResult, cases: list[IkCase]) -> list[str]:
    """The wrong solutions by branch, then their three commonest explanations."""
    why = Counter(c.explanation for c in cases if c.kind == "wrong")
    poses = len({c.index for c in cases if c.kind == "wrong"})
    return [
        f"{result.wrong_solutions} wrong solutions on {poses} poses, by branch: "
        + ", ".join(f"{b or 'unnamed'} ({n})" for b, n in result.wrong_by_branch.items()),
        *(f"  {n}×: {text}" for text, n in why.most_common(3)),
    ]


def _missed_line(result: IkResult, cases: list[IkCase]) -> str:
    """The missed poses by branch and by where their configurations came from."""
    origins = Counter(c.origin for c in cases if c.kind == "missed")
    return (
        f"{result.missed} poses missed their configuration, by branch: "
        + ", ".join(f"{b or 'unnamed'} ({n})" for b, n in result.missed_by_branch.items())
        + "; from: "
        + ", ".join(f"{o} ({n})" for o, n in origins.most_common())
    )
