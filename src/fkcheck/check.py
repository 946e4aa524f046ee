"""The cross-check: every backend against the in-house core, pose by pose.

:func:`run_check` samples configurations, computes ``from_T_to`` with the
in-house DH core (the reference row) and with each backend, and turns the
differences into :class:`BackendResult` rows and a :class:`CheckResult` verdict.

A backend that cannot run is *skipped* with its reason; one that raises, times
out or returns something that is not a pose is an *error* with the message; only
a backend that ran and agreed within tolerance is a *pass*. A run where no
backend ran is never a pass (verdict ``error``).
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import functools
import threading
import time
import traceback
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from fkcheck.backends.base import (
    Backend,
    BackendUnavailable,
    FixedConfigurations,
    FrameUnavailable,
    SharesDHFrames,
)
from fkcheck.errors import FkcheckError
from fkcheck.frames import frame_poses_from_dh, relative_pose, resolve_frame
from fkcheck.isolation import (
    IsolatedDied,
    IsolatedTimeout,
    answer_limit,
    run_isolated,
    terminate_all,
)
from fkcheck.metrics import position_error_m, rotation_error_rad, se3_defect
from fkcheck.model import Model
from fkcheck.sampling import Sampler, Samples, sample_configurations
from fkcheck.tolerances import ROUNDED_URDF

__all__ = [
    "CHUNK",
    "REFERENCE_NAME",
    "BackendResult",
    "CheckResult",
    "Status",
    "Verdict",
    "reference_poses",
    "run_check",
]

Float = NDArray[np.float64]
Status = Literal["pass", "fail", "error", "skipped"]
Progress = Callable[[str, int, int], None]
Verdict = Literal["pass", "fail", "error"]

#: Name of the reference row: the in-house DH core.
REFERENCE_NAME = "fkcheck-dh"
#: Configurations handed to a backend per call: bounds memory for large runs.
CHUNK = 65_536
#: A backend's output must be a rigid transform to this accuracy; worse is an error.
#: Looser than any round-off (1e-15) and than a URDF's rounded π/2 (1e-11), tight
#: enough to catch a scaled, sheared or transposed "rotation".
SE3_TOLERANCE = 1e3 * ROUNDED_URDF


@dataclass(frozen=True, eq=False)
class BackendResult:
    """One backend's outcome.

    Attributes:
        name: Backend name.
        status: ``pass``, ``fail``, ``error`` or ``skipped``.
        message: Why it was skipped or errored, or a summary of the failure.
        method: The library call it used.
        duration_s: Wall time of its run, seconds (import included).
        position_error_m: Per-configuration position error against the reference, metres.
        rotation_error_rad: Per-configuration rotation error, radians.
        worst_index: Index of the worst configuration (largest error relative to tolerance).
        worst_dh_frames: For backends built from the DH table that failed: their DH
            frames ``(n+1, 4, 4)`` at the worst configuration, to find where chains part.
    """

    name: str
    status: Status
    message: str = ""
    method: str = ""
    duration_s: float = 0.0
    position_error_m: Float | None = None
    rotation_error_rad: Float | None = None
    worst_index: int | None = None
    worst_dh_frames: Float | None = None

    @property
    def ran(self) -> bool:
        """Whether the backend produced poses that were compared."""
        return self.position_error_m is not None

    def _stat(self, values: Float | None, q: float | None) -> float | None:
        if values is None or values.size == 0:
            return None
        if q is None:
            return float(values.max())
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
        model: The model checked.
        samples: Number of random samples asked for.
        seed: Seed of the random samples.
        sampler: ``sobol`` or ``uniform``.
        frame_from: Frame the compared pose is expressed in.
        frame_to: Frame whose pose is compared.
        tol_pos_m: Position tolerance, metres.
        tol_rot_rad: Rotation tolerance, radians.
        q: ``(N, n)`` configurations checked (radians / metres).
        origin: Where each configuration came from (see :mod:`fkcheck.sampling`).
        backends: One result per backend, in the order asked.
        verdict: ``pass``, ``fail`` or ``error``.
        created: ISO 8601 UTC time the check started.
        duration_s: Wall time of the check, seconds.
        command: The command line that reproduces it (set by the CLI).
    """

    model: Model
    samples: int
    seed: int
    sampler: str
    frame_from: str
    frame_to: str
    tol_pos_m: float
    tol_rot_rad: float
    q: Float
    origin: tuple[str, ...]
    backends: tuple[BackendResult, ...]
    verdict: Verdict
    created: str = ""
    duration_s: float = 0.0
    command: str = ""

    @property
    def ran(self) -> tuple[BackendResult, ...]:
        """The backends that produced poses."""
        return tuple(b for b in self.backends if b.ran)


def reference_poses(model: Model, q: Float, frames: Sequence[str]) -> Float:
    """Named-frame poses from the in-house core: ``(len(frames), N, 4, 4)``."""
    out = np.empty((len(frames), q.shape[0], 4, 4))
    for start in range(0, q.shape[0], CHUNK):
        chunk = q[start : start + CHUNK]
        out[:, start : start + CHUNK] = frame_poses_from_dh(
            model, model.fk(chunk, all_frames=True), model.fk(chunk), frames
        )
    return out


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


def _verdict(results: Sequence[BackendResult]) -> Verdict:
    if not any(r.ran for r in results):
        return "error"
    if any(r.status == "fail" for r in results):
        return "fail"
    if any(r.status == "error" for r in results):
        return "error"
    return "pass"


