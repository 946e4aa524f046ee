"""The cross-check's run: every backend in its own thread and time limit.

:func:`run_request` takes a check through its three stages
(:mod:`fkcheck.engine.request`): :func:`~fkcheck.engine.prepare.prepare` reads
the inputs, samples the configurations (or takes a measured-poses backend's)
and plans how many of them each backend compares (:mod:`fkcheck.engine.plan`:
a backend whose declared cost does not fit its limit gets a stated subset);
then the core's kernels load (a phase of its own, charged to no backend) and
:func:`run_backends` runs each backend in a thread — an isolated one's poses in
a child process, started first, while the libraries of the others are imported
(unless its share, of a short description, is too small to be worth one:
:func:`in_own_processes`) — within its time limit, with
:func:`fkcheck.engine.compare.compare` comparing each with the in-house core;
:func:`~fkcheck.engine.judge.judge` gives the
:class:`~fkcheck.engine.results.CheckResult` with the verdict. :func:`run_check`
is one request from a model, backends and options by name.

The words of the result (pass, fail, error, skipped) are defined in
:mod:`fkcheck.engine.results`.
"""

from __future__ import annotations

import contextlib
import functools
import importlib
import itertools
import threading
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, Unpack

import numpy as np

from fkcheck.backends.base import Backend, reads_format
from fkcheck.core.typing import Float, JacobianReference
from fkcheck.description.registry import load_description, model_format, model_formats
from fkcheck.engine.compare import Job, NoAnswerError, Progress, compare
from fkcheck.engine.jacobian import Explain
from fkcheck.engine.judge import judge
from fkcheck.engine.plan import BackendPlan, Plan
from fkcheck.engine.prepare import EVIDENCE_MIN_S, PreparedCheck, prepare
from fkcheck.engine.request import CheckRequest
from fkcheck.engine.results import BackendResult, CheckResult
from fkcheck.errors import FkcheckError, Skip, failure_text
from fkcheck.model.options import OptionArgs, resolve_options
from fkcheck.model.types import Model
from fkcheck.process.cpus import usable_cores
from fkcheck.process.isolation import (
    IsolatedDied,
    IsolatedTimeout,
    answer_limit,
    run_isolated,
    terminate_all,
)
from fkcheck.process.supervise import acting_for
from fkcheck.process.threads import child_environment

if TYPE_CHECKING:
    from fkcheck.urdf.mapping import LinkFit

__all__ = [
    "EVIDENCE_MIN_S",
    "IN_PROCESS_MAX_DESCRIPTION_CHARS",
    "IN_PROCESS_MAX_S",
    "CheckRequest",
    "Progress",
    "in_own_processes",
    "load_kernels",
    "run_backends",
    "run_check",
    "run_request",
]


def _error(backend: Backend, message: str, duration_s: float = 0.0) -> BackendResult:
    return BackendResult(
        backend.name, "error", message, backend.method, duration_s, evidence=backend.evidence
    )


def _skipped(backend: Backend, reason: str) -> BackendResult:
    return BackendResult(backend.name, "skipped", reason, backend.method, evidence=backend.evidence)


def _run_one(
    job: Job,
    timeout_s: float,
    on_progress: Progress | None = None,
    processes: int | None = None,
    *,
    own_processes: bool = False,
) -> BackendResult | FkcheckError:
    """Run one backend with a time limit; returns a result, or bad input to re-raise.

    ``own_processes``: its poses are computed in processes of its own
    (:func:`in_own_processes`).
    """
    backend = job.backend
    try:
        reason = backend.unavailable_reason(job.model)
    except Exception as exc:  # a broken availability probe is that backend's error
        return _error(backend, f"{type(exc).__name__}: {exc}")
    if reason is not None:
        return _skipped(backend, reason)

    if own_processes:
        job = replace(job, backend=_InChild(backend, timeout_s, processes))

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


