"""Timing the reading of a recording against pandas' CSV reader, on the same file.

One RTDE recording is written for the run, as UR's recorder writes one (``record.py``:
space-separated, each float as ``repr`` writes it, a header of output names) with
the columns ``timestamp``, ``actual_q_0…5`` and ``actual_TCP_pose_0…5`` — 13
columns, about 240 bytes a row, as an hour at 500 Hz is 417 MiB — of
:data:`RECORDING_ROWS` seeded configurations and the in-house core's poses. Then:

* **fkcheck read**: the rows as ``poses:`` reads them, chunk by chunk
  (:func:`fkcheck.backends.measured.open_recording`): each read field a plain number,
  the bounds, the rotation vectors made matrices;
* **fkcheck read + compare**: what ``fkcheck check --against poses:`` does with
  them: read, compared with the in-house core row by row, the sample and the
  worst rows kept, the kept rows' duplicates refused
  (:class:`fkcheck.engine.stream.StreamSummary`);
* **pandas.read_csv** (the peer): ``sep=" "``, the 12 read columns, float64, its C
  parser: numbers only, no poses, no checks; its largest difference from
  fkcheck's numbers is reported (its default float parser may differ from
  Python's correctly rounded one in the last bit).

Rows a second and megabytes (10⁶ bytes) of file a second; each the median of
``repeat`` runs after one warm-up run. pandas is in the ``bench`` dependency group,
not a dependency of fkcheck: without it that row is skipped.
"""

from __future__ import annotations

import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from fkcheck.bench.timing import bench_configurations, median_seconds
from fkcheck.core.typing import Float
from fkcheck.model.frames import reference_poses, relative_pose
from fkcheck.model.types import Model

__all__ = ["RECORDING_ROWS", "RecordingTiming", "run_recording_bench", "write_recording"]

#: Rows of the recording timed: about 12 MB, a second or two per run.
RECORDING_ROWS = 50_000


@dataclass
class RecordingTiming:
    """One reader's result on the recording.

    Attributes:
        name: What was timed.
        kind: ``in-house`` or ``peer``.
        rows: Rows of the recording.
        bytes: Its size in bytes.
        seconds: Median seconds per read (``None`` when skipped or failed).
        max_diff: Largest difference of its joint and pose numbers from fkcheck's
            read (``None`` where not compared).
        note: How it was called.
        skipped: Why it did not run.
        error: It is installed but failed.
    """

    name: str
    kind: str
    rows: int
    bytes: int
    seconds: float | None = None
    max_diff: float | None = None
    note: str = ""
    skipped: str = ""
    error: str = ""

    @property
    def rows_per_s(self) -> float | None:
        """Rows read a second."""
        return None if self.seconds is None else self.rows / self.seconds

    @property
    def mb_per_s(self) -> float | None:
        """Megabytes (10⁶ bytes) of file read a second."""
        return None if self.seconds is None else self.bytes / self.seconds / 1e6


def write_recording(path: Path, model: Model, rows: int, seed: int) -> Float:
    """Write an RTDE recording of ``rows`` seeded configurations there; returns its 12 numbers.

    The poses are the in-house core's ``from_T_to`` for the model's ``[check]`` pair.
    """
    from scipy.spatial.transform import Rotation

    q = bench_configurations(model, rows, seed)
    pair = (model.check.frame_from, model.check.frame_to)
    ref = reference_poses(model, q, pair)
    poses = relative_pose(ref[0], ref[1])
    rotvec = Rotation.from_matrix(poses[:, :3, :3]).as_rotvec()
    numbers = np.hstack([q, poses[:, :3, 3], rotvec])
    header = ["timestamp", *(f"actual_q_{i}" for i in range(6))]
    header += [f"actual_TCP_pose_{i}" for i in range(6)]
    with path.open("w", encoding="utf-8") as f:
        f.write(" ".join(header) + "\n")
        for k, row in enumerate(numbers.tolist()):
            f.write(" ".join(map(repr, [0.002 * k, *row])) + "\n")
    return numbers


