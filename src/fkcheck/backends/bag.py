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
at most :data:`MAX_CHUNK_BYTES` (rosbags' decompressors are replaced only while its
reader runs: :class:`_BoundedDecompression`). Messages are at most :data:`MAX_MESSAGE_BYTES`,
a joint state names at most :data:`MAX_JOINT_NAMES` joints, a tf message holds at
most :data:`MAX_TRANSFORMS` transforms, the tree at most :data:`MAX_FRAMES` frames.
Anything the reader cannot read (a truncated file, a corrupt database, bad
metadata) is one line naming the bag, never a traceback.

The bag's files are screened and its limits set in :mod:`.bag_screen`, the tf
tree is :mod:`.bag_tf`, the joint states' names are matched in :mod:`.bag_joints`;
this module reads the messages and pairs them; :mod:`.bag_recording` gives the pairs
to the check (:func:`bag_pairs`, :class:`BagRecording`, :func:`read_bag`).

Reading streams: :class:`BagPairs` yields the pairs in chunks of a bounded number
of rows, and keeps only the joint states of the last
:data:`REORDER_WINDOW_S` of stamps, so memory does not grow with the bag's length.
"""

from __future__ import annotations

import bisect
import threading
from collections import deque
from collections.abc import Callable, Generator, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from fkcheck.backends.bag_joints import _Joints
from fkcheck.backends.bag_recording import BagRecording, bag_pairs, read_bag
from fkcheck.backends.bag_screen import MAX_DEPTH as MAX_DEPTH
from fkcheck.backends.bag_screen import MAX_FRAME_ID_CHARS as MAX_FRAME_ID_CHARS
from fkcheck.backends.bag_screen import MAX_FRAMES as MAX_FRAMES
from fkcheck.backends.bag_screen import MAX_JOINT_NAMES as MAX_JOINT_NAMES
from fkcheck.backends.bag_screen import (
    MAX_MESSAGE_BYTES,
    MAX_TRANSFORMS,
    BagError,
    _Bad,
    _screen,
    bag_files,
    is_bag,
)
from fkcheck.backends.bag_screen import MAX_METADATA_BYTES as MAX_METADATA_BYTES
from fkcheck.backends.bag_screen import QUATERNION_NORM_TOL as QUATERNION_NORM_TOL
from fkcheck.backends.bag_tf import _NS, _frame_id, _stamp_ns, _Tree
from fkcheck.backends.registry import BackendOptions
from fkcheck.core.typing import Float
from fkcheck.model.options import MAX_BAG_STAMP_TOLERANCE_S

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
#: readings of other cycles whenever one is missing (the flag's and key's rule too).
MAX_STAMP_TOLERANCE_S = MAX_BAG_STAMP_TOLERANCE_S
#: The message types read, by their ROS 2 names.
JOINT_STATE_TYPE = "sensor_msgs/msg/JointState"
TF_MESSAGE_TYPE = "tf2_msgs/msg/TFMessage"
#: Largest MCAP chunk, decompressed (bytes); ``ros2 bag record`` writes about 1 MiB.
MAX_CHUNK_BYTES = 64 << 20
#: How far (in stamps) a joint state may arrive after a pose it belongs to (seconds):
#: a pose waits for a joint state stamped after it, at most this long.
REORDER_WINDOW_S = 1.0
#: Joint states kept for pairing at most (the oldest go first).
MAX_KEPT_JOINT_STATES = 100_000
#: Rows per chunk :meth:`BagPairs.chunks` yields by default.
DEFAULT_CHUNK_ROWS = 10_000
#: Messages read at most between two chunks :meth:`BagPairs.chunks` yields: after
#: this many without a full chunk (joint states alone, other frames' transforms,
#: static transforms, pairs that come rarely), it yields a chunk of no pairs, so
#: that its caller looks at its time limit (about 0.1 s of messages); the pairs
#: found so far wait for their chunk.
QUIET_MESSAGES = 4096


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


def _bounded(make: Any) -> Callable[[bytes, int], bytes]:
    """A decompressor (rosbags' signature) that stops one byte past the declared size."""

    def decompress(data: bytes, size: int) -> bytes:
        if not 0 <= size <= MAX_CHUNK_BYTES:
            raise _Bad(f"a chunk declares {size:,} bytes (at most {MAX_CHUNK_BYTES:,} are read)")
        out: bytes = make().decompress(data, max_length=size + 1)
        if len(out) > size:
            raise _Bad(f"a chunk decompresses to more than its declared {size:,} bytes")
        return out

    return decompress


class _BoundedDecompression:
    """Makes :mod:`rosbags` decompress an MCAP chunk to at most its declared size, for a while.

    rosbags decompresses a chunk whole, then compares its size with the declared
    one: a few kilobytes of zstd can expand to gigabytes first. Its decompressors
    are a module-level table (``rosbags.rosbag2.storage_mcap.DECOMPRESSORS``, looked
    up at each chunk) that no reader takes in its place, so the bounded ones
    (:func:`_bounded`: they stop at the declared size, itself at most
    :data:`MAX_CHUNK_BYTES`) are put in it only while a bag's reader runs, as
    ``with _BOUNDED:``, and what was there before is put back when the last reader
    running leaves (two reads at once, in two threads, share one replacement: a
    lock guards the count). An entry that someone else replaced in between is left
    as they set it.
    """

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._depth = 0
        self._saved: dict[str, Callable[[bytes, int], bytes]] = {}
        self._ours: dict[str, Callable[[bytes, int], bytes]] = {}

    def __enter__(self) -> None:
        from rosbags.rosbag2 import storage_mcap

        with self._lock:
            if not self._depth:
                table = storage_mcap.DECOMPRESSORS
                self._ours = self._ours or _bounded_decompressors()
                self._saved = {codec: table[codec] for codec in self._ours if codec in table}
                table.update(self._ours)
            self._depth += 1

    def __exit__(self, *exc: object) -> None:
        from rosbags.rosbag2 import storage_mcap

        with self._lock:
            self._depth -= 1
            if self._depth:
                return
            table = storage_mcap.DECOMPRESSORS
            for codec, ours in self._ours.items():
                if table.get(codec) is not ours:
                    continue  # replaced by someone else meanwhile: theirs stays
                if codec in self._saved:
                    table[codec] = self._saved[codec]
                else:
                    del table[codec]
            self._saved = {}


def _bounded_decompressors() -> dict[str, Callable[[bytes, int], bytes]]:
    """The bounded decompressors of MCAP chunks, by rosbags' codec names."""
    import lz4.frame  # type: ignore[import-untyped]

    try:
        from compression import zstd  # type: ignore[import-not-found,unused-ignore]
    except ImportError:
        from backports import zstd  # type: ignore[no-redef,import-not-found,unused-ignore]

    return {
        "zstd": _bounded(zstd.ZstdDecompressor),
        "lz4": _bounded(lz4.frame.LZ4FrameDecompressor),
    }


#: The one scoped replacement of rosbags' decompressors (:class:`_BoundedDecompression`).
_BOUNDED = _BoundedDecompression()


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
        poses and ``(m,)`` the poses' stamps in seconds since the epoch, ``m <= rows``;
        after :data:`QUIET_MESSAGES` messages without a chunk, a chunk of no pairs
        (``m = 0``, so that a caller's time limit is looked at).

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
        reading = self._read(storage, rows)
        try:
            while True:
                # rosbags' decompressors are bounded while its reader runs, not while
                # the caller holds a chunk (nor after a read that fails or is dropped)
                with _BOUNDED:
                    chunk = next(reading, None)
                if chunk is None:
                    return
                yield chunk
        except BagError:
            raise
        except _Bad as exc:
            raise BagError(self.path, str(exc)) from None
        except Exception as exc:  # rosbags' and the bag's: any failure is one line
            text = str(exc).splitlines()[0][:300] if str(exc).strip() else type(exc).__name__
            raise BagError(self.path, f"not readable as a ROS 2 bag ({storage}): {text}") from None
        finally:
            reading.close()  # the bag's files, now, when the caller stops early

    def _read(self, storage: str, rows: int) -> Generator[tuple[Float, Float, Float]]:
        from rosbags.rosbag2 import Reader
        from rosbags.typesys import Stores, get_typestore

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
            for k, (_, _, raw) in enumerate(reader.messages(connections=static) if static else ()):
                if k % QUIET_MESSAGES == QUIET_MESSAGES - 1:  # no rows yet: the caller's clock
                    yield self._no_rows()
                for tf in self._transforms(store, raw):
                    tree.set_static(
                        _frame_id(tf.header.frame_id), _frame_id(tf.child_frame_id), tf.transform
                    )
            moving = [c for c in conns if c.topic in (t.joint_states, t.tf)]
            messages = reader.messages(connections=moving)
            yield from self._pairs(store, tree, messages, rows, storage)

    def _no_rows(self) -> tuple[Float, Float, Float]:
        """A chunk of no pairs (see :data:`QUIET_MESSAGES`)."""
        return np.empty((0, len(self._joints.accepted))), np.empty((0, 4, 4)), np.empty(0)

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

        quiet = 0  # messages read since the last chunk
        for conn, _, raw in messages:
            quiet += 1
            if quiet >= QUIET_MESSAGES:  # a chunk of no rows, for the caller's clock
                quiet = 0
                yield self._no_rows()
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
                quiet = 0
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
