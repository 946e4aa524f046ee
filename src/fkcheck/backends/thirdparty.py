"""Third-party backends run in processes of their own, never in fkcheck's.

A backend an installed distribution registers (the ``fkcheck.backends`` entry-point
group, :mod:`fkcheck.backends.registry`) is code fkcheck did not write and cannot
vouch for. It may print a fake ``verdict: pass``, call ``os._exit(0)`` on a table
it does not like, loop holding the GIL, or crash in C. None of that may reach
fkcheck's own process, its output or its exit code, so every piece of its code —
importing its module, building it, asking whether it can run and which files it
reads, computing poses and Jacobians — runs in a child process under the
supervisor (:func:`~fkcheck.process.isolation.run_isolated`), within the check's
time limit (:attr:`~fkcheck.backends.registry.BackendOptions.timeout_s`, per call),
with its stdout sent to that child's stderr, of which only a tail is kept for an
error message.

In fkcheck's process the backend is an :class:`IsolatedBackend`: the members it
declared (read in its process when it is built, then held to the contract here
again) and methods that each build it afresh in a child and call it there. Each
call costs a process start (about half a second on a quiet machine); what a backend
answers about a model (:meth:`~IsolatedBackend.unavailable_reason` and
:meth:`~IsolatedBackend.inputs`) is asked once per model, in one process.

Its failures become what a built-in's would: a :class:`~fkcheck.errors.Skip`
(``BackendUnavailable``, ``FrameUnavailable``) skips it, bad input
(:class:`~fkcheck.errors.FkcheckError`) ends the check with exit 2, and anything else
— an exception, a process that ended without an answer (``os._exit(0)`` included),
the time limit — is its *error* (:class:`ThirdPartyError`), never a pass.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from fkcheck.backends.base import CONTRACT, FixedConfigurations, contract_problems
from fkcheck.backends.registry import (
    BackendContractError,
    BackendOptions,
    Registration,
    build_in_process,
    name_problems,
)
from fkcheck.core.typing import Float, JacobianReference
from fkcheck.errors import (
    BackendUnavailable,
    FkcheckError,
    FrameUnavailable,
    Skip,
    failure_text,
)
from fkcheck.model.types import Model
from fkcheck.process.isolation import (
    ANSWER_BASE_BYTES,
    IsolatedDied,
    IsolatedTimeout,
    answer_limit,
    run_isolated,
)

__all__ = ["IsolatedBackend", "ThirdPartyError", "class_members"]

#: The optional members read from a built backend besides :data:`~fkcheck.backends.base.CONTRACT`'s.
_OPTIONAL = ("pose_cost_us", "jacobian_cost_us", "formats")
#: The skips that travel back by name (a third party's own Skip subclass is a Skip).
_SKIPS: dict[str, type[Skip]] = {
    "BackendUnavailable": BackendUnavailable,
    "FrameUnavailable": FrameUnavailable,
}
#: What a child's answer may start with (see :func:`_outcome`).
_KINDS = ("ok", "skip", "bad-input", "error")
#: Longest message kept from a third party's process, characters.
_MESSAGE_CHARS = 1000


class ThirdPartyError(RuntimeError):
    """A third-party backend's failure: its exception, its process's end, its time limit.

    The check reports it as that backend's *error* (exit 1), its message as it is.
    """


def _short(text: str) -> str:
    return text if len(text) <= _MESSAGE_CHARS else text[:_MESSAGE_CHARS] + "…"


def _outcome(call: functools.partial[Any]) -> tuple[Any, ...]:
    """``call()`` as something that pickles: ``("ok", value)`` or why not.

    Exceptions with their own constructors do not round-trip through pickle, so
    a failure travels as ``("skip", kind, message)``, ``("bad-input", message)``
    or ``("error", message)``.
    """
    try:
        return ("ok", call())
    except Skip as exc:
        kind = next((k for k, t in _SKIPS.items() if isinstance(exc, t)), "BackendUnavailable")
        return ("skip", kind, _short(str(exc)))
    except FkcheckError as exc:
        return ("bad-input", _short(str(exc)))
    except Exception as exc:
        return ("error", _short(failure_text(exc)))


def _describe(registration: Registration, arg: str, options: BackendOptions) -> dict[str, Any]:
    """In the backend's process: build it, hold it to the contract, return what it declares."""
    backend = build_in_process(registration, arg, options)
    members = {m: getattr(backend, m) for m in CONTRACT}
    members |= {m: getattr(backend, m, None) for m in _OPTIONAL}
    members["fixed_configurations"] = isinstance(backend, FixedConfigurations)
    # Only plain values come back: a tuple subclass or a str subclass could run code here.
    return {k: _plain(v) for k, v in members.items()}


