"""The Jacobian section: each backend's columns against fkcheck's.

View models (:mod:`fkcheck.report.views`): plain text, numbers and nested views only.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = [
    "JacobianCell",
    "JacobianRow",
    "JacobianSection",
]


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
        diagnosis: Which convention would make it agree (``""`` when not diagnosed).
        diagnosis_details: The diagnosis's further lines.
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
    diagnosis: str
    diagnosis_details: tuple[str, ...]
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
