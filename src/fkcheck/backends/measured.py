"""The ``poses:<file.csv>`` backend: measured or teach-pendant poses as the reference.

A team's real robot becomes a reference: a CSV of joint values and the pose a
controller showed (or a tracker measured) for each. The file:

.. code-block:: text

    # fkcheck poses: from=base to=tool0        (optional; default: the model's [check])
    q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg,x_mm,y_mm,z_mm,rx,ry,rz
    30,-60,90,-120,-90,45,-505.612,-417.951,178.795,2.492393,1.912480,0.000000

Columns, by header name:

* joints ``q1 … qn`` in radians / metres, each revolute one optionally ``_deg``
  (degrees), each prismatic one ``_mm`` (millimetres);
* position ``x, y, z`` in metres, or ``x_mm, y_mm, z_mm``;
* rotation, one of: ``qx, qy, qz, qw`` (quaternion); ``rx, ry, rz`` (rotation vector in
  radians, as a UR pendant shows it); ``roll, pitch, yaw`` (URDF rpy); ``A, B, C``
  (Z-Y'-X'' Euler) — the angles in radians, or with ``_deg`` in degrees.

A suffix is valid only for the quantity it measures (``q1_mm`` on a revolute joint,
``x_deg``, ``rx_mm``, ``qx_deg`` are refused in one line).

**A recording of Universal Robots' RTDE recorder** (``record.py`` of UR's RTDE
client library, without ``--binary``) is read as it is: a header line of output
names (a vector output ``name`` as ``name_0 … name_5``), values separated by
spaces (the recorder's default) or commas. A header naming ``actual_q_0`` makes
the file such a recording; of its columns the joints are ``actual_q_0 …
actual_q_5`` (radians) and the pose ``actual_TCP_pose_0 … actual_TCP_pose_5``
(x, y, z in metres, then the rotation vector rx, ry, rz in radians): the
controller's ``base`` frame to its active TCP, which is the DH table's flange
(``tool0`` of the bundled UR models) when the TCP offset in the robot's
installation is zero. Every other column is ignored (it may hold anything, even
``nan``); a missing needed column, one of them named twice, a row with another
number of fields, or a binary recording (``--binary``: a line of type names, then
packed numbers) is refused in one line. The fields are split by :mod:`csv`; the
numbers read as everywhere else.

The poses are ``from_T_to`` for one frame pair: the one a ``# fkcheck poses:``
comment names, else the model's ``[check]`` pair (an RTDE recording has no
comments: the model's pair, ``base`` → ``tool0`` for the bundled UR models). They
exist only at the file's configurations, so this backend answers for exactly those:
the check must run on them (``configurations()``), and any other configuration makes it *skipped*
with that reason. Measured poses are noisy: compare them with a tolerance that
fits the measurement (``--tol-pos 1e-3``).

The file is read as other tables are (:mod:`fkcheck.io.files`: a regular file,
lines of at most 64 KiB, UTF-8 with or without a byte-order mark; numbers by
:func:`fkcheck.io.numbers.parse_number`), but in chunks
(:class:`~fkcheck.backends.recording.Recording`: :func:`open_recording` picks the
reader by the recording's kind), so that it may be long: at most
:data:`~fkcheck.backends.recording.MAX_RECORDING_BYTES` (4 GiB) and
:data:`MAX_POSES_ROWS` rows (10 million), counted as they are read. It is refused
with the line, column and header name of the first problem: a column named
twice, an empty field, a value beyond the model files' bounds (joint values
within ±1000 rad / ±1000 m, positions within ±1000 m, rotation numbers within
±1000). A ``# fkcheck poses:`` comment comes before the data rows.

The rows a check runs on are those its keeper keeps
(:meth:`MeasuredPoses.keep_with`): a recording of at most
:data:`~fkcheck.backends.recording.KEEP_ROWS` rows whole; of a longer one a
deterministic sample and, with the check's keeper
(:class:`fkcheck.engine.stream.StreamSummary`, which compares every row with the core
as it is read), its worst rows. The same configuration (within :data:`MATCH_TOL`)
may appear on several kept lines only with the same pose (within :data:`MATCH_TOL` m
and rad): the table cannot hold two answers for one question. Matching
configurations to rows is a hash lookup (a k-d tree for ones that are not bit for
bit a row), so tens of thousands of rows are matched in well under a second.

The columns of a poses CSV are read in :mod:`.poses_columns`, those of an RTDE
recording in :mod:`.poses_rtde`, and the rows kept are looked up (and their
duplicates refused) in :mod:`.poses_table`; this module streams the file and is
the backend.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol

import numpy as np

from fkcheck.backends.base import (
    BackendDefaults,
    BackendUnavailable,
    Evidence,
    FrameUnavailable,
    Reads,
    validated_q,
)
from fkcheck.backends.poses_columns import CSV_METHOD, PosesFileError, _Layout, _read_header, _show
from fkcheck.backends.poses_columns import MAX_ROTATION_NUMBER as MAX_ROTATION_NUMBER
from fkcheck.backends.poses_rtde import RTDE_COLUMNS as RTDE_COLUMNS
from fkcheck.backends.poses_rtde import _RtdeLayout
from fkcheck.backends.poses_table import MATCH_TOL as MATCH_TOL
from fkcheck.backends.poses_table import _check_duplicates, _Table
from fkcheck.backends.recording import (
    CHUNK_CHARS,
    CHUNK_ROWS,
    MAX_RECORDING_BYTES,
    MAX_RECORDING_ROWS,
    PoseChunk,
    ReadClock,
    Recording,
    RowKeeper,
    SampleKeeper,
)
from fkcheck.backends.registry import BackendOptions
from fkcheck.core.typing import Float
from fkcheck.io.files import InputFileError, read_lines
from fkcheck.model.types import Model, resolve_frame

__all__ = [
    "MAX_POSES_ROWS",
    "MeasuredPoses",
    "PosesFileError",
    "open_recording",
    "read_poses_file",
]


#: Data rows a poses file or RTDE recording may hold: read in chunks, a recording
#: takes the same memory whatever its length, so the limit bounds the time
#: (:data:`~fkcheck.backends.recording.MAX_RECORDING_ROWS`: 5.5 hours at 500 Hz).
MAX_POSES_ROWS = MAX_RECORDING_ROWS
_PAIR = re.compile(r"^#\s*fkcheck poses:\s*from\s*=\s*(\S+)\s+to\s*=\s*(\S+)\s*$")


def read_poses_file(path: Path, model: Model) -> tuple[Float, Float, tuple[str, str] | None]:
    """Read a measured-poses CSV, or a UR RTDE recording.

    Args:
        path: The file.
        model: The model (joint count and types).

    Returns:
        ``(q, poses, pair)``: ``(N, n)`` joint values (radians / metres), ``(N, 4, 4)``
        poses ``from_T_to`` and the frame pair the file declares, if it does. For a
        recording longer than :data:`~fkcheck.backends.recording.KEEP_ROWS` rows, the
        rows the check runs on (:class:`~fkcheck.backends.recording.StreamSummary`).

    Raises:
        PosesFileError: Not a regular file, too large, not UTF-8, a missing or
            repeated column, a bad or out-of-bounds number (with its line and
            column), no rows or more than :data:`MAX_POSES_ROWS`, or one configuration with
            two different poses among the rows kept.
    """
    table = _read(path, model)
    return table.q, table.poses, table.pair


def _layout(line: str, lineno: int, model: Model, path: Path) -> _Layout | _RtdeLayout:
    """The layout a header line gives: an RTDE recording when it names ``actual_q_0``."""
    if "actual_q_0" in re.split(r"[\s,]+", line.strip()):
        return _RtdeLayout(line, lineno, model, path)
    return _Layout(_read_header(line, lineno, path), model, path)


def open_recording(path: Path, model: Model, options: BackendOptions | None = None) -> Recording:
    """The reader of the recording ``poses:PATH`` names, by its kind: the one dispatch point.

    A ROS 2 bag (:class:`fkcheck.backends.bag.BagRecording`, read as ``options`` set:
    frames, topics, stamp tolerance), else a text file (fkcheck's poses CSV, or UR's
    RTDE recorder CSV).
    """
    from fkcheck.backends.bag import BagRecording, bag_pairs, is_bag

    if is_bag(path):
        return BagRecording(bag_pairs(path, model, options or BackendOptions()))
    return _CsvRecording(path, model)


class _CsvRecording:
    """A poses CSV or RTDE recording as a :class:`~fkcheck.backends.recording.Recording`."""

    where = "line"

    def __init__(self, path: Path, model: Model) -> None:
        self.path = path
        self.model = model
        self.pair: tuple[str, str] | None = None
        self.method = MeasuredPoses.method

    def chunks(self) -> Iterator[PoseChunk]:
        """The file's rows, :data:`CHUNK_ROWS` (or :data:`CHUNK_CHARS` of text) at a time.

        Raises:
            PosesFileError: Any problem, with its line (see :func:`read_poses_file`).
        """
        path, model = self.path, self.model
        layout: _Layout | _RtdeLayout | None = None
        lines: list[str] = []
        linenos: list[int] = []
        chars = 0
        rows = 0
        idle, idle_chars = 0, 0  # lines (and their text) read since the last yield, not rows
        try:
            for lineno, line in read_lines(path, MAX_RECORDING_BYTES):
                text = line.strip()
                match = _PAIR.match(text)
                if match:
                    if rows:
                        raise PosesFileError(
                            path,
                            f"line {lineno}: '# fkcheck poses: from=… to=…' comes after data "
                            "rows; put it before the header line",
                        )
                    self.pair = _model_pair(match.group(1), match.group(2), model, lineno, path)
                elif not text or text.startswith("#"):
                    pass  # a comment or a blank line
                elif layout is None:
                    layout = _layout(line, lineno, model, path)
                    self.method = layout.method
                else:
                    if rows == MAX_POSES_ROWS:  # counted while streaming: refused unparsed
                        raise PosesFileError(
                            path,
                            f"line {lineno}: more than {MAX_POSES_ROWS:,} data rows (at most "
                            f"{MAX_POSES_ROWS:,}); cut the recording or keep every k-th row",
                        )
                    rows += 1
                    lines.append(line)
                    linenos.append(lineno)
                    chars += len(line)
                    if len(lines) == CHUNK_ROWS or chars >= CHUNK_CHARS:
                        yield _chunk(layout, lines, linenos, path)
                        lines, linenos, chars, idle, idle_chars = [], [], 0, 0, 0
                    continue
                idle, idle_chars = idle + 1, idle_chars + len(line)
                if idle >= CHUNK_ROWS or idle_chars >= CHUNK_CHARS:  # no rows for a while:
                    idle, idle_chars = 0, 0  # a chunk of none, for the caller's clock
                    yield _none(model)
        except (InputFileError, PosesFileError) as exc:
            # The first problem in the file is the one said: the rows read before this
            # one (a binary recording's line of types before its packed numbers) first.
            if layout is not None and lines:
                _chunk(layout, lines, linenos, path)
            if isinstance(exc, InputFileError):
                raise PosesFileError(path, exc.problem) from None
            raise
        if layout is None or not rows:
            raise PosesFileError(path, "no header line and data rows")
        if lines:
            yield _chunk(layout, lines, linenos, path)


def _none(model: Model) -> PoseChunk:
    """A chunk of no rows: what a reader yields while it finds none (see :class:`Recording`)."""
    return PoseChunk(
        np.empty((0, model.dof)), np.empty((0, 4, 4)), None, np.empty(0, dtype=np.int64)
    )


def _chunk(
    layout: _Layout | _RtdeLayout, lines: list[str], linenos: list[int], path: Path
) -> PoseChunk:
    """The rows of ``lines`` (their numbers ``linenos``), read and checked against the bounds."""
    from fkcheck.core.pose_formats import matrix_from_pose

    values = np.array(layout.rows(lines, linenos, path), dtype=np.float64).reshape(len(lines), -1)
    if np.any(layout.factor != 1.0):  # an RTDE recording's are all 1: no copy
        values = values * layout.factor
    bad = np.argwhere(np.abs(values) > layout.bound)
    if bad.size:
        row, k = (int(v) for v in bad[0])
        name = _show(layout.header[layout.columns[k]])
        raise PosesFileError(
            path,
            f"line {linenos[row]} ({name}): {values[row, k]:g}{layout.unit[k]} is beyond "
            f"±{layout.bound[k]:g}{layout.unit[k]}",
        )
    q = values[:, : layout.n].copy()
    try:
        poses = matrix_from_pose(values[:, layout.n :], layout.fmt)  # type: ignore[arg-type]
    except ValueError as exc:
        raise PosesFileError(path, str(exc)) from None
    return PoseChunk(q, poses, None, np.array(linenos, dtype=np.int64))


class KeeperFactory(Protocol):
    """Makes the keeper of a recording's rows for a model and the recording's frame pair.

    Attributes:
        read_limit_s: How long a read through it may take, seconds, from its start
            (opening the recording) to its end; ``None``: no limit.
    """

    @property
    def read_limit_s(self) -> float | None:
        """The read's time limit, seconds (``None``: none)."""
        ...

    def __call__(self, model: Model, pair: tuple[str, str]) -> RowKeeper:
        """The keeper of a recording of ``pair``'s poses, for ``model``."""
        ...


