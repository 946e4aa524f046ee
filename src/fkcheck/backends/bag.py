"""ROS 2 bags as measured poses: ``poses:BAG`` reads joint states and tf as a robot wrote them.

UR's ROS 2 driver publishes ``/joint_states`` (``sensor_msgs/msg/JointState``) and,
on ``/tf`` (``tf2_msgs/msg/TFMessage``), the transform ``base`` → ``tool0_controller``
that the controller computed from its own, calibrated kinematics. A bag of a few
seconds of motion therefore holds pairs (joint values, tool pose) that a calibrated
model must reproduce. ``poses:PATH`` reads such a bag when ``PATH`` is a bag
directory (``metadata.yaml`` with its ``.mcap`` or ``.db3`` files) or a single
``.mcap`` or ``.db3`` file, with :mod:`rosbags` (pure Python, no ROS installation).

**Joints** are matched by name: each of the model's joints by its own name or by
its URDF joint name (``[urdf] joints``), in whatever order a message lists them.
Names the model does not have (a gripper's, another arm's) are ignored and said;
a message naming some of the model's joints but not all is refused in one line;
one naming none of them is skipped and counted.

**The pose** is the transform between the check's two frames (``--from``/``--to``,
else the model's ``[check]`` pair), looked up by frame id in the tf tree of the bag:
``/tf_static`` (read first, valid at all times) and ``/tf`` (the latest transform
of each frame). A pose is taken each time a ``/tf`` message changes a transform on
the path between the two frames, stamped with the path's ``header.stamp`` (every
changing transform on the path must carry the same stamp; the controller's
``base`` → ``tool0_controller`` is one transform). Frames are the model's frame
names: declare ``[frames.tool0_controller]`` to compare the driver's frame.

**Pairing by stamp**: each pose is paired with the joint state stamped at or before
it, the latest such, when it is at most the stamp tolerance earlier (default
:data:`DEFAULT_STAMP_TOLERANCE_S`, 1 ms: half a cycle of a 500 Hz controller, so a
pose is never paired with the reading of the cycle before when one is missing).
The controller computed the pose from a reading it already had, never from a later
one. A pose without such a joint state is not compared and is counted in the
report; a bag in which no pose finds one is refused in one line, saying how far
the nearest joint state was. A pose stamped the same as the one before it is the
same answer published twice and is counted once.

**A bag is untrusted input.** Only messages of the two types above are read from
the topics named (another type there is refused in one line), with the type
definitions :mod:`rosbags` ships for ROS 2 Humble: the bag's own message
definitions are never compiled (:meth:`rosbags.typesys.Typestore.register` runs
generated code; it is not called). A bag directory's files must be regular files
in it (no symbolic link leads out of it) and it may not be compressed as a
whole or per message (``ros2 bag convert`` writes it uncompressed); an MCAP
file's compressed chunks are decompressed to at most their declared size, itself
at most :data:`MAX_CHUNK_BYTES`. Messages are at most :data:`MAX_MESSAGE_BYTES`,
a joint state names at most :data:`MAX_JOINT_NAMES` joints, a tf message holds at
most :data:`MAX_TRANSFORMS` transforms, the tree at most :data:`MAX_FRAMES` frames.
Anything the reader cannot read (a truncated file, a corrupt database, bad
metadata) is one line naming the bag, never a traceback.

Reading streams: :class:`BagPairs` yields the pairs in chunks of a bounded number
of rows, and keeps only the joint states of the last
:data:`REORDER_WINDOW_S` of stamps, so memory does not grow with the bag's length.
"""

from __future__ import annotations

import bisect
import math
import os
import stat
from collections import deque
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from fkcheck.backends.measured import PosesFileError
from fkcheck.backends.recording import CHUNK_ROWS, MAX_RECORDING_ROWS, PoseChunk
from fkcheck.backends.registry import BackendOptions
from fkcheck.core.typing import Float
from fkcheck.model.types import MAX_JOINT_RAD, MAX_LENGTH_M, Model, resolve_frame

__all__ = [
    "DEFAULT_STAMP_TOLERANCE_S",
    "JOINT_STATE_TYPE",
    "TF_MESSAGE_TYPE",
    "BagError",
    "BagPairs",
    "BagProvenance",
    "BagRecording",
    "BagTopics",
    "bag_files",
    "bag_pairs",
    "is_bag",
    "read_bag",
]