def _fkcheck_read(path: Path, model: Model) -> Float:
    from fkcheck.backends.measured import open_recording

    parts = [
        np.hstack([c.q, c.poses.reshape(-1, 16)]) for c in open_recording(path, model).chunks()
    ]
    return np.vstack(parts)


def _fkcheck_check(path: Path, model: Model) -> None:
    from fkcheck.backends.measured import MeasuredPoses
    from fkcheck.engine.stream import StreamKeeper

    backend = MeasuredPoses(str(path))
    backend.keep_with(StreamKeeper((model.check.tol_pos_m, model.check.tol_rot_rad)))
    backend.configurations(model)


def _pandas_read(path: Path) -> Float:
    import pandas as pd

    columns = [f"actual_q_{i}" for i in range(6)] + [f"actual_TCP_pose_{i}" for i in range(6)]
    frame = pd.read_csv(path, sep=" ", usecols=columns, dtype=np.float64, engine="c")
    numbers: Float = frame[columns].to_numpy()
    return numbers


def run_recording_bench(
    model: Model, repeat: int, seed: int, progress: Callable[[str], None] | None = None
) -> list[RecordingTiming]:
    """Time reading one written recording: fkcheck's read, its check's pass, pandas.

    Returns:
        One row per reader; all skipped when the model has not 6 joints (an RTDE
        recording holds 6).
    """
    say = progress or (lambda _name: None)
    names = ("fkcheck read (poses:)", "fkcheck read + compare (check)", "pandas.read_csv (C)")
    if model.dof != 6:
        why = f"an RTDE recording holds 6 joints; model {model.name} has {model.dof}"
        return [
            RecordingTiming(n, "peer" if n.startswith("pandas") else "in-house", 0, 0, skipped=why)
            for n in names
        ]
    with tempfile.TemporaryDirectory(prefix="fkcheck-bench-") as tmp:
        path = Path(tmp) / "recording.csv"
        say("writing a recording")
        numbers = write_recording(path, model, RECORDING_ROWS, seed)
        size = path.stat().st_size
        out: list[RecordingTiming] = []
        say(names[0])
        read = _fkcheck_read(path, model)
        seconds = median_seconds(lambda: _fkcheck_read(path, model), repeat)
        q_and_pose = read[:, :6]
        out.append(
            RecordingTiming(
                names[0], "in-house", RECORDING_ROWS, size, seconds,
                float(np.abs(q_and_pose - numbers[:, :6]).max()),
                note="open_recording(path, model).chunks(): fields checked, poses as matrices",
            )
        )  # fmt: skip
        say(names[1])
        seconds = median_seconds(lambda: _fkcheck_check(path, model), repeat)
        out.append(
            RecordingTiming(
                names[1], "in-house", RECORDING_ROWS, size, seconds,
                note="MeasuredPoses with StreamSummary: read, every row compared with the "
                "in-house core, sample and worst rows kept",
            )
        )  # fmt: skip
        say(names[2])
        try:
            theirs = _pandas_read(path)
        except ImportError as exc:
            out.append(RecordingTiming(names[2], "peer", RECORDING_ROWS, size,
                                       skipped=f"not installed: {exc}"))  # fmt: skip
            return out
        except Exception as exc:  # installed but failed: an error, and the bench fails
            out.append(RecordingTiming(names[2], "peer", RECORDING_ROWS, size,
                                       error=f"{type(exc).__name__}: {exc}"))  # fmt: skip
            return out
        seconds = median_seconds(lambda: _pandas_read(path), repeat)
        out.append(
            RecordingTiming(
                names[2], "peer", RECORDING_ROWS, size, seconds,
                float(np.abs(theirs - numbers).max()),
                note='read_csv(sep=" ", usecols=the 12 read columns, dtype=float64): numbers '
                "only, no poses, no checks",
            )
        )  # fmt: skip
    return out