@dataclass(frozen=True)
class _SampleKeeperFactory:
    """The deterministic sample of a recording (:class:`SampleKeeper`), read without a limit."""

    read_limit_s: float | None = None

    def __call__(self, model: Model, pair: tuple[str, str]) -> RowKeeper:
        return SampleKeeper(model.dof)


_sample_keeper = _SampleKeeperFactory()


def _read(
    path: Path,
    model: Model,
    keeper: KeeperFactory = _sample_keeper,
    options: BackendOptions | None = None,
) -> _Table:
    """Stream the recording at ``path`` through ``keeper``: the rows it keeps, as a table.

    Within the keeper's time limit (:attr:`KeeperFactory.read_limit_s`), from before
    the recording is opened: its first rows, and whatever precedes them, included.

    Raises:
        TimeLimitError: The read took longer.
        PosesFileError: The recording cannot be read.
    """
    clock = ReadClock(path, keeper.read_limit_s)
    recording = open_recording(path, model, options)
    kept: RowKeeper | None = None
    rows = 0
    for chunk in recording.chunks():
        clock.check(rows)
        if not chunk.q.shape[0]:
            continue  # the reader found no rows for a while: only the clock is looked at
        if kept is None:  # the pair is known once the first rows are
            pair = recording.pair or (model.check.frame_from, model.check.frame_to)
            kept = keeper(model, pair)
        kept.add(chunk)
        rows += chunk.q.shape[0]
    clock.check(rows)
    if kept is None:  # a reader yields at least one row or refuses
        raise PosesFileError(path, "no data rows")
    q, poses, lines = kept.kept()
    _check_duplicates(q, poses, lines, path)
    return _Table(q, poses, recording, kept)