def _plain(value: Any) -> Any:
    """``value`` as builtin types only (what the contract allows: str, bool, float, tuples)."""
    if value is None or type(value) in (bool, str, int, float):
        return value
    if isinstance(value, str):
        return str(value)
    if isinstance(value, bool | int | float):
        return float(value)
    if isinstance(value, tuple):
        return tuple(_plain(v) for v in value)
    return repr(value)  # the contract check here refuses it


def _class_declares(registration: Registration) -> dict[str, Any]:
    """In a child: what a prefix's class declares (``reads``, ``evidence``, ``formats``…)."""
    cls = registration.factory()
    declares = ("reads", "evidence", "distributions", "formats")
    return {m: _plain(getattr(cls, m, None)) for m in declares}


def _call_method(
    registration: Registration,
    arg: str,
    options: BackendOptions,
    method: str,
    args: tuple[Any, ...],
) -> Any:
    """In the backend's process: build it and call one of its array methods (poses, Jacobians)."""
    backend = build_in_process(registration, arg, options)
    answer = getattr(backend, method)(*args)
    return None if answer is None else np.asarray(answer, dtype=np.float64)


def _probe_model(
    registration: Registration, arg: str, options: BackendOptions, model: Model
) -> tuple[str | None, tuple[Path, ...]]:
    """In the backend's process: whether it can run on ``model``, and the files it reads."""
    backend = build_in_process(registration, arg, options)
    reason = backend.unavailable_reason(model)
    if reason is not None:
        return str(reason), ()
    return None, tuple(Path(p) for p in backend.inputs(model))


def _run(
    what: str,
    job: functools.partial[Any],
    timeout_s: float,
    limit: int = ANSWER_BASE_BYTES,
) -> Any:
    """``job`` in the backend's own process; its value, or its failure raised here.

    Raises:
        Skip: It does not apply here.
        FkcheckError: Bad input it reported.
        ThirdPartyError: Anything else, its process's end and its time limit included.
    """
    try:
        answer = run_isolated(functools.partial(_outcome, job), timeout_s, limit)
    except IsolatedTimeout:
        raise ThirdPartyError(
            f"{what} timed out after {timeout_s:g} s (its process was killed)"
        ) from None
    except IsolatedDied as exc:
        raise ThirdPartyError(f"{what}: {exc}") from None
    if not isinstance(answer, tuple) or not answer or answer[0] not in _KINDS:
        raise ThirdPartyError(f"{what}: its process answered something fkcheck did not ask for")
    if answer[0] == "ok":
        return answer[1]
    if answer[0] == "skip":
        raise _SKIPS.get(str(answer[1]), BackendUnavailable)(str(answer[2]))
    if answer[0] == "bad-input":
        raise FkcheckError(str(answer[1]))
    raise ThirdPartyError(str(answer[1]))


@functools.cache
def class_members(registration: Registration) -> dict[str, Any]:
    """What a third-party prefix's class declares, read in a process of its own.

    Raises:
        BackendContractError: Its module cannot be imported, or the process failed.
    """
    job = functools.partial(_class_declares, registration)
    try:
        found: dict[str, Any] = _run("reading it", job, BackendOptions().timeout_s)
    except (FkcheckError, Skip, ThirdPartyError) as exc:
        raise BackendContractError(
            f"backend {registration.name} ({registration.origin}): {exc}"
        ) from None
    return found


