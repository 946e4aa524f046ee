"""One record per backend, and one per check: what every output format reads.

A finished check (:class:`~fkcheck.engine.results.CheckResult`) and its
diagnoses are turned once into a :class:`CheckRecord` holding one
:class:`BackendRecord` per backend: the numbers (SI floats), the sentences
(summary, reasons, worst configuration, diagnosis headline, Jacobian numbers)
and the check's headline, evidence sentences and numbers line. The terminal,
JSON, JUnit, Markdown, HTML, the GitHub annotations, :mod:`fkcheck.testing`
and the pytest plugin lay these fields out; none of them derives a sentence
from the raw result. A new report field is a field of a record
(:mod:`fkcheck.report.record_types`, re-exported here), its value here, plus the templates (or
writers) that show it.

Every number goes through :mod:`fkcheck.io.format`; nothing here runs a
backend, the core or a diagnosis.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from fkcheck.engine.compare import joint_label
from fkcheck.engine.results import BackendResult, CheckResult, JacobianResult, status_label
from fkcheck.engine.verdict import (
    KINDS,
    EvidenceSummary,
    evidence_sentences,
    headline,
    numbers_line,
    subset_text,
)
from fkcheck.io.format import (
    format_angle_summary,
    format_length_summary,
    format_scientific,
    format_value,
)
from fkcheck.report.diagnosis import diagnosis_for, diagnosis_headline, diagnosis_view
from fkcheck.report.record_types import (
    BackendRecord,
    CheckRecord,
    ColumnRecord,
    EvidenceRecord,
    JacobianRecord,
)

if TYPE_CHECKING:
    from fkcheck.diagnose.failures import BackendDiagnosis
    from fkcheck.model.types import Model

__all__ = [
    "BackendRecord",
    "CheckRecord",
    "ColumnRecord",
    "EvidenceRecord",
    "JacobianRecord",
    "backend_record",
    "check_record",
    "verdict_line",
]


#: How the verdict sentence counts backends of each status beyond pass and fail.
_COUNTED = (
    ("error", "{n} errored: {names}"),
    ("skipped", "{n} skipped: {names}"),
    ("xfail", "{n} disagree as the model records (expected failure, known difference): {names}"),
    (
        "xpass",
        "{n} agree though the model records a difference (known difference no longer seen): "
        "{names}",
    ),
)
#: How it counts Jacobians that disagreed or errored.
_JACOBIANS_COUNTED = (
    ("fail", "the Jacobian of {n} disagrees: {names}"),
    ("error", "the Jacobian of {n} errored: {names}"),
)


def verdict_line(check: CheckResult) -> str:
    """The verdict as one sentence: who agrees, disagrees, errored, was skipped."""
    ran = check.ran
    failing = [r for r in check.backends if r.status == "fail"]
    if not ran:
        parts = ["No reference backend ran: nothing was cross-checked"]
    elif failing:
        parts = _disagreeing(ran, failing)
    else:
        agreed = sum(r.status == "pass" for r in ran)
        parts = [f"{agreed} of {len(ran)} backends that ran agree with the in-house core"]
    for status, sentence in _COUNTED:
        names = [r.name for r in check.backends if r.status == status]
        if names:
            parts.append(sentence.format(n=len(names), names=", ".join(names)))
    for status, sentence in _JACOBIANS_COUNTED:
        names = [r.name for r in check.backends if r.jacobian and r.jacobian.status == status]
        if names:
            parts.append(sentence.format(n=len(names), names=", ".join(names)))
    return "; ".join(parts) + "."


def _disagreeing(ran: Sequence[BackendResult], failing: Sequence[BackendResult]) -> list[str]:
    """Who disagrees, said as the evidence says it (as the headline blames the table or not).

    Backends independent of the table (a URDF, measured poses) that disagree
    disagree with the table; other implementations of the same table disagree
    with the in-house core. When only the former disagree, the implementations
    that agree are named too: the core computed the table as written.
    """
    parts = []
    for kind, whom in (("implementation", "the in-house core"), ("table", "the table")):
        names = [r.name for r in failing if r.evidence == kind and not r.reader_finding]
        if names:
            parts.append(
                f"{len(names)} of {len(ran)} backends that ran disagree with {whom}: "
                + ", ".join(names)
            )
    readers = [r.name for r in failing if r.reader_finding]
    if readers:
        parts.append(
            f"{len(readers)} of {len(ran)} backends that ran disagree with another reader of the "
            f"same description, which agrees with the table: {', '.join(readers)} (a finding "
            "about the reader, not the table)"
        )
    if all(r.evidence == "table" for r in failing):
        agree = [r.name for r in ran if r.evidence == "implementation" and r.status == "pass"]
        if agree:
            parts.append(
                f"{len(agree)} other implementation{'s' if len(agree) > 1 else ''} of the table "
                f"{'agree' if len(agree) > 1 else 'agrees'} with the in-house core: "
                + ", ".join(agree)
            )
    return parts


def _derived_note(check: CheckResult) -> str:
    """``; table derived by fkcheck from A (the source), B checked against it: …`` or ``""``.

    A table fkcheck derived from one description (``check --source``) is checked
    against the other: its verdict is about the two descriptions, and says so
    wherever it is shown.
    """
    derived = check.model.derived
    return "" if derived is None else f"; {derived.line}"


def _lint_note(check: CheckResult) -> str:
    """``; lint: 1 warning (fkcheck lint names it)`` when lint flags the model, else ``""``.

    What lint flags (degrees in a radian file, a rounded published number) a
    check cannot see: every backend reads the same numbers.
    """
    n = len(check.lint)
    if not n:
        return ""
    noun, them = ("warnings", "them") if n > 1 else ("warning", "it")
    return f"; lint: {n} {noun} (fkcheck lint names {them})"


def _partial(verdict: str, evidence: EvidenceSummary) -> str:
    """What a pass proves less than the table, in a few words; ``""`` otherwise."""
    if verdict != "pass" or evidence.table.status == "verified":
        return ""
    if evidence.table.status == "expected-failure":
        return "expected failure: known difference"
    if evidence.table.status == "partly-verified":
        return "table partly verified"
    return "implementation only"


def _q(model: Model, q: np.ndarray | None) -> tuple[tuple[float, ...] | None, str]:
    """A configuration as floats and as ``[30.00°, 0.1000 m]``; ``(None, "")`` when absent."""
    if q is None:
        return None, ""
    values = tuple(float(v) for v in q)
    joints = model.joints
    text = (format_value(v, j.type == "prismatic") for v, j in zip(values, joints, strict=True))
    return values, "[" + ", ".join(text) + "]"


def _jacobian(check: CheckResult, j: JacobianResult) -> JacobianRecord:
    model = check.model
    first = j.first_bad_column
    bad = j.bad_columns
    columns: tuple[ColumnRecord, ...] = ()
    if j.column_linear is not None and j.column_angular is not None and bad is not None:
        columns = tuple(
            ColumnRecord(joint.name, float(lin), float(ang), bool(b), joint.type == "prismatic")
            for joint, lin, ang, b in zip(
                model.joints, j.column_linear, j.column_angular, bad, strict=True
            )
        )
    numbers = ""
    detail = j.message
    if j.ran:
        numbers = (
            f"max linear difference {format_scientific(j.max_linear_error, 'm/rad')}, "
            f"max angular difference {format_scientific(j.max_angular_error, 'rad/rad')}"
        )
        shown = f"{numbers} (tolerance {j.tolerance:g}; {j.method})"
        detail = f"{detail}; {shown}" if detail else shown
    worst = check.q[j.worst_index] if j.worst_index is not None else None
    return JacobianRecord(
        status=j.status,
        message=j.message,
        method=j.method,
        reference=j.reference,
        tolerance=j.tolerance,
        ran=j.ran,
        max_linear=j.max_linear_error,
        max_angular=j.max_angular_error,
        worst_q=_q(model, worst)[0],
        first_column=first,
        first_joint=None if first is None else model.joints[first].name,
        first_label="" if first is None else joint_label(model, first),
        columns=columns,
        numbers=numbers,
        detail=detail,
        diagnosis=j.diagnosis,
        diagnosis_details=j.diagnosis_details,
    )


def _beyond(check: CheckResult, r: BackendResult) -> int:
    """Configurations beyond either tolerance; NaN is beyond (as the engine counts)."""
    if r.position_error_m is None or r.rotation_error_rad is None:
        return 0
    within = (r.position_error_m <= check.tol_pos_m) & (r.rotation_error_rad <= check.tol_rot_rad)
    return int((~within).sum())


def _numbers_and_summary(
    check: CheckResult, r: BackendResult, beyond: int, configurations: int
) -> tuple[str, str]:
    """A backend's ``numbers`` (empty when it did not run) and its ``summary``."""
    if not r.ran:
        return "", r.message
    numbers = (
        f"max position error {format_length_summary(r.max_position_error_m)}, "
        f"max rotation error {format_angle_summary(r.max_rotation_error_rad)}"
    )
    summary = (
        f"{numbers}; {beyond} of {configurations} configurations beyond tolerance "
        f"({check.tol_pos_m:g} m, {check.tol_rot_rad:g} rad)"
    )
    if r.subset is not None:
        summary += f"; a subset: {subset_text(*r.subset)}"
    return numbers, summary


