"""One backend against the in-house core, pose by pose: the comparison and what it keeps.

:func:`compare` runs a backend over every configuration in chunks, compares each
``from_T_to`` with the core's, and turns the differences into a
:class:`~fkcheck.engine.results.BackendResult` — status, per-configuration
errors, the worst configuration and, for a failure, the evidence a report shows
(:mod:`fkcheck.engine.evidence`). The run around it — threads, time limits,
isolated processes — is :mod:`fkcheck.engine.runner`.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from fkcheck.backends.base import Backend, FixedConfigurations, SharesDHFrames
from fkcheck.backends.measured import MeasuredPoses
from fkcheck.backends.recording import Recording
from fkcheck.core.metrics import position_error_m, rotation_error_rad, se3_defect
from fkcheck.core.tolerances import ROUNDED_URDF
from fkcheck.core.typing import Float
from fkcheck.engine.evidence import (
    FailureDetail,
    WorstTracker,
    arm_pose,
    dh_parting,
    urdf_axes,
)
from fkcheck.engine.jacobian import Explain, JacobianComparison, JacobianSpec
from fkcheck.engine.plan import count_text
from fkcheck.engine.results import REFERENCE_NAME, BackendResult, JacobianResult, Status
from fkcheck.engine.stream import StreamSummary
from fkcheck.io.format import format_angle_summary, format_length_summary
from fkcheck.model.frames import (
    CHUNK,
    reference_poses,
    relative_pose,
)
from fkcheck.model.types import Model

__all__ = [
    "SE3_TOLERANCE",
    "Job",
    "NoAnswerError",
    "Progress",
    "compare",
    "joint_label",
]

Progress = Callable[[str, int, int], None]

#: A backend's output must be a rigid transform to this accuracy; worse is a failure.
#: Looser than any round-off (1e-15) and than a URDF's rounded π/2 (1e-11), tight
#: enough to catch a scaled, sheared or transposed "rotation".
SE3_TOLERANCE = 1e3 * ROUNDED_URDF


@dataclass(frozen=True, eq=False)
class Job:
    """One backend's comparison (run in a thread of the engine's process).

    Attributes:
        backend: The backend to run.
        model: The model checked.
        q: ``(N, n)`` configurations, radians / metres.
        pair: ``(frame_from, frame_to)`` of the compared pose.
        tol: ``(position m, rotation rad)`` tolerances.
        jacobian: Also compare the Jacobian of ``pair[1]`` (``check --jacobian``).
        explain: Names a Jacobian disagreement (see :data:`fkcheck.engine.jacobian.Explain`).
    """

    backend: Backend
    model: Model
    q: Float
    pair: tuple[str, str]
    tol: tuple[float, float]
    jacobian: JacobianSpec | None = None
    explain: Explain | None = None


def _q_text(q: Float) -> str:
    return "[" + ", ".join(f"{v:.6g}" for v in q) + "]"


class NoAnswerError(RuntimeError):
    """A backend's output cannot be compared (wrong shape), or the reference is not finite."""


