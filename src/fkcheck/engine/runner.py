"""The cross-check's run: sample, run every backend in its own thread and time limit.

:func:`run_check` samples configurations (or takes a measured-poses backend's),
plans how many of them each backend compares (:mod:`fkcheck.engine.plan`: a
backend whose declared cost does not fit its limit gets a stated subset),
loads the core's kernels (a phase of its own, charged to no backend), runs each
backend in a thread — an isolated one's poses in a child process, started first,
while the libraries of the others are imported — within its time limit, has
:func:`fkcheck.engine.compare.compare` judge each against the in-house core,
and returns a :class:`~fkcheck.engine.results.CheckResult` with the verdict.

The words of the result (pass, fail, error, skipped) are defined in
:mod:`fkcheck.engine.results`.
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import functools
import importlib
import itertools
import threading
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from fkcheck.backends.base import Backend, FixedConfigurations, reads_format
from fkcheck.backends.registry import check_known_differences
from fkcheck.calibration.description import screen_kinematics
from fkcheck.calibration.effect import CalibrationEffect, calibration_effect, nominal_model
from fkcheck.calibration.lint import lint_calibrated
from fkcheck.calibration.provenance import calibration_provenance
from fkcheck.core.tolerances import pose_tolerances
from fkcheck.core.typing import Float, JacobianReference
from fkcheck.description.registry import load_description, model_format, model_formats
from fkcheck.description.types import Description, DescriptionFormat
from fkcheck.engine.compare import Job, NoAnswerError, Progress, compare
from fkcheck.engine.expected import apply_known_differences, known_difference_findings
from fkcheck.engine.jacobian import Explain, JacobianSpec, check_fixed_from
from fkcheck.engine.plan import Plan, plan_check
from fkcheck.engine.provenance import apply_provenance
from fkcheck.engine.results import BackendResult, CheckResult
from fkcheck.engine.verdict import KINDS, Kind, summarize, verdict_of
from fkcheck.errors import BackendUnavailable, FkcheckError, FrameError, Skip, failure_text
from fkcheck.model.coverage import Competitor, coverage
from fkcheck.model.frames import (
    resolve_frame,
)
from fkcheck.model.lint import lint_lines
from fkcheck.model.options import (
    DEFAULT_SAMPLER,
    DEFAULT_SAMPLES,
    DEFAULT_SEED,
    DEFAULT_TIMEOUT_S,
    CheckOptions,
)
from fkcheck.model.sampling import Sampler, Samples, sample_configurations
from fkcheck.model.types import URDF_FRAME_PREFIX, Model
from fkcheck.process.cpus import usable_cores
from fkcheck.process.isolation import (
    IsolatedDied,
    IsolatedTimeout,
    answer_limit,
    run_isolated,
    terminate_all,
)
from fkcheck.process.supervise import acting_for
from fkcheck.urdf.chain import competing_links
from fkcheck.urdf.locate import display_path

if TYPE_CHECKING:
    from fkcheck.urdf.mapping import LinkFit

__all__ = ["EVIDENCE_MIN_S", "Progress", "load_kernels", "run_check"]


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


def _error(backend: Backend, message: str, duration_s: float = 0.0) -> BackendResult:
    return BackendResult(
        backend.name, "error", message, backend.method, duration_s, evidence=backend.evidence
    )


def _skipped(backend: Backend, reason: str) -> BackendResult:
    return BackendResult(backend.name, "skipped", reason, backend.method, evidence=backend.evidence)


def _run_one(
    job: Job, timeout_s: float, on_progress: Progress | None = None
) -> BackendResult | FkcheckError:
    """Run one backend with a time limit; returns a result, or bad input to re-raise."""
    backend = job.backend
    try:
        reason = backend.unavailable_reason(job.model)
    except Exception as exc:  # a broken availability probe is that backend's error
        return _error(backend, f"{type(exc).__name__}: {exc}")
    if reason is not None:
        return _skipped(backend, reason)

    if backend.isolated:
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


def _outcome(job: Job, on_progress: Progress | None = None) -> BackendResult | FkcheckError:
    """Compare one backend; any exception becomes a result (or bad input to re-raise)."""
    backend = job.backend
    start = time.perf_counter()
    try:
        return compare(job, on_progress)
    except Skip as exc:
        return _skipped(backend, str(exc))
    except FkcheckError as exc:
        return exc
    except Exception as exc:
        return _error(backend, failure_text(exc), time.perf_counter() - start)


def _in_child(call: Callable[[], Any]) -> tuple[str, Any]:
    """In an isolated backend's own process: its answer (poses or a Jacobian), or why not.

    Exceptions with their own constructors do not round-trip through pickle, so
    the outcome travels as ``("ok", array)``, ``("none", None)`` (no Jacobian),
    ``("skip", reason)``, ``("bad-input", message)`` or ``("error", message)``.
    """
    try:
        answer = call()
        if answer is None:
            return "none", None
        return "ok", np.asarray(answer, dtype=np.float64)
    except Skip as exc:
        return "skip", str(exc)
    except FkcheckError as exc:
        return "bad-input", str(exc)
    except Exception as exc:
        return "error", failure_text(exc)


#: An isolated backend's configurations are split over several processes (one per
#: core, at most) only when each process gets at least this many: starting one costs
#: about a second (an interpreter, NumPy, the backend's library, its model), about
#: 3,000 of yourdfpy's UR5 poses.
SPLIT_MIN_CONFIGS = 2_500


def _split(n: int) -> list[tuple[int, int]]:
    """Contiguous ``[start, stop)`` parts of ``n`` configurations, one per process."""
    worth = n // SPLIT_MIN_CONFIGS  # parts worth a process each
    parts = min(usable_cores(), worth) if worth > 1 else 1
    bounds = [n * k // parts for k in range(parts + 1)]
    return list(itertools.pairwise(bounds))


class _InChild:
    """An isolated backend (``isolated = True``) as the engine sees it.

    Only the backend's poses (and its own Jacobians) are computed in processes of its
    own (:func:`~fkcheck.process.isolation.run_isolated`); the reference and the
    comparison stay in this process, like every other backend's. A slow pure-Python
    backend that holds the GIL then uses the other cores: its configurations are
    split over up to one process per core (:data:`SPLIT_MIN_CONFIGS` each at least),
    run at once and joined in order. A crash of a process (e.g. a segfault in a C
    extension) or an answer larger than :func:`~fkcheck.process.isolation.answer_limit`
    is the backend's error, and at the time limit every process it started is killed
    with all they started.
    """

    def __init__(self, backend: Backend, timeout_s: float) -> None:
        self.backend = backend
        self.name = backend.name
        self.method = backend.method
        self.evidence = backend.evidence
        self.reads = backend.reads
        self.formats = getattr(backend, "formats", ())
        self.isolated = False  # it is the isolation
        self.imports: tuple[str, ...] = ()  # imported in its own process
        self.distributions = backend.distributions
        self.jacobian_method = backend.jacobian_method
        self.jacobian_references = backend.jacobian_references
        self.timeout_s = timeout_s
        self.deadline = time.monotonic() + min(timeout_s, threading.TIMEOUT_MAX)

    def unavailable_reason(self, model: Model) -> str | None:
        return self.backend.unavailable_reason(model)

    def inputs(self, model: Model) -> tuple[Path, ...]:
        return self.backend.inputs(model)

    def frame_poses(self, model: Model, q: Float, frames: Sequence[str]) -> Float:
        """``(len(frames), N, 4, 4)``, computed in the backend's processes."""
        calls = [
            (functools.partial(self.backend.frame_poses, model, part, tuple(frames)), len(part))
            for part in self._parts(q)
        ]
        poses: Float = self._run(calls, axis=1)
        return poses

    def frame_jacobian(
        self, model: Model, q: Float, frame: str, reference: JacobianReference
    ) -> Float | None:
        """The backend's own Jacobian, ``(N, 6, n)``, from its processes; ``None``: none."""
        if self.backend.jacobian_method is None:
            return None
        calls = [
            (
                functools.partial(self.backend.frame_jacobian, model, part, frame, reference),
                len(part),
            )
            for part in self._parts(q)
        ]
        jac: Float | None = self._run(calls, axis=0)
        return jac

    @staticmethod
    def _parts(q: Float) -> list[Float]:
        return [q[start:stop] for start, stop in _split(q.shape[0])]

    def _run(self, calls: list[tuple[functools.partial[Any], int]], axis: int) -> Any:
        """Each ``(call, configurations)`` in a process of its own, at once, joined on ``axis``."""
        if len(calls) == 1:
            answers: list[tuple[str, Any] | BaseException] = [self._answer(*calls[0])]
        else:
            owner = threading.current_thread()
            boxes: list[list[tuple[str, Any] | BaseException]] = [[] for _ in calls]

            def part(k: int) -> None:
                try:
                    with acting_for(owner):  # abandoning the backend stops every part
                        boxes[k].append(self._answer(*calls[k]))
                except BaseException as exc:
                    boxes[k].append(exc)

            helpers = [
                threading.Thread(target=part, args=(k,), name=f"{owner.name}-{k}", daemon=True)
                for k in range(len(calls))
            ]
            for helper in helpers:
                helper.start()
            for helper in helpers:  # each ends by the deadline (its process is killed then)
                helper.join()
            answers = [box[0] for box in boxes]
        for answer in answers:  # the first part that did not answer says why
            if isinstance(answer, BaseException):
                raise answer
            kind, value = answer
            if kind == "skip":
                raise Skip(value)
            if kind == "bad-input":
                raise FkcheckError(value)
            if kind == "error":
                raise NoAnswerError(value)
        kinds = {a[0] for a in answers if isinstance(a, tuple)}
        if kinds == {"none"}:
            return None
        if kinds != {"ok"}:
            raise NoAnswerError("it gave a Jacobian for some configurations and none for others")
        return np.concatenate([a[1] for a in answers if isinstance(a, tuple)], axis=axis)

    def _answer(self, call: functools.partial[Any], n: int) -> tuple[str, Any]:
        """One process's ``(kind, value)`` over ``n`` configurations (see :func:`_in_child`)."""
        remaining = max(0.0, self.deadline - time.monotonic())
        try:
            answer: tuple[str, Any] = run_isolated(
                functools.partial(_in_child, call), remaining, answer_limit(n)
            )
        except IsolatedTimeout:
            raise NoAnswerError(f"timed out after {self.timeout_s:g} s") from None
        except IsolatedDied as exc:
            raise NoAnswerError(str(exc)) from None
        return answer


