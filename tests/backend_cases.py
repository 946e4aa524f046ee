"""Cases shared by the URDF backend tests: mapped frames, edited models, a small URDF robot."""

from __future__ import annotations

import itertools
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from fkcheck.backends import registry
from fkcheck.model.frames import frame_poses_from_dh, relative_pose
from fkcheck.model.read import bundled_model_paths, load_model
from fkcheck.model.types import Model
from fkcheck.model.write import model_to_toml
from fkcheck.urdf.source import load_urdf
from tests.helpers import assert_pose_close, rotation_angle, ur5_ros1

#: Every registered backend that reads the model's URDF (derived from the registry).
URDF_BACKENDS = registry.names(reads="urdf")

#: Bundled models with a reference URDF and frames mapped onto it.
URDF_MODELS = ["ur5", "ur3", "ur10", "panda"]


def mapped_frames(model: Model) -> list[str]:
    """Names of the model's frames that have a URDF twin."""
    return [spec.name for spec in model.frames.values() if spec.urdf is not None]


def core_frame_poses(model: Model, q: np.ndarray, frames: list[str]) -> np.ndarray:
    """The in-house core's world poses of named frames, ``(len(frames), N, 4, 4)``."""
    return frame_poses_from_dh(model, model.fk(q, all_frames=True), model.fk(q), frames)


def assert_every_pair_agrees(
    model: Model, q: np.ndarray, frames: list[str], poses: np.ndarray, tol: float
) -> None:
    """``from_T_to`` of every pair of frames agrees with the core (the roots may differ)."""
    expected = core_frame_poses(model, q, frames)
    for i, j in itertools.permutations(range(len(frames)), 2):
        assert_pose_close(
            relative_pose(poses[i], poses[j]),
            relative_pose(expected[i], expected[j]),
            tol,
            what=f"{model.name}: {frames[i]} -> {frames[j]}",
        )


def pair_errors(
    model: Model, q: np.ndarray, frame_from: str, frame_to: str, poses: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Position (m) and rotation (rad) errors of ``from_T_to`` against the core, per sample."""
    expected = core_frame_poses(model, q, [frame_from, frame_to])
    want = relative_pose(expected[0], expected[1])
    got = relative_pose(poses[0], poses[1])
    pos = np.linalg.norm(got[:, :3, 3] - want[:, :3, 3], axis=-1)
    return pos, rotation_angle(want[:, :3, :3], got[:, :3, :3])


def edited_bundled_model(tmp_path: Path, name: str, old: str, new: str) -> Model:
    """A copy of a bundled model file (or of the model file ``name``) with one exact piece
    of text replaced."""
    source = bundled_model_paths().get(name) or Path(name)
    text = source.read_text()
    assert text.count(old) == 1, f"{old!r} is not in {source.name} exactly once"
    path = tmp_path / f"{source.stem}_edited.toml"
    path.write_text(text.replace(old, new))
    return load_model(path)


def edited_ur5_ros1(tmp_path: Path, old: str, new: str) -> Path:
    """The bundled UR5 on example-robot-data's ROS 1 ``ur5_robot.urdf`` (``ur5_ros1``),
    written to a model file with one exact piece of text replaced."""
    text = model_to_toml(ur5_ros1())
    assert text.count(old) == 1, f"{old!r} is not in the ROS 1 UR5 model exactly once"
    path = tmp_path / "ur5_ros1_edited.toml"
    path.write_text(text.replace(old, new))
    return path


def urdf_origin_rpy(model: Model, child_link: str) -> tuple[float, float, float]:
    """The ``<origin rpy>`` of the joint whose child is ``child_link``, read from the URDF."""
    root = ET.fromstring(load_urdf(model).text)
    for joint in root.iter("joint"):
        child = joint.find("child")
        if child is not None and child.get("link") == child_link:
            origin = joint.find("origin")
            assert origin is not None
            r, p, y = (float(v) for v in origin.get("rpy", "0 0 0").split())
            return r, p, y
    raise AssertionError(f"no joint with child {child_link!r}")


def rpy_rotation(rpy: tuple[float, float, float]) -> Rotation:
    """URDF ``rpy`` (fixed axes x, y, z: R = Rz·Ry·Rx) as a SciPy rotation."""
    return Rotation.from_euler("xyz", rpy)


# A small robot written both ways: a URDF with two continuous joints (the second
# turning about -z) and a prismatic one, and the DH table of the same chain
# (standard DH: the -z joint is a flipped joint, the prismatic one has d = q).
ARM3_URDF = """<?xml version="1.0" encoding="utf-8"?>
<robot name="arm3">
  <link name="base"/>
  <link name="l1"/>
  <link name="l2"/>
  <link name="l3"/>
  <link name="tip">
    <visual><geometry><mesh filename="package://nowhere/tip.stl"/></geometry></visual>
  </link>
  <joint name="j1" type="continuous">
    <parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.3" rpy="0 0 0"/><axis xyz="0 0 1"/>
  </joint>
  <joint name="j2" type="continuous">
    <parent link="l1"/><child link="l2"/>
    <origin xyz="0.4 0 0" rpy="0 0 0"/><axis xyz="0 0 -1"/>
  </joint>
  <joint name="j3" type="prismatic">
    <parent link="l2"/><child link="l3"/>
    <origin xyz="0.25 0 0" rpy="0 0 0"/><axis xyz="0 0 1"/>
    <limit lower="0" upper="0.2" effort="1" velocity="1"/>
  </joint>
  <joint name="tip_joint" type="fixed">
    <parent link="l3"/><child link="tip"/>
    <origin xyz="0 0 0.05" rpy="0 0 0"/>
  </joint>
</robot>
"""

ARM3_TOML = """
name = "arm3"
convention = "standard"

[[joint]]
name = "j1"
a = 0.4
alpha = 0.0
d = 0.3

[[joint]]
name = "j2"
a = 0.25
alpha = 0.0
d = 0.0
flip = true

[[joint]]
name = "j3"
type = "prismatic"
a = 0.0
alpha = 0.0
d = 0.0
limits = [0.0, 0.2]

[tool]
xyz = [0.0, 0.0, 0.05]

[urdf]
path = "arm3.urdf"
joints = ["j1", "j2", "j3"]

[frames.base]
dh = 0
urdf = "base"

[frames.l1]
dh = 1
xyz = [-0.4, 0.0, 0.0]
urdf = "l1"

[frames.l3]
dh = 3
urdf = "l3"

[frames.tip]
dh = "tcp"
urdf = "tip"
"""


def arm3_model(tmp_path: Path) -> Model:
    """The three-joint robot, its model file and URDF written to ``tmp_path``."""
    (tmp_path / "arm3.urdf").write_text(ARM3_URDF)
    path = tmp_path / "arm3.toml"
    path.write_text(ARM3_TOML)
    return load_model(path)