def compare(job: Job, on_progress: Progress | None = None) -> BackendResult:
    """Run one backend over all configurations and compare with the reference.

    A wrong answer is a failure that keeps its numbers: rows that are NaN/inf
    count as infinitely wrong, and a matrix that is not a rigid transform is
    named with its defect and configuration, its position and rotation errors
    still measured.

    Raises:
        NoAnswerError: The backend returned the wrong shape (it gave no answer to
            compare), or the reference itself is not finite.
    """
    backend, model, q, pair = job.backend, job.model, job.q, job.pair
    start = time.perf_counter()
    pos = np.empty(q.shape[0])
    rot = np.empty(q.shape[0])
    defect_max, defect_at = 0.0, -1
    non_finite = 0
    first_non_finite = -1
    tol_pos, tol_rot = job.tol
    tracker = WorstTracker()
    jac = _JacobianRun(job)
    for first in range(0, q.shape[0], CHUNK):
        chunk = q[first : first + CHUNK]
        poses = np.asarray(backend.frame_poses(model, chunk, pair), dtype=np.float64)
        expected_shape = (2, chunk.shape[0], 4, 4)
        if poses.shape != expected_shape:
            raise NoAnswerError(f"returned shape {poses.shape}, expected {expected_shape}")
        ref = reference_poses(model, chunk, pair)
        if not np.isfinite(ref).all():
            k = int(np.argmax(~np.isfinite(ref).all(axis=(0, 2, 3))))
            raise NoAnswerError(
                f"the reference ({REFERENCE_NAME}) is not finite at q = {_q_text(chunk[k])}: "
                "the model's numbers overflow; nothing can be compared"
            )
        raw = poses
        finite = np.isfinite(poses).all(axis=(0, 2, 3))
        if not finite.all():
            bad = np.flatnonzero(~finite)
            if first_non_finite < 0:
                first_non_finite = first + int(bad[0])
            non_finite += bad.size
            poses = poses.copy()
            poses[:, bad] = np.eye(4)  # placeholders; their errors are set to inf below
        theirs = relative_pose(poses[0], poses[1])
        ours = relative_pose(ref[0], ref[1])
        as_returned = relative_pose(raw[0], raw[1]) if raw is not poses else theirs
        defect = se3_defect(poses).max(axis=0)
        k = int(np.argmax(defect))
        if defect[k] > defect_max:
            defect_max, defect_at = float(defect[k]), first + k
            tracker.keep(defect_at, ours[k], as_returned[k])
        pos_chunk = position_error_m(ours, theirs)
        rot_chunk = rotation_error_rad(ours, theirs)
        pos_chunk[~finite] = np.inf
        rot_chunk[~finite] = np.inf
        score_chunk = np.maximum(pos_chunk / tol_pos, rot_chunk / tol_rot)
        score_chunk[np.isnan(score_chunk)] = np.inf
        tracker.add(first, score_chunk, ours, as_returned)
        pos[first : first + CHUNK] = pos_chunk
        rot[first : first + CHUNK] = rot_chunk
        jac.add(first, chunk, ref, ours, raw)
        if on_progress is not None:
            on_progress(backend.name, first + chunk.shape[0], q.shape[0])
    score = np.maximum(pos / tol_pos, rot / tol_rot)
    score[np.isnan(score)] = np.inf
    worst = int(np.argmax(score)) if score.size else None
    reasons = []
    if non_finite:
        reasons.append(
            f"returned NaN or inf at {non_finite} of {q.shape[0]} configurations "
            f"(first at q = {_q_text(q[first_non_finite])})"
        )
    if defect_max > SE3_TOLERANCE:
        reasons.append(
            f"not a rigid transform: defect {defect_max:.3g} at q = {_q_text(q[defect_at])}"
        )
        worst = defect_at
    n_bad = int((score > 1.0).sum())
    stream = _streamed(job)
    if n_bad:
        # A long recording: the kept rows hold its worst ones, so it fails exactly when
        # they do; how many of all its rows differ was counted as it streamed.
        counted = (
            f"{n_bad} of {q.shape[0]} configurations"
            if stream is None
            else f"{_rows_beyond(stream, job)} of {stream[1].rows} rows"
        )
        reasons.append(
            f"{counted} differ: max position error "
            f"{format_length_summary(float(pos.max()))}, max rotation error "
            f"{format_angle_summary(float(rot.max()))}"
        )
        if isinstance(backend, FixedConfigurations):
            reasons.append(_spread(pos, rot) if stream is None else _stream_spread(stream[1]))
    failed = bool(reasons)
    if stream is not None:
        reasons.append(_stream_note(stream[1], q.shape[0], stream[0].where))
    detail = None
    if failed and worst is not None:
        detail = _failure_detail(job, worst, tracker)
    return BackendResult(
        name=backend.name,
        status="fail" if failed else "pass",
        message="; ".join(reasons),
        method=backend.method,
        duration_s=time.perf_counter() - start,
        evidence=backend.evidence,
        position_error_m=pos,
        rotation_error_rad=rot,
        worst_index=worst,
        detail=detail,
        jacobian=jac.result(),
    )


