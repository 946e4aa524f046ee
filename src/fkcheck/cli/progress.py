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
  :data:`PLAIN_INTERVAL_S`), one line per backend still running, with its rate
  and estimated time left, e.g. ``fkcheck: pinocchio-urdf 120000/200181
  configurations, 9.1 s, 13,200/s, ETA 6 s`` (and ``beyond its 120 s limit``
  when the estimate says it cannot finish in time);
* ``quiet``: nothing.

Before that, :func:`kernels_phase` loads the core's numba kernels as a phase of
its own: a machine's first run compiles them (8–30 s), which a line says at once
(numba's cache holds no index for them; any load longer than
:data:`ANNOUNCE_AFTER_S` is said too), so a log is never silent and no backend's
time includes it.

The callback is called from the backends' threads: every update takes a lock.
"""

from __future__ import annotations

import contextlib
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

__all__ = [
    "ANNOUNCE_AFTER_S",
    "PLAIN_INTERVAL_S",
    "check_progress",
    "kernels_phase",
    "plain_line",
]

#: Seconds between two plain progress lines of one backend when stderr is no terminal.
PLAIN_INTERVAL_S = 10.0
#: Loading the core's kernels longer than this (seconds) is announced: they are compiling.
ANNOUNCE_AFTER_S = 2.0
_COMPILING = "fkcheck: compiling the core's kernels (first run only: 8–30 s)…"
_LOADING = "fkcheck: loading the core's kernels…"


@dataclass
class _State:
    """One backend's progress so far (guarded by the display's lock).

    ``first_done`` and ``first_at`` are its first report (after its first chunk):
    its rate is measured from there, past its start-up (imports, the first load).
    """

    done: int = 0
    total: int = 0
    first_done: int = 0
    first_at: float = 0.0
    last_at: float = 0.0


def _rate(state: _State, start: float) -> float | None:
    """Configurations a second: since its first report, else since the check began."""
    if state.done > state.first_done and state.last_at > state.first_at:
        return (state.done - state.first_done) / (state.last_at - state.first_at)
    if state.last_at > start and state.done:
        return state.done / (state.last_at - start)
    return None


def _clock(seconds: float) -> str:
    """``6 s``, ``4:07``: a duration as a log line shows it."""
    if seconds < 60:
        return f"{seconds:.0f} s"
    minutes, secs = divmod(round(seconds), 60)
    return f"{minutes}:{secs:02d}"


def plain_line(
    name: str,
    done: int,
    total: int,
    elapsed_s: float,
    rate: float | None = None,
    limit_s: float | None = None,
) -> str:
    """``fkcheck: pinocchio-urdf 120000/200181 configurations, 9.1 s, 13,200/s, ETA 6 s``.

    With ``limit_s`` (the backend's time limit), an estimate that ends past it
    says so: ``…, ETA 4:07, beyond its 120 s limit``.
    """
    line = f"fkcheck: {terminal_text(name)} {done}/{total} configurations, {elapsed_s:.1f} s"
    if rate is None or rate <= 0:
        return line
    eta = (total - done) / rate
    line += f", {rate:,.0f}/s, ETA {_clock(eta)}"
    if limit_s is not None and elapsed_s + eta > limit_s:
        line += f", beyond its {limit_s:g} s limit"
    return line


def kernels_phase(
    *, jacobian: bool, configurations: int, stream: TextIO | None = None, quiet: bool = False
) -> None:
    """Load the core's numba kernels now, as a phase of its own, said when it is slow.

    When numba's cache does not hold them (a machine's first run), a line says
    at once that they compile; otherwise a line comes only if loading takes more
    than :data:`ANNOUNCE_AFTER_S` (a stale cache compiles too). Either is
    followed by one when they are ready. Nothing with ``quiet``. Done before the
    backends start, the compile is charged to no backend. A check of fewer than
    :data:`~fkcheck.core.dh.JIT_MIN_POSES` configurations loads no kernels.
    """
    from fkcheck.core.dh import JIT_MIN_POSES, kernels_cached
    from fkcheck.engine.runner import load_kernels

    if configurations < JIT_MIN_POSES:
        return
    out = sys.stderr if stream is None else stream
    finished = threading.Event()
    said: list[bool] = []
    cold = kernels_cached(jacobian=jacobian) is False

    def announce() -> None:
        if not finished.wait(0.0 if cold else ANNOUNCE_AFTER_S) and not quiet:
            with contextlib.suppress(OSError, ValueError):
                print(_COMPILING if cold else _LOADING, file=out, flush=True)
                said.append(True)

    start = time.monotonic()
    announcer = threading.Thread(target=announce, name="fkcheck-kernels", daemon=True)
    announcer.start()
    try:
        load_kernels(jacobian, configurations)
    finally:
        finished.set()
        announcer.join()
    if said:
        with contextlib.suppress(OSError, ValueError):
            print(f"fkcheck: kernels ready ({time.monotonic() - start:.1f} s)", file=out,
                  flush=True)  # fmt: skip


def _is_terminal(stream: TextIO) -> bool:
    try:
        return stream.isatty()
    except (AttributeError, ValueError):  # replaced or closed stream
        return False


@contextmanager
def _plain(
    names: Sequence[str], interval_s: float, stream: TextIO, limit_s: float | None
) -> Iterator[Progress]:
    """Every ``interval_s`` seconds, a line per backend that has started and not finished."""
    lock = threading.Lock()
    states = {name: _State() for name in names}
    stop = threading.Event()
    start = time.monotonic()

    def update(name: str, done: int, total: int) -> None:
        now = time.monotonic()
        with lock:
            state = states.setdefault(name, _State())
            if not state.first_at:
                state.first_done, state.first_at = done, now
            state.done, state.total, state.last_at = done, total, now

    def tick() -> None:
        while not stop.wait(interval_s):
            with lock:
                running = [
                    (n, s.done, s.total, _rate(s, start))
                    for n, s in states.items()
                    if 0 < s.done < s.total
                ]
            elapsed = time.monotonic() - start
            try:
                for name, done, total, rate in running:
                    line = plain_line(name, done, total, elapsed, rate, limit_s)
                    print(line, file=stream, flush=True)
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
    limit_s: float | None = None,
) -> Iterator[Progress | None]:
    """The ``on_progress`` callback for a check of ``names``, shown while the block runs.

    Args:
        names: The backends, in the order asked (a bar or line each).
        quiet: Show nothing; the callback is then ``None``.
        interval_s: Seconds between plain lines when ``stream`` is not a terminal.
        stream: Where to show it (default: ``sys.stderr``).
        limit_s: Each backend's time limit, seconds: a plain line whose estimate
            ends past it says so.

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
        with _plain(names, interval_s, out, limit_s) as update:
            yield update