#: Largest lag of a joint state before the pose it is paired with (seconds): the
#: default of :attr:`~fkcheck.backends.registry.BackendOptions.bag_stamp_tolerance_s`.
DEFAULT_STAMP_TOLERANCE_S: float = BackendOptions.bag_stamp_tolerance_s
#: Largest stamp tolerance that may be set (seconds): a larger one pairs poses with
#: readings of other cycles whenever one is missing.
MAX_STAMP_TOLERANCE_S = 1.0
#: The message types read, by their ROS 2 names.
JOINT_STATE_TYPE = "sensor_msgs/msg/JointState"
TF_MESSAGE_TYPE = "tf2_msgs/msg/TFMessage"
#: Largest message read (bytes, serialised): a joint state of a few arms or a tf
#: message of a few hundred frames is a few kilobytes.
MAX_MESSAGE_BYTES = 1 << 20
#: Largest MCAP chunk, decompressed (bytes); ``ros2 bag record`` writes about 1 MiB.
MAX_CHUNK_BYTES = 64 << 20
#: Largest ``metadata.yaml`` (bytes).
MAX_METADATA_BYTES = 1 << 20
#: Joints one joint state may name, transforms one tf message may hold, frames the
#: tree may hold, characters a frame id may have.
MAX_JOINT_NAMES = 1_000
MAX_TRANSFORMS = 10_000
MAX_FRAMES = 10_000
MAX_FRAME_ID_CHARS = 256
#: Frames between a frame and the root of its tf tree at most.
MAX_DEPTH = 256
#: How far (in stamps) a joint state may arrive after a pose it belongs to (seconds):
#: a pose waits for a joint state stamped after it, at most this long.
REORDER_WINDOW_S = 1.0
#: Joint states kept for pairing at most (the oldest go first).
MAX_KEPT_JOINT_STATES = 100_000
#: Rows per chunk :meth:`BagPairs.chunks` yields by default.
DEFAULT_CHUNK_ROWS = 10_000
#: Largest distance of a quaternion's norm from 1 on the compared path (tf2 refuses
#: quaternions further than about 1e-3 from unit length, too).
QUATERNION_NORM_TOL = 1e-3
_NS = 1_000_000_000


class BagError(PosesFileError):
    """A bag that cannot be read as measured poses (one line, exit 2)."""


class _Bad(Exception):
    """What a message of the bag holds cannot be used (becomes a :class:`BagError`)."""


@dataclass(frozen=True)
class BagTopics:
    """Where a bag's joint states and transforms are.

    Attributes:
        joint_states: Topic of ``sensor_msgs/msg/JointState``.
        tf: Topic of the changing transforms (``tf2_msgs/msg/TFMessage``).
        tf_static: Topic of the static ones, valid at all times.
    """

    joint_states: str = BackendOptions.bag_joint_states
    tf: str = BackendOptions.bag_tf
    tf_static: str = BackendOptions.bag_tf_static


@dataclass(frozen=True)
class BagProvenance:
    """What was read of a bag, for the report.

    Attributes:
        path: The bag.
        storage: ``"mcap"`` or ``"sqlite3"``.
        topics: The topics read.
        frames: ``(from, to)``: the transform compared.
        pairs: Pairs of a joint state and a pose found.
        first_s: Earliest stamp of a pair's pose (seconds since the epoch).
        last_s: Latest stamp of a pair's pose.
        unpaired: Poses without a joint state at or before them within the tolerance.
        repeated: Poses stamped the same as the one before (counted once).
        skipped_states: Joint states naming none of the model's joints.
        ignored_joints: Joint names the model does not have, sorted.
        tolerance_s: The stamp tolerance.
    """

    path: Path
    storage: str
    topics: BagTopics
    frames: tuple[str, str]
    pairs: int
    first_s: float
    last_s: float
    unpaired: int
    repeated: int
    skipped_states: int
    ignored_joints: tuple[str, ...]
    tolerance_s: float

    @property
    def method(self) -> str:
        """One line for the report: the bag's topics, frames, time span and pairs."""
        t = self.topics
        text = (
            f"ROS 2 bag ({self.storage}): {self.frames[0]} → {self.frames[1]} from {t.tf} and "
            f"{t.tf_static}, joints from {t.joint_states}; {self.pairs:,} pairs over "
            f"{self.last_s - self.first_s:.3f} s (stamps {self.first_s:.3f} … "
            f"{self.last_s:.3f} s), each pose with the joint state at or before it within "
            f"{self.tolerance_s * 1e3:g} ms"
        )
        if self.unpaired:
            text += f"; {self.unpaired:,} poses without one not compared"
        if self.repeated:
            text += f"; {self.repeated:,} poses repeating the stamp before counted once"
        if self.skipped_states:
            text += f"; {self.skipped_states:,} joint states without the model's joints skipped"
        if self.ignored_joints:
            shown = ", ".join(self.ignored_joints[:5])
            more = (
                f" and {len(self.ignored_joints) - 5} more" if len(self.ignored_joints) > 5 else ""
            )
            text += f"; joints not in the model ignored: {shown}{more}"
        return text