class _JacobianRun:
    """The Jacobian part of one backend's comparison: its errors, or why it has none."""

    def __init__(self, job: Job) -> None:
        self.spec = job.jacobian
        self.explain = job.explain
        self.comparison: JacobianComparison | None = None
        self.failure: str | None = None
        self.skip: str | None = None
        if self.spec is None:
            return
        self.comparison = JacobianComparison(
            job.backend, job.model, job.pair, self.spec, job.q.shape[0]
        )
        self.skip = self.comparison.skip_reason

    def add(
        self, first: int, q: Float, ours_root: Float, ours_from_T_to: Float, theirs_root: Float
    ) -> None:
        if self.comparison is None or self.skip or self.failure:
            return
        try:
            self.comparison.add(first, q, ours_root, ours_from_T_to, theirs_root)
        except Exception as exc:  # the Jacobian's own error; the poses stand
            own = type(exc).__module__.startswith("fkcheck.")
            self.failure = str(exc) if own else f"{type(exc).__name__}: {exc}"

    def result(self) -> JacobianResult | None:
        spec, comparison = self.spec, self.comparison
        if spec is None or comparison is None:
            return None
        # A Jacobian that never came (skipped, or it raised) names no method it did not use.
        method = comparison.method if comparison.own is not None else ""
        tol = comparison.tolerance
        if self.skip or self.failure:
            status: Status = "skipped" if self.skip else "error"
            return JacobianResult(
                status, self.skip or self.failure or "", method, spec.reference, tol
            )
        lin, ang = comparison.linear_error, comparison.angular_error
        score = np.maximum(lin, ang)
        score[np.isnan(score)] = np.inf
        sample = comparison.sample()
        result = JacobianResult(
            "pass",
            "",
            method,
            spec.reference,
            tol,
            linear_error=lin,
            angular_error=ang,
            column_linear=comparison.column_linear,
            column_angular=comparison.column_angular,
            worst_index=int(np.argmax(score)) if score.size else None,
            sample=sample,
        )
        n_bad = int((~(score <= tol)).sum())
        if not n_bad:
            return result
        rough = comparison.too_rough(tol)
        if rough is not None:  # no finding either way: the method could not resolve it
            return JacobianResult("error", rough, method, spec.reference, tol)
        first = result.first_bad_column
        where = (
            ""
            if first is None
            else f"; first column to disagree: {joint_label(comparison.model, first)}"
        )
        message = (
            f"Jacobian ({spec.reference}): {n_bad} of {score.size} configurations differ: "
            f"max linear difference {lin.max():.3g} m/rad, max angular {ang.max():.3g} "
            f"rad/rad{where}"
        )
        diagnosis, details = "", tuple[str, ...]()
        if self.explain is not None:
            try:  # evidence never changes a verdict: a failed diagnosis only says so
                diagnosis, details = self.explain(sample, comparison.model, spec, tol)
            except Exception as exc:
                diagnosis = f"the Jacobian diagnosis failed: {type(exc).__name__}: {exc}"
        return replace(
            result,
            status="fail",
            message=message,
            diagnosis=diagnosis,
            diagnosis_details=details,
        )


def joint_label(model: Model, index: int) -> str:
    """``joint 3 (elbow)``: a 0-based joint index as the reports name it."""
    name = model.joints[index].name
    return f"joint {index + 1} ({name})" if name else f"joint {index + 1}"