def _model_pair(
    frame_from: str, frame_to: str, model: Model, lineno: int, path: Path
) -> tuple[str, str]:
    """The file's declared pair as the model's frame names (``urdf:LINK`` resolved).

    Raises:
        PosesFileError: The model has no such frame (bad input, as a wrong ``--to`` is).
    """
    from fkcheck.errors import FrameError

    try:
        return (resolve_frame(model, frame_from).name, resolve_frame(model, frame_to).name)
    except FrameError as exc:
        where = f"line {lineno}: '# fkcheck poses: from=… to=…'"
        raise PosesFileError(path, f"{where}: {exc}") from None


def _reading(model: Model) -> tuple[object, ...]:
    """What reading a recording takes from a model: its joints, URDF joint names and frames.

    The columns (by joint count and type), a bag's joint names and the frame pair
    (the model's ``[check]`` pair, frame names and their URDF twins); not its numbers.
    """
    urdf = model.urdf.joints if model.urdf is not None and model.urdf.joints else ()
    return (
        tuple((j.name, j.type) for j in model.joints),
        tuple(urdf),
        (model.check.frame_from, model.check.frame_to),
        tuple((key, spec.name, spec.urdf) for key, spec in model.frames.items()),
    )


class MeasuredPoses(BackendDefaults):
    """Reference poses read from a CSV file, at that file's configurations.

    Attributes:
        name: ``"poses:<path>"``.
        method: ``"measured poses (CSV)"``; once an RTDE recording is read, which of
            its columns were used (``"UR RTDE recording (space-separated): joints
            actual_q_0…actual_q_5 …; 62 other columns ignored"``).
        path: The CSV file.
    """

    method = CSV_METHOD
    evidence: Evidence = "table"
    reads: Reads = "poses"

    def __init__(self, arg: str, options: BackendOptions | None = None) -> None:
        """Build the backend for the CSV file ``arg``."""
        self.path = Path(arg)
        self.name = f"poses:{arg}"
        self.options = options or BackendOptions()
        self._read: tuple[Model, _Table] | None = None
        self._keeper: KeeperFactory = _sample_keeper

    def keep_with(self, keeper: KeeperFactory) -> None:
        """Read the recording through ``keeper`` from now on (the check's: it compares as it reads).

        A recording already read through another keeper (one not equal to it) is read
        again when next asked for.
        """
        if keeper != self._keeper:
            self._keeper = keeper
            self._read = None

    def streamed(self, model: Model) -> tuple[Recording, RowKeeper] | None:
        """The recording and its keeper when the check runs on some of its rows, else ``None``."""
        table = self._table(model)
        whole = getattr(table.keeper, "whole", True)
        return None if whole else (table.recording, table.keeper)

    def _table(self, model: Model) -> _Table:
        """The file, read once per model (the check asks for it chunk by chunk).

        Once per *equal* model: the command line reads it before its header, and the
        check's copy of the model (its xacro expansion kept, which takes no part in
        equality) must not read a recording of 10⁵ rows again.
        """
        if self._read is None or self._read[0] != model:
            self._read = model, _read(self.path, model, self._keeper, self.options)
            self.method = self._read[1].method
        return self._read[1]

    def _table_for(self, model: Model) -> _Table:
        """The table to look up ``model``'s poses in: the one read, if ``model`` reads alike.

        A recorded pose does not depend on the model, only which rows were kept and
        how the recording was read: a diagnosis's changed model (other numbers, the
        same joints and frames) looks up the rows kept for the check's model, rather
        than reading a recording of millions of rows again for each change it verifies.
        """
        if self._read is not None and _reading(self._read[0]) == _reading(model):
            return self._read[1]
        return self._table(model)

    @property
    def recording(self) -> bool:
        """Whether the file read is a UR RTDE recording: poses the controller computed itself."""
        return self._read is not None and self._read[1].method != MeasuredPoses.method

    def unavailable_reason(self, model: Model) -> str | None:
        """``None`` when the path exists; it is read (and validated: a regular file) when used."""
        return None if os.path.lexists(self.path) else f"no such file: {self.path}"

    def inputs(self, model: Model) -> tuple[Path, ...]:
        """The CSV file; a bag's files (no output may replace one)."""
        from fkcheck.backends.bag import bag_files, is_bag

        return bag_files(self.path) if is_bag(self.path) else (self.path,)

    def configurations(self, model: Model) -> Float:
        """The file's joint values, ``(N, n)``: the check must run on these."""
        return self._table(model).q

    def frame_poses(self, model: Model, q: Float, frames: Sequence[str]) -> Float:
        """``[identity, from_T_to]`` for the file's pair, at the file's configurations.

        Raises:
            PosesFileError: The file cannot be read.
            FrameUnavailable: ``frames`` is not the file's pair.
            BackendUnavailable: A configuration is not in the file.
            JointInputError: ``q`` has the wrong shape or non-finite values.
        """
        q = validated_q(model, q)
        table = self._table_for(model)
        pair = table.pair or (model.check.frame_from, model.check.frame_to)
        if tuple(frames) != pair:
            raise FrameUnavailable(
                f"{self.path.name} holds poses of {pair[1]} in {pair[0]}, not "
                f"{' → '.join(frames)} (the pair is the file's '# fkcheck poses: from=… to=…' "
                "comment, else the model's [check] pair)"
            )
        rows = table.rows_of(q)
        missing = np.flatnonzero(rows < 0)
        if missing.size:
            raise BackendUnavailable(
                f"{self.path.name} has no pose for configuration {int(missing[0])} (measured "
                "poses exist only at the file's configurations: run on them, e.g. fkcheck "
                "diagnose)"
            )
        out = np.empty((2, rows.size, 4, 4))
        out[0] = np.eye(4)
        out[1] = table.poses[rows]
        return out
