"""Running a program fkcheck does not trust, in a process it can always kill.

Every ``cmd:`` program, every Python plugin and the pose computation of every
backend marked ``isolated = True`` runs in a child process, under a small supervisor
(:mod:`fkcheck.process._supervisor`), never in fkcheck's own process. Whatever that code
does — loops forever holding the GIL, calls ``os._exit(0)``, leaves a
non-daemon thread running, starts children that leave the session with
``setsid``, writes gigabytes — fkcheck keeps control:

* **Time.** A run that has not ended by its time limit is stopped: the
  supervisor SIGKILLs the program and every process it started (on Linux it is
  their *child subreaper*, so even those that left the process group are
  found). Every run therefore ends within its time limit plus
  :data:`TERMINATE_GRACE_S` (after which the supervisor's whole process group is
  SIGKILLed as a last resort); the supervisor's own sweep takes milliseconds.
* **Leftovers.** When the program ends, whatever it left running is killed too.
  When the check gives up on a backend at its time limit it stops the programs
  that backend started (:func:`terminate_all` with ``started_by``); those still
  running when the interpreter exits (e.g. fkcheck was stopped by SIGTERM or
  Ctrl-C) are stopped by an :mod:`atexit` hook; if fkcheck itself is killed,
  each supervisor gets SIGTERM from the kernel (``PR_SET_PDEATHSIG``) and
  cleans up the same way.
* **Output.** stdout is read up to a limit the caller gives (bytes, and for
  line protocols bytes per line and lines); past it the program is stopped.
  Of stderr only the last :data:`STDERR_TAIL_BYTES` are kept.

:func:`run_supervised` runs one program this way; :mod:`fkcheck.process.isolation`
builds on it to run a pickled Python job.

POSIX only (the supervisor relies on sessions, process groups and signals).
"""

from __future__ import annotations

import atexit
import contextlib
import os
import selectors
import signal
import subprocess
import sys
import threading
import time
import weakref
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import IO

__all__ = [
    "MAX_TIMEOUT_S",
    "STDERR_TAIL_BYTES",
    "TERMINATE_GRACE_S",
    "Finished",
    "IsolatedDied",
    "IsolatedOutputLimit",
    "IsolatedTimeout",
    "SpawnError",
    "acting_for",
    "ended",
    "last_stderr_line",
    "run_supervised",
    "terminate_all",
]

#: Longest time limit fkcheck takes, seconds (a day: longer than any CI job runs;
#: a far larger one overflows the thread and process waits). Every limit a user
#: gives is checked against it by :func:`fkcheck.model.options.option_problem`.
MAX_TIMEOUT_S = 86_400.0


#: After a stop is asked for (time limit, output limit, exit), how long the
#: supervisor has to kill everything before its process group is SIGKILLed, s.
TERMINATE_GRACE_S = 2.0
#: How much of a child's stderr is kept (its last bytes), for error messages.
STDERR_TAIL_BYTES = 64 * 1024

_SUPERVISOR = str(Path(__file__).with_name("_supervisor.py"))
_READ_CHUNK = 64 * 1024
_WRITE_CHUNK = 64 * 1024
#: Longest single wait in the select loop, s (a time limit of 1e10 s overflows select).
_MAX_WAIT_S = 3600.0
#: Longest stderr line quoted in a message, characters.
_QUOTE_CHARS = 300


class IsolatedTimeout(Exception):
    """The child did not end within the time limit (it has been killed, with its children)."""


class IsolatedDied(Exception):
    """The child ended without an answer (e.g. a segfault in a C extension, ``os._exit``)."""


class IsolatedOutputLimit(Exception):
    """The child printed more than allowed on stdout (it has been killed).

    Attributes:
        problem: What limit it passed, e.g. ``printed more than 4100 lines``.
    """

    def __init__(self, problem: str) -> None:
        self.problem = problem
        super().__init__(problem)


class SpawnError(OSError):
    """The program could not be started (``errno`` and ``strerror`` say why)."""


@dataclass(frozen=True)
class Finished:
    """A supervised program that ended by itself.

    Attributes:
        stdout: Everything it printed on stdout (within the limits asked for).
        stderr_tail: The last :data:`STDERR_TAIL_BYTES` of its stderr.
        returncode: Its exit status, or ``-N`` when signal ``N`` killed it.
    """

    stdout: bytes
    stderr_tail: bytes
    returncode: int


