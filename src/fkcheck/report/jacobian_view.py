"""The report's Jacobian section (``check --jacobian``): the view model, from the results only."""

from __future__ import annotations

from fkcheck.engine.results import CheckResult
from fkcheck.io.format import format_scientific
from fkcheck.report.views import JacobianCell, JacobianRow, JacobianSection

__all__ = ["jacobian_section"]

#: What each reference frame means, in the page's words.
_MEANING = {
    "world-aligned": "the {to} origin's velocity and the angular velocity, in {frm} axes "
    "(Pinocchio LOCAL_WORLD_ALIGNED; Robotics Toolbox jacob0)",
    "local": "the same twist in {to}'s own axes (Pinocchio LOCAL; Robotics Toolbox jacobe)",
    "world": "the spatial twist at the {frm} origin, in {frm} axes (Pinocchio WORLD)",
}


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
        first, bad = j.first_bad_column, j.bad_columns
        cells: tuple[JacobianCell, ...] = ()
        if j.column_linear is not None and j.column_angular is not None and bad is not None:
            per = ("m" if joint.type == "prismatic" else "rad" for joint in check.model.joints)
            cells = tuple(
                JacobianCell(
                    format_scientific(float(lin), f"m/{unit}"),
                    format_scientific(float(ang), f"rad/{unit}"),
                    bool(bad[k]),
                    k == first,
                )
                for k, (lin, ang, unit) in enumerate(
                    zip(j.column_linear, j.column_angular, per, strict=True)
                )
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
                diagnosis=j.diagnosis,
                diagnosis_details=j.diagnosis_details,
                cells=cells,
            )
        )
    meaning = _MEANING[spec.reference].format(to=check.frame_to, frm=check.frame_from)
    return JacobianSection(
        spec.reference, check.frame_to, meaning, f"{spec.tol:g}", joints, tuple(rows)
    )
