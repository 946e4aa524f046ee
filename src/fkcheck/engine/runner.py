"""The cross-check: every backend against the in-house core, pose by pose.

:func:`run_check` samples configurations, computes ``from_T_to`` with the
in-house DH core (the reference row) and with each backend, and turns the
differences into :class:`BackendResult` rows and a :class:`CheckResult` verdict.

The words of the result (pass, fail, error, skipped) are defined in
:mod:`fkcheck.engine.results`.
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import functools
import importlib
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from fkcheck.backends.base import Backend, Evidence, FixedConfigurations, SharesDHFrames
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
from fkcheck.engine.results import REFERENCE_NAME, BackendResult, CheckResult
from fkcheck.engine.verdict import KINDS, Kind, summarize, verdict_of
from fkcheck.errors import BackendUnavailable, FkcheckError, Skip, UnmappedFrameError
from fkcheck.model.frames import (
    CHUNK,
    reference_poses,
    relative_pose,
    resolve_frame,
)
from fkcheck.model.sampling import Sampler, Samples, sample_configurations
from fkcheck.model.types import Model
from fkcheck.process.isolation import (
    IsolatedDied,
    IsolatedTimeout,
    answer_limit,
    run_isolated,
    terminate_all,
)

__all__ = ["Progress", "run_check"]

Progress = Callable[[str, int, int], None]

#: A backend's output must be a rigid transform to this accuracy; worse is a failure.
#: Looser than any round-off (1e-15) and than a URDF's rounded π/2 (1e-11), tight
#: enough to catch a scaled, sheared or transposed "rotation".
SE3_TOLERANCE = 1e3 * ROUNDED_URDF


def _fixed_configurations(model: Model, backends: Sequence[Backend]) -> Samples | None:
    """The configurations a measured-poses backend dictates, if one takes part."""
    fixed = [b for b in backends if isinstance(b, FixedConfigurations)]
    if not fixed:
        return None
    q = np.asarray(fixed[0].configurations(model), dtype=np.float64)
    for other in fixed[1:]:
        if not np.array_equal(np.asarray(other.configurations(model)), q):
            raise FkcheckError(
                f"{fixed[0].name} and {other.name} hold poses at different configurations; "
                "check them one at a time"
            )
    return Samples(q=q, origin=(f"file:{fixed[0].name}",) * q.shape[0])


@dataclass(frozen=True, eq=False)
class _Job:
    """One backend's comparison (run in a thread of the engine's process).

    Attributes:
        backend: The backend to run.
        model: The model checked.
        q: ``(N, n)`` configurations, radians / metres.
        pair: ``(frame_from, frame_to)`` of the compared pose.
        tol: ``(position m, rotation rad)`` tolerances.
    """

    backend: Backend
    model: Model
    q: Float
    pair: tuple[str, str]
    tol: tuple[float, float]


def _evidence(backend: Backend) -> Evidence:
    """What a backend's agreement proves; one that does not say proves only the implementation."""
    kind = getattr(backend, "evidence", "implementation")
    return "table" if kind == "table" else "implementation"


def _error(backend: Backend, message: str, duration_s: float = 0.0) -> BackendResult:
    return BackendResult(
        backend.name, "error", message, backend.method, duration_s, evidence=_evidence(backend)
    )


def _skipped(backend: Backend, reason: str) -> BackendResult:
    return BackendResult(
        backend.name, "skipped", reason, backend.method, evidence=_evidence(backend)
    )


def _q_text(q: Float) -> str:
    return "[" + ", ".join(f"{v:.6g}" for v in q) + "]"


class NoAnswerError(RuntimeError):
    """A backend's output cannot be compared (wrong shape), or the reference is not finite."""


def _compare(job: _Job, on_progress: Progress | None = None) -> BackendResult:
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
    if n_bad:
        reasons.append(
            f"{n_bad} of {q.shape[0]} configurations differ: max position error "
            f"{pos.max():.3g} m, max rotation error {rot.max():.3g} rad"
        )
    failed = bool(reasons)
    detail = None
    if failed and worst is not None:
        detail = _failure_detail(job, worst, tracker)
    return BackendResult(
        name=backend.name,
        status="fail" if failed else "pass",
        message="; ".join(reasons),
        method=backend.method,
        duration_s=time.perf_counter() - start,
        evidence=_evidence(backend),
        position_error_m=pos,
        rotation_error_rad=rot,
        worst_index=worst,
        detail=detail,
    )


def _failure_detail(job: _Job, worst: int, tracker: WorstTracker) -> FailureDetail:
    """What a report needs to show why a backend failed, kept while it is at hand."""
    model, q = job.model, job.q[worst]
    arm = arm_pose(model, q, job.pair)
    if isinstance(job.backend, SharesDHFrames):
        theirs = np.asarray(job.backend.dh_frames(model, q[None]))[0]
        parting = dh_parting(worst, arm.world_T_dh, theirs, job.tol)
        return FailureDetail(tracker.cases(worst), arm, dh_parting=parting)
    axes = urdf_axes(model, worst, q, job.pair[0], job.tol)
    return FailureDetail(tracker.cases(worst), arm, urdf_axes=axes)