def _spread(pos: Float, rot: Float) -> str:
    """How a disagreement spreads over a file's rows: max, median, 95th percentile.

    For backends with configurations of their own (measured poses): a table that
    differs from the recorded robot by its factory calibration shows millimetres
    on every row, not one worst case.
    """
    finite = np.isfinite(pos) & np.isfinite(rot)
    p_mm = pos[finite] * 1e3
    r_deg = np.degrees(rot[finite])
    if not p_mm.size:
        return "no row compared to a finite pose"

    def three(values: Float, unit: str, digits: int) -> str:
        return ", ".join(
            f"{label} {v:.{digits}f}{unit}"
            for label, v in (
                ("max", values.max()),
                ("median", np.median(values)),
                ("95th percentile", np.percentile(values, 95)),
            )
        )

    return (
        f"over the {p_mm.size} rows: position {three(p_mm, ' mm', 3)}; "
        f"rotation {three(r_deg, '°', 4)}"
    )


def _streamed(job: Job) -> tuple[Recording, StreamSummary] | None:
    """The recording and what the check kept of it, when it runs on some of its rows only."""
    backend = job.backend
    if not isinstance(backend, MeasuredPoses):
        return None
    streamed = backend.streamed(job.model)
    if streamed is None or not isinstance(streamed[1], StreamSummary):
        return None
    return streamed[0], streamed[1]


def _rows_beyond(stream: tuple[Recording, StreamSummary], job: Job) -> int:
    """A streamed recording's rows beyond the job's tolerances, over every row.

    Counted as it streamed, in its one read under the read's clock: the check's
    tolerances are its summary's (:func:`~fkcheck.engine.stream.stream_recordings`
    is handed the prepared check's, as its jobs are), and a recording answers only
    for its own frame pair (``FrameUnavailable`` before this). The recording is
    never read again here, which would be a pass without a time limit.

    Raises:
        RuntimeError: The summary counted against other tolerances or another pair
            than the job's: a broken contract (the backend's error), not a count.
    """
    summary = stream[1]
    if summary.tol != job.tol or summary.pair != job.pair:
        raise RuntimeError(
            f"the recording was counted against tolerances {summary.tol} and pair "
            f"{summary.pair}, not the check's {job.tol} and {job.pair}; it is not read again"
        )
    return summary.beyond


def _stream_spread(summary: StreamSummary) -> str:
    """:func:`_spread` over every row of a streamed recording, from its histograms."""

    def three(which: str, scale: float, unit: str, digits: int) -> str:
        values = (
            ("max", summary.max_position_m if which == "position" else summary.max_rotation_rad),
            ("median", summary.percentile(which, 0.5)),
            ("95th percentile", summary.percentile(which, 0.95)),
        )
        return ", ".join(f"{label} {v * scale:.{digits}f}{unit}" for label, v in values)

    return (
        f"over the {summary.rows} rows: position {three('position', 1e3, ' mm', 3)}; "
        f"rotation {three('rotation', 180 / np.pi, '°', 4)}"
    )


def _stream_note(summary: StreamSummary, kept: int, where: str) -> str:
    """What a streamed recording's check compared: every row, and which rows it runs on.

    ``where`` is the recording's word for its row numbers (``line``, ``row``).
    """
    return (
        f"streamed {count_text(summary.rows)} rows ({where}s {summary.first_line}–"
        f"{summary.last_line}), each compared with {REFERENCE_NAME} as read; the check's "
        f"{count_text(kept)} configurations are one row in {summary.stride} and the "
        f"{summary.worst_added()} worst rows besides them"
    )


def _failure_detail(job: Job, worst: int, tracker: WorstTracker) -> FailureDetail:
    """What a report needs to show why a backend failed, kept while it is at hand."""
    model, q = job.model, job.q[worst]
    arm = arm_pose(model, q, job.pair)
    if isinstance(job.backend, SharesDHFrames):
        theirs = np.asarray(job.backend.dh_frames(model, q[None]))[0]
        parting = dh_parting(worst, arm.world_T_dh, theirs, job.tol)
        return FailureDetail(tracker.cases(worst), arm, dh_parting=parting)
    axes = urdf_axes(model, worst, q, job.pair[0], job.tol)
    return FailureDetail(tracker.cases(worst), arm, urdf_axes=axes)