class IsolatedBackend:
    """A third-party backend as fkcheck's process sees it: declarations, and calls to a child.

    Attributes:
        registration: Its registration (the entry point).
        arg: The argument of a prefixed backend (``""`` for a plain one).
        options: The options it is built with in each of its processes.
        timeout_s: Time limit of each call, seconds.

    Every member of the :class:`~fkcheck.backends.base.Backend` contract is the
    value the backend declared when it was built in its process. ``isolated`` is
    ``False``: it is its own isolation (the engine starts no process for it).
    """

    def __init__(
        self,
        registration: Registration,
        arg: str,
        options: BackendOptions,
        members: dict[str, Any],
    ) -> None:
        self.registration = registration
        self.arg = arg
        self.options = options
        self.timeout_s = options.timeout_s
        self.name: str = members["name"]
        self.method: str = members["method"]
        self.evidence = members["evidence"]
        self.reads = members["reads"]
        self.formats: tuple[str, ...] = tuple(members.get("formats") or ())
        self.distributions: tuple[str, ...] = members["distributions"]
        self.jacobian_method: str | None = members["jacobian_method"]
        self.jacobian_references: tuple[JacobianReference, ...] = members["jacobian_references"]
        self.isolated = False
        self.imports: tuple[str, ...] = ()  # imported in its own processes only
        self.pose_cost_us: float | None = members.get("pose_cost_us")
        self.jacobian_cost_us: float | None = members.get("jacobian_cost_us")
        self._probes: list[tuple[Model, tuple[str | None, tuple[Path, ...]] | Exception]] = []

    @classmethod
    def build(
        cls, registration: Registration, arg: str, options: BackendOptions
    ) -> IsolatedBackend:
        """Build the backend in a process of its own and keep what it declares.

        Raises:
            BackendContractError: It cannot be imported or built, breaks the
                contract, or its process ended or timed out instead.
        """
        job = functools.partial(_describe, registration, arg, options)
        who = f"backend {registration.name} ({registration.origin})"
        try:
            members = _run("building it", job, options.timeout_s)
        except FkcheckError as exc:
            raise BackendContractError(str(exc)) from None
        except (Skip, ThirdPartyError) as exc:
            raise BackendContractError(f"{who}: {exc}") from None
        if not isinstance(members, dict) or not set(CONTRACT) <= set(members):
            raise BackendContractError(f"{who}: building it gave no declarations")
        kind = _FixedIsolatedBackend if members.get("fixed_configurations") else cls
        backend = kind(registration, arg, options, members)
        problems = contract_problems(backend) or name_problems(registration, backend)
        if problems:  # held to it here too: its process could have answered anything
            raise BackendContractError(
                f"backend {registration.name} ({registration.origin}, {registration.target}) "
                f"breaks fkcheck's backend contract: {'; '.join(problems)}"
            )
        return backend

    def _call(self, method: str, args: tuple[Any, ...], limit: int = ANSWER_BASE_BYTES) -> Any:
        job = functools.partial(
            _call_method, self.registration, self.arg, self.options, method, args
        )
        return _run(f"{method}()", job, self.timeout_s, limit)

    def _probe(self, model: Model) -> tuple[str | None, tuple[Path, ...]]:
        """Whether it can run on ``model`` and the files it reads, asked once per model.

        Raises:
            Skip, FkcheckError, ThirdPartyError: What asking it gave (kept: asked again,
                the same is raised without a second process).
        """
        for seen, known in self._probes:
            if seen is model:
                if isinstance(known, Exception):
                    raise known
                return known
        job = functools.partial(_probe_model, self.registration, self.arg, self.options, model)
        try:
            reason, inputs = _run("asking it about the model", job, self.timeout_s)
            answer = (
                None if reason is None else str(reason),
                tuple(Path(p) for p in inputs),  # only paths: its process could answer anything
            )
        except (Skip, FkcheckError, ThirdPartyError) as exc:
            self._probes.append((model, exc))
            raise
        except (TypeError, ValueError):
            failed = ThirdPartyError("asking it about the model: it answered something else")
            self._probes.append((model, failed))
            raise failed from None
        self._probes.append((model, answer))
        return answer

    def unavailable_reason(self, model: Model) -> str | None:
        """Why it cannot check ``model`` here (asked in its process), or ``None``.

        Raises:
            Skip, FkcheckError, ThirdPartyError: Asking it failed (the check reports it).
        """
        return self._probe(model)[0]

    def inputs(self, model: Model) -> tuple[Path, ...]:
        """The files it reads for ``model`` (asked in its process); none when asking failed.

        Never raises: a failure is reported when the check asks whether it can run.
        """
        try:
            return self._probe(model)[1]
        except (Skip, FkcheckError, ThirdPartyError):
            return ()

    def frame_poses(self, model: Model, q: Float, frames: Sequence[str]) -> Float:
        """Its poses, ``(len(frames), N, 4, 4)``, computed in its process."""
        limit = answer_limit(int(np.shape(q)[0]) * max(1, len(frames)))
        poses: Float = self._call("frame_poses", (model, np.asarray(q), tuple(frames)), limit)
        return poses

    def frame_jacobian(
        self, model: Model, q: Float, frame: str, reference: JacobianReference
    ) -> Float | None:
        """Its own Jacobian, ``(N, 6, n)``, computed in its process; ``None``: none."""
        if self.jacobian_method is None:
            return None
        limit = answer_limit(int(np.shape(q)[0]) * max(1, model.dof))
        jacobian: Float | None = self._call(
            "frame_jacobian", (model, np.asarray(q), frame, reference), limit
        )
        return jacobian


class _FixedIsolatedBackend(IsolatedBackend):
    """An isolated backend that knows poses at its own configurations only (measured poses)."""

    def configurations(self, model: Model) -> Float:
        """Its configurations, ``(N, n)``, read in its process."""
        q: Float = self._call("configurations", (model,))
        return q