def _run_one(
    job: _Job, timeout_s: float, on_progress: Progress | None = None
) -> BackendResult | FkcheckError:
    """Run one backend with a time limit; returns a result, or bad input to re-raise."""
    backend = job.backend
    try:
        reason = backend.unavailable_reason(job.model)
    except Exception as exc:  # a broken availability probe is that backend's error
        return _error(backend, f"{type(exc).__name__}: {exc}")
    if reason is not None:
        return _skipped(backend, reason)

    if getattr(backend, "isolated", False):
        job = replace(job, backend=_InChild(backend, timeout_s))

    box: list[BackendResult | FkcheckError] = []

    def target() -> None:
        try:
            box.append(_outcome(job, on_progress))
        except BaseException as exc:  # SystemExit and the like end no run: an error
            box.append(_error(backend, f"{type(exc).__name__}: {exc} (ended its thread)"))

    # A daemon thread: a backend that hangs is abandoned at the time limit and
    # does not keep the process alive; the programs it runs (plugins, cmd:) are
    # killed then, whatever their own time limit.
    thread = threading.Thread(target=target, name=f"fkcheck-{backend.name}", daemon=True)
    thread.start()
    thread.join(min(timeout_s, threading.TIMEOUT_MAX))  # 1e10 s: as good as no limit
    if thread.is_alive() or not box:
        terminate_all(started_by=thread)
        return _error(backend, f"timed out after {timeout_s:g} s", timeout_s)
    return box[0]


def _outcome(job: _Job, on_progress: Progress | None = None) -> BackendResult | FkcheckError:
    """Compare one backend; any exception becomes a result (or bad input to re-raise)."""
    backend = job.backend
    start = time.perf_counter()
    try:
        return _compare(job, on_progress)
    except Skip as exc:
        return _skipped(backend, str(exc))
    except FkcheckError as exc:
        return exc
    except Exception as exc:
        # fkcheck's own messages are sentences; a library's exception keeps its type name.
        own = isinstance(exc, UnmappedFrameError) or type(exc).__module__.startswith("fkcheck.")
        detail = str(exc) if own else f"{type(exc).__name__}: {exc}"
        return _error(backend, detail, time.perf_counter() - start)


def _poses_in_child(
    backend: Backend, model: Model, q: Float, frames: tuple[str, ...]
) -> tuple[str, Any]:
    """In an isolated backend's own process: its poses, or why not.

    Exceptions with their own constructors do not round-trip through pickle, so
    the outcome travels as ``("ok", poses)``, ``("skip", reason)``,
    ``("bad-input", message)`` or ``("error", message)``.
    """
    try:
        return "ok", np.asarray(backend.frame_poses(model, q, frames), dtype=np.float64)
    except Skip as exc:
        return "skip", str(exc)
    except FkcheckError as exc:
        return "bad-input", str(exc)
    except Exception as exc:
        own = isinstance(exc, UnmappedFrameError) or type(exc).__module__.startswith("fkcheck.")
        return "error", str(exc) if own else f"{type(exc).__name__}: {exc}"


class _InChild:
    """An isolated backend (``isolated = True``) as the engine sees it.

    Only the backend's poses are computed in a process of its own
    (:func:`~fkcheck.process.isolation.run_isolated`); the reference and the comparison
    stay in this process, like every other backend's. A slow pure-Python backend
    that holds the GIL then uses the second core; a crash of its process (e.g.
    a segfault in a C extension) or an answer larger than
    :func:`~fkcheck.process.isolation.answer_limit` is its error, and at the time limit
    its process is killed with all it started.
    """

    def __init__(self, backend: Backend, timeout_s: float) -> None:
        self.backend = backend
        self.name = backend.name
        self.method = backend.method
        self.evidence = _evidence(backend)
        self.timeout_s = timeout_s
        self.deadline = time.monotonic() + min(timeout_s, threading.TIMEOUT_MAX)

    def unavailable_reason(self, model: Model) -> str | None:
        return self.backend.unavailable_reason(model)

    def frame_poses(self, model: Model, q: Float, frames: Sequence[str]) -> Float:
        job = functools.partial(_poses_in_child, self.backend, model, q, tuple(frames))
        remaining = max(0.0, self.deadline - time.monotonic())
        try:
            kind, value = run_isolated(job, remaining, answer_limit(q.shape[0]))
        except IsolatedTimeout:
            raise NoAnswerError(f"timed out after {self.timeout_s:g} s") from None
        except IsolatedDied as exc:
            raise NoAnswerError(str(exc)) from None
        if kind == "ok":
            poses: Float = value
            return poses
        if kind == "skip":
            raise Skip(value)
        if kind == "bad-input":
            raise FkcheckError(value)
        raise NoAnswerError(value)