def is_bag(path: Path) -> bool:
    """Whether ``poses:PATH`` names a ROS 2 bag: a directory, or a ``.mcap`` / ``.db3`` file."""
    return path.is_dir() or path.suffix.lower() in (".mcap", ".db3")


def bag_files(path: Path) -> tuple[Path, ...]:
    """The bag and the files in its directory: what no output of the run may replace.

    At most :data:`MAX_FRAMES` entries of the directory are listed (a bag has a few).
    """
    if not path.is_dir():
        return (path,)
    try:
        with os.scandir(path) as entries:
            found = [Path(e.path) for _, e in zip(range(MAX_FRAMES), entries, strict=False)]
    except OSError:
        found = []
    return (path, *sorted(found))


def _regular(path: Path, what: str, bag: Path, *, follow: bool) -> None:
    """Refuse anything but a regular file (a FIFO would hang the read; a link may lead out)."""
    try:
        info = os.stat(path) if follow else os.lstat(path)
    except OSError as exc:
        raise BagError(bag, f"{what}: {exc.strerror or exc}") from None
    if stat.S_ISLNK(info.st_mode):
        raise BagError(bag, f"{what} is a symbolic link; a bag's files must be in it")
    if not stat.S_ISREG(info.st_mode):
        raise BagError(bag, f"{what} is not a regular file")


def _screen(path: Path) -> str:
    """The bag's storage, ``mcap`` or ``sqlite3``, once its files are known to be safe to read.

    Raises:
        BagError: Not a bag, a file of it not a regular file in it, compressed, or
            metadata that is not a bag's.
    """
    import yaml

    if not path.is_dir():
        _regular(path, "the bag", path, follow=True)
        return "mcap" if path.suffix.lower() == ".mcap" else "sqlite3"
    meta = path / "metadata.yaml"
    if not os.path.lexists(meta):
        raise BagError(
            path,
            "is a directory, not a regular file, and not a ROS 2 bag either (no "
            "metadata.yaml): give a poses CSV, the bag directory ros2 bag record wrote, or "
            "its .mcap or .db3 file",
        )
    _regular(meta, "metadata.yaml", path, follow=False)
    if os.path.getsize(meta) > MAX_METADATA_BYTES:
        raise BagError(path, f"metadata.yaml is larger than {MAX_METADATA_BYTES >> 20} MiB")
    try:
        text = meta.read_bytes()
        # Plain data, as ROS writes it: an alias bomb of a few hundred bytes expands to
        # billions of values in whoever walks it (rosbags reads this file too).
        for event in yaml.parse(text, Loader=yaml.SafeLoader):
            if isinstance(event, yaml.AliasEvent) or getattr(event, "anchor", None):
                raise BagError(
                    path, "metadata.yaml has an anchor or alias (&name, *name); ROS writes none"
                )
        doc = yaml.safe_load(text)
        info = doc["rosbag2_bagfile_information"]
        storage = info["storage_identifier"]
        files = info["relative_file_paths"]
        mode = str(info.get("compression_mode", "") or "").lower()
    except (yaml.YAMLError, KeyError, TypeError, AttributeError, OSError, UnicodeError) as exc:
        reason = type(exc).__name__ if isinstance(exc, KeyError) else exc
        raise BagError(path, f"metadata.yaml is not a ROS 2 bag's ({reason})") from None
    if storage not in ("mcap", "sqlite3"):
        raise BagError(path, f"storage {str(storage)[:40]!r} is not mcap or sqlite3")
    if mode not in ("", "none"):
        raise BagError(
            path,
            f"the bag is compressed (compression_mode {mode[:20]!r}); write it uncompressed "
            "(ros2 bag convert) or record it with the mcap storage, whose chunk compression "
            "is read",
        )
    if not isinstance(files, list) or not files or len(files) > 10_000:
        raise BagError(path, "metadata.yaml's relative_file_paths is not a list of files")
    for name in files:
        _regular(path / Path(str(name)).name, f"its file {Path(str(name)).name}", path,
                 follow=False)  # fmt: skip
    return str(storage)