def _import_libraries(model: Model, backends: Sequence[Backend]) -> None:
    """Import what in-process backends import lazily, once, before their threads start.

    Two threads importing one heavy library for the first time at the same time
    can end in ``_DeadlockError`` (seen with ``roboticstoolbox.ets``); importing
    here, in one thread, makes the later imports dictionary look-ups. A library
    that fails to import is left to its backend, which reports it.
    """
    for backend in backends:
        if backend.isolated or not backend.imports:  # nothing to import here
            continue
        try:
            if backend.unavailable_reason(model) is not None:
                continue
        except Exception:  # reported by the backend's own run
            continue
        for module in backend.imports:
            with contextlib.suppress(Exception):
                importlib.import_module(module)


def load_kernels(jacobian: bool, configurations: int) -> None:
    """Load (on a machine's first run: compile) the core's numba kernels before backends start.

    Compiling takes seconds; done here, once, it is charged to no backend's time.
    Nothing is loaded for a check of fewer than :data:`~fkcheck.core.dh.JIT_MIN_POSES`
    configurations (the core's NumPy path is quicker there than loading numba),
    nor without numba (the core keeps its NumPy path).
    """
    from fkcheck.core import dh
    from fkcheck.core import jacobian as core_jacobian

    if configurations < dh.JIT_MIN_POSES:
        return
    dh.load_jit()
    if jacobian:
        core_jacobian.load_kernel()