@dataclass(frozen=True)
class _Limits:
    max_bytes: int
    max_line_bytes: int | None
    max_lines: int | None


# ---------------------------------------------------------------- live supervisors

#: Running supervisors, with the thread that started each.
_live: dict[subprocess.Popen[bytes], int] = {}
_live_lock = threading.Lock()
#: Threads the check has given up on (:func:`terminate_all` with ``started_by``):
#: they may start no new program, so an abandoned backend's next batch never runs.
_abandoned: weakref.WeakSet[threading.Thread] = weakref.WeakSet()
#: Helper threads starting programs for another thread (:func:`acting_for`), by ident.
_helpers: dict[int, threading.Thread] = {}


@contextlib.contextmanager
def acting_for(owner: threading.Thread) -> Iterator[None]:
    """Programs this thread starts within the block count as ``owner``'s.

    For a backend's helper threads (its configurations split over several
    processes): :func:`terminate_all` with ``started_by=owner`` stops their
    programs too, and once ``owner`` is given up they may start no new one.
    """
    ident = threading.get_ident()
    with _live_lock:
        _helpers[ident] = owner
    try:
        yield
    finally:
        with _live_lock:
            _helpers.pop(ident, None)


def _starter() -> tuple[threading.Thread, int]:
    """The thread a program started now belongs to, and its ident (``_live_lock`` held)."""
    owner = _helpers.get(threading.get_ident())
    if owner is None or owner.ident is None:
        return threading.current_thread(), threading.get_ident()
    return owner, owner.ident


def _send(proc: subprocess.Popen[bytes], sig: int, *, group: bool = False) -> None:
    """Signal the supervisor (or its process group) unless it has been reaped."""
    # Until reaped (returncode set) its pid, also its group id, cannot be reused.
    if proc.returncode is not None:
        return
    with contextlib.suppress(ProcessLookupError, PermissionError):
        if group:
            os.killpg(proc.pid, sig)
        else:
            os.kill(proc.pid, sig)


def _reap(procs: list[subprocess.Popen[bytes]], deadline: float) -> None:
    """Wait for the supervisors until ``deadline``; SIGKILL the groups of the rest."""
    for proc in procs:
        try:
            proc.wait(max(deadline - time.monotonic(), 0.0))
        except subprocess.TimeoutExpired:
            _send(proc, signal.SIGKILL, group=True)
            proc.wait()


def terminate_all(started_by: threading.Thread | None = None) -> None:
    """Stop every supervised program still running (and all they started).

    Waits at most :data:`TERMINATE_GRACE_S` before SIGKILLing what is left.
    Called at interpreter exit, and by the check for a backend it gives up on;
    safe to call at any time.

    Args:
        started_by: Only the programs this thread started (default: all).
    """
    with _live_lock:
        if started_by is not None:
            _abandoned.add(started_by)
        procs = [p for p, t in _live.items() if started_by is None or t == started_by.ident]
    for proc in procs:
        _send(proc, signal.SIGTERM)
    _reap(procs, time.monotonic() + TERMINATE_GRACE_S)


def _at_exit() -> None:
    if threading.current_thread() is threading.main_thread():
        # A second SIGTERM or Ctrl-C must not interrupt the clean-up with a traceback.
        for sig in (signal.SIGTERM, signal.SIGINT):
            signal.signal(sig, signal.SIG_IGN)
    terminate_all()


atexit.register(_at_exit)


# ---------------------------------------------------------------- running a program


