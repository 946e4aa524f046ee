"""Running a pickled Python job in a fresh interpreter under the supervisor.

:func:`run_isolated` runs ``job()`` with :func:`~fkcheck.process.supervise.run_supervised`
(time limit, bounded output, nothing left running): the parent starts
``python -P -c 'from fkcheck.process.isolation import main; main()'`` (this
fkcheck's directory first on ``sys.path``, the current directory not on it),
writes the pickled job and this process's ``sys.path`` on its stdin and reads
back one framed, pickled answer, of at most the size the caller allows. The
job's own prints go to stderr, so they can never be mistaken for the answer.
Unlike ``multiprocessing``'s spawn, the child never imports the caller's
``__main__``, so scripts that call :func:`fkcheck.engine.runner.run_check` need no
``if __name__ == "__main__":`` guard.

The errors :func:`run_isolated` raises (:class:`IsolatedTimeout`,
:class:`IsolatedDied`) and :func:`terminate_all` are
:mod:`fkcheck.process.supervise`'s, importable from here too.
"""

from __future__ import annotations

import contextlib
import os
import pickle
import struct
import sys
import traceback
from collections.abc import Mapping
from pathlib import Path
from typing import Any, NoReturn

from fkcheck.process.supervise import (
    IsolatedDied,
    IsolatedOutputLimit,
    IsolatedTimeout,
    SpawnError,
    ended,
    last_stderr_line,
    run_supervised,
    terminate_all,
)

__all__ = [
    "ANSWER_BASE_BYTES",
    "ANSWER_BYTES_PER_CONFIG",
    "IsolatedDied",
    "IsolatedTimeout",
    "answer_limit",
    "main",
    "run_isolated",
    "terminate_all",
]

#: Largest answer an isolated job may send, whatever the number of configurations.
ANSWER_BASE_BYTES = 16 * 1024 * 1024
#: ... plus this much per configuration (a result holds a few numbers for each).
ANSWER_BYTES_PER_CONFIG = 1024

_PACKAGE_ROOT = str(Path(__file__).resolve().parents[2])  # the directory holding fkcheck/
_ANSWER_MAGIC = b"fkcheck-answer\n"
_LENGTH = struct.Struct(">Q")


def answer_limit(n_configs: int) -> int:
    """Largest answer allowed for a job over ``n_configs`` configurations, bytes."""
    return ANSWER_BASE_BYTES + ANSWER_BYTES_PER_CONFIG * n_configs


def run_isolated(
    job: Any,
    timeout_s: float,
    max_answer_bytes: int = ANSWER_BASE_BYTES,
    *,
    env: Mapping[str, str] | None = None,
) -> Any:
    """Run ``job()`` in a fresh interpreter and return what it returns.

    ``job`` must pickle (e.g. a ``functools.partial`` of a module-level function).
    The child gets this process's ``sys.path`` before it unpickles the job, and
    the same current directory; its environment is this process's, or ``env``
    (``{}``: an empty one), given when it is executed.

    Raises:
        IsolatedTimeout: No answer within ``timeout_s``; the child is killed.
        IsolatedDied: The child exited without an answer, or its answer was
            larger than ``max_answer_bytes``; the message says which, with its
            exit code or signal and the last line of its stderr.
    """
    payload = pickle.dumps((list(sys.path), pickle.dumps(job)))
    # This very fkcheck first on sys.path, and not the current directory (-P): nothing
    # there is imported before main() takes this process's sys.path.
    boot = f"import sys; sys.path.insert(0, {_PACKAGE_ROOT!r}); "
    boot += "from fkcheck.process.isolation import main; main()"
    frame = len(_ANSWER_MAGIC) + _LENGTH.size
    try:
        done = run_supervised(
            [sys.executable, "-P", "-c", boot],
            payload,
            timeout_s,
            max_stdout_bytes=frame + max_answer_bytes,
            env=env,
        )
    except IsolatedOutputLimit:
        raise IsolatedDied(
            f"its answer was larger than {max_answer_bytes} bytes (its process was killed)"
        ) from None
    except SpawnError as exc:
        raise IsolatedDied(f"its process could not start: {exc.strerror}") from None
    out = done.stdout
    if out[: len(_ANSWER_MAGIC)] == _ANSWER_MAGIC and len(out) >= frame:
        (length,) = _LENGTH.unpack_from(out, len(_ANSWER_MAGIC))
        if len(out) == frame + length:
            return pickle.loads(memoryview(out)[frame:])
    what = "without an answer" if not out else "with a truncated or garbled answer"
    last = last_stderr_line(done.stderr_tail)
    raise IsolatedDied(
        f"its process {ended(done.returncode)} {what}" + (f": {last}" if last else "")
    )


def _exit_now(code: int) -> NoReturn:
    """Flush what the job printed, then end at once (no thread joins, no atexit)."""
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(Exception):
            stream.flush()
    os._exit(code)


def main() -> None:
    """Child side: read the job from stdin, run it, write the framed answer, exit."""
    answer_fd = os.dup(1)
    os.dup2(2, 1)  # what the job prints goes to stderr, never into the answer
    path, job_blob = pickle.loads(sys.stdin.buffer.read())
    devnull = os.open(os.devnull, os.O_RDONLY)
    os.dup2(devnull, 0)
    sys.path[:] = path
    try:
        blob = pickle.dumps(pickle.loads(job_blob)())
    except SystemExit as exc:  # the job called sys.exit(): end as Python would
        code = exc.code
        _exit_now(code if isinstance(code, int) else 0 if code is None else 1)
    except BaseException:
        traceback.print_exc()
        _exit_now(1)
    data = memoryview(_ANSWER_MAGIC + _LENGTH.pack(len(blob)) + blob)
    while data:
        data = data[os.write(answer_fd, data) :]
    # A non-daemon thread the job left, or an atexit hook, must not keep it alive.
    _exit_now(0)


if __name__ == "__main__":
    main()