def _bounded_decompressors() -> None:
    """Make :mod:`rosbags` decompress an MCAP chunk to at most its declared size.

    rosbags decompresses a chunk whole, then compares its size with the declared
    one: a few kilobytes of zstd can expand to gigabytes first. These replacements
    stop at the declared size (at most :data:`MAX_CHUNK_BYTES`).
    """
    import lz4.frame  # type: ignore[import-untyped]
    from rosbags.rosbag2 import storage_mcap

    try:
        from compression import zstd  # type: ignore[import-not-found,unused-ignore]
    except ImportError:
        from backports import zstd  # type: ignore[no-redef,import-not-found,unused-ignore]

    def bounded(make: Any) -> Any:
        def decompress(data: bytes, size: int) -> bytes:
            if not 0 <= size <= MAX_CHUNK_BYTES:
                raise _Bad(
                    f"a chunk declares {size:,} bytes (at most {MAX_CHUNK_BYTES:,} are read)"
                )
            out: bytes = make().decompress(data, max_length=size + 1)
            if len(out) > size:
                raise _Bad(f"a chunk decompresses to more than its declared {size:,} bytes")
            return out

        return decompress

    storage_mcap.DECOMPRESSORS["zstd"] = bounded(zstd.ZstdDecompressor)
    storage_mcap.DECOMPRESSORS["lz4"] = bounded(lz4.frame.LZ4FrameDecompressor)


def _stamp_ns(header: Any) -> int:
    stamp = header.stamp
    sec, nanosec = int(stamp.sec), int(stamp.nanosec)
    if not 0 <= nanosec < _NS:
        raise _Bad(f"a stamp's nanosec is {nanosec} (0 … 999999999)")
    return sec * _NS + nanosec


def _frame_id(name: str) -> str:
    """A frame id as tf2 compares it: without a leading ``/``."""
    if len(name) > MAX_FRAME_ID_CHARS:
        raise _Bad(f"a frame id of {len(name)} characters (at most {MAX_FRAME_ID_CHARS})")
    return name[1:] if name.startswith("/") else name


def _matrix(transform: Any) -> Float:
    """``parent_T_child`` of a ``geometry_msgs/msg/Transform``, its quaternion normalised."""
    t, r = transform.translation, transform.rotation
    x, y, z, w = float(r.x), float(r.y), float(r.z), float(r.w)
    p = (float(t.x), float(t.y), float(t.z))
    norm = math.sqrt(x * x + y * y + z * z + w * w)
    if not (math.isfinite(norm) and all(math.isfinite(v) for v in p)):
        raise _Bad("a transform with a non-finite number")
    if abs(norm - 1.0) > QUATERNION_NORM_TOL:
        raise _Bad(f"a rotation quaternion of norm {norm:.6g} (tf2 needs unit length)")
    if max(abs(v) for v in p) > MAX_LENGTH_M:
        raise _Bad(f"a translation beyond ±{MAX_LENGTH_M:g} m")
    x, y, z, w = x / norm, y / norm, z / norm, w / norm
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w), p[0]],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w), p[1]],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y), p[2]],
            [0.0, 0.0, 0.0, 1.0],
        ]
    )


