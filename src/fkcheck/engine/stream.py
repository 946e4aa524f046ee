"""A long recording compared with the core as it streams: what the check keeps of every row.

:class:`StreamSummary` is the :class:`~fkcheck.backends.recording.RowKeeper` the
check hands to a measured-poses backend (:func:`stream_recordings`). As the
recording's chunks pass, every row is compared with the in-house core at once
(its ``from_T_to`` for the recording's pair: position and rotation error) and
forgotten; what is kept is bounded whatever the recording's length:

* **the sample** of :class:`~fkcheck.backends.recording.SampleKeeper` (every
  ``k``-th row, at most :data:`~fkcheck.backends.recording.KEEP_ROWS`);
* **the worst rows**: the :data:`~fkcheck.engine.evidence.WORST_CASES` largest
  position errors and as many largest rotation errors, with their joint values
  and recorded poses. Whatever the check's tolerances, its worst rows (by error
  relative to tolerance) are among these: a row among the ``k`` worst by
  ``max(pos / tol_pos, rot / tol_rot)`` is among the ``k`` worst by the error
  that decides its score;
* **the largest errors** and **histograms** of both, in bins :data:`HISTOGRAM_RATIO`
  apart, for the median and 95th percentile of a failure's spread (the bin's middle:
  within 0.05 % of the exact value).

* **the count of rows beyond the check's tolerances**, known before the recording
  is read (:class:`StreamKeeper` carries them), so that a failure's count is over
  every row without reading the recording again.

The check runs on the kept rows — the sample and the worst rows, in the
recording's order: every other backend, the coverage of the table's numbers, the
calibration's effect and the plots see those, and its verdict on the recording is
exact, as the worst rows are among them. The recording is read once, under the
read's clock (:attr:`StreamKeeper.read_limit_s`). There is no second pass: the
check's comparison of it (:mod:`fkcheck.engine.compare`) has the tolerances
and frame pair the summary counted against, both from the one prepared check
(``stream_recordings`` is handed the check's tolerances, and a recording
answers only for its own pair); a summary that does not match them is a broken
contract, that backend's error, never an unbounded read.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Protocol, runtime_checkable

import numpy as np
from numpy.typing import NDArray

from fkcheck.backends.base import Backend
from fkcheck.backends.recording import PoseChunk, SampleKeeper
from fkcheck.core.metrics import position_error_m, rotation_error_rad
from fkcheck.core.typing import Float
from fkcheck.engine.evidence import WORST_CASES
from fkcheck.model.frames import reference_poses, relative_pose
from fkcheck.model.types import Model

if TYPE_CHECKING:
    from fkcheck.backends.measured import KeeperFactory

__all__ = [
    "HISTOGRAM_RATIO",
    "READ_MIN_S",
    "StreamKeeper",
    "StreamSummary",
    "stream_recordings",
]

#: Neighbouring bins of the error histograms are this far apart (ratio).
HISTOGRAM_RATIO = 1.001
#: The histograms cover errors from this small (metres or radians; smaller ones
#: count in the first bin) ...
_HIST_LOW = 1e-16
#: ... to this large (larger ones, and infinite ones, count in the last).
_HIST_HIGH = 1e4
_BINS = math.ceil(math.log(_HIST_HIGH / _HIST_LOW) / math.log(HISTOGRAM_RATIO))
#: Reading a recording has the check's time limit, but never less than this, seconds:
#: a ``--timeout`` short enough for a hanging backend (0.5 s) must not end the read of
#: a recording of a few minutes (about 13 µs a row: 10 s is some 750,000 rows).
READ_MIN_S = 10.0


def _bin(values: Float) -> NDArray[np.intp]:
    with np.errstate(divide="ignore", invalid="ignore"):
        raw = np.floor(
            np.log(np.maximum(values, _HIST_LOW) / _HIST_LOW) / math.log(HISTOGRAM_RATIO)
        )
    raw = np.where(np.isfinite(raw), raw, _BINS - 1)
    out: NDArray[np.intp] = np.clip(raw, 0, _BINS - 1).astype(np.intp)
    return out


def _errors(model: Model, pair: tuple[str, str], chunk: PoseChunk) -> tuple[Float, Float]:
    """Position and rotation error of each row against the core; ``inf`` where not finite."""
    ref = reference_poses(model, chunk.q, pair)
    ours = relative_pose(ref[0], ref[1])
    with np.errstate(invalid="ignore", over="ignore"):
        pos = position_error_m(ours, chunk.poses)
        rot = rotation_error_rad(ours, chunk.poses)
    bad = ~(np.isfinite(pos) & np.isfinite(rot))
    return np.where(bad, np.inf, pos), np.where(bad, np.inf, rot)


class _Top:
    """The ``k`` rows with the largest values of one error, over chunks."""

    def __init__(self, k: int, n: int) -> None:
        self.k = k
        self.value = np.empty(0)
        self.order = np.empty(0, dtype=np.int64)  # the row's index in the recording
        self.q = np.empty((0, n))
        self.poses = np.empty((0, 4, 4))
        self.lines = np.empty(0, dtype=np.int64)

    def add(self, first: int, value: Float, chunk: PoseChunk) -> None:
        top = np.argsort(-value, kind="stable")[: self.k]
        merged = np.concatenate([self.value, value[top]])
        order = np.concatenate([self.order, first + top])
        keep = np.lexsort((order, -merged))[: self.k]
        self.value = merged[keep]
        self.order = order[keep]
        self.q = np.concatenate([self.q, chunk.q[top]])[keep]
        self.poses = np.concatenate([self.poses, chunk.poses[top]])[keep]
        self.lines = np.concatenate([self.lines, chunk.lines[top]])[keep]


class StreamSummary(SampleKeeper):
    """The sample, and every row compared with the core: worst rows, maxima, histograms.

    Attributes:
        model: The model compared with.
        pair: The frame pair of the recording's poses.
        tol: ``(position m, rotation rad)``: the tolerances :attr:`beyond` counts against.
        beyond: Rows whose position error exceeds ``tol[0]`` or whose rotation error
            exceeds ``tol[1]`` (a row that is not finite counts), over every row.
        max_position_m: Largest position error over every row (``inf``: a row whose
            reference or pose is not finite).
        max_rotation_rad: Largest rotation error over every row.
    """

    def __init__(
        self,
        model: Model,
        pair: tuple[str, str],
        tol: tuple[float, float],
    ) -> None:
        """Compare rows of ``pair``'s poses with ``model``'s core; count those beyond ``tol``."""
        super().__init__(model.dof)
        self.model = model
        self.pair = pair
        self.tol = tol
        self.beyond = 0
        self.max_position_m = 0.0
        self.max_rotation_rad = 0.0
        self._hist = {
            "position": np.zeros(_BINS, dtype=np.int64),
            "rotation": np.zeros(_BINS, dtype=np.int64),
        }
        self._top_pos = _Top(WORST_CASES, model.dof)
        self._top_rot = _Top(WORST_CASES, model.dof)

    def add(self, chunk: PoseChunk) -> None:
        """Compare one chunk's rows with the core; keep the sample, the worst, the statistics."""
        if not chunk.q.shape[0]:
            return
        first = self.rows
        pos, rot = _errors(self.model, self.pair, chunk)
        self.beyond += _count_beyond(pos, rot, self.tol)
        self.max_position_m = max(self.max_position_m, float(pos.max()))
        self.max_rotation_rad = max(self.max_rotation_rad, float(rot.max()))
        self._hist["position"] += np.bincount(_bin(pos), minlength=_BINS)
        self._hist["rotation"] += np.bincount(_bin(rot), minlength=_BINS)
        self._top_pos.add(first, pos, chunk)
        self._top_rot.add(first, rot, chunk)
        super().add(chunk)

    def kept(self) -> tuple[Float, Float, NDArray[np.int64]]:
        """The sample and the worst rows, in the recording's order, each row once."""
        order, q, poses, lines = self.sample()
        tops = (self._top_pos, self._top_rot)
        all_order = np.concatenate([order, *(t.order for t in tops)])
        _, first = np.unique(all_order, return_index=True)  # sorted by row, each once
        return (
            np.concatenate([q, *(t.q for t in tops)])[first],
            np.concatenate([poses, *(t.poses for t in tops)])[first],
            np.concatenate([lines, *(t.lines for t in tops)])[first],
        )

    def worst_added(self) -> int:
        """How many worst rows the sample did not hold (kept besides it)."""
        extra = np.union1d(self._top_pos.order, self._top_rot.order)
        return int(np.setdiff1d(extra, self.sample()[0]).size)

    def percentile(self, which: str, share: float) -> float:
        """The ``share`` quantile (0.5: the median) of ``which`` error over every row.

        ``which`` is ``"position"`` or ``"rotation"``. From the histogram: the middle
        of the bin that holds it (within half a bin, 0.05 %, of the exact value), never
        beyond the exact maximum; ``nan`` before any row.
        """
        hist = self._hist[which]
        top = self.max_position_m if which == "position" else self.max_rotation_rad
        if not self.rows:
            return math.nan
        k = int(np.searchsorted(np.cumsum(hist), share * self.rows, side="left"))
        if k == 0:
            return min(top, _HIST_LOW)
        return min(top, float(_HIST_LOW * HISTOGRAM_RATIO ** (min(k, _BINS - 1) + 0.5)))


