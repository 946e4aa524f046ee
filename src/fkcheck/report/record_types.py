"""The records every output format reads: one per check, one per backend, their parts.

Built by :mod:`fkcheck.report.record` (:func:`~fkcheck.report.record.check_record`),
which re-exports them; every field is already a number (SI) or a sentence.
"""

from __future__ import annotations

from dataclasses import dataclass

from fkcheck.calibration.effect import CalibrationEffect
from fkcheck.engine.verdict import KINDS, Kind, KindStatus

__all__ = [
    "BackendRecord",
    "CheckRecord",
    "ColumnRecord",
    "EvidenceRecord",
    "JacobianRecord",
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
        label: Its status as every table shows it: the status, or ``fail
            (reader)`` for a reader finding
            (:func:`~fkcheck.engine.results.status_label`).
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
    label: str
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
