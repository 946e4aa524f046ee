"""What an IK check finds: the failing poses, the counts, the explanation.

:class:`IkResult` is what :func:`~fkcheck.ik.check.check_ik` returns (and
``fkcheck ik --json`` writes, :mod:`fkcheck.ik.output`); :func:`explained` words
a failing solver's cases as lines and :func:`worst_cases` picks the ones kept.
"""

from __future__ import annotations

import dataclasses
from collections import Counter
from dataclasses import dataclass, field

__all__ = ["WORST_CASES", "IkCase", "IkResult", "explained", "worst_cases"]

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
        singular_poses: Of them, singular (:data:`~fkcheck.ik.check.SINGULAR_SIGMA`).
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


def worst_cases(cases: list[IkCase]) -> list[IkCase]:
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


def explained(result: IkResult, cases: list[IkCase]) -> IkResult:
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
