"""The report's backend rows and per-backend details (worst cases, arm drawing) as views.

Every number goes through :mod:`fkcheck.io.format`; text from a model
file or URDF passes through unchanged and is escaped by the templates.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from fkcheck.engine.evidence import WorstCases
from fkcheck.engine.results import BackendResult, CheckResult
from fkcheck.io.format import (
    format_seconds,
)
from fkcheck.report.record import BackendRecord
from fkcheck.report.views import (
    ArmDrawing,
    BackendDetail,
    BackendRow,
    WorstCase,
)

if TYPE_CHECKING:
    pass

from fkcheck.report.measures import (
    difference_entry,
    joint_values,
    matrix_view,
    measure_m,
    measure_rad,
    pose_forms,
    q_text,
)

__all__ = ["anchor", "backend_detail", "backend_row", "worst_cases"]


def anchor(name: str) -> str:
    """The HTML anchor of a backend's detail section."""
    safe = "".join(c if c.isalnum() else "-" for c in name.lower())
    return f"backend-{safe}"


def backend_row(r: BackendRecord, has_detail: bool) -> BackendRow:
    """One row of the backends table, from the backend's record: errors (max, p99, median)."""
    return BackendRow(
        name=r.name,
        anchor=anchor(r.name) if has_detail else "",
        status=r.status,
        label=r.label,
        method=r.method,
        duration=format_seconds(r.duration_s),
        message=r.message,
        pos_max=measure_m(r.max_position_m),
        pos_p99=measure_m(r.p99_position_m),
        pos_median=measure_m(r.median_position_m),
        rot_max=measure_rad(r.max_rotation_rad),
        rot_p99=measure_rad(r.p99_rotation_rad),
        rot_median=measure_rad(r.median_rotation_rad),
        worst_q=r.worst_q_text if r.ran else "",
        worst_origin=r.worst_origin if r.ran else "",
    )


def worst_cases(check: CheckResult, r: BackendResult, worst: WorstCases) -> tuple[WorstCase, ...]:
    """A failing backend's worst configurations as views: both poses, the difference marked."""
    assert r.position_error_m is not None
    assert r.rotation_error_rad is not None
    tol = np.full((4, 4), check.tol_rot_rad)
    tol[:, 3] = check.tol_pos_m
    out = []
    for rank, index in enumerate(worst.indices, start=1):
        ours, theirs = worst.ours[rank - 1], worst.theirs[rank - 1]
        delta = theirs - ours
        marked = ~(np.abs(delta) <= tol)  # NaN entries are marked too
        out.append(
            WorstCase(
                rank=rank,
                index=index,
                origin=check.origin[index],
                q=joint_values(check.model, check.q[index]),
                position_error=measure_m(float(r.position_error_m[index])),
                rotation_error=measure_rad(float(r.rotation_error_rad[index])),
                ours=pose_forms(ours, marked),
                theirs=pose_forms(theirs, marked),
                difference=matrix_view(delta, marked, difference_entry),
            )
        )
    return tuple(out)


def backend_detail(check: CheckResult, r: BackendResult, plots: bool) -> BackendDetail:
    """A failing backend's detail section: summary, worst q, arm drawing, worst cases."""
    from fkcheck.report.plots import arm_drawing

    arm = None
    if plots and r.detail is not None:
        image = arm_drawing(check, r, r.detail)
        arm = ArmDrawing(image) if image is not None else None
    worst_q = q_text(check.model, check.q[r.worst_index]) if r.worst_index is not None else ""
    return BackendDetail(
        name=r.name,
        anchor=anchor(r.name),
        summary=r.message,
        worst_q=worst_q,
        arm=arm,
        worst_cases=worst_cases(check, r, r.detail.worst) if r.detail is not None else (),
    )