#: An isolated backend whose planned share is declared to take less than this, seconds,
#: runs in the engine's process instead: a process of its own costs more to start than
#: such a share's work (an interpreter, NumPy, the backend's library and its model:
#: 0.7 s of CPU for yourdfpy's, against its 40 ms for 64 UR5 poses). A backend that
#: declares no cost (``pose_cost_us``) always runs in processes of its own.
IN_PROCESS_MAX_S = 0.5

#: An isolated backend that reads a description longer than this, characters, runs in
#: processes of its own whatever its share: the declared cost counts poses only, and a
#: reader's load can grow faster than its description (yourdfpy's: 0.7 s for 1,000
#: links with a box visual each, 3 s for 2,000, minutes at fkcheck's URDF limits), while
#: a thread left running at the time limit cannot be stopped — it would go on taking a
#: core and the GIL from the caller of ``fkcheck.check()`` long after the check ended.
#: The largest bundled URDF, Baxter's arm, has 48,391.
IN_PROCESS_MAX_DESCRIPTION_CHARS = 64_000


def in_own_processes(backend: Backend, plan: BackendPlan, description_chars: int = 0) -> bool:
    """Whether the engine runs ``backend``'s share of a check in processes of its own.

    An isolated backend does, unless its declared cost puts the ``plan``'s share
    under :data:`IN_PROCESS_MAX_S` and the longest description it reads,
    ``description_chars`` long, is at most :data:`IN_PROCESS_MAX_DESCRIPTION_CHARS`;
    no other backend does.
    """
    if not backend.isolated:
        return False
    if plan.full_s is None or plan.total == 0:
        return True
    if description_chars > IN_PROCESS_MAX_DESCRIPTION_CHARS:
        return True
    return plan.full_s * plan.compared / plan.total >= IN_PROCESS_MAX_S


def _description_chars(model: Model, backend: Backend) -> int:
    """The length of the longest description of ``model`` that ``backend`` reads (0: none).

    The descriptions were read while the check was prepared (this is the cache's
    answer); one that cannot be read counts 0: the backend's own run reports it.
    """
    chars = 0
    for fmt in model_formats(model):
        if reads_format(backend, fmt.name):
            with contextlib.suppress(Exception):
                chars = max(chars, len(load_description(model, language=fmt.language).text))
    return chars