def _place_urdf_links(
    model: Model, asked: Sequence[str], xacro_timeout_s: float
) -> tuple[Model, dict[str, LinkFit]]:
    """The model with ``urdf:LINK`` frames for the undeclared links ``asked`` names.

    ``xacro_timeout_s`` is the time limit of a xacro expansion.

    Raises:
        FkcheckError: The URDF cannot be read (example-robot-data missing included),
            the link is not in it, or it is at no constant offset from any DH frame.
    """
    wanted = [
        name
        for name in asked
        if name.startswith(URDF_FRAME_PREFIX)
        and not any(s.urdf == name[len(URDF_FRAME_PREFIX) :] for s in model.frames.values())
    ]
    if not wanted or model_format(model, "urdf") is None:
        return model, {}  # resolve_frame says what is wrong, if anything
    from fkcheck.urdf.mapping import with_link_frames  # scipy.optimize: only when needed

    try:
        kin = load_description(model, xacro_timeout_s, language="urdf").tree
    except BackendUnavailable as exc:
        raise FkcheckError(f"{wanted[0]}: the URDF cannot be read here: {exc}") from None
    return with_link_frames(model, kin, wanted)


def _placed_reason(placed: Mapping[str, LinkFit]) -> str:
    """Why a backend that does not read the URDF skips a check of a placed ``urdf:LINK``."""
    name, fit = next(iter(placed.items()))
    return (
        f"{name} is declared by no frame: its offset from DH frame {fit.anchor} was taken "
        f"from the URDF (xyz {list(fit.offset.xyz)} m, rpy {list(fit.offset.rpy)} rad), so only "
        "URDF backends compare it; declare it in [frames.NAME] to check it with every backend"
    )