@dataclass(frozen=True, eq=False)
class _Job:
    """One backend's comparison (pickled whole to an isolated backend's process).

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


def _error(backend: Backend, message: str, duration_s: float = 0.0) -> BackendResult:
    return BackendResult(backend.name, "error", message, backend.method, duration_s)


def _compare(job: _Job, on_progress: Progress | None = None) -> BackendResult:
    """Run one backend over all configurations and compare with the reference."""
    backend, model, q, pair = job.backend, job.model, job.q, job.pair
    start = time.perf_counter()
    pos = np.empty(q.shape[0])
    rot = np.empty(q.shape[0])
    for first in range(0, q.shape[0], CHUNK):
        chunk = q[first : first + CHUNK]
        poses = np.asarray(backend.frame_poses(model, chunk, pair), dtype=np.float64)
        expected_shape = (2, chunk.shape[0], 4, 4)
        if poses.shape != expected_shape:
            raise RuntimeError(f"returned shape {poses.shape}, expected {expected_shape}")
        if not np.isfinite(poses).all():
            raise RuntimeError("returned non-finite values (NaN or inf) in poses")
        defect = se3_defect(poses)
        if defect.max() > SE3_TOLERANCE:
            k = int(np.unravel_index(np.argmax(defect), defect.shape)[1])
            raise RuntimeError(
                f"returned a matrix that is not a rigid transform (defect {defect.max():.3g}) "
                f"at configuration {first + k}"
            )
        theirs = relative_pose(poses[0], poses[1])
        ref = reference_poses(model, chunk, pair)
        ours = relative_pose(ref[0], ref[1])
        pos[first : first + CHUNK] = position_error_m(ours, theirs)
        rot[first : first + CHUNK] = rotation_error_rad(ours, theirs)
        if on_progress is not None:
            on_progress(backend.name, first + chunk.shape[0], q.shape[0])
    tol_pos, tol_rot = job.tol
    score = np.maximum(pos / tol_pos, rot / tol_rot)
    worst = int(np.argmax(score)) if score.size else None
    failed = bool(score.size and score.max() > 1.0)
    worst_frames = None
    message = ""
    if failed and worst is not None:
        n_bad = int((score > 1.0).sum())
        message = (
            f"{n_bad} of {q.shape[0]} configurations differ: max position error "
            f"{pos.max():.3g} m, max rotation error {rot.max():.3g} rad"
        )
        if isinstance(backend, SharesDHFrames):
            worst_frames = np.asarray(backend.dh_frames(model, q[worst : worst + 1]))[0]
    return BackendResult(
        name=backend.name,
        status="fail" if failed else "pass",
        message=message,
        method=backend.method,
        duration_s=time.perf_counter() - start,
        position_error_m=pos,
        rotation_error_rad=rot,
        worst_index=worst,
        worst_dh_frames=worst_frames,
    )


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
        return BackendResult(backend.name, "skipped", reason, backend.method)

    if getattr(backend, "isolated", False):
        return _run_in_process(job, timeout_s)

    box: list[BackendResult | FkcheckError] = []

    def target() -> None:
        box.append(_outcome(job, on_progress))

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
    except (BackendUnavailable, FrameUnavailable) as exc:
        return BackendResult(backend.name, "skipped", str(exc), backend.method)
    except FkcheckError as exc:
        return exc
    except Exception as exc:
        where = traceback.extract_tb(exc.__traceback__)[-1]
        detail = f"{type(exc).__name__}: {exc} ({where.filename.rsplit('/', 1)[-1]}:{where.lineno})"
        return _error(backend, detail, time.perf_counter() - start)


def _isolated_outcome(job: _Job) -> BackendResult | tuple[str, str]:
    """What an isolated backend's process sends back.

    Exceptions with their own constructors do not round-trip through pickle:
    bad input travels as ``("bad-input", message)``.
    """
    outcome = _outcome(job)
    return ("bad-input", str(outcome)) if isinstance(outcome, FkcheckError) else outcome


def _run_in_process(job: _Job, timeout_s: float) -> BackendResult | FkcheckError:
    """Run a backend in its own process (``isolated = True``).

    For slow, pure-Python backends that hold the GIL: in a process of their own
    they use the second core instead of queueing behind the others. A crash of
    the process (e.g. a segfault in a C extension) or an answer larger than
    :func:`~fkcheck.isolation.answer_limit` is that backend's error; at the time
    limit the process is killed with all it started (:mod:`fkcheck.isolation`).
    """
    start = time.perf_counter()
    try:
        outcome = run_isolated(
            functools.partial(_isolated_outcome, job), timeout_s, answer_limit(job.q.shape[0])
        )
    except IsolatedTimeout:
        return _error(job.backend, f"timed out after {timeout_s:g} s", timeout_s)
    except IsolatedDied as exc:
        return _error(job.backend, str(exc), time.perf_counter() - start)
    if isinstance(outcome, tuple):
        return FkcheckError(outcome[1])
    result: BackendResult = outcome
    return replace(result, duration_s=time.perf_counter() - start)


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
    from fkcheck.urdf_source import load_urdf

    created = _dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat()
    t0 = time.perf_counter()
    pair = (frame_from or model.check.frame_from, frame_to or model.check.frame_to)
    for name in pair:
        resolve_frame(model, name)
    tol = (tol_pos_m or model.check.tol_pos_m, tol_rot_rad or model.check.tol_rot_rad)
    if model.urdf is not None:
        # Bad URDF input is exit 2 before anything runs; a missing example-robot-data
        # is not: each URDF backend then reports itself skipped.
        with contextlib.suppress(BackendUnavailable):
            load_urdf(model)
    q = _fixed_configurations(model, backends) or sample_configurations(
        model, samples, seed, sampler
    )

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
        verdict=_verdict(ordered),
        created=created,
        duration_s=time.perf_counter() - t0,
    )