class _Tree:
    """The tf tree: each child frame's parent and transform; changing ones with their stamp."""

    def __init__(self, base: str, tip: str) -> None:
        self.base, self.tip = base, tip
        self.static: dict[str, tuple[str, Any]] = {}  # child: (parent, Transform message)
        self.moving: dict[str, tuple[str, Any, int]] = {}  # child: (parent, Transform, stamp)
        # The child frames from base and from tip up to their common ancestor, once
        # connected; recomputed only after a frame's parent changed.
        self.path: tuple[tuple[str, ...], tuple[str, ...]] | None = None
        self._changed = True
        self._on: frozenset[str] = frozenset()

    def _set_parent(self, child: str, old: str | None, parent: str) -> None:
        if old is None and len(self.static) + len(self.moving) >= MAX_FRAMES:
            raise _Bad(f"more than {MAX_FRAMES:,} frames in the tf tree")
        if old != parent:
            self._changed = True

    def set_static(self, parent: str, child: str, transform: Any) -> None:
        """Store one static transform."""
        old = self.static.get(child)
        self._set_parent(child, old[0] if old else None, parent)
        self.static[child] = (parent, transform)

    def set_moving(self, parent: str, child: str, transform: Any, stamp: int) -> bool:
        """Store one changing transform; whether it is on the compared path."""
        old = self.moving.get(child)
        self._set_parent(child, old[0] if old else self._parent(child), parent)
        self.moving[child] = (parent, transform, stamp)
        return child in self._on_path()

    def _parent(self, child: str) -> str | None:
        if child in self.moving:
            return self.moving[child][0]
        if child in self.static:
            return self.static[child][0]
        return None

    def _up(self, frame: str) -> tuple[str, ...]:
        """``frame`` and its ancestors, to the root."""
        chain = [frame]
        seen = {frame}
        parent = self._parent(frame)
        while parent is not None:
            if parent in seen:
                raise _Bad(f"the tf tree has a loop through frame {parent[:80]!r}")
            if len(chain) > MAX_DEPTH:
                raise _Bad(f"a tf tree deeper than {MAX_DEPTH} frames")
            chain.append(parent)
            seen.add(parent)
            parent = self._parent(parent)
        return tuple(chain)

    def _on_path(self) -> frozenset[str]:
        """The child frames whose transforms make up the compared path (empty: none yet)."""
        if self._changed:
            self._changed = False
            up_base, up_tip = self._up(self.base), self._up(self.tip)
            common = next((f for f in up_tip if f in set(up_base)), None)
            if common is None:
                self.path, self._on = None, frozenset()
            else:
                self.path = (up_base[: up_base.index(common)], up_tip[: up_tip.index(common)])
                self._on = frozenset((*self.path[0], *self.path[1]))
        return self._on

    def pose(self) -> tuple[Float, int | None] | None:
        """``base_T_tip`` and the stamp of its changing transforms (``None``: none changes).

        ``None`` when the frames are not connected, or the changing transforms on the
        path carry different stamps.
        """
        self._on_path()
        if self.path is None:
            return None
        up_base, up_tip = self.path
        stamps: set[int] = set()

        def to_common(chain: tuple[str, ...]) -> Float | None:
            out = None  # None: the identity (base is the common frame, as for UR's driver)
            for child in chain:  # child, its parent, …: common_T_frame = … · parent_T_child
                if child in self.moving:
                    _, transform, stamp = self.moving[child]
                    stamps.add(stamp)
                else:
                    transform = self.static[child][1]
                out = _matrix(transform) if out is None else _matrix(transform) @ out
            return out

        common_T_base, common_T_tip = to_common(up_base), to_common(up_tip)
        if len(stamps) > 1:
            return None
        stamp = stamps.pop() if stamps else None
        if common_T_tip is None:
            common_T_tip = np.eye(4)
        if common_T_base is None:
            return common_T_tip, stamp
        base_T_common = np.eye(4)  # the rigid inverse: rotation transposed
        base_T_common[:3, :3] = common_T_base[:3, :3].T
        base_T_common[:3, 3] = -common_T_base[:3, :3].T @ common_T_base[:3, 3]
        return base_T_common @ common_T_tip, stamp

    def needles(self) -> tuple[bytes, ...] | None:
        """The path's child frame ids as bytes, once the path is known (else ``None``).

        A tf message whose serialised bytes hold none of them cannot change the path
        (only a new parent of a frame on it could), so it need not be deserialised.
        """
        self._on_path()
        return None if self.path is None else tuple(f.encode() for f in self._on)


