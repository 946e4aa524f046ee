"""Check results → view models: every number formatted, every sentence written, here.

The templates only lay out what these functions return (see
:mod:`fkcheck.report.views`). Text from a model file or URDF passes through
unchanged and is escaped by the template engine on output.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from fkcheck._version import __version__
from fkcheck.core.geometry import rpy_from_matrix
from fkcheck.core.tolerances import SAME_CHAIN
from fkcheck.core.typing import Float
from fkcheck.engine.evidence import DhParting, UrdfAxes, WorstCases
from fkcheck.engine.results import REFERENCE_NAME, BackendResult, CheckResult
from fkcheck.engine.verdict import KINDS, evidence_sentences
from fkcheck.engine.verdict import headline as verdict_headline
from fkcheck.model.types import FrameSpec, Model, Offset
from fkcheck.report.format import (
    format_constant,
    format_deg,
    format_fixed,
    format_m,
    format_mm,
    format_rad,
    format_seconds,
    format_value,
)
from fkcheck.report.views import (
    ArmDrawing,
    BackendDetail,
    BackendRow,
    DhRow,
    DiagnosisView,
    EvidenceLine,
    Fact,
    FrameRow,
    FrameSide,
    Image,
    IndexModel,
    IndexPage,
    IndexRow,
    JointValue,
    MatrixCell,
    MatrixView,
    Measure,
    ModelView,
    PartingRow,
    PartingView,
    PoseForms,
    ReportPage,
    TransformView,
    WorstCase,
)

if TYPE_CHECKING:
    from fkcheck.diagnose.failures import BackendDiagnosis

__all__ = [
    "IndexEntry",
    "build_index_page",
    "build_report_page",
    "measure_deg",
    "measure_m",
    "measure_rad",
    "overall_verdict",
    "pose_forms",
    "verdict_line",
]


_STANDARD_A = (
    ("cos θᵢ", "−sin θᵢ cos αᵢ", "sin θᵢ sin αᵢ", "aᵢ cos θᵢ"),
    ("sin θᵢ", "cos θᵢ cos αᵢ", "−cos θᵢ sin αᵢ", "aᵢ sin θᵢ"),
    ("0", "sin αᵢ", "cos αᵢ", "dᵢ"),
    ("0", "0", "0", "1"),
)
_MODIFIED_A = (
    ("cos θᵢ", "−sin θᵢ", "0", "aᵢ₋₁"),
    ("sin θᵢ cos αᵢ₋₁", "cos θᵢ cos αᵢ₋₁", "−sin αᵢ₋₁", "−dᵢ sin αᵢ₋₁"),
    ("sin θᵢ sin αᵢ₋₁", "cos θᵢ sin αᵢ₋₁", "cos αᵢ₋₁", "dᵢ cos αᵢ₋₁"),
    ("0", "0", "0", "1"),
)
_FORMULA = {
    "standard": "standard DH: Aᵢ = Rz(θᵢ) · Tz(dᵢ) · Tx(aᵢ) · Rx(αᵢ), mapping frame i−1 to frame i",
    "modified": "modified DH (Craig): Aᵢ = Rx(αᵢ₋₁) · Tx(aᵢ₋₁) · Rz(θᵢ) · Tz(dᵢ), mapping frame "
    "i−1 to frame i; row i of the table holds aᵢ₋₁ and αᵢ₋₁",
}
_VARIABLE_NOTE = (
    "Revolute joint: θᵢ = sᵢ·qᵢ + θ offset, dᵢ fixed; prismatic joint: dᵢ = sᵢ·qᵢ + d "
    "offset, θᵢ fixed; sᵢ = −1 for a flipped joint, else +1. "
    "world_T_tcp = base · A₁ ⋯ Aₙ · tool."
)


# --------------------------------------------------------------------------- numbers


def measure_m(value: float | None) -> Measure:
    """A length: millimetres first, metres second."""
    return Measure(value, format_mm(value), format_m(value))


def measure_rad(value: float | None) -> Measure:
    """An angle: radians first, degrees second."""
    return Measure(value, format_rad(value), format_deg(value))


def measure_deg(value: float | None) -> Measure:
    """An angle: degrees first, radians second (the diagnosis speaks in degrees)."""
    return Measure(value, format_deg(value), format_rad(value))


def _xyz_rpy(offset: Offset) -> str:
    if offset.is_identity:
        return "none"
    xyz = ", ".join(format_constant(v) for v in offset.xyz)
    rpy = ", ".join(format_constant(math.degrees(v)) for v in offset.rpy)
    return f"xyz ({xyz}) m, rpy ({rpy})°"


def _difference_entry(value: float) -> str:
    """An entry of ``theirs − ours``; round-off (≤ SAME_CHAIN) reads as 0."""
    return "0" if abs(value) <= SAME_CHAIN else f"{value:.2e}"


def _matrix(
    T: Float, marked: NDArray[np.bool_] | None = None, fmt: Callable[[float], str] | None = None
) -> MatrixView:
    show = fmt or (lambda v: format_fixed(v, 9))
    rows = tuple(
        tuple(
            MatrixCell(show(float(T[i, j])), bool(marked[i, j]) if marked is not None else False)
            for j in range(4)
        )
        for i in range(4)
    )
    return MatrixView(rows)


def pose_forms(T: Float, marked: NDArray[np.bool_] | None = None) -> PoseForms:
    """A pose as a matrix, xyz + quaternion (x, y, z, w) and xyz + rpy (degrees).

    The quaternion is SciPy's, scalar last, with w ≥ 0; rpy is fixed-axis
    roll-pitch-yaw as in URDF (``R = Rz(yaw) Ry(pitch) Rx(roll)``) from
    :func:`fkcheck.core.geometry.rpy_from_matrix`: at pitch ±90° yaw is 0 and roll
    carries the rotation.
    """
    from scipy.spatial.transform import Rotation

    xyz = ", ".join(format_fixed(v, 9) for v in T[:3, 3])
    if not np.isfinite(T[:3, :3]).all():  # a backend's NaN/inf answer: no rotation to convert
        quaternion = rpy_text = "(not a rotation: NaN or inf entries)"
    else:
        quat = Rotation.from_matrix(T[:3, :3]).as_quat(canonical=True)
        quaternion = "(" + ", ".join(format_fixed(v, 9) for v in quat) + ")"
        rpy = np.degrees(rpy_from_matrix(T))
        rpy_text = "(" + ", ".join(format_fixed(v, 6) for v in rpy) + ")°"
    return PoseForms(
        matrix=_matrix(T, marked), xyz=f"({xyz}) m", quaternion=quaternion, rpy=rpy_text
    )


def _q_text(model: Model, q: Float) -> str:
    parts = (
        format_value(float(v), j.type == "prismatic") for v, j in zip(q, model.joints, strict=True)
    )
    return "[" + ", ".join(parts) + "]"


def _joint_values(model: Model, q: Float) -> tuple[JointValue, ...]:
    out = []
    for v, joint in zip(q, model.joints, strict=True):
        if joint.type == "prismatic":
            out.append(JointValue(joint.name, f"{format_fixed(v, 9)} m", ""))
        else:
            out.append(
                JointValue(joint.name, format_fixed(v, 9), f"{format_fixed(math.degrees(v), 6)}°")
            )
    return tuple(out)


# --------------------------------------------------------------------------- frames


def _placement(model: Model, spec: FrameSpec) -> str:
    if spec.dh == "world":
        return "the world frame (before the base transform)"
    if spec.dh == "tcp":
        return "the TCP (after the tool transform)"
    if spec.dh == 0:
        return "DH frame 0 (the DH base)"
    joint = model.joints[spec.dh - 1]
    last = ", the last DH frame" if spec.dh == model.dof else ""
    return f"DH frame {spec.dh} (after joint {spec.dh}, {joint.name}{last})"


def _urdf_twin(model: Model, spec: FrameSpec) -> str:
    if spec.urdf is None:
        return "no URDF twin: only backends built from the DH table compare it"
    where = f" of {model.urdf.path}" if model.urdf is not None else ""
    return f"URDF link {spec.urdf}{where}"


def _sides(check: CheckResult) -> tuple[FrameSide, ...]:
    model = check.model
    out = []
    for role, name in (("from", check.frame_from), ("to", check.frame_to)):
        spec = model.frames[name]
        out.append(
            FrameSide(
                role, name, _placement(model, spec), _xyz_rpy(spec.offset), _urdf_twin(model, spec)
            )
        )
    return tuple(out)


# --------------------------------------------------------------------------- backends


def _anchor(name: str) -> str:
    safe = "".join(c if c.isalnum() else "-" for c in name.lower())
    return f"backend-{safe}"


def _backend_row(check: CheckResult, r: BackendResult, has_detail: bool) -> BackendRow:
    worst_q = worst_origin = ""
    if r.ran and r.worst_index is not None:
        worst_q = _q_text(check.model, check.q[r.worst_index])
        worst_origin = check.origin[r.worst_index]
    return BackendRow(
        name=r.name,
        anchor=_anchor(r.name) if has_detail else "",
        status=r.status,
        method=r.method,
        duration=format_seconds(r.duration_s),
        message=r.message,
        pos_max=measure_m(r.max_position_error_m),
        pos_p99=measure_m(r.percentile("position", 99)),
        pos_median=measure_m(r.percentile("position", 50)),
        rot_max=measure_rad(r.max_rotation_error_rad),
        rot_p99=measure_rad(r.percentile("rotation", 99)),
        rot_median=measure_rad(r.percentile("rotation", 50)),
        worst_q=worst_q,
        worst_origin=worst_origin,
    )


def _worst_cases(check: CheckResult, r: BackendResult, worst: WorstCases) -> tuple[WorstCase, ...]:
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
                q=_joint_values(check.model, check.q[index]),
                position_error=measure_m(float(r.position_error_m[index])),
                rotation_error=measure_rad(float(r.rotation_error_rad[index])),
                ours=pose_forms(ours, marked),
                theirs=pose_forms(theirs, marked),
                difference=_matrix(delta, marked, _difference_entry),
            )
        )
    return tuple(out)


def _dh_frame_label(model: Model, i: int) -> str:
    if i == 0:
        return "DH frame 0 (base)"
    return f"DH frame {i} (after joint {i}, {model.joints[i - 1].name})"


def _parting_view(check: CheckResult, r: BackendResult, parting: DhParting) -> PartingView:
    model = check.model
    rows = tuple(
        PartingRow(
            frame=_dh_frame_label(model, i),
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
            f"The chains part at {_dh_frame_label(model, i)}: {agree}; this frame is "
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
        f"{_dh_frame_label(model, parting.first)}",
        what=(
            f"Every DH frame at configuration #{parting.index} (this backend's worst), from "
            f"{REFERENCE_NAME} and from {r.name}'s own chain built from the same table, both in "
            "the world frame. The first frame beyond tolerance is where the chains part."
        ),
        rows=rows,
    )


def _axis_parting_view(check: CheckResult, r: BackendResult, parting: UrdfAxes) -> PartingView:
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
            f"The DH table parts from the URDF at {_dh_frame_label(model, frame)}: the axis of "
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
        f"{_dh_frame_label(model, parting.first if standard else parting.first + 1)} "
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


def _partings(check: CheckResult) -> tuple[PartingView, ...]:
    """DH frames of failing DH backends; joint axes against the URDF for the first other one."""
    out = []
    urdf_done = False
    for r in check.backends:
        if r.status != "fail" or r.detail is None:
            continue
        if r.detail.dh_parting is not None:
            out.append(_parting_view(check, r, r.detail.dh_parting))
        elif not urdf_done and r.detail.urdf_axes is not None:
            out.append(_axis_parting_view(check, r, r.detail.urdf_axes))
            urdf_done = True
    return tuple(out)


def _detail(check: CheckResult, r: BackendResult, plots: bool) -> BackendDetail:
    from fkcheck.report.plots import arm_drawing

    arm = None
    if plots and r.detail is not None:
        image = arm_drawing(check, r, r.detail)
        arm = ArmDrawing(image) if image is not None else None
    worst_q = _q_text(check.model, check.q[r.worst_index]) if r.worst_index is not None else ""
    return BackendDetail(
        name=r.name,
        anchor=_anchor(r.name),
        summary=r.message,
        worst_q=worst_q,
        arm=arm,
        worst_cases=_worst_cases(check, r, r.detail.worst) if r.detail is not None else (),
    )


# --------------------------------------------------------------------------- the model


def _transform_view(label: str, offset: Offset) -> TransformView:
    summary = "identity" if offset.is_identity else _xyz_rpy(offset)
    return TransformView(label, summary, _matrix(offset.matrix, fmt=lambda v: format_fixed(v, 6)))


def _limits(model: Model, i: int) -> str:
    joint = model.joints[i]
    if joint.limits is None:
        return "none"
    lo, hi = joint.limits
    if joint.type == "prismatic":
        return f"{format_constant(lo)} … {format_constant(hi)} m"
    return f"{format_constant(math.degrees(lo))} … {format_constant(math.degrees(hi))}°"


def _model_view(check: CheckResult) -> ModelView:
    model = check.model
    urdf_joints = model.urdf.joints if model.urdf is not None else ()
    rows = tuple(
        DhRow(
            index=i + 1,
            joint=j.name,
            type=j.type,
            a=format_constant(j.a),
            alpha=format_constant(math.degrees(j.alpha)),
            d=format_constant(j.d),
            theta=format_constant(math.degrees(j.theta)),
            flip="yes" if j.flip else "",
            limits=_limits(model, i),
            urdf_joint=urdf_joints[i] if i < len(urdf_joints) else "",
            variable="d" if j.type == "prismatic" else "θ",
        )
        for i, j in enumerate(model.joints)
    )
    compared = {check.frame_from: "from", check.frame_to: "to"}
    frames = tuple(
        FrameRow(
            name=name,
            placement=_placement(model, spec),
            offset=_xyz_rpy(spec.offset),
            urdf=spec.urdf or "",
            compared=compared.get(name, ""),
        )
        for name, spec in model.frames.items()
    )
    return ModelView(
        name=model.name,
        description=model.description,
        source=model.source,
        path=str(model.path) if model.path is not None else "(built in memory)",
        convention=model.convention,
        convention_formula=_FORMULA[model.convention],
        a_matrix=_STANDARD_A if model.convention == "standard" else _MODIFIED_A,
        variable_note=_VARIABLE_NOTE,
        rows=rows,
        base=_transform_view("base: world → DH frame 0", model.base),
        tool=_transform_view(f"tool: DH frame {model.dof} → TCP", model.tool),
        frames=frames,
        urdf=model.urdf.path if model.urdf is not None else "",
    )


# --------------------------------------------------------------------------- the page


def verdict_line(check: CheckResult) -> str:
    """The verdict as one sentence."""
    ran = check.ran
    failing = [r.name for r in check.backends if r.status == "fail"]
    errored = [r.name for r in check.backends if r.status == "error"]
    skipped = [r.name for r in check.backends if r.status == "skipped"]
    parts = []
    if not ran:
        parts.append("No reference backend ran: nothing was cross-checked")
    elif failing:
        parts.append(
            f"{len(failing)} of {len(ran)} backends that ran disagree with the in-house core: "
            + ", ".join(failing)
        )
    else:
        parts.append(f"All {len(ran)} backends that ran agree with the in-house core")
    if errored:
        parts.append(f"{len(errored)} errored: " + ", ".join(errored))
    if skipped:
        parts.append(f"{len(skipped)} skipped: " + ", ".join(skipped))
    return "; ".join(parts) + "."


def _headline(check: CheckResult) -> tuple[str, ...]:
    out = []
    for r in check.backends:
        if r.status != "fail":
            continue
        assert r.position_error_m is not None
        assert r.rotation_error_rad is not None
        n_bad = int(
            (
                (r.position_error_m > check.tol_pos_m) | (r.rotation_error_rad > check.tol_rot_rad)
            ).sum()
        )
        out.append(
            f"{r.name}: max position error {format_mm(r.max_position_error_m)} "
            f"({format_m(r.max_position_error_m)}), max rotation error "
            f"{format_rad(r.max_rotation_error_rad)} ({format_deg(r.max_rotation_error_rad)}); "
            f"{n_bad} of {r.position_error_m.size} configurations beyond tolerance"
        )
    return tuple(out)


def _with_also(d: DiagnosisView) -> str:
    """``pinocchio-urdf`` or ``pinocchio-urdf (and yourdfpy-urdf, rtb-urdf)``."""
    return d.backend + (f" (and {', '.join(d.also)})" if d.also else "")


def _configurations(check: CheckResult) -> str:
    counts = Counter(o.split(":")[0] for o in check.origin)
    names = {
        "pose": "named poses",
        "zero": "zero",
        "mid": "mid-range",
        "corner": "limit corners",
        "edge": "limit edges",
        "random": f"{check.sampler} samples",
    }
    parts = [f"{counts[key]} {label}" for key, label in names.items() if counts.get(key)]
    return f"{check.q.shape[0]} ({', '.join(parts)}); seed {check.seed}"


def build_report_page(
    check: CheckResult,
    *,
    diagnoses: Sequence[BackendDiagnosis] = (),
    versions: dict[str, str] | None = None,
    plots: bool = True,
) -> ReportPage:
    """The report page of one check, from what the check and the diagnosis gathered.

    Runs no backend, no forward kinematics and no parser: the worst
    configurations' poses, the chains and the axes come from each failing
    backend's :attr:`~fkcheck.engine.results.BackendResult.detail`.

    Args:
        check: The check result.
        diagnoses: The diagnoses of its disagreements (see
            :func:`fkcheck.diagnose.failures.diagnose_failures`), for the
            Diagnosis section; each also gets a line on the first screen.
        versions: Library versions to show (default: the installed ones).
        plots: Draw the pictures (Matplotlib); off, the page has none.

    Returns:
        The page's view model.
    """
    from fkcheck.report.diagnosis import diagnosis_view
    from fkcheck.report.plots import error_against_joints, error_distribution
    from fkcheck.report.versions import library_versions

    failing = [r for r in check.backends if r.status == "fail"]
    details = tuple(_detail(check, r, plots) for r in failing)
    diagnosis_views = tuple(diagnosis_view(d) for d in diagnoses)
    rows = tuple(_backend_row(check, r, r.status == "fail") for r in check.backends)
    images: list[Image] = []
    if plots:
        images = [
            im for im in (error_distribution(check), error_against_joints(check)) if im is not None
        ]
    versions = library_versions() if versions is None else versions
    tol = (
        f"{check.tol_pos_m:g} m ({format_mm(check.tol_pos_m)}) position, "
        f"{check.tol_rot_rad:g} rad ({format_deg(check.tol_rot_rad)}) rotation"
    )
    model = check.model
    facts = (
        Fact("model", model.name),
        Fact(
            "compared",
            f"{check.frame_from}_T_{check.frame_to}: the pose of "
            f"{check.frame_to} in {check.frame_from}",
        ),
        Fact("tolerance", tol),
        Fact("configurations", _configurations(check)),
        Fact("reference", f"{REFERENCE_NAME}: the in-house DH core ({model.convention} DH)"),
        Fact(
            "model file",
            str(model.path) if model.path is not None else "(built in memory)",
            volatile="path",
        ),
        Fact("checked at", check.created or "–", volatile="date"),
        Fact("took", format_seconds(check.duration_s), volatile="duration"),
        Fact("versions", " · ".join(f"{k} {v}" for k, v in versions.items()), volatile="version"),
        Fact("reproduce", check.command or "(run from Python: no command line)", code=True),
    )
    partings = _partings(check)
    headline = (
        _headline(check)
        + tuple(f"Diagnosis against {_with_also(d)}: {d.short}" for d in diagnosis_views)
        + tuple(f"Where the chains part: {p.short}." for p in partings if p.short)
    )
    evidence = check.evidence
    return ReportPage(
        title=f"fkcheck {model.name}: {check.verdict.upper()}",
        model=model.name,
        verdict=check.verdict,
        verdict_line=verdict_line(check),
        verdict_headline=verdict_headline(check.verdict, evidence, len(check.ran)),
        evidence=tuple(
            EvidenceLine(kind, evidence.of(kind).status, text)
            for kind, text in zip(KINDS, evidence_sentences(evidence), strict=True)
        ),
        badge_note="implementation only"
        if check.verdict == "pass" and evidence.table.status != "verified"
        else "",
        disagreeing=tuple(r.name for r in failing),
        headline=headline,
        facts=facts,
        sides=_sides(check),
        backends=rows,
        plots=tuple(images),
        partings=partings,
        details=details,
        model_view=_model_view(check),
        generator=f"fkcheck {__version__}",
        diagnoses=diagnosis_views,
    )


# --------------------------------------------------------------------------- the index


@dataclass(frozen=True, eq=False)
class IndexEntry:
    """One model on the index: its result and where its files are (relative links).

    Attributes:
        check: The model's check result.
        report: Relative path of its HTML report.
        json: Relative path of its JSON result.
        junit: Relative path of its JUnit XML.
    """

    check: CheckResult
    report: str
    json: str
    junit: str


def overall_verdict(verdicts: Sequence[str]) -> str:
    """The verdict of a run over several models.

    ``fail`` when any model fails; else ``error`` when any errors or there are
    none; else ``unverified`` when any lacks required evidence; else ``pass``.
    """
    if any(v == "fail" for v in verdicts):
        return "fail"
    if any(v == "error" for v in verdicts) or not verdicts:
        return "error"
    if any(v == "unverified" for v in verdicts):
        return "unverified"
    return "pass"


def build_index_page(
    entries: Sequence[IndexEntry],
    *,
    command: str = "",
    created: str = "",
    versions: dict[str, str] | None = None,
) -> IndexPage:
    """The dashboard of a run over several models.

    Args:
        entries: One per model, in the order to list them.
        command: The command line that reproduces the run.
        created: When the run started (ISO 8601).
        versions: Library versions to show (default: the installed ones).
    """
    from fkcheck.report.versions import library_versions

    models = tuple(
        IndexModel(
            name=e.check.model.name,
            verdict=e.check.verdict,
            report=e.report,
            json=e.json,
            junit=e.junit,
            pair=f"{e.check.frame_from} → {e.check.frame_to}",
            configurations=int(e.check.q.shape[0]),
            table_evidence=e.check.evidence.table.status,
            evidence_text=evidence_sentences(e.check.evidence)[1],
            rows=tuple(
                IndexRow(
                    backend=r.name,
                    status=r.status,
                    pos_max=measure_m(r.max_position_error_m),
                    rot_max=measure_rad(r.max_rotation_error_rad),
                    message=r.message,
                )
                for r in e.check.backends
            ),
        )
        for e in entries
    )
    verdicts = [m.verdict for m in models]
    overall = overall_verdict(verdicts)
    counts = Counter(verdicts)
    verdict_words = ("pass", "fail", "error", "unverified")
    line = ", ".join(f"{counts[v]} {v}" for v in verdict_words if counts.get(v))
    verified = sum(m.table_evidence == "verified" for m in models)
    line += f"; table verified independently for {verified} of {len(models)}"
    versions = library_versions() if versions is None else versions
    facts = [Fact("checked at", created or "–", volatile="date")]
    facts += [Fact(k, v, volatile="version") for k, v in versions.items()]
    if command:
        facts.append(Fact("command", command, code=True))
    return IndexPage(
        title=f"fkcheck: {len(models)} models, {overall.upper()}",
        verdict=overall,
        verdict_line=f"{len(models)} models checked: {line or 'none'}.",
        badge_note=f"table verified for {verified} of {len(models)}"
        if overall == "pass" and verified < len(models)
        else "",
        facts=tuple(facts),
        models=models,
        generator=f"fkcheck {__version__}",
    )
