"""Progress of a running check, on stderr: a live display on a terminal, plain lines in a log.

:func:`check_progress` gives the ``on_progress`` callback
(:data:`fkcheck.engine.runner.Progress`: ``(backend, configurations done,
total)``) that ``fkcheck check`` passes to the run, and shows it:

* stderr is a terminal: a rich display, one bar per backend with the
  configurations done of the total (updated after each chunk of
  configurations), the rate since the check began, the time elapsed and the
  estimated time left; it starts
  before the backends do (each bar waits until its backend reports) and is
  cleared when the check ends, leaving the result table;
* stderr is not a terminal (a CI log): every ``interval_s`` seconds (default
  :data:`PLAIN_INTERVAL_S`), one line per backend still running, e.g.
  ``fkcheck: pinocchio-urdf 120000/200181 configurations, 9.1 s``;
* ``quiet``: nothing.

The callback is called from the backends' threads: every update takes a lock.
"""

from __future__ import annotations

import sys
import threading
import time
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from typing import TYPE_CHECKING, TextIO

from fkcheck.io.text import terminal_markup, terminal_text

if TYPE_CHECKING:
    from fkcheck.engine.runner import Progress

__all__ = ["PLAIN_INTERVAL_S", "check_progress", "plain_line"]

#: Seconds between two plain progress lines of one backend when stderr is no terminal.
PLAIN_INTERVAL_S = 10.0


@dataclass
class _State:
    """One backend's progress so far (guarded by the display's lock)."""

    done: int = 0
    total: int = 0


def plain_line(name: str, done: int, total: int, elapsed_s: float) -> str:
    """``fkcheck: pinocchio-urdf 120000/200181 configurations, 9.1 s``."""
    return f"fkcheck: {terminal_text(name)} {done}/{total} configurations, {elapsed_s:.1f} s"


def _is_terminal(stream: TextIO) -> bool:
    try:
        return stream.isatty()
    except (AttributeError, ValueError):  # replaced or closed stream
        return False


@contextmanager
def _plain(names: Sequence[str], interval_s: float, stream: TextIO) -> Iterator[Progress]:
    """Every ``interval_s`` seconds, a line per backend that has started and not finished."""
    lock = threading.Lock()
    states = {name: _State() for name in names}
    stop = threading.Event()
    start = time.monotonic()

    def update(name: str, done: int, total: int) -> None:
        with lock:
            state = states.setdefault(name, _State())
            state.done, state.total = done, total

    def tick() -> None:
        while not stop.wait(interval_s):
            with lock:
                running = [(n, s.done, s.total) for n, s in states.items() if 0 < s.done < s.total]
            elapsed = time.monotonic() - start
            try:
                for name, done, total in running:
                    print(plain_line(name, done, total, elapsed), file=stream, flush=True)
            except (OSError, ValueError):  # a closed log ends the lines, not the check
                return

    ticker = threading.Thread(target=tick, name="fkcheck-progress", daemon=True)
    ticker.start()
    try:
        yield update
    finally:
        stop.set()
        ticker.join()


@contextmanager
def _live(names: Sequence[str]) -> Iterator[Progress]:
    """A rich display on stderr: a bar per backend (done/total, rate, time left)."""
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TaskID,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    from fkcheck.cli._console import console

    display = Progress(
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TextColumn("configurations"),
        TextColumn("{task.fields[rate]}"),
        TimeElapsedColumn(),
        TextColumn("ETA"),
        TimeRemainingColumn(),
        console=console(stderr=True),
        transient=True,
    )
    lock = threading.Lock()
    tasks: dict[str, TaskID] = {}
    start = time.monotonic()

    def task(name: str) -> TaskID:
        if name not in tasks:
            tasks[name] = display.add_task(terminal_markup(name), total=None, rate="")
        return tasks[name]

    for name in names:
        task(name)

    def update(name: str, done: int, total: int) -> None:
        elapsed = time.monotonic() - start
        with lock:
            rate = f"{done / elapsed:,.0f}/s" if elapsed > 0 else ""
            display.update(task(name), completed=done, total=total, rate=rate)

    with display:
        yield update


@contextmanager
def check_progress(
    names: Sequence[str],
    *,
    quiet: bool = False,
    interval_s: float = PLAIN_INTERVAL_S,
    stream: TextIO | None = None,
) -> Iterator[Progress | None]:
    """The ``on_progress`` callback for a check of ``names``, shown while the block runs.

    Args:
        names: The backends, in the order asked (a bar or line each).
        quiet: Show nothing; the callback is then ``None``.
        interval_s: Seconds between plain lines when ``stream`` is not a terminal.
        stream: Where to show it (default: ``sys.stderr``).

    Yields:
        The callback to pass to the check, or ``None`` when ``quiet``.
    """
    out = sys.stderr if stream is None else stream
    if quiet:
        yield None
    elif _is_terminal(out) and stream is None:
        with _live(names) as update:
            yield update
    else:
        with _plain(names, interval_s, out) as update:
            yield update
