"""Where two chains part: DH frames against DH frames, or joint axes against the URDF, as views.

Every number goes through :mod:`fkcheck.io.format`; text from a model
file or URDF passes through unchanged and is escaped by the templates.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from fkcheck.engine.evidence import DhParting, UrdfAxes
from fkcheck.engine.results import REFERENCE_NAME, BackendResult, CheckResult
from fkcheck.io.format import (
    format_deg,
    format_mm,
)
from fkcheck.model.types import Model
from fkcheck.report.views import (
    PartingRow,
    PartingView,
)

if TYPE_CHECKING:
    pass

from fkcheck.report.measures import measure_m, measure_rad

__all__ = ["axis_parting_view", "dh_frame_label", "parting_view", "partings"]


def dh_frame_label(model: Model, i: int) -> str:
    """``DH frame i (after joint i, NAME)``, or ``DH frame 0 (base)``."""
    if i == 0:
        return "DH frame 0 (base)"
    return f"DH frame {i} (after joint {i}, {model.joints[i - 1].name})"


def parting_view(check: CheckResult, r: BackendResult, parting: DhParting) -> PartingView:
    """Every DH frame of a DH backend against the in-house one: where the chains part."""
    model = check.model
    rows = tuple(
        PartingRow(
            frame=dh_frame_label(model, i),
            position_error=measure_m(float(parting.position_error_m[i])),
            rotation_error=measure_rad(float(parting.rotation_error_rad[i])),
            differs=bool(
                parting.position_error_m[i] > check.tol_pos_m
                or parting.rotation_error_rad[i] > check.tol_rot_rad
            ),
            first=i == parting.first,
        )
        for i in range(parting.ours.shape[0])
    )
    if parting.first is None:
        verdict = (
            "Every DH frame agrees within tolerance at this configuration: the chains do not "
            "part; the difference comes after the last DH frame (the tool transform or a "
            "frame's fixed offset)."
        )
    else:
        i = parting.first
        agree = (
            "no frame before it agrees (the base differs)"
            if i == 0
            else (f"frames 0–{i - 1} agree" if i > 1 else "frame 0 agrees")
        )
        verdict = (
            f"The chains part at {dh_frame_label(model, i)}: {agree}; this frame is "
            f"{format_mm(float(parting.position_error_m[i]))} and "
            f"{format_deg(float(parting.rotation_error_rad[i]))} off. Look at row {i} of "
            "the DH table (and the rows' units and signs)."
        )
    return PartingView(
        title=f"{r.name}: DH frames world_T_i, i = 0…{model.dof}",
        verdict=verdict,
        parted=parting.first is not None,
        short=""
        if parting.first is None
        else f"{r.name}'s chain parts from the in-house one at "
        f"{dh_frame_label(model, parting.first)}",
        what=(
            f"Every DH frame at configuration #{parting.index} (this backend's worst), from "
            f"{REFERENCE_NAME} and from {r.name}'s own chain built from the same table, both in "
            "the world frame. The first frame beyond tolerance is where the chains part."
        ),
        rows=rows,
    )


def axis_parting_view(check: CheckResult, r: BackendResult, parting: UrdfAxes) -> PartingView:
    """Each joint's axis from the table against the URDF's: the first that differs."""
    model = check.model
    standard = model.convention == "standard"
    rows = []
    for i, (joint, axis) in enumerate(zip(model.joints, parting.rows, strict=True)):
        frame = i if standard else i + 1
        rows.append(
            PartingRow(
                frame=f"joint {i + 1}, {joint.name} (URDF {parting.urdf_joints[i]}): "
                f"z of DH frame {frame}",
                position_error=measure_m(axis.distance_m),
                rotation_error=measure_rad(axis.angle_rad),
                differs=not axis.agrees,
                first=i == parting.first,
            )
        )
    if parting.first is None:
        verdict = (
            "Every joint axis of the DH table lies on the URDF's at this configuration: the "
            "difference comes after the last joint axis — the last row's d or θ offset, the "
            f"tool transform, or the mapping of {check.frame_to}."
        )
    else:
        i = parting.first
        frame = i if standard else i + 1
        axis = parting.rows[i]
        agree = (
            f"the axes of joints 1–{i} agree"
            if i > 1
            else ("the axis of joint 1 agrees" if i == 1 else "no joint before it")
        )
        look = (
            f"Look at row {frame} of the DH table."
            if frame > 0
            else f"Look at the base transform and the mapping of {check.frame_from}."
        )
        off = (
            f"{format_mm(axis.distance_m)} off and turned"
            if axis.distance_m is not None
            else "turned"  # a sliding joint's axis is a direction only
        )
        verdict = (
            f"The DH table parts from the URDF at {dh_frame_label(model, frame)}: the axis of "
            f"joint {i + 1} ({model.joints[i].name}, URDF {parting.urdf_joints[i]}) is "
            f"{off} {format_deg(axis.angle_rad)} from the URDF's; {agree}. {look}"
        )
    return PartingView(
        title=f"DH table against the URDF: joint axes in {check.frame_from}",
        verdict=verdict,
        parted=parting.first is not None,
        short=""
        if parting.first is None
        else "the DH table parts from the URDF at "
        f"{dh_frame_label(model, parting.first if standard else parting.first + 1)} "
        f"(axis of joint {parting.first + 1} differs)",
        what=(
            f"Each joint's axis as a line in {check.frame_from}, at configuration "
            f"#{parting.index} ({r.name}'s worst): from the DH table (z of the DH frame the "
            "joint turns about, reversed for a flipped joint) and from the URDF (the joint's "
            "<axis> in its joint frame). Position: distance between the two lines (none for "
            "a prismatic joint, whose axis is a direction only); rotation: angle between the "
            "two directions (180° = the joint turns the other way). DH frames and URDF links "
            "are different frames, but each joint's axis is one physical line. Computed "
            "during the check by fkcheck.engine.axes from the URDF text, apart from the backends."
        ),
        rows=tuple(rows),
    )


def partings(check: CheckResult) -> tuple[PartingView, ...]:
    """DH frames of failing DH backends; joint axes against the URDF for the first other one."""
    out = []
    urdf_done = False
    for r in check.backends:
        if r.status != "fail" or r.detail is None:
            continue
        if r.detail.dh_parting is not None:
            out.append(parting_view(check, r, r.detail.dh_parting))
        elif not urdf_done and r.detail.urdf_axes is not None:
            out.append(axis_parting_view(check, r, r.detail.urdf_axes))
            urdf_done = True
    return tuple(out)