@dataclass(frozen=True)
class StreamKeeper:
    """Makes the check's :class:`StreamSummary` of a recording: a keeper factory.

    Equal for equal tolerances, so that a backend handed an equal one again keeps
    the recording it read (:meth:`fkcheck.backends.measured.MeasuredPoses.keep_with`):
    the time limit takes no part (a diagnosis after the check reads nothing again).

    Attributes:
        tol: ``(position m, rotation rad)``: the check's tolerances.
        timeout_s: The check's (or the diagnosis's) ``--timeout``; ``None``: none.
    """

    tol: tuple[float, float]
    timeout_s: float | None = field(default=None, compare=False)

    @property
    def read_limit_s(self) -> float | None:
        """The read's time limit: :attr:`timeout_s`, but at least :data:`READ_MIN_S`.

        From before the recording is opened to its last row
        (:class:`~fkcheck.backends.recording.ReadClock`); ``None``: none.
        """
        return None if self.timeout_s is None else max(self.timeout_s, READ_MIN_S)

    def __call__(self, model: Model, pair: tuple[str, str]) -> StreamSummary:
        """The summary of a recording of ``pair``'s poses, compared with ``model``."""
        return StreamSummary(model, pair, self.tol)


def stream_recordings(
    backends: Sequence[Backend], tol: tuple[float, float], timeout_s: float | None = None
) -> None:
    """Hand each backend that reads a recording chunk by chunk the check's keeper.

    ``tol`` is the check's ``(position m, rotation rad)`` tolerances: the rows
    beyond them are counted as the recording streams. ``timeout_s`` is the check's
    time limit: a read that takes longer (and at least :data:`READ_MIN_S`), from
    before the recording is opened, ends in :class:`~fkcheck.errors.TimeLimitError`.
    """
    for backend in backends:
        if isinstance(backend, _KeepsRows):  # a wrapper of one too (fkcheck diagnose's)
            backend.keep_with(StreamKeeper(tol, timeout_s))


@runtime_checkable
class _KeepsRows(Protocol):
    """A backend that reads a recording through the keeper it is handed (``poses:``)."""

    def keep_with(self, keeper: KeeperFactory) -> None:
        """Read the recording through ``keeper`` from now on."""
        ...


def _count_beyond(pos: Float, rot: Float, tol: tuple[float, float]) -> int:
    """Rows whose position or rotation error exceeds its tolerance (``inf`` does)."""
    return int(np.count_nonzero((pos > tol[0]) | (rot > tol[1])))