def _reasons(r: BackendResult, beyond: int, numbers: str, tolerance: str) -> str:
    """Why a backend has its status: its message, and for a failure the numbers and tolerance."""
    reasons = r.message
    if r.status == "fail":
        if not beyond and numbers:  # the engine's message states the numbers only when beyond
            reasons = f"{reasons}; {numbers}" if reasons else numbers
        reasons = f"{reasons} ({tolerance})"
    return reasons


def _diagnosis_fields(
    check: CheckResult, r: BackendResult, outcome: BackendDiagnosis | None
) -> tuple[tuple[str, ...], str, str, str, str]:
    """``(diagnosed_with, diagnosis, diagnosis_short, diagnosis_command, diagnosis_field)``."""
    group: tuple[str, ...] = (r.name,)
    if outcome is None:
        return group, "", "", "", ""
    if r.status == "fail":
        failed = {b.name for b in check.backends if b.status == "fail"}
        group = tuple(n for n in (outcome.backend, *outcome.also) if n in failed)
    best = outcome.diagnosis.best if outcome.diagnosis is not None else None
    field = best.changes[0].field if best is not None and best.changes else ""
    return (
        group,
        diagnosis_headline(outcome),
        diagnosis_view(outcome).short,
        outcome.command,
        field,
    )


def backend_record(
    check: CheckResult,
    r: BackendResult,
    diagnoses: Sequence[BackendDiagnosis] = (),
    tolerance: str = "",
) -> BackendRecord:
    """One backend's record (see :class:`BackendRecord`)."""
    tolerance = tolerance or _tolerance(check)
    pos, rot = r.max_position_error_m, r.max_rotation_error_rad
    configurations = 0 if r.position_error_m is None else int(r.position_error_m.size)
    beyond = _beyond(check, r)
    worst = check.q[r.worst_index] if r.worst_index is not None else None
    worst_q, worst_text = _q(check.model, worst)
    origin = check.origin[r.worst_index] if worst is not None and r.worst_index is not None else ""
    numbers, summary = _numbers_and_summary(check, r, beyond, configurations)
    reasons = _reasons(r, beyond, numbers, tolerance)
    group, diagnosis, short, command, field = _diagnosis_fields(
        check, r, diagnosis_for(diagnoses, r.name)
    )
    return BackendRecord(
        name=r.name,
        status=r.status,
        label=status_label(r.status, r.reader_finding),
        evidence=r.evidence,
        method=r.method,
        message=r.message,
        duration_s=r.duration_s,
        ran=r.ran,
        max_position_m=pos,
        p99_position_m=r.percentile("position", 99),
        median_position_m=r.percentile("position", 50),
        max_rotation_rad=rot,
        p99_rotation_rad=r.percentile("rotation", 99),
        median_rotation_rad=r.percentile("rotation", 50),
        configurations=configurations,
        beyond=beyond,
        worst_index=r.worst_index if worst is not None else None,
        worst_q=worst_q,
        worst_q_text=worst_text,
        worst_origin=origin,
        numbers=numbers,
        summary=summary,
        reasons=reasons,
        diagnosis=diagnosis,
        diagnosis_short=short,
        diagnosis_command=command,
        diagnosis_field=field,
        diagnosed_with=group,
        jacobian=_jacobian(check, r.jacobian) if r.jacobian is not None else None,
        subset=subset_text(*r.subset) if r.subset is not None else "",
        reader_finding=r.reader_finding,
    )