def _split(n: int, processes: int | None = None) -> list[tuple[int, int]]:
    """Contiguous ``[start, stop)`` parts of ``n`` configurations, one per process.

    At most ``processes`` parts (``None``: one per usable core).
    """
    worth = n // SPLIT_MIN_CONFIGS  # parts worth a process each
    parts = min(processes or usable_cores(), worth) if worth > 1 else 1
    bounds = [n * k // parts for k in range(parts + 1)]
    return list(itertools.pairwise(bounds))


class _InChild:
    """An isolated backend (``isolated = True``) as the engine sees it.

    Only the backend's poses (and its own Jacobians) are computed in processes of its
    own (:func:`~fkcheck.process.isolation.run_isolated`); the reference and the
    comparison stay in this process, like every other backend's. A slow pure-Python
    backend that holds the GIL then uses the other cores: its configurations are
    split over up to one process per core, or the options' ``processes``
    (:data:`SPLIT_MIN_CONFIGS` each at least),
    run at once and joined in order. A crash of a process (e.g. a segfault in a C
    extension) or an answer larger than :func:`~fkcheck.process.isolation.answer_limit`
    is the backend's error, and at the time limit every process it started is killed
    with all they started.
    """

    def __init__(self, backend: Backend, timeout_s: float, processes: int | None = None) -> None:
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
        self.processes = processes
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

    def _parts(self, q: Float) -> list[Float]:
        return [q[start:stop] for start, stop in _split(q.shape[0], self.processes)]

    def _run(self, calls: list[tuple[functools.partial[Any], int]], axis: int) -> Any:
        """Each ``(call, configurations)`` in a process of its own, at once, joined on ``axis``."""
        if len(calls) == 1:
            answers: list[tuple[str, Any] | BaseException] = [self._answer(*calls[0], 1)]
        else:
            owner = threading.current_thread()
            boxes: list[list[tuple[str, Any] | BaseException]] = [[] for _ in calls]

            def part(k: int) -> None:
                try:
                    with acting_for(owner):  # abandoning the backend stops every part
                        boxes[k].append(self._answer(*calls[k], len(calls)))
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

    def _answer(self, call: functools.partial[Any], n: int, parts: int) -> tuple[str, Any]:
        """One process's ``(kind, value)`` over ``n`` configurations (see :func:`_in_child`).

        One of ``parts`` processes at once: its thread pools are sized to its share of
        the cores (:func:`fkcheck.process.threads.child_environment`).
        """
        remaining = max(0.0, self.deadline - time.monotonic())
        try:
            answer: tuple[str, Any] = run_isolated(
                functools.partial(_in_child, call),
                remaining,
                answer_limit(n),
                env=child_environment(parts),
            )
        except IsolatedTimeout:
            raise NoAnswerError(f"timed out after {self.timeout_s:g} s") from None
        except IsolatedDied as exc:
            raise NoAnswerError(str(exc)) from None
        return answer


def _import_libraries(model: Model, backends: Sequence[Backend]) -> None:
    """Import what ``backends`` (those run here) import lazily, once, before their threads start.

    Two threads importing one heavy library for the first time at the same time
    can end in ``_DeadlockError`` (seen with ``roboticstoolbox.ets``); importing
    here, in one thread, makes the later imports dictionary look-ups. A library
    that fails to import is left to its backend, which reports it.
    """
    for backend in backends:
        if not backend.imports:  # nothing to import here
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


def _placed_reason(placed: Mapping[str, LinkFit]) -> str:
    """Why a backend that does not read the URDF skips a check of a placed ``urdf:LINK``."""
    name, fit = next(iter(placed.items()))
    return (
        f"{name} is declared by no frame: its offset from DH frame {fit.anchor} was taken "
        f"from the URDF (xyz {list(fit.offset.xyz)} m, rpy {list(fit.offset.rpy)} rad), so only "
        "URDF backends compare it; declare it in [frames.NAME] to check it with every backend"
    )


#: How long the main thread waits on a backend's thread at a time, s (see run_backends).
_JOIN_SLICE_S = 0.1


def run_check(
    model: Model,
    backends: Sequence[Backend],
    *,
    lint_ignore: Sequence[str] = (),
    explain_jacobian: Explain | None = None,
    on_done: Callable[[BackendResult], None] | None = None,
    on_progress: Progress | None = None,
    on_plan: Callable[[Plan], None] | None = None,
    **options: Unpack[OptionArgs],
) -> CheckResult:
    """Check ``backends`` against the in-house core: :func:`run_request` of one request.

    Args:
        model: The model.
        backends: Backends to compare (see :mod:`fkcheck.backends.registry`).
        lint_ignore: Lint rules left out of the check's ``lint``.
        explain_jacobian: Names each Jacobian disagreement.
        on_done: Called with each backend's result as it finishes.
        on_progress: Called as ``(backend name, configurations done, total)``.
        on_plan: Called with the plan once it is made, before any backend starts.
        **options: The check's options by name (``samples=…``, ``seed=…``,
            ``jacobian=True``…; :class:`~fkcheck.model.options.CheckOptions`).

    Returns:
        The check result.

    Raises:
        OptionError: An option out of its range (a ``ToleranceError`` for a tolerance).
        FkcheckError: Bad input, as :func:`run_request` says.
    """
    request = CheckRequest(
        model, tuple(backends), resolve_options(options), tuple(lint_ignore), explain_jacobian
    )
    return run_request(request, on_done=on_done, on_progress=on_progress, on_plan=on_plan)


def run_request(
    request: CheckRequest | PreparedCheck,
    *,
    on_done: Callable[[BackendResult], None] | None = None,
    on_progress: Progress | None = None,
    on_plan: Callable[[Plan], None] | None = None,
) -> CheckResult:
    """A check's three stages: *prepare* (unless done), *run* and *judge*.

    Backends run concurrently (one thread each), each within the options'
    ``timeout_s``. When a backend holds poses only at fixed configurations
    (measured poses), the check runs on those instead of sampling.

    Args:
        request: The request, or the request already prepared
            (:func:`~fkcheck.engine.prepare.prepare`: the command line reads its
            inputs before printing its header).
        on_done: Called with each backend's result as it finishes.
        on_progress: Called as ``(backend name, configurations done, total)`` after
            each chunk a backend finishes (from that backend's thread).
        on_plan: Called with the plan, before the core's kernels load and any backend starts.

    Returns:
        The check result.

    Raises:
        FrameError: An unknown frame name.
        UrdfError: The model's URDF is missing, unsafe or does not fit the model.
        TimeLimitError: The per-number evidence did not finish within ``timeout_s``
            (or :data:`~fkcheck.engine.prepare.EVIDENCE_MIN_S`, when longer).
        FkcheckError: Other bad input reported by a backend.
    """
    prepared = request if isinstance(request, PreparedCheck) else prepare(request)
    if on_plan is not None:
        on_plan(prepared.plan)
    load_kernels(prepared.jacobian is not None, prepared.plan.total)
    return judge(prepared, run_backends(prepared, on_done=on_done, on_progress=on_progress))


def run_backends(
    prepared: PreparedCheck,
    *,
    on_done: Callable[[BackendResult], None] | None = None,
    on_progress: Progress | None = None,
) -> list[BackendResult]:
    """Run each backend in its own thread, within its time limit: one result each, in order.

    Raises:
        FkcheckError: Bad input a backend reported (the first one).
    """
    backends, model = prepared.request.backends, prepared.model
    results: dict[int, BackendResult] = {}
    errors: list[FkcheckError] = []
    lock = threading.Lock()

    own = [
        in_own_processes(b, p, _description_chars(model, b) if b.isolated else 0)
        for b, p in zip(backends, prepared.plan.backends, strict=True)
    ]

    def run_and_collect(index: int, backend: Backend) -> None:
        outcome = _one_backend(prepared, index, backend, on_progress, own_processes=own[index])
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
    for worker, in_child in zip(workers, own, strict=True):
        if in_child:
            worker.start()
    _import_libraries(model, [b for b, in_child in zip(backends, own, strict=True) if not in_child])
    for worker, in_child in zip(workers, own, strict=True):
        if not in_child:
            worker.start()
    for worker in workers:
        # In slices: a signal that lands on a backend's thread (SIGTERM, Ctrl-C) runs its
        # Python handler only when the main thread runs again — an unbounded join()
        # would hold it until the slowest backend ended.
        while worker.is_alive():
            worker.join(_JOIN_SLICE_S)
    if errors:
        raise errors[0]
    return [results[i] for i in range(len(backends))]


def _one_backend(
    prepared: PreparedCheck,
    index: int,
    backend: Backend,
    on_progress: Progress | None,
    *,
    own_processes: bool,
) -> BackendResult | FkcheckError:
    """One backend's result on its share of the plan (or bad input to re-raise)."""
    urdf = model_format(prepared.model, "urdf")  # placed urdf:LINK frames are its readers' alone
    if prepared.placed and not (urdf is not None and reads_format(backend, urdf.name)):
        return _skipped(backend, _placed_reason(prepared.placed))
    share = prepared.plan.backends[index]
    request = prepared.request
    job = Job(backend, prepared.model, prepared.samples.q[: share.compared], prepared.pair,
              prepared.tol, prepared.jacobian, request.explain_jacobian)  # fmt: skip
    options = request.options
    outcome = _run_one(
        job, options.timeout_s, on_progress, options.processes, own_processes=own_processes
    )
    if share.subset and isinstance(outcome, BackendResult):
        outcome = replace(outcome, subset=(share.compared, share.total))
    return outcome