def _check_twins(
    model: Model, pair: Sequence[str], fmt: DescriptionFormat, described: Description
) -> None:
    """The description's frames of the compared frames exist (one not compared may lack its own).

    Raises:
        FrameError: A compared frame names a frame the description does not have (listing them).
    """
    links = described.frames
    for name in pair:
        link = fmt.frame(resolve_frame(model, name))
        if link is not None and link not in links:
            where = f"{described.language.upper()} {described.path.name} (frame {name})"
            raise FrameError(link, where, links)


#: How long the main thread waits on a backend's thread at a time, s (see run_check).
_JOIN_SLICE_S = 0.1
#: The per-number evidence's time limit is the check's ``timeout_s``, but never less
#: than this, seconds: it costs a few seconds even at 256 joints (about 5 s of one
#: core), and a ``--timeout`` short enough for a hanging backend (0.5 s) must not end
#: a six-joint check on a busy machine.
EVIDENCE_MIN_S = 10.0


def run_check(
    model: Model,
    backends: Sequence[Backend],
    *,
    samples: int = DEFAULT_SAMPLES,
    seed: int = DEFAULT_SEED,
    sampler: Sampler = DEFAULT_SAMPLER,
    frame_from: str | None = None,
    frame_to: str | None = None,
    tol_pos_m: float | None = None,
    tol_rot_rad: float | None = None,
    timeout_s: float = DEFAULT_TIMEOUT_S,
    require: Sequence[Kind] = (),
    jacobian: JacobianSpec | None = None,
    explain_jacobian: Explain | None = None,
    on_done: Callable[[BackendResult], None] | None = None,
    on_progress: Progress | None = None,
    tolerance_source: str | tuple[str, str] = "",
    full: bool = False,
    on_plan: Callable[[Plan], None] | None = None,
    lint_ignore: Sequence[str] = (),
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
        timeout_s: Time limit per backend, seconds (and of a xacro expansion, when
            shorter than :data:`~fkcheck.urdf.xacro.XACRO_TIMEOUT_S`).
        require: Kinds of evidence (``"table"``, ``"implementation"``) that must be
            verified, on top of the model's ``[check] require``; when one is not,
            the verdict is ``unverified``.
        jacobian: Also compare each backend's Jacobian of ``frame_to`` with the
            core's (:mod:`fkcheck.engine.jacobian`); a disagreement fails the check.
        explain_jacobian: Names each Jacobian disagreement (``fkcheck.check`` passes
            the diagnosis's); without it a failure carries its numbers only.
        on_done: Called with each backend's result as it finishes.
        on_progress: Called as ``(backend name, configurations done, total)`` after
            each chunk a backend finishes (from that backend's thread).
        tolerance_source: Where ``tol_pos_m``/``tol_rot_rad`` came from, for the
            headline: one for both, or ``(position's, rotation's)`` (default: "the
            caller"); a tolerance not given is the model's ``[check]``'s, said so.
        full: Every backend compares every configuration; by default a backend
            whose declared cost does not fit its limit compares a stated subset
            (:mod:`fkcheck.engine.plan`).
        on_plan: Called with the plan once it is made, before any backend starts.
        lint_ignore: Lint rules left out of the check's ``lint`` (a project's
            ``[tool.fkcheck] lint_ignore``), on top of the model's own ``[lint]``.

    Returns:
        The check result.

    Raises:
        FrameError: An unknown frame name.
        OptionError: ``samples``, ``seed``, ``sampler`` or ``timeout_s`` out of its
            range (:mod:`fkcheck.model.options`); a tolerance is a ``ToleranceError``.
        UrdfError: The model's URDF is missing, unsafe or does not fit the model.
        TimeLimitError: The per-number evidence did not finish within ``timeout_s``
            (or :data:`EVIDENCE_MIN_S`, when longer).
        FkcheckError: Other bad input reported by a backend.
    """
    from fkcheck.urdf.xacro import XACRO_TIMEOUT_S

    CheckOptions(samples=samples, seed=seed, sampler=sampler, timeout_s=timeout_s)  # in range
    created = _dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat()
    t0 = time.perf_counter()
    check_known_differences(model, backends)
    screen_kinematics(model)  # a calibration YAML is read as fkcheck calibration reads it
    asked = (frame_from or model.check.frame_from, frame_to or model.check.frame_to)
    # ``urdf:LINK`` resolves to the declared frame mapped onto that link; a link no
    # frame declares is placed from the URDF, and only URDF backends compare it.
    xacro_timeout_s = min(timeout_s, XACRO_TIMEOUT_S)  # the check's limit, when shorter
    model, placed = _place_urdf_links(model, asked, xacro_timeout_s)
    pair = (resolve_frame(model, asked[0]).name, resolve_frame(model, asked[1]).name)
    tol = pose_tolerances(
        tol_pos_m, tol_rot_rad, (model.check.tol_pos_m, model.check.tol_rot_rad), model.reach_m
    )
    if jacobian is not None:
        check_fixed_from(model, pair[0])
    competitors: dict[str, list[Competitor]] = {}
    for fmt in model_formats(model):
        read = any(reads_format(b, fmt.name) for b in backends)
        if fmt.executes and not read:  # code in a description (xacro) runs only when read
            continue
        # Bad description input is exit 2 before anything runs; a missing
        # example-robot-data is not: each reader then reports itself skipped.
        with contextlib.suppress(BackendUnavailable):
            described = load_description(model, xacro_timeout_s, language=fmt.language)
            if read:
                _check_twins(model, pair, fmt, described)
                for name, found in competing_links(model, pair, described.tree, fmt.frame).items():
                    competitors.setdefault(name, []).extend(found)
            model = fmt.carry(model, described)  # an expansion travels: run the file once
    urdf = model_format(model, "urdf")  # placed urdf:LINK frames are its readers' alone
    q = _fixed_configurations(model, backends) or sample_configurations(
        model, samples, seed, sampler
    )
    calibration = _calibration_effect(model, q.q, pair)
    required = tuple(k for k in KINDS if k in (*model.check.require, *require))
    # What it exercises, and what a choice among links could hide, within the check's
    # time limit (at least EVIDENCE_MIN_S).
    numbers = coverage(
        model,
        pair[0],
        pair[1],
        *tol,
        q=q.q,
        competitors=competitors,
        time_limit_s=max(timeout_s, EVIDENCE_MIN_S),
    )
    if "table" in required and numbers.spans_no_joint:
        raise FkcheckError(
            f"require table: the frame pair {pair[0]} → {pair[1]} spans no joint of model "
            f"{model.name}, so it cannot verify the table; compare a pair with joints "
            "between them (e.g. the model's [check] from/to)"
        )
    plan = plan_check(backends, q.origin, dof=model.dof, timeout_s=timeout_s,
                      jacobian=jacobian is not None, full=full)  # fmt: skip
    if on_plan is not None:
        on_plan(plan)
    load_kernels(jacobian is not None, plan.total)

    results: dict[int, BackendResult] = {}
    errors: list[FkcheckError] = []
    lock = threading.Lock()

    def run_and_collect(index: int, backend: Backend) -> None:
        if placed and not (urdf is not None and reads_format(backend, urdf.name)):
            outcome: BackendResult | FkcheckError = _skipped(backend, _placed_reason(placed))
        else:
            share = plan.backends[index]
            outcome = _run_one(
                Job(backend, model, q.q[: share.compared], pair, tol, jacobian, explain_jacobian),
                timeout_s,
                on_progress,
            )
            if share.subset and isinstance(outcome, BackendResult):
                outcome = replace(outcome, subset=(share.compared, share.total))
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
    # An isolated backend's process starts first: it imports its own libraries on the
    # other core while this process imports those of the backends that run here.
    for worker, backend in zip(workers, backends, strict=True):
        if backend.isolated:
            worker.start()
    _import_libraries(model, backends)
    for worker, backend in zip(workers, backends, strict=True):
        if not backend.isolated:
            worker.start()
    for worker in workers:
        # In slices: a signal that lands on a backend's thread (SIGTERM, Ctrl-C) runs its
        # Python handler only when the main thread runs again — an unbounded join()
        # would hold it until the slowest backend ended.
        while worker.is_alive():
            worker.join(_JOIN_SLICE_S)
    if errors:
        raise errors[0]
    ordered = apply_known_differences(
        model,
        pair,
        tol,
        [results[i] for i in range(len(backends))],
        {b.name: b.reads for b in backends},
    )
    ordered = apply_provenance(model, backends, tol, ordered)  # a URDF from this very table
    answered = _table_answered(ordered, len(q.q))
    if 0 < answered < len(q.q):  # the numbers are judged on what the table's evidence compared
        numbers = coverage(
            model, pair[0], pair[1], *tol, q=q.q[:answered], competitors=competitors,
            time_limit_s=max(timeout_s, EVIDENCE_MIN_S),
        )  # fmt: skip
    # A Jacobian that disagrees fails the check, one that could not be computed is
    # its error; the evidence (what the poses proved) is the poses' alone.
    jacobians = [replace(r, status=r.jacobian.status) for r in ordered if r.jacobian and r.ran]
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
        verdict=verdict_of((*ordered, *jacobians), summarize(ordered, required, numbers)),
        required=required,
        created=created,
        duration_s=time.perf_counter() - t0,
        jacobian=jacobian,
        numbers=numbers,
        tolerance_source=_tolerance_source(model, tol_pos_m, tol_rot_rad, tolerance_source),
        calibration=calibration,
        lint=lint_lines(
            model,
            [
                *lint_calibrated(model, lint_ignore)[0],
                *known_difference_findings(model, lint_ignore),
            ],
        ),
    )


def _table_answered(results: Sequence[BackendResult], total: int) -> int:
    """How many configurations the agreeing table evidence compared: the most any one did.

    A backend on a subset compares a prefix of the check's configurations
    (:mod:`fkcheck.engine.plan`), so the prefixes nest: the longest one is their
    union, and it is one backend's own. Each number is then verified only when
    configurations that one agreeing backend answered tell it apart. ``0`` when
    no table evidence agreed (no number is verified then anyway).
    """
    return max(
        (
            r.subset[0] if r.subset is not None else total
            for r in results
            if r.evidence == "table" and r.status == "pass"
        ),
        default=0,
    )


def _calibration_effect(model: Model, q: Float, pair: tuple[str, str]) -> CalibrationEffect | None:
    """What a calibrated model's calibration changes at ``q`` (``None`` for other models).

    The nominal model must load (a bad ``[calibration] nominal`` is bad input);
    a frame pair the nominal model does not have is not compared.

    Raises:
        ModelError: The nominal model is missing, invalid or has other joints.
    """
    if model.calibration is None:
        return None
    nominal = nominal_model(model)
    try:
        name = Path(model.calibration.file).name
        effect = calibration_effect(model, nominal, q, pair[0], pair[1], name)
    except FrameError:
        return None
    # Said with the effect: whether the file and the table are still as calibrated.
    return replace(effect, provenance=calibration_provenance(model, nominal))


def _tolerance_source(
    model: Model,
    tol_pos_m: float | None,
    tol_rot_rad: float | None,
    given: str | tuple[str, str],
) -> tuple[str, str]:
    """Where each of the check's tolerances came from, in words: ``(position, rotation)``."""
    said = (given, given) if isinstance(given, str) else given
    of = f" of {display_path(model.path)}" if model.path is not None else ""
    own = f"the model's [check]{of}"
    return (
        own if tol_pos_m is None else said[0] or "the caller",
        own if tol_rot_rad is None else said[1] or "the caller",
    )
