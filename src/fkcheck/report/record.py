"""One record per backend, and one per check: what every output format reads.

A finished check (:class:`~fkcheck.engine.results.CheckResult`) and its
diagnoses are turned once into a :class:`CheckRecord` holding one
:class:`BackendRecord` per backend: the numbers (SI floats), the sentences
(summary, reasons, worst configuration, diagnosis headline, Jacobian numbers)
and the check's headline, evidence sentences and numbers line. The terminal,
JSON, JUnit, Markdown, HTML, the GitHub annotations, :mod:`fkcheck.testing`
and the pytest plugin lay these fields out; none of them derives a sentence
from the raw result. A new report field is a field here plus the templates
(or writers) that show it.

Every number goes through :mod:`fkcheck.io.format`; nothing here runs a
backend, the core or a diagnosis.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from fkcheck.calibration.effect import CalibrationEffect
from fkcheck.engine.compare import joint_label
from fkcheck.engine.results import BackendResult, CheckResult, JacobianResult
from fkcheck.engine.verdict import (
    KINDS,
    EvidenceSummary,
    Kind,
    KindStatus,
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


@dataclass(frozen=True)
class ColumnRecord:
    """One joint column of a Jacobian comparison.

    Attributes:
        joint: The joint's name.
        linear: Largest linear difference of the column (m/rad, m/m for a prismatic joint).
        angular: Largest angular difference (rad/rad, rad/m).
        bad: Beyond the tolerance somewhere (NaN counts).
        prismatic: The joint is prismatic (the column's unit is per metre).
    """

    joint: str
    linear: float
    angular: float
    bad: bool
    prismatic: bool


@dataclass(frozen=True)
class JacobianRecord:
    """One backend's Jacobian against the core's, as every format shows it.

    Attributes:
        status: ``pass``, ``fail``, ``error``, ``skipped`` or ``xfail``.
        message: Why it failed, errored or was skipped (the engine's words).
        method: Its library's Jacobian, or central differences of its poses.
        reference: ``world-aligned``, ``local`` or ``world``.
        tolerance: The tolerance applied (m/rad and rad/rad).
        ran: Both Jacobians were computed and compared.
        max_linear: Largest linear difference, m/rad (``None``: not compared).
        max_angular: Largest angular difference, rad/rad (``None``: not compared).
        worst_q: The configuration with the largest difference (``None``: none).
        first_column: 0-based index of the first joint whose column disagrees.
        first_joint: That joint's name (``None`` when none disagrees).
        first_label: That joint as the reports name it, ``joint 3 (elbow)``.
        columns: One per joint (empty when not compared).
        numbers: ``max linear difference … m/rad, max angular difference … rad/rad``
            (``""`` when not compared).
        detail: The numbers with the tolerance and the method, after the
            message when there is one: what a CI case shows.
        diagnosis: Which convention would make them agree, one sentence (``""``: none).
        diagnosis_details: The diagnosis's further lines.
    """

    status: str
    message: str
    method: str
    reference: str
    tolerance: float
    ran: bool
    max_linear: float | None
    max_angular: float | None
    worst_q: tuple[float, ...] | None
    first_column: int | None
    first_joint: str | None
    first_label: str
    columns: tuple[ColumnRecord, ...]
    numbers: str
    detail: str
    diagnosis: str
    diagnosis_details: tuple[str, ...]


@dataclass(frozen=True)
class BackendRecord:
    """One backend's outcome, every field derived once and the same in every format.

    Attributes:
        name: Backend name.
        status: ``pass``, ``fail``, ``error``, ``skipped``, ``xfail`` or ``xpass``.
        evidence: ``implementation`` or ``table``: what its agreement proves.
        method: The library call it used.
        message: The engine's words: why it was skipped or errored, or why it fails.
        duration_s: Wall time of its run, seconds.
        ran: It produced poses that were compared.
        max_position_m: Largest position error, metres (``None``: it did not run).
        p99_position_m: 99th percentile of the position error, metres.
        median_position_m: Median position error, metres.
        max_rotation_rad: Largest rotation error, radians.
        p99_rotation_rad: 99th percentile of the rotation error, radians.
        median_rotation_rad: Median rotation error, radians.
        configurations: Configurations compared (0 when it did not run).
        beyond: Configurations beyond either tolerance (NaN counts), as the
            engine counts them: exactly when some are does its message state
            the numbers (:mod:`fkcheck.engine.compare`).
        worst_index: Index of its worst configuration in the check (``None``: none).
        worst_q: That configuration, radians or metres (``None``: none).
        worst_q_text: That configuration, ``[30.00°, -60.00°, 0.1000 m]`` (``""``: none).
        worst_origin: Where it came from (``random``, ``pose:home`` …; ``""``: none).
        numbers: ``max position error 0.300 mm (3.00e-04 m), max rotation error
            0.00° (0.00e+00 rad)`` (``""`` when it did not run).
        summary: One line: the numbers and how many configurations are beyond
            the tolerance, ``…; 5 of 6 configurations beyond tolerance (1e-06 m,
            1e-06 rad)``; for a backend that did not run, its message.
        reasons: For a failure, why, each fact once: the engine's message, the
            numbers when that message does not state them, the tolerance.
            Otherwise the message.
        diagnosis: The headline of the diagnosis standing for it (``""``: none).
        diagnosis_short: The diagnosis with the changes it proposes, as the
            report's first screen shows it (``""``: none).
        diagnosis_command: The command that explains it (``""``: none).
        diagnosis_field: The model-file field its best explanation changes first,
            ``joint[4].alpha`` (``""``: none).
        diagnosed_with: For a failure, the failing backends its diagnosis stands
            for, in its order (this one among them); otherwise just this one.
        jacobian: Its Jacobian comparison, when the check compared Jacobians.
        subset: ``95 081 of 1 000 081 configurations`` when the check's plan gave
            it a subset only (:mod:`fkcheck.engine.plan`); ``""``: it had them all.
        reader_finding: For a reader that disagrees where another reader of the
            same description agrees with the table, that sentence (with both
            libraries' versions; :mod:`fkcheck.engine.readers`); ``""`` otherwise.
    """

    name: str
    status: str
    evidence: str
    method: str
    message: str
    duration_s: float
    ran: bool
    max_position_m: float | None
    p99_position_m: float | None
    median_position_m: float | None
    max_rotation_rad: float | None
    p99_rotation_rad: float | None
    median_rotation_rad: float | None
    configurations: int
    beyond: int
    worst_index: int | None
    worst_q: tuple[float, ...] | None
    worst_q_text: str
    worst_origin: str
    numbers: str
    summary: str
    reasons: str
    diagnosis: str
    diagnosis_short: str
    diagnosis_command: str
    diagnosis_field: str
    diagnosed_with: tuple[str, ...]
    jacobian: JacobianRecord | None
    subset: str = ""
    reader_finding: str = ""


@dataclass(frozen=True)
class EvidenceRecord:
    """What the run proved of one kind, in one sentence.

    Attributes:
        kind: ``implementation`` or ``table``.
        status: ``verified``, ``partly-verified``, ``failed``, ``expected-failure``
            or ``not-checked``.
        sentence: The sentence every format shows
            (:func:`fkcheck.engine.verdict.evidence_sentences`).
        required: The kind is required (``--require``) and not verified.
    """

    kind: Kind
    status: KindStatus
    sentence: str
    required: bool


@dataclass(frozen=True)
class CheckRecord:
    """A whole check as every format reads it.

    Attributes:
        model: The model's name.
        verdict: ``pass``, ``fail``, ``error`` or ``unverified``.
        headline: The verdict with what it proved, one line.
        verdict_line: The verdict as one sentence: who agrees, disagrees, errored.
        partial: For a pass that proves less than the table: ``expected failure:
            known difference``, ``table partly verified`` or ``implementation
            only``; ``""`` otherwise.
        evidence: One per kind, implementation then table.
        numbers_line: What the check verified of the model's numbers, one line
            (``""`` when not analysed).
        frame_from: Frame the compared pose is expressed in.
        frame_to: Frame whose pose is compared.
        tol_pos_m: Position tolerance, metres.
        tol_rot_rad: Rotation tolerance, radians.
        tolerance: ``tolerance 1e-06 m, 1e-06 rad``.
        configurations: Configurations checked.
        answered: Backends that produced poses.
        backends: One record per backend, in the order asked.
        calibration: For a calibrated model, what its calibration changes
            against the nominal model over these configurations.
        calibration_line: That, one line (``""`` for other models).
    """

    model: str
    verdict: str
    headline: str
    verdict_line: str
    partial: str
    evidence: tuple[EvidenceRecord, ...]
    numbers_line: str
    frame_from: str
    frame_to: str
    tol_pos_m: float
    tol_rot_rad: float
    tolerance: str
    configurations: int
    answered: int
    backends: tuple[BackendRecord, ...]
    calibration: CalibrationEffect | None = None
    calibration_line: str = ""

    def of(self, kind: Kind) -> EvidenceRecord:
        """The evidence of one kind."""
        return self.evidence[KINDS.index(kind)]

    def backend(self, name: str) -> BackendRecord:
        """The record of the backend called ``name``.

        Raises:
            KeyError: No backend of the check has that name.
        """
        for record in self.backends:
            if record.name == name:
                return record
        raise KeyError(name)


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
    numbers = summary = ""
    if r.ran:
        numbers = (
            f"max position error {format_length_summary(pos)}, "
            f"max rotation error {format_angle_summary(rot)}"
        )
        summary = (
            f"{numbers}; {beyond} of {configurations} configurations beyond tolerance "
            f"({check.tol_pos_m:g} m, {check.tol_rot_rad:g} rad)"
        )
        if r.subset is not None:
            summary += f"; a subset: {subset_text(*r.subset)}"
    else:
        summary = r.message
    reasons = r.message
    if r.status == "fail":
        if not beyond and numbers:  # the engine's message states the numbers only when beyond
            reasons = f"{reasons}; {numbers}" if reasons else numbers
        reasons = f"{reasons} ({tolerance})"
    outcome = diagnosis_for(diagnoses, r.name)
    group: tuple[str, ...] = (r.name,)
    diagnosis = short = command = field = ""
    if outcome is not None:
        if r.status == "fail":
            failed = {b.name for b in check.backends if b.status == "fail"}
            group = tuple(n for n in (outcome.backend, *outcome.also) if n in failed)
        diagnosis = diagnosis_headline(outcome)
        short = diagnosis_view(outcome).short
        command = outcome.command
        best = outcome.diagnosis.best if outcome.diagnosis is not None else None
        field = best.changes[0].field if best is not None and best.changes else ""
    return BackendRecord(
        name=r.name,
        status=r.status,
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
        headline=headline(check.verdict, evidence, len(check.ran)) + _lint_note(check),
        verdict_line=verdict_line(check),
        partial=_partial(check.verdict, evidence),
        evidence=tuple(
            EvidenceRecord(k, evidence.of(k).status, text, k in evidence.unmet)
            for k, text in zip(KINDS, sentences, strict=True)
        ),
        numbers_line=(
            numbers_line(check.numbers, evidence.table.status) if check.numbers is not None else ""
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