def run_supervised(
    argv: list[str],
    stdin: bytes,
    timeout_s: float,
    *,
    max_stdout_bytes: int,
    max_line_bytes: int | None = None,
    max_lines: int | None = None,
    env: Mapping[str, str] | None = None,
) -> Finished:
    """Run ``argv`` under the supervisor: feed ``stdin``, collect its output, bounded.

    Args:
        argv: The program and its arguments (run without a shell; a name without
            ``/`` is looked up on ``PATH``).
        stdin: Written to its stdin, which is then closed.
        timeout_s: Time limit for the whole run, seconds.
        max_stdout_bytes: It may print at most this many bytes on stdout.
        max_line_bytes: If given, no stdout line may be longer (newline excluded).
        max_lines: If given, stdout may hold at most this many lines.
        env: The environment the supervisor and the program are executed with,
            exactly (``{}``: none at all; default: this process's).

    Returns:
        What it printed and how it ended, once it (and all it started) ended.

    Raises:
        SpawnError: It could not be started (not found, not executable, …).
        IsolatedTimeout: It had not ended by ``timeout_s``; it and everything it
            started have been killed.
        IsolatedOutputLimit: It printed past a limit; it has been killed.
        IsolatedDied: Its supervisor was stopped or killed from outside (fkcheck
            exiting, or the program killing its own process group).
    """
    limits = _Limits(max_stdout_bytes, max_line_bytes, max_lines)
    deadline = time.monotonic() + timeout_s
    with _live_lock:
        if _starter()[0] in _abandoned:
            raise IsolatedTimeout("the check gave this backend up: no new program is started")
    status_r, status_w = os.pipe()
    try:
        proc = subprocess.Popen(
            [sys.executable, "-I", "-S", _SUPERVISOR, str(os.getpid()), str(status_w),
             "inherit" if env is None else "exact", "--", *argv],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            pass_fds=(status_w,),
            start_new_session=True,  # a group of its own, out of reach of the terminal
            env=None if env is None else dict(env),  # given at exec: /proc/PID/environ too
        )  # fmt: skip
    except BaseException:
        os.close(status_r)
        raise
    finally:
        os.close(status_w)
    with _live_lock:
        owner, owner_ident = _starter()
        given_up = owner in _abandoned
        if not given_up:
            _live[proc] = owner_ident
    if given_up:  # abandoned between the check above and now
        _send(proc, signal.SIGTERM)
        _reap([proc], time.monotonic() + TERMINATE_GRACE_S)
        os.close(status_r)
        for stream in (proc.stdin, proc.stdout, proc.stderr):
            if stream is not None:
                stream.close()
        raise IsolatedTimeout("the check gave this backend up: no new program is started")
    try:
        return _collect(proc, status_r, stdin, deadline, limits)
    finally:
        _send(proc, signal.SIGTERM)
        _reap([proc], time.monotonic() + TERMINATE_GRACE_S)
        with _live_lock:
            _live.pop(proc, None)
        os.close(status_r)
        for pipe in (proc.stdin, proc.stdout, proc.stderr):
            if pipe is not None:
                with contextlib.suppress(OSError):
                    pipe.close()


class _Reader:
    """stdout within limits, the tail of stderr, and the supervisor's status line."""

    def __init__(self, limits: _Limits) -> None:
        self.limits = limits
        self.stdout = bytearray()
        self.stderr = bytearray()
        self.status = bytearray()
        self.lines = 0
        self.line_bytes = 0

    def out(self, data: bytes) -> str | None:
        """Keep ``data``; a problem if a limit is now passed."""
        limits = self.limits
        if limits.max_line_bytes is not None or limits.max_lines is not None:
            *complete, last = data.split(b"\n")
            for piece in complete:
                if self._too_long(self.line_bytes + len(piece)):
                    return f"printed a line longer than {limits.max_line_bytes} bytes"
                self.lines += 1
                self.line_bytes = 0
            self.line_bytes += len(last)
            if self._too_long(self.line_bytes):
                return f"printed a line longer than {limits.max_line_bytes} bytes"
            if (
                limits.max_lines is not None
                and self.lines + (self.line_bytes > 0) > limits.max_lines
            ):
                return f"printed more than {limits.max_lines} lines"
        if len(self.stdout) + len(data) > limits.max_bytes:
            return f"printed more than {limits.max_bytes} bytes"
        self.stdout += data
        return None

    def _too_long(self, n: int) -> bool:
        return self.limits.max_line_bytes is not None and n > self.limits.max_line_bytes

    def err(self, data: bytes) -> None:
        self.stderr += data
        del self.stderr[:-STDERR_TAIL_BYTES]