class _Joints:
    """The model's joints in a joint state's names: indices, cached per list of names."""

    def __init__(self, accepted: Sequence[Sequence[str]], bounds: Sequence[float]) -> None:
        self.accepted = [tuple(dict.fromkeys(names)) for names in accepted]
        self.bounds = np.asarray(bounds, dtype=np.float64)
        self.known = {n for names in self.accepted for n in names}
        self.ignored: set[str] = set()
        self._cache: dict[tuple[str, ...], list[int] | None] = {}

    def indices(self, names: tuple[str, ...]) -> list[int] | None:
        """Where each model joint is in ``names``; ``None`` when none of them is there.

        Raises:
            _Bad: Some of the model's joints are there and some are not, or
                one is named twice (by its own and its URDF name, say).
        """
        if names in self._cache:
            return self._cache[names]
        out = self._match(names)
        if len(self._cache) < 64:
            self._cache[names] = out
        return out

    def _match(self, names: tuple[str, ...]) -> list[int] | None:
        """:meth:`indices`, uncached; a match notes the names the model does not have."""
        if len(names) > MAX_JOINT_NAMES:
            raise _Bad(f"a joint state names {len(names):,} joints (at most {MAX_JOINT_NAMES:,})")
        where = {n: k for k, n in enumerate(names)}
        if len(where) != len(names):
            raise _Bad("a joint state names one joint twice")
        found = [[where[n] for n in options if n in where] for options in self.accepted]
        if not any(found):
            return None
        self._each_once(names, found)
        self.ignored.update(n for n in names if n not in self.known)
        return [f[0] for f in found]

    def _each_once(self, names: tuple[str, ...], found: list[list[int]]) -> None:
        """Refuse a match that lacks one of the model's joints or names one twice."""
        missing = [" or ".join(o) for o, f in zip(self.accepted, found, strict=True) if not f]
        if missing:
            raise _Bad(
                f"a joint state lacks the model's joint{'s' if len(missing) > 1 else ''} "
                f"{', '.join(missing)}; it names {', '.join(n[:60] for n in names[:20])}"
            )
        twice = [o for o, f in zip(self.accepted, found, strict=True) if len(f) > 1]
        if twice:
            raise _Bad(f"a joint state names joint {' and '.join(twice[0])} both")

    def values(self, msg: Any) -> Float | None:
        """The model's joint values in one joint state (``None``: it names none of them)."""
        names = tuple(str(n) for n in msg.name)
        at = self.indices(names)
        if at is None:
            return None
        position = np.asarray(msg.position, dtype=np.float64)
        if position.shape != (len(names),):
            raise _Bad(
                f"a joint state names {len(names)} joints but holds {position.size} positions"
            )
        q = position[at]
        bad = np.flatnonzero(~(np.abs(q) <= self.bounds))
        if bad.size:
            k = int(bad[0])
            raise _Bad(
                f"joint {self.accepted[k][0]} is {q[k]:g}, not a finite number within "
                f"±{self.bounds[k]:g}"
            )
        return q


