"""Plugins that misbehave at the process level (test fixtures for issue 15).

Those that start processes write their pids, atomically, to the file named by
``$FKCHECK_TEST_PIDS`` (the plugin's process inherits fkcheck's environment).
"""

from __future__ import annotations

import ctypes
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
from ur5_closed_form import forward


def _note(*pids: int) -> None:
    target = Path(os.environ["FKCHECK_TEST_PIDS"])
    tmp = target.with_suffix(".tmp")
    tmp.write_text(" ".join(map(str, pids)))
    tmp.replace(target)  # readers never see a half-written file


def exit_zero(q: np.ndarray) -> np.ndarray:
    os._exit(0)


def sys_exit(q: np.ndarray) -> np.ndarray:
    sys.exit(0)


def kills_itself(q: np.ndarray) -> np.ndarray:
    print("about to die", file=sys.stderr)
    os.kill(os.getpid(), signal.SIGKILL)
    raise AssertionError("unreachable")


def prints(q: np.ndarray) -> np.ndarray:
    print("not a pose " * 100)
    sys.stdout.buffer.write(b"\x80garbage")
    return forward(q)


def long_error(q: np.ndarray) -> np.ndarray:
    raise ValueError("y" * 10_000_000)


def thread_left(q: np.ndarray) -> np.ndarray:
    threading.Thread(target=time.sleep, args=(600,), daemon=False).start()
    return forward(q)


def session_left(q: np.ndarray) -> np.ndarray:
    child = subprocess.Popen(["sleep", "600"], start_new_session=True)
    _note(os.getpid(), child.pid)
    return forward(q)


def holds_gil(q: np.ndarray) -> np.ndarray:
    _note(os.getpid())
    ctypes.PyDLL(None).sleep(600)  # a C call that keeps the GIL: no thread of it runs
    raise AssertionError("unreachable")


def sleeps(q: np.ndarray) -> np.ndarray:
    child = subprocess.Popen(["sleep", "600"], start_new_session=True)
    _note(os.getpid(), child.pid)
    time.sleep(600)
    raise AssertionError("unreachable")
