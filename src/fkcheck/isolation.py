"""Running one backend in a Python process of its own.

The parent starts ``python -m fkcheck.isolation``, writes the pickled job on
its stdin and reads the pickled outcome from its stdout. Unlike
``multiprocessing``'s spawn, the child never imports the caller's ``__main__``,
so scripts that call :func:`fkcheck.check.run_check` need no
``if __name__ == "__main__":`` guard.
"""

from __future__ import annotations

import pickle
import subprocess
import sys
from typing import Any

__all__ = ["IsolatedDied", "IsolatedTimeout", "main", "run_isolated"]


class IsolatedTimeout(Exception):
    """The child did not answer within the time limit (it has been killed)."""


class IsolatedDied(Exception):
    """The child ended without an answer (e.g. a segfault in a C extension)."""


def run_isolated(job: Any, timeout_s: float) -> Any:
    """Run ``job()`` in a fresh interpreter and return what it returns.

    ``job`` must pickle (e.g. a ``functools.partial`` of a module-level function).
    The child gets this process's ``sys.path`` before it unpickles the job.

    Raises:
        IsolatedTimeout: No answer within ``timeout_s``; the child is killed.
        IsolatedDied: The child exited without an answer; the message has its exit
            code and the last line of its stderr.
    """
    payload = pickle.dumps((list(sys.path), pickle.dumps(job)))
    proc = subprocess.Popen(
        [sys.executable, "-m", "fkcheck.isolation"],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    try:
        out, err = proc.communicate(payload, timeout=timeout_s)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.communicate()
        raise IsolatedTimeout from None
    except BaseException:  # Ctrl-C, SIGTERM: do not leave the child behind
        proc.kill()
        proc.wait()
        raise
    if proc.returncode != 0 or not out:
        lines = err.decode("utf-8", "replace").strip().splitlines()
        tail = f": {lines[-1]}" if lines else ""
        raise IsolatedDied(f"its process died (exit code {proc.returncode}){tail}")
    return pickle.loads(out)


def main() -> None:
    """Child side: read the job from stdin, run it, write the result to stdout."""
    path, job_blob = pickle.loads(sys.stdin.buffer.read())
    sys.path[:] = path
    job = pickle.loads(job_blob)
    result = job()
    sys.stdout.buffer.write(pickle.dumps(result))
    sys.stdout.buffer.flush()


if __name__ == "__main__":
    main()