def _tolerance(check: CheckResult) -> str:
    return f"tolerance {check.tol_pos_m:g} m, {check.tol_rot_rad:g} rad"


def check_record(check: CheckResult, diagnoses: Sequence[BackendDiagnosis] = ()) -> CheckRecord:
    """The record of a check and of each of its backends, built once for every format.

    Args:
        check: The finished check.
        diagnoses: Its diagnoses (:func:`fkcheck.diagnose.failures.diagnose_failures`),
            for each failing backend's diagnosis fields.
    """
    evidence = check.evidence
    sentences = evidence_sentences(evidence)
    tolerance = _tolerance(check)
    return CheckRecord(
        model=check.model.name,
        verdict=check.verdict,
        headline=headline(check.verdict, evidence, len(check.ran))
        + _lint_note(check)
        + _derived_note(check),
        verdict_line=verdict_line(check),
        partial=_partial(check.verdict, evidence),
        evidence=tuple(
            EvidenceRecord(
                k,
                evidence.of(k).status,
                text + (_derived_note(check) if k == "table" else ""),
                k in evidence.unmet,
            )
            for k, text in zip(KINDS, sentences, strict=True)
        ),
        numbers_line=(
            numbers_line(
                check.numbers, evidence.table.status, derived=check.model.derived is not None
            )
            if check.numbers is not None
            else ""
        ),
        frame_from=check.frame_from,
        frame_to=check.frame_to,
        tol_pos_m=check.tol_pos_m,
        tol_rot_rad=check.tol_rot_rad,
        tolerance=tolerance,
        configurations=int(check.q.shape[0]),
        answered=len(check.ran),
        backends=tuple(backend_record(check, r, diagnoses, tolerance) for r in check.backends),
        calibration=check.calibration,
        calibration_line=check.calibration.line if check.calibration is not None else "",
    )
