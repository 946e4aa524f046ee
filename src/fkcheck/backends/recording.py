"""Recordings read in chunks, so that memory does not grow with their length.

A recording (fkcheck's poses CSV, UR's RTDE recorder CSV; a ROS 2 bag) is read
as a sequence of :class:`PoseChunk` — the joint values, the recorded pose and,
where the recording has one, the time of each row — from an object that follows
the :class:`Recording` protocol: a provenance header (``method``, the frame
``pair``) and :meth:`Recording.chunks`. Any reader that yields chunks plugs in;
:func:`fkcheck.backends.measured.open_recording` picks the reader by the
recording's kind.

A :class:`RowKeeper` takes the chunks one at a time and keeps a bounded set of
rows for the check to run on. :class:`SampleKeeper` keeps a deterministic
sample: every ``k``-th row, ``k`` a power of two doubled whenever more than
:data:`KEEP_ROWS` rows would be kept (so between half of it and all of it); a
recording of at most :data:`KEEP_ROWS` rows is kept whole. The check's keeper,
:class:`fkcheck.engine.stream.StreamSummary`, also compares every row with the
in-house core as it passes and keeps the worst rows and the statistics: a backend
never computes the core's poses itself, so the keeper is handed to it
(:meth:`fkcheck.backends.measured.MeasuredPoses.keep_with`).
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol, runtime_checkable

import numpy as np
from numpy.typing import NDArray

from fkcheck.core.typing import Float
from fkcheck.errors import TimeLimitError

__all__ = [
    "CHUNK_CHARS",
    "CHUNK_ROWS",
    "KEEP_ROWS",
    "MAX_RECORDING_BYTES",
    "MAX_RECORDING_ROWS",
    "PoseChunk",
    "ReadClock",
    "Recording",
    "RowKeeper",
    "SampleKeeper",
]

#: Rows of a recording read, parsed and compared at a time.
CHUNK_ROWS = 16_384
#: Characters of text held for one chunk at most (a chunk ends early at this many):
#: with lines of up to 64 KiB, rows alone would not bound a chunk's memory.
CHUNK_CHARS = 8 << 20
#: Rows a recording may hold: 5.5 hours at 500 Hz. Reading and comparing costs about
#: 10 µs a row on a busy 2-core machine, so the limit bounds the time (about two
#: minutes); memory does not grow with the rows.
MAX_RECORDING_ROWS = 10_000_000
#: Bytes a recording file may hold: an RTDE recording of joints and TCP pose
#: (about 240 bytes a row, as UR's recorder writes it) of 10 million rows, with room.
MAX_RECORDING_BYTES = 4 << 30
#: Rows of a recording the check runs on at most (the deterministic sample, plus
#: the worst rows): a recording up to this long is checked row by row, whole.
KEEP_ROWS = 20_000


@dataclass(frozen=True, eq=False)
class PoseChunk:
    """Consecutive rows of a recording.

    Attributes:
        q: ``(m, n)`` joint values, radians / metres.
        poses: ``(m, 4, 4)`` the recorded ``from_T_to`` of each row.
        t: ``(m,)`` each row's time, seconds, or ``None`` when the recording has none
            read.
        lines: ``(m,)`` where each row is in the recording, for messages: its line
            number in a text file, else its 1-based row number.
    """

    q: Float
    poses: Float
    t: Float | None
    lines: NDArray[np.int64]


@runtime_checkable
class Recording(Protocol):
    """A recording of joint values and poses, read chunk by chunk.

    Attributes:
        method: How its rows were read, for the reports (which columns or topics).
        pair: The frame pair its poses are of, when it says (model frame names), else
            ``None`` (the model's ``[check]`` pair). Known once :meth:`chunks` has
            yielded its first chunk with rows (a text file may say it before its rows).
        where: ``"line"`` when :attr:`PoseChunk.lines` are line numbers, else ``"row"``.
    """

    method: str
    pair: tuple[str, str] | None
    where: str

    def chunks(self) -> Iterator[PoseChunk]:
        """The rows, in order, at most :data:`CHUNK_ROWS` at a time; read as they are asked for.

        A chunk may hold no rows: a reader yields one once it has read
        :data:`CHUNK_ROWS` lines (or :data:`CHUNK_CHARS` of text) of a text file
        that are no rows, or :data:`fkcheck.backends.bag.QUIET_MESSAGES` messages
        of a bag, since its last chunk (comments, blank lines, joint states alone,
        other frames), so that its caller can look at its time limit
        (:class:`ReadClock`) whatever precedes or separates the rows.

        Raises:
            FkcheckError: Bad input (with where it is), or more than
                :data:`MAX_RECORDING_ROWS` rows (refused before they are read).
        """
        ...


class ReadClock:
    """The time limit of one read of a recording, from its start (opening it) to its end.

    Looked at as each chunk arrives, the empty ones a reader yields while it finds
    no rows included (:meth:`Recording.chunks`), and once more at the end: a read
    ends within its limit plus the time of one chunk, whatever the recording holds
    before its first row.

    Attributes:
        path: The recording, for the message.
        limit_s: The limit, seconds; ``None``: none.
    """

    def __init__(self, path: Path, limit_s: float | None) -> None:
        """Start the clock now."""
        self.path = path
        self.limit_s = limit_s
        self._deadline = math.inf if limit_s is None else time.monotonic() + limit_s

    def check(self, rows: int) -> None:
        """Raise once the limit has passed; ``rows``: the rows read so far, for the message.

        Raises:
            TimeLimitError: The limit has passed.
        """
        if time.monotonic() > self._deadline:
            raise TimeLimitError(
                f"reading {self.path} did not finish within its time limit of "
                f"{self.limit_s:g} s ({rows:,} rows read); give it more with --timeout"
            )


@runtime_checkable
class RowKeeper(Protocol):
    """What keeps a bounded set of a recording's rows as its chunks pass (see the module)."""

    def add(self, chunk: PoseChunk) -> None:
        """Take one chunk's rows (chunks come in order)."""
        ...

    def kept(self) -> tuple[Float, Float, NDArray[np.int64]]:
        """The kept rows in the recording's order: ``(q (K, n), poses (K, 4, 4), lines (K,))``."""
        ...


class SampleKeeper:
    """Every ``stride``-th row, at most :data:`KEEP_ROWS` of them (see the module docstring).

    Attributes:
        rows: Rows seen.
        first_line: Line (or row) number of the first row; ``0`` before any.
        last_line: Line (or row) number of the last row.
        stride: The sample holds every ``stride``-th row (a power of two; ``1``: every row).
    """

    def __init__(self, dof: int) -> None:
        """Keep rows of ``dof`` joint values."""
        self.rows = 0
        self.first_line = 0
        self.last_line = 0
        self.stride = 1
        self._order = np.empty(0, dtype=np.int64)
        self._q = np.empty((0, dof))
        self._poses = np.empty((0, 4, 4))
        self._lines = np.empty(0, dtype=np.int64)

    def add(self, chunk: PoseChunk) -> None:
        """Count the chunk's rows and keep those of the sample."""
        m = chunk.q.shape[0]
        if not m:
            return
        if not self.rows:
            self.first_line = int(chunk.lines[0])
        first = self.rows
        self.rows += m
        self.last_line = int(chunk.lines[-1])
        index = first + np.arange(m, dtype=np.int64)
        take = np.flatnonzero(index % self.stride == 0)
        self._order = np.concatenate([self._order, index[take]])
        self._q = np.concatenate([self._q, chunk.q[take]])
        self._poses = np.concatenate([self._poses, chunk.poses[take]])
        self._lines = np.concatenate([self._lines, chunk.lines[take]])
        while self._order.size > KEEP_ROWS:  # thin to every other kept row
            self.stride *= 2
            every = np.flatnonzero(self._order % self.stride == 0)
            self._order = self._order[every]
            self._q = self._q[every]
            self._poses = self._poses[every]
            self._lines = self._lines[every]

    @property
    def whole(self) -> bool:
        """Whether every row was kept (the recording held at most :data:`KEEP_ROWS` rows)."""
        return self.stride == 1

    def sample(self) -> tuple[NDArray[np.int64], Float, Float, NDArray[np.int64]]:
        """The sample: ``(row indices, q, poses, lines)``."""
        return self._order, self._q, self._poses, self._lines

    def kept(self) -> tuple[Float, Float, NDArray[np.int64]]:
        """The sample's rows."""
        return self._q, self._poses, self._lines
