"""The report's Jacobian section (``check --jacobian``): the view model, from the results only."""

from __future__ import annotations

from dataclasses import dataclass

from fkcheck.engine.results import CheckResult
from fkcheck.io.format import format_scientific

__all__ = ["JacobianCell", "JacobianRow", "JacobianSection", "jacobian_section"]

#: What each reference frame means, in the page's words.
_MEANING = {
    "world-aligned": "the {to} origin's velocity and the angular velocity, in {frm} axes "
    "(Pinocchio LOCAL_WORLD_ALIGNED; Robotics Toolbox jacob0)",
    "local": "the same twist in {to}'s own axes (Pinocchio LOCAL; Robotics Toolbox jacobe)",
    "world": "the spatial twist at the {frm} origin, in {frm} axes (Pinocchio WORLD)",
}


@dataclass(frozen=True)
class JacobianCell:
    """One joint column of one backend: its largest differences.

    Attributes:
        linear: Largest linear difference of the column (m/rad), formatted.
        angular: Largest angular difference (rad/rad), formatted.
        bad: Beyond the tolerance.
        first: The first joint whose column disagrees, for this backend.
    """

    linear: str
    angular: str
    bad: bool
    first: bool


@dataclass(frozen=True)
class JacobianRow:
    """One backend's Jacobian comparison.

    Attributes:
        name: Backend name.
        status: ``pass``, ``fail``, ``error`` or ``skipped``.
        linear: Largest linear difference, formatted (``–`` if not compared).
        angular: Largest angular difference, formatted.
        method: Its library's Jacobian, or the finite differences of its poses.
        tolerance: The tolerance applied to it, formatted.
        message: Why it failed, errored or was skipped.
        first_column: The first joint whose column disagrees (``""`` when none).
        cells: One per joint column (empty if not compared).
    """

    name: str
    status: str
    linear: str
    angular: str
    method: str
    tolerance: str
    message: str
    first_column: str
    cells: tuple[JacobianCell, ...]


@dataclass(frozen=True)
class JacobianSection:
    """The Jacobian section of a report.

    Attributes:
        reference: ``world-aligned``, ``local`` or ``world``.
        target: The frame whose Jacobian is compared (the check's ``to``).
        meaning: What that reference frame is, for this check's frames.
        tolerance: The asked tolerance, formatted.
        joints: Column headers, one per joint.
        rows: One per backend that was asked.
    """

    reference: str
    target: str
    meaning: str
    tolerance: str
    joints: tuple[str, ...]
    rows: tuple[JacobianRow, ...]


def jacobian_section(check: CheckResult) -> JacobianSection | None:
    """The section, or ``None`` when the check compared no Jacobian."""
    spec = check.jacobian
    if spec is None:
        return None
    joints = tuple(f"{i + 1} {j.name}" for i, j in enumerate(check.model.joints))
    rows = []
    for r in check.backends:
        j = r.jacobian
        if j is None:
            continue
        first = j.first_bad_column
        cells: tuple[JacobianCell, ...] = ()
        if j.column_linear is not None and j.column_angular is not None:
            cells = tuple(
                JacobianCell(
                    format_scientific(float(lin), "m/rad"),
                    format_scientific(float(ang), "rad/rad"),
                    not (max(lin, ang) <= j.tolerance),
                    k == first,
                )
                for k, (lin, ang) in enumerate(zip(j.column_linear, j.column_angular, strict=True))
            )
        rows.append(
            JacobianRow(
                name=r.name,
                status=j.status,
                linear=format_scientific(j.max_linear_error, "m/rad"),
                angular=format_scientific(j.max_angular_error, "rad/rad"),
                method=j.method,
                tolerance=f"{j.tolerance:g}",
                message=j.message,
                first_column="" if first is None else joints[first],
                cells=cells,
            )
        )
    meaning = _MEANING[spec.reference].format(to=check.frame_to, frm=check.frame_from)
    return JacobianSection(
        spec.reference, check.frame_to, meaning, f"{spec.tol:g}", joints, tuple(rows)
    )
