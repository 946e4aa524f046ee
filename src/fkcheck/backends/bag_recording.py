"""A ROS 2 bag as a recording: the adapter the check and the stream read it through.

Part of :mod:`fkcheck.backends.bag`: :func:`bag_pairs` sets up the reader of a bag's
pairs (:class:`~fkcheck.backends.bag.BagPairs`) from a model and the check's
options; :class:`BagRecording` streams them as a
:class:`~fkcheck.backends.recording.Recording`; :func:`read_bag` reads them whole,
as :func:`fkcheck.backends.measured.read_poses_file` reads a file.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from fkcheck.backends.bag_screen import BagError
from fkcheck.backends.measured import PosesFileError
from fkcheck.backends.poses_table import _check_duplicates
from fkcheck.backends.recording import CHUNK_ROWS, MAX_RECORDING_ROWS, PoseChunk
from fkcheck.backends.registry import BackendOptions
from fkcheck.core.typing import Float
from fkcheck.model.types import MAX_JOINT_RAD, MAX_LENGTH_M, Model, resolve_frame

if TYPE_CHECKING:
    from fkcheck.backends.bag import BagPairs

__all__ = ["BagRecording", "bag_pairs", "read_bag"]


class BagRecording:
    """A bag's pairs as a :class:`~fkcheck.backends.recording.Recording`, streamed.

    What :func:`fkcheck.backends.measured.open_recording` returns for a bag: its rows
    are the pairs, numbered from 1 in the order their poses were recorded; its
    :attr:`method` is the provenance line once the bag has been read to its end.
    """

    where = "row"

    def __init__(self, pairs: BagPairs) -> None:
        self.pairs = pairs
        self.pair: tuple[str, str] | None = pairs.frames
        self.method = "ROS 2 bag"

    def chunks(self) -> Iterator[PoseChunk]:
        """The pairs, :data:`~fkcheck.backends.recording.CHUNK_ROWS` at a time.

        Raises:
            BagError: See :meth:`BagPairs.chunks`; or more than
                :data:`~fkcheck.backends.recording.MAX_RECORDING_ROWS` pairs.
        """
        count = 0
        for q, poses, t in self.pairs.chunks(CHUNK_ROWS):
            first, count = count, count + q.shape[0]
            if count > MAX_RECORDING_ROWS:
                raise BagError(
                    self.pairs.path,
                    f"more than {MAX_RECORDING_ROWS:,} pairs (at most {MAX_RECORDING_ROWS:,}); "
                    "cut the bag (ros2 bag convert with a start and end time)",
                )
            yield PoseChunk(q, poses, t, np.arange(first + 1, count + 1, dtype=np.int64))
        self.method = self.pairs.provenance.method


def bag_pairs(path: Path, model: Model, options: BackendOptions) -> BagPairs:
    """The reader of a bag's pairs for ``model``, as the check's options set it.

    Args:
        path: The bag.
        model: The model: its joints (names, URDF joint names, types) and ``[check]`` pair.
        options: The check's frames (``None``: the model's pair), topics and tolerance.

    Raises:
        BagError: A frame the model does not have, or a stamp tolerance out of range.
    """
    from fkcheck.backends.bag import BagPairs, BagTopics
    from fkcheck.errors import FrameError

    try:
        pair = (
            resolve_frame(model, options.frame_from or model.check.frame_from).name,
            resolve_frame(model, options.frame_to or model.check.frame_to).name,
        )
    except FrameError as exc:
        raise BagError(path, str(exc)) from None
    urdf = model.urdf.joints if model.urdf is not None and model.urdf.joints else ()
    names = [(j.name, *((urdf[i],) if i < len(urdf) else ())) for i, j in enumerate(model.joints)]
    bounds = [MAX_JOINT_RAD if j.type == "revolute" else MAX_LENGTH_M for j in model.joints]
    topics = BagTopics(options.bag_joint_states, options.bag_tf, options.bag_tf_static)
    return BagPairs(path, joint_names=names, joint_bounds=bounds, frames=pair, topics=topics,
                    stamp_tolerance_s=options.bag_stamp_tolerance_s)  # fmt: skip


def read_bag(
    path: Path, model: Model, options: BackendOptions
) -> tuple[Float, Float, tuple[str, str], str]:
    """Read a bag whole, as :func:`fkcheck.backends.measured.read_poses_file` reads a file.

    Args:
        path: The bag.
        model: The model (see :func:`bag_pairs`).
        options: The check's frames, topics and tolerance.

    Returns:
        ``(q, poses, pair, method)``: ``(N, n)`` joint values, ``(N, 4, 4)`` poses
        ``from_T_to``, the pair (the model's frame names) and the report's method text.

    Raises:
        BagError: See :func:`bag_pairs` and :meth:`BagPairs.chunks`; also more pairs
            than :data:`~fkcheck.backends.measured.MAX_POSES_ROWS`, or one
            configuration paired with two different poses.
    """
    from fkcheck.backends import measured

    pairs = bag_pairs(path, model, options)
    pair = pairs.frames
    qs: list[Float] = []
    poses: list[Float] = []
    count = 0
    for q, T, _ in pairs.chunks():
        count += q.shape[0]
        if count > measured.MAX_POSES_ROWS:
            raise BagError(
                path,
                f"more than {measured.MAX_POSES_ROWS:,} pairs (at most "
                f"{measured.MAX_POSES_ROWS:,}); cut the bag (ros2 bag convert with a start and "
                "end time)",
            )
        qs.append(q)
        poses.append(T)
    q_all, poses_all = np.concatenate(qs), np.concatenate(poses)
    try:
        _check_duplicates(q_all, poses_all, np.arange(1, count + 1, dtype=np.int64), path)
    except PosesFileError as exc:  # its rows are the pairs, counted from 1 as recorded
        raise BagError(path, exc.problem.replace("lines", "pairs", 1)) from None
    return q_all, poses_all, pair, pairs.provenance.method
