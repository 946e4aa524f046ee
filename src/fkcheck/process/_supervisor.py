"""Run one program and leave nothing of it behind (the supervisor process).

fkcheck runs every piece of code it does not trust — a ``cmd:`` program, a
Python plugin, an isolated backend — under this small supervisor, started as
``python -I -S _supervisor.py PARENT_PID STATUS_FD ENV -- PROGRAM ARGS…`` by
:func:`fkcheck.process.supervise.run_supervised` in a session of its own. It imports
nothing but the standard library, so it starts in a few tens of milliseconds.
``ENV`` is ``inherit`` (the program gets the supervisor's environment) or
``exact``: the program gets exactly the environment the supervisor was executed
with, read back from ``/proc/self/environ`` on Linux — Python adds ``LC_CTYPE``
to its own environment when executed without a locale (PEP 538), and an empty
environment must stay empty.

What it does:

1. On Linux it becomes a *child subreaper* (``prctl(PR_SET_CHILD_SUBREAPER)``):
   a process the program starts and orphans — even one that left the session
   with ``setsid`` — is re-parented to the supervisor instead of to init, so
   it can still be found (``/proc/*/stat``) and killed. It asks for SIGTERM
   when fkcheck dies (``PR_SET_PDEATHSIG``), so a killed fkcheck leaves nothing
   running either.
2. It sets the core-file size limit to 0 (a crashing program writes no
   ``core`` file into the current directory) and starts the program with the
   supervisor's stdin, stdout and stderr (the pipes to fkcheck), the program
   itself being killed if the supervisor dies.
3. It waits for the program to end. Then it SIGKILLs every descendant still
   running, waits until none is left (it has no child any more), and writes
   the program's end — ``exit N``, ``signal N`` — as one line to
   ``STATUS_FD``. When it cannot start the program it writes
   ``spawn-error ERRNO MESSAGE`` instead.
4. On SIGTERM (fkcheck's time limit, fkcheck exiting, or fkcheck's death) it
   kills everything the same way, writes ``stopped`` and exits.

Elsewhere than Linux there is no subreaper: after writing its status line it
kills its own process group (the program and whatever stayed in it, and the
supervisor itself).
"""

from __future__ import annotations

import contextlib
import ctypes
import errno
import os
import resource
import signal
import subprocess
import sys
import time
from typing import NoReturn

__all__ = ["SWEEP_LIMIT_S", "main"]

#: How long the sweep keeps killing descendants before giving up (processes in
#: uninterruptible sleep may take a moment to die), seconds.
SWEEP_LIMIT_S = 1.5

_PR_SET_PDEATHSIG = 1
_PR_SET_CHILD_SUBREAPER = 36
_LINUX = sys.platform.startswith("linux")


class _Stop(Exception):
    """SIGTERM arrived: stop the program and everything it started."""


def _on_signal(signum: int, frame: object) -> None:
    signal.signal(signal.SIGTERM, signal.SIG_IGN)  # one stop is enough
    raise _Stop


def _prctl(option: int, value: int) -> bool:
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        return int(libc.prctl(option, value, 0, 0, 0)) == 0
    except (OSError, AttributeError):
        return False


def _die_with_supervisor() -> None:
    """In the program, between fork and exec: SIGKILL when the supervisor dies."""
    _prctl(_PR_SET_PDEATHSIG, signal.SIGKILL)


def _descendants(root: int) -> list[int]:
    """Every process below ``root``, read from ``/proc/*/stat``."""
    children: dict[int, list[int]] = {}
    try:
        entries = os.listdir("/proc")
    except OSError:
        return []
    for name in entries:
        if not name.isdigit():
            continue
        try:
            with open(f"/proc/{name}/stat", "rb") as f:
                stat = f.read()
            ppid = int(stat.rsplit(b")", 1)[1].split()[1])
        except (OSError, IndexError, ValueError):
            continue  # gone meanwhile
        children.setdefault(ppid, []).append(int(name))
    found: list[int] = []
    todo = [root]
    while todo:
        for child in children.get(todo.pop(), ()):
            found.append(child)
            todo.append(child)
    return found


def _reap() -> bool:
    """Reap every ended child; ``False`` once the supervisor has no child left."""
    try:
        while os.waitpid(-1, os.WNOHANG)[0] != 0:
            pass
    except ChildProcessError:
        return False
    return True


def _sweep() -> None:
    """SIGKILL every descendant, and again, until no child is left to reap."""
    give_up = time.monotonic() + SWEEP_LIMIT_S
    while _reap() and time.monotonic() < give_up:
        for pid in _descendants(os.getpid()):
            with contextlib.suppress(OSError):
                os.kill(pid, signal.SIGKILL)
        time.sleep(0.002)


def _finish(status_fd: int, line: str) -> NoReturn:
    """Kill what is left, report ``line`` and exit."""
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    if _LINUX:
        _sweep()
    with contextlib.suppress(OSError):
        os.write(status_fd, line.encode() + b"\n")
    if not _LINUX:
        os.killpg(0, signal.SIGKILL)  # no subreaper here: the group is what we can reach
    os._exit(0)


def _environment(mode: str) -> dict[str, str] | None:
    """The program's environment: ``None`` (inherit), or with ``exact`` the one executed with."""
    if mode != "exact":
        return None
    try:
        with open("/proc/self/environ", "rb") as f:
            raw = f.read()
    except OSError:  # not Linux: what Python left of it
        return dict(os.environ)
    items = (entry.partition(b"=") for entry in raw.split(b"\0") if b"=" in entry)
    return {os.fsdecode(key): os.fsdecode(value) for key, _, value in items}


def main(argv: list[str]) -> None:
    """Supervise ``argv[4:]`` (after ``PARENT_PID STATUS_FD ENV --``)."""
    signal.signal(signal.SIGTERM, _on_signal)
    parent, status_fd = int(argv[0]), int(argv[1])
    env = _environment(argv[2])
    program = argv[4:]
    worker = 0
    try:
        if _LINUX:
            _prctl(_PR_SET_CHILD_SUBREAPER, 1)
            _prctl(_PR_SET_PDEATHSIG, signal.SIGTERM)
        if os.getppid() != parent:  # fkcheck died before the line above
            raise _Stop
        resource.setrlimit(resource.RLIMIT_CORE, (0, resource.getrlimit(resource.RLIMIT_CORE)[1]))
        try:
            proc = subprocess.Popen(
                program, env=env, preexec_fn=_die_with_supervisor if _LINUX else None
            )
        except OSError as exc:
            code = exc.errno or errno.EIO
            _finish(status_fd, f"spawn-error {code} {exc.strerror or exc}")
        worker = proc.pid
        devnull = os.open(os.devnull, os.O_RDWR)
        for fd in (0, 1, 2):  # the pipes now belong to the program alone
            os.dup2(devnull, fd)
        while True:
            pid, status = os.waitpid(-1, 0)
            if pid == worker:
                break
        if os.WIFSIGNALED(status):
            _finish(status_fd, f"signal {os.WTERMSIG(status)}")
        _finish(status_fd, f"exit {os.waitstatus_to_exitcode(status)}")
    except _Stop:
        if worker:
            with contextlib.suppress(OSError):
                os.kill(worker, signal.SIGKILL)
        _finish(status_fd, "stopped")


if __name__ == "__main__":
    main(sys.argv[1:])