def _import_libraries(model: Model, backends: Sequence[Backend]) -> None:
    """Import what in-process backends import lazily, once, before their threads start.

    Two threads importing one heavy library for the first time at the same time
    can end in ``_DeadlockError`` (seen with ``roboticstoolbox.ets``); importing
    here, in one thread, makes the later imports dictionary look-ups. A library
    that fails to import is left to its backend, which reports it.
    """
    for backend in backends:
        if getattr(backend, "isolated", False):
            continue
        try:
            if backend.unavailable_reason(model) is not None:
                continue
        except Exception:  # reported by the backend's own run
            continue
        for module in getattr(backend, "imports", ()):
            with contextlib.suppress(Exception):
                importlib.import_module(module)


def run_check(
    model: Model,
    backends: Sequence[Backend],
    *,
    samples: int = 1000,
    seed: int = 0,
    sampler: Sampler = "sobol",
    frame_from: str | None = None,
    frame_to: str | None = None,
    tol_pos_m: float | None = None,
    tol_rot_rad: float | None = None,
    timeout_s: float = 120.0,
    require: Sequence[Kind] = (),
    on_done: Callable[[BackendResult], None] | None = None,
    on_progress: Progress | None = None,
) -> CheckResult:
    """Check ``backends`` against the in-house core on sampled configurations.

    Backends run concurrently (one thread each), each within ``timeout_s``. When a
    backend holds poses only at fixed configurations (measured poses), the check
    runs on those instead of sampling.

    Args:
        model: The model.
        backends: Backends to compare (see :mod:`fkcheck.backends.registry`).
        samples: Number of random samples (on top of poses, corners and mid-points).
        seed: Seed for the random samples.
        sampler: ``sobol`` or ``uniform``.
        frame_from: Frame to express the pose in (default: the model's ``[check]``).
        frame_to: Frame whose pose is compared (default: the model's ``[check]``).
        tol_pos_m: Position tolerance, metres (default: the model's ``[check]``).
        tol_rot_rad: Rotation tolerance, radians (default: the model's ``[check]``).
        timeout_s: Time limit per backend, seconds.
        require: Kinds of evidence (``"table"``, ``"implementation"``) that must be
            verified, on top of the model's ``[check] require``; when one is not,
            the verdict is ``unverified``.
        on_done: Called with each backend's result as it finishes.
        on_progress: Called as ``(backend name, configurations done, total)`` after
            each chunk a backend finishes (from that backend's thread).

    Returns:
        The check result.

    Raises:
        FrameError: An unknown frame name.
        UrdfError: The model's URDF is missing, unsafe or does not fit the model.
        FkcheckError: Other bad input reported by a backend.
    """
    from fkcheck.urdf.source import load_urdf

    created = _dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat()
    t0 = time.perf_counter()
    asked = (frame_from or model.check.frame_from, frame_to or model.check.frame_to)
    # ``urdf:LINK`` resolves to the declared frame mapped onto that link.
    pair = (resolve_frame(model, asked[0]).name, resolve_frame(model, asked[1]).name)
    tol = (tol_pos_m or model.check.tol_pos_m, tol_rot_rad or model.check.tol_rot_rad)
    if model.urdf is not None:
        # Bad URDF input is exit 2 before anything runs; a missing example-robot-data
        # is not: each URDF backend then reports itself skipped.
        with contextlib.suppress(BackendUnavailable):
            load_urdf(model)
    q = _fixed_configurations(model, backends) or sample_configurations(
        model, samples, seed, sampler
    )
    required = tuple(k for k in KINDS if k in (*model.check.require, *require))
    _import_libraries(model, backends)

    results: dict[int, BackendResult] = {}
    errors: list[FkcheckError] = []
    lock = threading.Lock()

    def run_and_collect(index: int, backend: Backend) -> None:
        outcome = _run_one(_Job(backend, model, q.q, pair, tol), timeout_s, on_progress)
        with lock:
            if isinstance(outcome, FkcheckError):
                errors.append(outcome)
                return
            results[index] = outcome
        if on_done is not None:
            on_done(outcome)

    workers = [
        threading.Thread(target=run_and_collect, args=(i, b), daemon=True)
        for i, b in enumerate(backends)
    ]
    for worker in workers:
        worker.start()
    for worker in workers:
        worker.join()
    if errors:
        raise errors[0]
    ordered = tuple(results[i] for i in range(len(backends)))
    return CheckResult(
        model=model,
        samples=samples,
        seed=seed,
        sampler=sampler,
        frame_from=pair[0],
        frame_to=pair[1],
        tol_pos_m=tol[0],
        tol_rot_rad=tol[1],
        q=q.q,
        origin=q.origin,
        backends=ordered,
        verdict=verdict_of(ordered, summarize(ordered, required)),
        required=required,
        created=created,
        duration_s=time.perf_counter() - t0,
    )
