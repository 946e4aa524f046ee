"""The report's Jacobian section (``check --jacobian``): the view model, from the results only."""

from __future__ import annotations

from fkcheck.engine.results import CheckResult
from fkcheck.io.format import format_scientific
from fkcheck.report.record import CheckRecord
from fkcheck.report.views import JacobianCell, JacobianRow, JacobianSection

__all__ = ["jacobian_section"]

#: What each reference frame means, in the page's words.
_MEANING = {
    "world-aligned": "the {to} origin's velocity and the angular velocity, in {frm} axes "
    "(Pinocchio LOCAL_WORLD_ALIGNED; Robotics Toolbox jacob0)",
    "local": "the same twist in {to}'s own axes (Pinocchio LOCAL; Robotics Toolbox jacobe)",
    "world": "the spatial twist at the {frm} origin, in {frm} axes (Pinocchio WORLD)",
}


def jacobian_section(check: CheckResult, record: CheckRecord) -> JacobianSection | None:
    """The section, or ``None`` when the check compared no Jacobian."""
    spec = check.jacobian
    if spec is None:
        return None
    joints = tuple(f"{i + 1} {j.name}" for i, j in enumerate(check.model.joints))
    rows = []
    for r in record.backends:
        j = r.jacobian
        if j is None:
            continue
        cells = tuple(
            JacobianCell(
                format_scientific(c.linear, "m/m" if c.prismatic else "m/rad"),
                format_scientific(c.angular, "rad/m" if c.prismatic else "rad/rad"),
                c.bad,
                k == j.first_column,
            )
            for k, c in enumerate(j.columns)
        )
        rows.append(
            JacobianRow(
                name=r.name,
                status=j.status,
                linear=format_scientific(j.max_linear, "m/rad"),
                angular=format_scientific(j.max_angular, "rad/rad"),
                method=j.method,
                tolerance=f"{j.tolerance:g}",
                message=j.message,
                first_column="" if j.first_column is None else joints[j.first_column],
                diagnosis=j.diagnosis,
                diagnosis_details=j.diagnosis_details,
                cells=cells,
            )
        )
    meaning = _MEANING[spec.reference].format(to=check.frame_to, frm=check.frame_from)
    return JacobianSection(
        spec.reference, check.frame_to, meaning, f"{spec.tol:g}", joints, tuple(rows)
    )
