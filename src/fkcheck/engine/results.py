"""Results of a check: one :class:`BackendResult` per backend and the whole :class:`CheckResult`.

Status words mean one thing each: ``pass`` — it answered and agrees within
tolerance; ``fail`` — it answered and the answer is wrong (disagrees beyond
tolerance, is not a rigid transform, or is NaN/inf: the message says which, where
and by how much, and the errors are still reported); ``error`` — it could not
answer (import failed, crashed, timed out, returned no poses of the right
shape, or a URDF it should compare was never mapped); ``skipped`` — it does not
apply here (library missing, frame out of its reach), with the reason;
``xfail`` — it disagrees as the model's ``[[known_difference]]`` records
(expected failure: the check may pass, the table is not verified by it);
``xpass`` — it was recorded to disagree but agrees (a stale record: the check
fails). See :mod:`fkcheck.engine.expected`. A ``fail`` that is a reader
finding (:mod:`fkcheck.engine.readers`: another reader of the same description
agrees with the table) is shown as ``fail (reader)`` in every table
(:func:`status_label`); its status stays ``fail``. What the
run proved — implementation and table evidence — and the verdict are in
:mod:`fkcheck.engine.verdict`. A run where no backend ran is never a pass.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from fkcheck.backends.base import Evidence
from fkcheck.calibration.effect import CalibrationEffect
from fkcheck.core.typing import Float
from fkcheck.engine.evidence import FailureDetail
from fkcheck.engine.jacobian import JacobianSample, JacobianSpec
from fkcheck.engine.verdict import EvidenceSummary, Kind, Verdict, summarize, tolerance_note
from fkcheck.model.coverage import Coverage
from fkcheck.model.options import CheckOptions
from fkcheck.model.types import Model
from fkcheck.urdf.locate import display_path

__all__ = [
    "READER_FAIL",
    "REFERENCE_NAME",
    "BackendResult",
    "CheckResult",
    "JacobianResult",
    "Status",
    "status_label",
]

Status = Literal["pass", "fail", "error", "skipped", "xfail", "xpass"]

#: Name of the reference row: the in-house DH core.
REFERENCE_NAME = "fkcheck-dh"

#: How a table shows a ``fail`` that is a reader finding (:func:`status_label`).
READER_FAIL = "fail (reader)"


def status_label(status: str, reader_finding: str = "") -> str:
    """A backend's status as a table shows it: ``fail (reader)`` for a reader finding.

    The one word set of every output (terminal, HTML, Markdown, JUnit): the
    status itself, except a ``fail`` that is a reader finding (another reader of
    the same description agrees with the table, :mod:`fkcheck.engine.readers`),
    which still fails the check but is the reader's, not the table's.

    Args:
        status: ``pass``, ``fail``, ``error``, ``skipped``, ``xfail`` or ``xpass``.
        reader_finding: The backend's reader-finding sentence (``""``: none).
    """
    return READER_FAIL if status == "fail" and reader_finding else status


def _max(values: Float | None) -> float | None:
    if values is None or values.size == 0:
        return None
    if np.isnan(values).any():  # never hide a NaN behind a max
        return float("nan")
    return float(values.max())


@dataclass(frozen=True, eq=False)
class JacobianResult:
    """One backend's Jacobian against the core's (``check --jacobian``).

    How each side is computed: :mod:`fkcheck.engine.jacobian`.

    Attributes:
        status: ``pass``, ``fail``, ``error`` or ``skipped``, as for poses.
        message: Why it was skipped or errored, or a summary of the failure.
        method: How the backend's Jacobian was obtained (its library, or central
            differences of its poses with their step).
        reference: ``world-aligned``, ``local`` or ``world``.
        tolerance: The tolerance applied, linear m/rad and angular rad/rad (the
            asked one, floored by finite differences' accuracy for pose-only backends).
        linear_error: Per configuration, the largest linear column difference (m/rad).
        angular_error: Per configuration, the largest angular column difference (rad/rad).
        column_linear: Per joint, the largest linear difference of its column.
        column_angular: Per joint, the largest angular difference of its column.
        worst_index: The configuration with the largest difference.
        sample: Both Jacobians at the first configurations and the worst.
        diagnosis: For a failure, which convention would make them agree (or
            that none does), in one sentence; ``""`` when not diagnosed.
        diagnosis_details: The diagnosis's further lines.
    """

    status: Status
    message: str = ""
    method: str = ""
    reference: str = "world-aligned"
    tolerance: float = 0.0
    linear_error: Float | None = None
    angular_error: Float | None = None
    column_linear: Float | None = None
    column_angular: Float | None = None
    worst_index: int | None = None
    sample: JacobianSample | None = None
    diagnosis: str = ""
    diagnosis_details: tuple[str, ...] = ()

    @property
    def ran(self) -> bool:
        """Whether both Jacobians were computed and compared."""
        return self.linear_error is not None

    @property
    def max_linear_error(self) -> float | None:
        """Largest linear difference, m/rad (``None`` if not compared)."""
        return _max(self.linear_error)

    @property
    def max_angular_error(self) -> float | None:
        """Largest angular difference, rad/rad (``None`` if not compared)."""
        return _max(self.angular_error)

    @property
    def bad_columns(self) -> NDArray[np.bool_] | None:
        """``(n,)``: which joints' columns disagree beyond tolerance somewhere (NaN counts)."""
        if self.column_linear is None or self.column_angular is None:
            return None
        bad: NDArray[np.bool_] = ~(
            (self.column_linear <= self.tolerance) & (self.column_angular <= self.tolerance)
        )
        return bad

    @property
    def first_bad_column(self) -> int | None:
        """0-based index of the first joint whose column disagrees beyond tolerance."""
        bad = self.bad_columns
        if bad is None or not bad.any():
            return None
        return int(np.argmax(bad))


@dataclass(frozen=True, eq=False)
class BackendResult:
    """One backend's outcome.

    Attributes:
        name: Backend name.
        status: ``pass``, ``fail``, ``error``, ``skipped``, ``xfail`` or ``xpass``.
        message: Why it was skipped or errored, or a summary of the failure.
        method: The library call it used.
        duration_s: Wall time of its run, seconds (import included).
        position_error_m: Per-configuration position error against the reference, metres.
        rotation_error_rad: Per-configuration rotation error, radians.
        worst_index: Index of the worst configuration (largest error relative to tolerance).
        detail: For a backend that failed: what the engine kept to show why (both
            poses at its worst configurations, the chains there; see
            :mod:`fkcheck.engine.evidence`). Reports read it; they never recompute.
        evidence: ``implementation`` or ``table``: what its agreement proves.
        jacobian: Its Jacobian against the core's, when the check compares Jacobians.
        subset: ``(compared, total)`` when the check's plan gave it the first
            ``compared`` of the ``total`` configurations only (:mod:`fkcheck.engine.plan`).
        reader_finding: For a reader that disagrees while another reader of the
            same description agrees with the table, that sentence (a finding
            about the reader, not the table: :mod:`fkcheck.engine.readers`);
            ``""`` otherwise.
    """

    name: str
    status: Status
    message: str = ""
    method: str = ""
    duration_s: float = 0.0
    position_error_m: Float | None = None
    rotation_error_rad: Float | None = None
    worst_index: int | None = None
    detail: FailureDetail | None = None
    evidence: Evidence = "implementation"
    jacobian: JacobianResult | None = None
    subset: tuple[int, int] | None = None
    reader_finding: str = ""

    @property
    def ran(self) -> bool:
        """Whether the backend produced poses that were compared."""
        return self.position_error_m is not None

    def _stat(self, values: Float | None, q: float | None) -> float | None:
        if values is None or values.size == 0:
            return None
        if np.isnan(values).any():  # never hide a NaN behind a max or percentile
            return float("nan")
        if q is None:
            return float(values.max())
        if np.isinf(values).any():  # no interpolating between infinities (inf − inf)
            return float(np.percentile(values, q, method="higher"))
        return float(np.percentile(values, q))

    @property
    def max_position_error_m(self) -> float | None:
        """Largest position error, metres (``None`` if it did not run)."""
        return self._stat(self.position_error_m, None)

    @property
    def max_rotation_error_rad(self) -> float | None:
        """Largest rotation error, radians (``None`` if it did not run)."""
        return self._stat(self.rotation_error_rad, None)

    def percentile(self, which: Literal["position", "rotation"], q: float) -> float | None:
        """A percentile (0–100) of the position (m) or rotation (rad) error."""
        values = self.position_error_m if which == "position" else self.rotation_error_rad
        return self._stat(values, q)


@dataclass(frozen=True, eq=False)
class CheckResult:
    """A whole check: what was compared, on which configurations, and the verdict.

    Attributes:
        model: The model checked (with the ``urdf:LINK`` frames the check placed).
        options: The request's options, as asked (``samples``, ``seed``,
            ``sampler``, ``timeout_s``…; :class:`~fkcheck.model.options.CheckOptions`);
            what they left ``None`` is resolved in the fields below.
        frame_from: Frame the compared pose is expressed in.
        frame_to: Frame whose pose is compared.
        tol_pos_m: Position tolerance, metres.
        tol_rot_rad: Rotation tolerance, radians.
        q: ``(N, n)`` configurations checked (radians / metres).
        origin: Where each configuration came from (see :mod:`fkcheck.model.sampling`).
        backends: One result per backend, in the order asked.
        verdict: ``pass``, ``fail``, ``error`` or ``unverified``
            (see :mod:`fkcheck.engine.verdict`).
        required: Kinds of evidence that had to be verified (``--require``).
        created: ISO 8601 UTC time the check started.
        duration_s: Wall time of the check, seconds.
        command: The command line that reproduces it (set by the CLI).
        jacobian: What ``--jacobian`` compared (reference frame, tolerance), or ``None``.
        numbers: What the compared frame pair can verify, number by number
            (:mod:`fkcheck.model.coverage`); ``None`` when not analysed.
        config: The ``pyproject.toml`` whose ``[tool.fkcheck]`` gave the check
            its defaults, as the CLI names it (set by the CLI); ``None``: none did.
        calibration: For a calibrated model (``[calibration]``), what the
            calibration changes against its nominal model over ``q``.
        lint: What ``fkcheck lint`` finds in the model, one line each (with the
            ignores the check was given): a check does not compare what lint
            flags (degrees read as radians agree with themselves), so its
            headline says so.
    """

    model: Model
    options: CheckOptions
    frame_from: str
    frame_to: str
    tol_pos_m: float
    tol_rot_rad: float
    q: Float
    origin: tuple[str, ...]
    backends: tuple[BackendResult, ...]
    verdict: Verdict
    required: tuple[Kind, ...] = ()
    created: str = ""
    duration_s: float = 0.0
    command: str = ""
    jacobian: JacobianSpec | None = None
    numbers: Coverage | None = None
    config: str | None = None
    calibration: CalibrationEffect | None = None
    lint: tuple[str, ...] = ()

    @property
    def tolerance_source(self) -> tuple[str, str]:
        """Where the position and the rotation tolerance came from, in words.

        ``--tol-pos``, ``[tool.fkcheck] tol_pos_m in …/pyproject.toml``, "the
        caller" (an argument), or the model's ``[check]`` when the options left it.
        """
        said = self.options.tolerance_source
        of = f" of {display_path(self.model.path)}" if self.model.path is not None else ""
        own = f"the model's [check]{of}"
        return (
            own if self.options.tol_pos_m is None else said[0] or "the caller",
            own if self.options.tol_rot_rad is None else said[1] or "the caller",
        )

    @property
    def ran(self) -> tuple[BackendResult, ...]:
        """The backends that produced poses."""
        return tuple(b for b in self.backends if b.ran)

    @property
    def evidence(self) -> EvidenceSummary:
        """What the run proved, by kind (implementation, table), and what was required."""
        loose = tolerance_note(self.tol_pos_m, self.tol_rot_rad, self.tolerance_source)
        return summarize(self.backends, self.required, self.numbers, loose)