def _feed(sel: selectors.BaseSelector, fd: int, pending: memoryview, feed: IO[bytes]) -> memoryview:
    """Write the next chunk of stdin; what is left to write.

    Once all is written (or the child stopped reading), ``feed`` is closed.
    """
    try:
        pending = pending[os.write(fd, pending[:_WRITE_CHUNK]) :]
    except BlockingIOError:
        return pending
    except OSError:  # it stopped reading (EPIPE): how it ends will say why
        pending = pending[:0]
    if not pending:
        sel.unregister(fd)
        feed.close()
    return pending


def _drain(
    sel: selectors.BaseSelector, key: selectors.SelectorKey, reader: _Reader, problem: str | None
) -> str | None:
    """Read what one of the three pipes has; the first output problem so far (or ``None``)."""
    data = os.read(key.fd, _READ_CHUNK)
    if not data:
        sel.unregister(key.fd)
    elif key.data == "out":
        if problem is None:
            problem = reader.out(data)
    elif key.data == "err":
        reader.err(data)
    elif len(reader.status) < 4096:
        reader.status += data
    return problem


def _collect(
    proc: subprocess.Popen[bytes], status_r: int, stdin: bytes, deadline: float, limits: _Limits
) -> Finished:
    """The select loop: feed stdin, read the three pipes, stop at a limit."""
    assert proc.stdin is not None
    assert proc.stdout is not None
    assert proc.stderr is not None
    feed = proc.stdin
    reader = _Reader(limits)
    problem: str | None = None
    timed_out = stopping = False
    pending = memoryview(stdin)
    with selectors.DefaultSelector() as sel:
        sel.register(proc.stdout.fileno(), selectors.EVENT_READ, "out")
        sel.register(proc.stderr.fileno(), selectors.EVENT_READ, "err")
        sel.register(status_r, selectors.EVENT_READ, "status")
        if pending:
            os.set_blocking(feed.fileno(), False)
            sel.register(feed.fileno(), selectors.EVENT_WRITE, "in")
        else:
            feed.close()
        while sel.get_map():
            remaining = deadline - time.monotonic()
            if remaining <= 0 or (problem is not None and not stopping):
                if stopping:
                    break  # the supervisor did not finish in its grace time
                timed_out = problem is None
                stopping = True
                deadline = time.monotonic() + TERMINATE_GRACE_S
                _send(proc, signal.SIGTERM)
                if not feed.closed:
                    sel.unregister(feed.fileno())
                    feed.close()
                continue
            for key, _ in sel.select(min(remaining, _MAX_WAIT_S)):
                if key.data == "in":
                    pending = _feed(sel, key.fd, pending, feed)
                else:
                    problem = _drain(sel, key, reader, problem)
    if timed_out:
        raise IsolatedTimeout
    if problem is not None:
        raise IsolatedOutputLimit(problem)
    return _finished(reader)


def _finished(reader: _Reader) -> Finished:
    """Read the supervisor's status line."""
    word, _, rest = bytes(reader.status).decode("utf-8", "replace").strip().partition(" ")
    if word == "exit":
        code = int(rest)
    elif word == "signal":
        code = -int(rest)
    elif word == "spawn-error":
        errno_text, _, message = rest.partition(" ")
        raise SpawnError(int(errno_text), message)
    elif word == "stopped":  # not by this run: fkcheck is exiting, or someone else
        raise IsolatedDied("its process was stopped: its supervisor got SIGTERM from outside")
    else:
        raise IsolatedDied("its process was killed together with its supervisor")
    return Finished(bytes(reader.stdout), bytes(reader.stderr), code)


def last_stderr_line(stderr: bytes) -> str:
    """The last non-blank line of ``stderr``, shortened to a readable length."""
    text = stderr.decode("utf-8", "replace")
    last = next((ln.strip() for ln in reversed(text.splitlines()) if ln.strip()), "")
    return last if len(last) <= _QUOTE_CHARS else last[:_QUOTE_CHARS] + "…"


def ended(returncode: int, noun: str = "code") -> str:
    """``exited with code N`` (or another ``noun``) or ``was killed by SIGNAME``."""
    if returncode >= 0:
        return f"exited with {noun} {returncode}"
    try:
        return f"was killed by {signal.Signals(-returncode).name}"
    except ValueError:
        return f"was killed by signal {-returncode}"