class BagPairs:
    """The pairs (joint values, pose) of one bag, read chunk by chunk.

    Args:
        path: The bag: a directory with ``metadata.yaml``, or an ``.mcap`` / ``.db3`` file.
        joint_names: Per model joint, in model order, the names it goes by in a
            joint state (its own, its URDF joint's).
        joint_bounds: Per model joint, the largest magnitude of a valid value.
        frames: ``(from, to)``: the frame ids of the transform compared.
        topics: The topics to read.
        stamp_tolerance_s: Largest lag of a joint state before its pose (seconds).
    """

    def __init__(
        self,
        path: Path,
        *,
        joint_names: Sequence[Sequence[str]],
        joint_bounds: Sequence[float],
        frames: tuple[str, str],
        topics: BagTopics = BagTopics(),
        stamp_tolerance_s: float = DEFAULT_STAMP_TOLERANCE_S,
    ) -> None:
        if not 0.0 <= stamp_tolerance_s <= MAX_STAMP_TOLERANCE_S:
            raise BagError(
                path,
                f"stamp tolerance {stamp_tolerance_s:g} s is not within 0 … "
                f"{MAX_STAMP_TOLERANCE_S:g} s",
            )
        self.path = path
        self.frames = frames
        self.topics = topics
        self.tolerance_s = stamp_tolerance_s
        self._joints = _Joints(joint_names, joint_bounds)
        self._provenance: BagProvenance | None = None

    @property
    def provenance(self) -> BagProvenance:
        """What was read, once :meth:`chunks` has been read to its end.

        Raises:
            RuntimeError: It has not.
        """
        if self._provenance is None:
            raise RuntimeError("the bag has not been read to its end")
        return self._provenance

    def chunks(self, rows: int = DEFAULT_CHUNK_ROWS) -> Iterator[tuple[Float, Float, Float]]:
        """The pairs in the order their poses were recorded, ``rows`` at a time.

        Each chunk is ``(q, base_T_tip, t)``: ``(m, n)`` joint values, ``(m, 4, 4)``
        poses and ``(m,)`` the poses' stamps in seconds since the epoch, ``m <= rows``.

        Raises:
            BagError: The bag cannot be read, a message on a topic read is not of
                its type or not valid, a joint state lacks one of the model's
                joints, or no pose finds a joint state (all in one line).
        """
        from fkcheck.errors import missing_extra

        storage = _screen(self.path)
        try:  # before the bag is opened: a missing library is not a bad bag
            import lz4.frame  # noqa: F401
            import rosbags.rosbag2  # noqa: F401
        except ImportError as exc:
            raise (missing_extra(exc) or exc) from None
        try:
            yield from self._read(storage, rows)
        except BagError:
            raise
        except _Bad as exc:
            raise BagError(self.path, str(exc)) from None
        except Exception as exc:  # rosbags' and the bag's: any failure is one line
            text = str(exc).splitlines()[0][:300] if str(exc).strip() else type(exc).__name__
            raise BagError(self.path, f"not readable as a ROS 2 bag ({storage}): {text}") from None

    def _read(self, storage: str, rows: int) -> Iterator[tuple[Float, Float, Float]]:
        from rosbags.rosbag2 import Reader
        from rosbags.typesys import Stores, get_typestore

        _bounded_decompressors()
        store = get_typestore(Stores.ROS2_HUMBLE)
        t = self.topics
        wanted = {
            t.joint_states: JOINT_STATE_TYPE,
            t.tf: TF_MESSAGE_TYPE,
            t.tf_static: TF_MESSAGE_TYPE,
        }
        with Reader(self.path) as reader:
            conns = [c for c in reader.connections if c.topic in wanted]
            for c in conns:
                if c.msgtype != wanted[c.topic]:
                    raise BagError(
                        self.path,
                        f"topic {c.topic} holds {c.msgtype[:80]}, not {wanted[c.topic]}; name "
                        "the topics with --bag-joint-states, --bag-tf, --bag-tf-static",
                    )
            have = {c.topic for c in conns}
            for topic in (t.joint_states, t.tf):
                if topic not in have:
                    listed = ", ".join(sorted({c.topic[:80] for c in reader.connections})[:20])
                    raise BagError(
                        self.path,
                        f"no topic {topic} in the bag; it has: {listed or 'no topics'} (name "
                        "the topics with --bag-joint-states, --bag-tf, --bag-tf-static)",
                    )
            tree = _Tree(*self.frames)
            static = [c for c in conns if c.topic == t.tf_static]
            for _, _, raw in reader.messages(connections=static) if static else ():
                for tf in self._transforms(store, raw):
                    tree.set_static(
                        _frame_id(tf.header.frame_id), _frame_id(tf.child_frame_id), tf.transform
                    )
            moving = [c for c in conns if c.topic in (t.joint_states, t.tf)]
            messages = reader.messages(connections=moving)
            yield from self._pairs(store, tree, messages, rows, storage)

    def _transforms(self, store: Any, raw: Any) -> Any:
        self._size(raw)
        msg = store.deserialize_cdr(raw, TF_MESSAGE_TYPE)
        if len(msg.transforms) > MAX_TRANSFORMS:
            raise _Bad(
                f"a tf message of {len(msg.transforms):,} transforms (at most {MAX_TRANSFORMS:,})"
            )
        return msg.transforms

    def _size(self, raw: Any) -> None:
        if len(raw) > MAX_MESSAGE_BYTES:
            raise _Bad(f"a message of {len(raw):,} bytes (at most {MAX_MESSAGE_BYTES:,})")

    def _pairs(
        self, store: Any, tree: _Tree, messages: Any, rows: int, storage: str
    ) -> Iterator[tuple[Float, Float, Float]]:
        tol = round(self.tolerance_s * _NS)
        window = round(REORDER_WINDOW_S * _NS)
        js_t: list[int] = []
        js_q: list[Float] = []
        pending: deque[tuple[int, Float]] = deque()
        out_q: list[Float] = []
        out_T: list[Float] = []
        out_t: list[int] = []
        counts = {"pairs": 0, "unpaired": 0, "repeated": 0, "skipped": 0}
        span = [0, 0]
        nearest = [-1]  # the smallest lag of an unpaired pose's joint state, ns (-1: none)
        last: list[int | None] = [None]
        latest_state = [-(2**63)]

        def resolve(force: bool) -> None:
            while pending and (
                force
                or latest_state[0] > pending[0][0]
                or pending[-1][0] - pending[0][0] > window
                or len(pending) > MAX_KEPT_JOINT_STATES
            ):
                stamp, pose = pending.popleft()
                k = bisect.bisect_right(js_t, stamp) - 1
                if k >= 0 and stamp - js_t[k] <= tol:
                    if not counts["pairs"]:
                        span[:] = [stamp, stamp]
                    span[0], span[1] = min(span[0], stamp), max(span[1], stamp)
                    counts["pairs"] += 1
                    out_q.append(js_q[k])
                    out_T.append(pose)
                    out_t.append(stamp)
                else:
                    counts["unpaired"] += 1
                    if k >= 0 and (nearest[0] < 0 or stamp - js_t[k] < nearest[0]):
                        nearest[0] = stamp - js_t[k]
            # joint states older than any pose still to come can go
            horizon = (pending[0][0] if pending else (last[0] or 0)) - tol - window
            drop = bisect.bisect_left(js_t, horizon) - 1
            drop = max(drop, len(js_t) - MAX_KEPT_JOINT_STATES)
            if drop > 0:
                del js_t[:drop], js_q[:drop]

        def chunk() -> tuple[Float, Float, Float]:
            q = np.array(out_q).reshape(len(out_q), len(self._joints.accepted))
            T = np.array(out_T).reshape(len(out_T), 4, 4)
            t = np.array(out_t, dtype=np.float64) / _NS
            out_q.clear()
            out_T.clear()
            out_t.clear()
            return q, T, t

        for conn, _, raw in messages:
            if conn.topic == self.topics.joint_states:
                self._size(raw)
                msg = store.deserialize_cdr(raw, JOINT_STATE_TYPE)
                q = self._joints.values(msg)
                if q is None:
                    counts["skipped"] += 1
                    continue
                stamp = _stamp_ns(msg.header)
                k = bisect.bisect_right(js_t, stamp)
                js_t.insert(k, stamp)
                js_q.insert(k, q)
                latest_state[0] = max(latest_state[0], stamp)
            else:
                needles = tree.needles()
                if (
                    needles is not None
                    and isinstance(raw, bytes)
                    and not any(n in raw for n in needles)
                ):
                    continue  # robot_state_publisher's links, other trees: not on the path
                on_path = False
                for tf in self._transforms(store, raw):
                    on_path |= tree.set_moving(
                        _frame_id(tf.header.frame_id), _frame_id(tf.child_frame_id),
                        tf.transform, _stamp_ns(tf.header),
                    )  # fmt: skip
                if not on_path:
                    continue
                found = tree.pose()
                if found is None or found[1] is None:
                    continue
                pose, stamp = found[0], found[1]
                if stamp == last[0]:
                    counts["repeated"] += 1
                    continue
                last[0] = stamp
                pending.append((stamp, pose))
            resolve(force=False)
            if len(out_t) >= rows:
                yield chunk()
        resolve(force=True)
        if out_t:
            yield chunk()
        if not counts["pairs"]:
            raise BagError(self.path, self._nothing_paired(tree, counts["unpaired"], nearest[0]))
        self._provenance = BagProvenance(
            path=self.path, storage=storage, topics=self.topics, frames=self.frames,
            pairs=counts["pairs"], first_s=span[0] / _NS, last_s=span[1] / _NS,
            unpaired=counts["unpaired"], repeated=counts["repeated"],
            skipped_states=counts["skipped"], ignored_joints=tuple(sorted(self._joints.ignored)),
            tolerance_s=self.tolerance_s,
        )  # fmt: skip

    def _nothing_paired(self, tree: _Tree, unpaired: int, nearest_ns: int) -> str:
        """Why no pair was found, in one line."""
        a, b = self.frames
        if unpaired:
            lag = (
                f"the nearest joint state before one was {nearest_ns / 1e6:g} ms earlier"
                if nearest_ns >= 0
                else "no joint state is stamped before any of them"
            )
            return (
                f"none of the {unpaired:,} poses of {b} in {a} has a joint state stamped at or "
                f"before it within {self.tolerance_s * 1e3:g} ms ({lag}); set "
                "--bag-stamp-tolerance SECONDS if the bag's stamps lag further"
            )
        frames = sorted({*tree.static, *tree.moving, *(p[0] for p in tree.static.values()),
                         *(p[0] for p in tree.moving.values())})  # fmt: skip
        shown = ", ".join(f[:60] for f in frames[:30]) or "none"
        return (
            f"no transform of {b} in {a} changes on {self.topics.tf} (the frames the bag's "
            f"tf tree connects, or its changing transforms' stamps, do not give one); its "
            f"frames: {shown}"
        )


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
        measured._check_duplicates(q_all, poses_all, np.arange(1, count + 1, dtype=np.int64), path)
    except PosesFileError as exc:  # its rows are the pairs, counted from 1 as recorded
        raise BagError(path, exc.problem.replace("lines", "pairs", 1)) from None
    return q_all, poses_all, pair, pairs.provenance.method
