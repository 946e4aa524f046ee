"""ROS 2 bags written by the tests with rosbags' writer, as UR's ROS 2 driver records them.

UR's driver publishes ``/joint_states`` (the URDF's joint names) and, on ``/tf``, the
controller's ``base`` → ``tool0_controller``; ``robot_state_publisher`` adds the
URDF's links on ``/tf`` and ``/tf_static``. The poses here come from the tests' own
composition of a UR table (:func:`tests.rtde_cases.poses_of`, not fkcheck's core),
the quaternions from SciPy.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin, Writer
from rosbags.typesys import Stores, get_typestore
from scipy.spatial.transform import Rotation

__all__ = ["UR_JOINTS", "BagSpec", "trajectory", "write_bag", "write_long_bag"]

STORE = get_typestore(Stores.ROS2_HUMBLE)
#: UR's URDF joint names, in DH order.
UR_JOINTS = (
    "shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint",
    "wrist_2_joint", "wrist_3_joint",
)  # fmt: skip
#: The bag's first stamp, nanoseconds since the epoch (2023-11-14).
T0_NS = 1_700_000_000 * 1_000_000_000
#: UR e-series controllers run at 500 Hz.
PERIOD_NS = 2_000_000


def trajectory(rng: np.random.Generator, count: int) -> np.ndarray:
    """``count`` joint configurations of a smooth motion sampled at 500 Hz, ``(count, 6)``."""
    t = np.arange(count) * PERIOD_NS / 1e9
    amplitude = rng.uniform(0.5, 1.5, size=6)
    omega = rng.uniform(0.5, 2.0, size=6)
    phase = rng.uniform(-np.pi, np.pi, size=6)
    start = rng.uniform(-1.0, 1.0, size=6)
    return start + amplitude * np.sin(omega * t[:, None] + phase)


class BagSpec:
    """What a bag holds besides its joint states and poses; the defaults are the driver's.

    Attributes:
        names: The joint names written, in DH order of the values (``None``: UR's).
        order: The order the joints are written in (a permutation of 0 … 5).
        extra: Names of joints the model does not have, written after them (value 0.01).
        offset_ns: The pose's stamp minus its joint state's.
        noise: Also write other frames' transforms, changing, on ``/tf``.
        topics: ``(joint_states, tf, tf_static)``.
        joint_type: The type written on the joint-state topic.
        compress: Compress the MCAP file's chunks with zstd (as the mcap storage
            plugin may); the bag's metadata then names no compression.
    """

    def __init__(
        self,
        *,
        names: Sequence[str] = UR_JOINTS,
        order: Sequence[int] = range(6),
        extra: Sequence[str] = (),
        offset_ns: int = 0,
        noise: bool = False,
        topics: tuple[str, str, str] = ("/joint_states", "/tf", "/tf_static"),
        joint_type: str = "sensor_msgs/msg/JointState",
        compress: bool = False,
    ) -> None:
        self.compress = compress
        self.names = tuple(names)
        self.order = tuple(order)
        self.extra = tuple(extra)
        self.offset_ns = offset_ns
        self.noise = noise
        self.topics = topics
        self.joint_type = joint_type


def _time(ns: int) -> Any:
    return STORE.types["builtin_interfaces/msg/Time"](sec=ns // 10**9, nanosec=ns % 10**9)


def _header(ns: int, frame: str = "") -> Any:
    return STORE.types["std_msgs/msg/Header"](stamp=_time(ns), frame_id=frame)


def _transform(parent: str, child: str, T: np.ndarray, ns: int) -> Any:
    types = STORE.types
    x, y, z, w = Rotation.from_matrix(T[:3, :3]).as_quat()
    return types["geometry_msgs/msg/TransformStamped"](
        header=_header(ns, parent),
        child_frame_id=child,
        transform=types["geometry_msgs/msg/Transform"](
            translation=types["geometry_msgs/msg/Vector3"](x=T[0, 3], y=T[1, 3], z=T[2, 3]),
            rotation=types["geometry_msgs/msg/Quaternion"](x=x, y=y, z=z, w=w),
        ),
    )


def _tf(transforms: list[Any]) -> bytes:
    msg = STORE.types["tf2_msgs/msg/TFMessage"](transforms=transforms)
    return bytes(STORE.serialize_cdr(msg, "tf2_msgs/msg/TFMessage"))


def _random_pose(rng: np.random.Generator) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3] = Rotation.random(random_state=rng).as_matrix()
    T[:3, 3] = rng.uniform(-1, 1, size=3)
    return T


def write_bag(
    path: Path,
    q: np.ndarray,
    poses: np.ndarray,
    *,
    storage: str = "mcap",
    spec: BagSpec | None = None,
    seed: int = 0,
) -> Path:
    """Write ``q`` on the joint-state topic and ``base_T_tool0_controller`` on ``/tf``.

    One joint state and one pose per 2 ms; the static ``base_link`` → ``base`` (a half
    turn about z, as UR's description has it) and ``tool0`` → ``camera`` on
    ``/tf_static``; a ``/chatter`` topic of strings no reader reads.
    """
    spec = spec or BagSpec()
    rng = np.random.default_rng(seed)
    plugin = StoragePlugin.MCAP if storage == "mcap" else StoragePlugin.SQLITE3
    turn = np.diag([-1.0, -1.0, 1.0, 1.0])
    writer = Writer(path, version=9, storage_plugin=plugin)
    if spec.compress:
        writer.set_compression(CompressionMode.STORAGE, CompressionFormat.ZSTD)
    with writer:
        js_topic, tf_topic, static_topic = spec.topics
        js = writer.add_connection(js_topic, spec.joint_type, typestore=STORE)
        tf = writer.add_connection(tf_topic, "tf2_msgs/msg/TFMessage", typestore=STORE)
        static = writer.add_connection(static_topic, "tf2_msgs/msg/TFMessage", typestore=STORE)
        chatter = writer.add_connection("/chatter", "std_msgs/msg/String", typestore=STORE)
        statics = [_transform("base_link", "base", turn, T0_NS),
                   _transform("tool0", "camera", _random_pose(rng), T0_NS)]  # fmt: skip
        writer.write(static, T0_NS, _tf(statics))
        text = STORE.types["std_msgs/msg/String"](data="hello")
        writer.write(chatter, T0_NS, bytes(STORE.serialize_cdr(text, "std_msgs/msg/String")))
        names = [spec.names[k] for k in spec.order] + list(spec.extra)
        for k in range(q.shape[0]):
            stamp = T0_NS + k * PERIOD_NS
            values = [float(q[k, i]) for i in spec.order] + [0.01] * len(spec.extra)
            if spec.joint_type == "sensor_msgs/msg/JointState":
                msg = STORE.types["sensor_msgs/msg/JointState"](
                    header=_header(stamp),
                    name=names,
                    position=np.array(values),
                    velocity=np.zeros(len(names)),
                    effort=np.zeros(len(names)),
                )
            else:
                msg = STORE.types["std_msgs/msg/String"](data=repr(values))
            raw = bytes(STORE.serialize_cdr(msg, spec.joint_type))
            pose_stamp = stamp + spec.offset_ns
            pose = _transform("base", "tool0_controller", poses[k], pose_stamp)
            if spec.noise:  # robot_state_publisher's links, another tree, mixed in and alone
                link = _transform("base_link", "shoulder_link", _random_pose(rng), stamp)
                other = _transform("map", "odom", _random_pose(rng), stamp + 500_000)
                writer.write(tf, stamp + 100_000, _tf([link, other]))
                transforms = [_transform("world", "fixture", _random_pose(rng), stamp), pose]
            else:
                transforms = [pose]
            # the pose may be recorded before its joint state: the bag's order is arrival
            if k % 2:
                writer.write(tf, pose_stamp + 200_000, _tf(transforms))
                writer.write(js, stamp + 300_000, raw)
            else:
                writer.write(js, stamp + 150_000, raw)
                writer.write(tf, pose_stamp + 250_000, _tf(transforms))
    return path


def write_long_bag(path: Path, q: np.ndarray, pose: np.ndarray, count: int) -> Path:
    """``count`` joint states of ``q`` and poses ``pose`` at 500 Hz, written fast (mcap).

    One message of each is serialised; the copies differ only in their stamps, packed
    into the CDR bytes where the header's ``sec`` and ``nanosec`` are (after the
    4-byte encapsulation header; a TFMessage's first transform after its length too).
    """
    import struct

    names = list(UR_JOINTS)
    js = STORE.types["sensor_msgs/msg/JointState"](
        header=_header(T0_NS), name=names, position=np.asarray(q, dtype=np.float64),
        velocity=np.zeros(6), effort=np.zeros(6),
    )  # fmt: skip
    js_raw = bytearray(STORE.serialize_cdr(js, "sensor_msgs/msg/JointState"))
    tf_raw = bytearray(_tf([_transform("base", "tool0_controller", pose, T0_NS)]))
    with Writer(path, version=9, storage_plugin=StoragePlugin.MCAP) as writer:
        js_conn = writer.add_connection("/joint_states", "sensor_msgs/msg/JointState",
                                        typestore=STORE)  # fmt: skip
        tf_conn = writer.add_connection("/tf", "tf2_msgs/msg/TFMessage", typestore=STORE)
        for k in range(count):
            stamp = T0_NS + k * PERIOD_NS
            sec, nanosec = divmod(stamp, 10**9)
            struct.pack_into("<iI", js_raw, 4, sec, nanosec)
            struct.pack_into("<iI", tf_raw, 8, sec, nanosec)
            writer.write(js_conn, stamp, bytes(js_raw))
            writer.write(tf_conn, stamp + 100_000, bytes(tf_raw))
    return path
