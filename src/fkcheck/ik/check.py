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
its own FK or its inversion is wrong (:attr:`IkResult.explanation`). The
result's types and wording are :mod:`fkcheck.ik.result`; calling the solver is
:mod:`fkcheck.ik.answers`.
"""

from __future__ import annotations

import math
import time
from collections import Counter
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from fkcheck.core.metrics import position_error_m, rotation_error_rad
from fkcheck.core.typing import Float
from fkcheck.ik.answers import solve_all
from fkcheck.ik.branches import branch_names, branch_values, classifiable
from fkcheck.ik.poses import ik_configurations
from fkcheck.ik.result import WORST_CASES, IkCase, IkResult, explained, worst_cases
from fkcheck.ik.solver import IkSolver
from fkcheck.model.sampling import Samples
from fkcheck.model.types import Model

__all__ = [
    "SAME_CONFIGURATION_RAD",
    "SINGULAR_SIGMA",
    "WORST_CASES",  # re-exported: defined in fkcheck.ik.result
    "IkCase",  # re-exported
    "IkResult",  # re-exported
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

    answers, errors, own_poses, messages, solve_s = solve_all(model, solver, targets, q_all)
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
        worst=tuple(worst_cases(cases)),
        explanation=(),
        solve_s=solve_s,
        check_s=check_s,
        messages=messages,
        completeness_checked=complete,
        error=errors.get(-1, ""),
    )
    return explained(result, cases)


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
