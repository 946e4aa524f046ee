"""Test helpers that look at processes through /proc (Linux): alive, descendants, gone."""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import time
from pathlib import Path

import pytest

#: Skip marker for tests that read /proc to see which processes still run.
LINUX_ONLY = pytest.mark.skipif(
    sys.platform != "linux", reason="reads /proc to see which processes run"
)


def interruptible() -> None:
    """``preexec_fn`` giving the child SIGINT's default action.

    A shell without job control starts a background command (``nox … &``) with SIGINT
    ignored, and a Python child inherits that: it honours the ignore, as ``nohup`` users
    expect, so a test that sends SIGINT would wait in vain. The tests start their fkcheck
    as an interactive shell would.
    """
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def alive(pid: int) -> bool:
    """Whether a process exists and is not a zombie (PID 1 may not reap in containers)."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except (FileNotFoundError, ProcessLookupError):
        return False
    return stat.rsplit(")", 1)[1].split()[0] != "Z"


def descendants(root: int) -> list[int]:
    """Every living process below ``root``."""
    children: dict[int, list[int]] = {}
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
        except (FileNotFoundError, ProcessLookupError):
            continue
        if fields[0] != "Z":
            children.setdefault(int(fields[1]), []).append(int(entry.name))
    found: list[int] = []
    todo = [root]
    while todo:
        for child in children.get(todo.pop(), ()):
            found.append(child)
            todo.append(child)
    return found


def assert_gone(pids: list[int], within_s: float) -> None:
    """Every process in ``pids`` ends within ``within_s`` seconds (else: killed, and fail)."""
    deadline = time.monotonic() + within_s
    while any(alive(p) for p in pids) and time.monotonic() < deadline:
        time.sleep(0.02)
    left = [p for p in pids if alive(p)]
    for pid in left:  # a failing test still cleans up after itself
        with contextlib.suppress(OSError):
            os.kill(pid, signal.SIGKILL)
    assert not left, f"still running: {left} of {pids} (now killed)"


def wait_for_pids(path: Path, timeout_s: float = 30.0) -> list[int]:
    """The pids a test program writes (atomically) to ``path``, once it has."""
    deadline = time.monotonic() + timeout_s
    while not path.exists():
        assert time.monotonic() < deadline, f"{path} never appeared"
        time.sleep(0.02)
    return [int(p) for p in path.read_text().split()]
