"""The yourdfpy backend: the reference URDF through yourdfpy's scene graph, and yourdfpy facts."""

from __future__ import annotations

import io
import math
import subprocess
import sys

import numpy as np
import pytest

from fkcheck.backends.base import Backend, BackendUnavailable, SharesDHFrames
from fkcheck.backends.registry import make_backend
from fkcheck.backends.yourdfpy_urdf import MeshAccessError, YourdfpyUrdf
from fkcheck.core.tolerances import ROUNDED_URDF, SAME_CHAIN
from fkcheck.errors import UnmappedFrameError, UrdfError
from fkcheck.model.read import load_model
from fkcheck.urdf.source import load_urdf
from tests.backend_cases import (
    ARM3_URDF,
    arm3_model,
    assert_every_pair_agrees,
    edited_bundled_model,
    edited_ur5_ros1,
    mapped_frames,
    pair_errors,
    rpy_rotation,
    urdf_origin_rpy,
)
from tests.helpers import assert_pose_close, random_q, ur5_ros1

yourdfpy = pytest.importorskip("yourdfpy")


@pytest.fixture(scope="module")
def backend() -> YourdfpyUrdf:
    return YourdfpyUrdf()


def load_text(text: str, **kwargs: object):
    return yourdfpy.URDF.load(io.BytesIO(text.encode()), load_meshes=False, **kwargs)


# ---------------------------------------------------------------- registry, availability


def test_registry_builds_the_backend() -> None:
    backend = make_backend("yourdfpy-urdf")
    assert isinstance(backend, YourdfpyUrdf)
    assert isinstance(backend, Backend)
    assert not isinstance(backend, SharesDHFrames)
    assert backend.name == "yourdfpy-urdf"
    assert backend.method == "URDF.update_cfg + URDF.get_transform (loop)"
    assert backend.isolated


def test_availability_is_decided_without_importing_yourdfpy() -> None:
    code = (
        "import sys\n"
        "from fkcheck.model import load_model\n"
        "from fkcheck.backends.yourdfpy_urdf import YourdfpyUrdf\n"
        "print(YourdfpyUrdf().unavailable_reason(load_model('ur5')))\n"
        "print('yourdfpy' in sys.modules, 'trimesh' in sys.modules)\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=120
    ).stdout.split("\n")
    assert out[:2] == ["None", "False False"]


def test_a_model_without_urdf_is_unavailable(backend: YourdfpyUrdf) -> None:
    planar = load_model("planar2")
    assert backend.unavailable_reason(planar) == "model has no [urdf]"
    with pytest.raises(BackendUnavailable, match=r"model has no \[urdf\]"):
        backend.frame_poses(planar, np.zeros((1, 2)), ["tcp"])


def test_missing_yourdfpy_is_reported_with_the_install_command(
    backend: YourdfpyUrdf, monkeypatch: pytest.MonkeyPatch
) -> None:
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util, "find_spec", lambda name, *a: None if name == "yourdfpy" else real(name)
    )
    reason = backend.unavailable_reason(load_model("ur5"))
    assert reason == "yourdfpy is not installed (pip install 'fkcheck[reference]')"


# ---------------------------------------------------------------- against the core


def test_continuous_flipped_and_prismatic_joints(
    backend: YourdfpyUrdf, tmp_path, rng: np.random.Generator
) -> None:
    model = arm3_model(tmp_path)
    q = random_q(model, rng, 40)
    frames = mapped_frames(model)
    assert_every_pair_agrees(model, q, frames, backend.frame_poses(model, q, frames), SAME_CHAIN)


def test_frame_without_twin_is_an_unmapped_frame_error(backend: YourdfpyUrdf) -> None:
    panda = load_model("panda")
    match = r"frame 'world' \(at the world\) has no URDF twin.*panda_link0"
    with pytest.raises(UnmappedFrameError, match=match):
        backend.frame_poses(panda, np.zeros((1, 7)), ["world", "panda_link8"])


def test_a_dh_joint_mapped_onto_a_mimic_joint_is_refused(backend: YourdfpyUrdf, tmp_path) -> None:
    # yourdfpy overwrites a mimic joint's value with its leader's, so the DH value would be lost.
    text = ARM3_URDF.replace(
        '<axis xyz="0 0 -1"/>', '<axis xyz="0 0 -1"/><mimic joint="j1" multiplier="2"/>'
    )
    model = arm3_model(tmp_path)
    (tmp_path / "arm3.urdf").write_text(text)
    with pytest.raises(UrdfError, match=r"joint 'j2' mimics 'j1' in the URDF"):
        backend.frame_poses(model, np.zeros((1, 3)), ["base", "tip"])


# ---------------------------------------------------------------- wrong mappings show up


def test_wrong_tool_mapping_shows_the_tool0_to_ee_link_rotation(
    backend: YourdfpyUrdf, tmp_path, rng: np.random.Generator
) -> None:
    # ee_link is ROS 1's (example-robot-data's ur5_robot.urdf); the bundled UR5 reads ROS 2's.
    model = load_model(edited_ur5_ros1(tmp_path, 'urdf = "tool0"', 'urdf = "ee_link"'))
    expected = (
        rpy_rotation(urdf_origin_rpy(model, "tool0")).inv()
        * rpy_rotation(urdf_origin_rpy(model, "ee_link"))
    ).magnitude()
    assert math.isclose(expected, 2 * math.pi / 3, abs_tol=ROUNDED_URDF)
    q = random_q(model, rng, 20)
    pos, rot = pair_errors(
        model, q, "base", "tool0", backend.frame_poses(model, q, ["base", "tool0"])
    )
    np.testing.assert_allclose(rot, expected, rtol=0, atol=ROUNDED_URDF)
    assert pos.max() < ROUNDED_URDF


def test_base_link_without_its_pi_turn_shows_a_pi_rotation(
    backend: YourdfpyUrdf, tmp_path, rng: np.random.Generator
) -> None:
    old = 'rpy = [0, 0, 180]\nurdf = "base_link"'
    model = edited_bundled_model(tmp_path, "ur5", old, 'urdf = "base_link"')
    expected = rpy_rotation(urdf_origin_rpy(model, "base")).magnitude()
    assert math.isclose(expected, math.pi, abs_tol=ROUNDED_URDF)
    q = random_q(model, rng, 20)
    poses = backend.frame_poses(model, q, ["base_link", "tool0"])
    _, rot = pair_errors(model, q, "base_link", "tool0", poses)
    np.testing.assert_allclose(rot, expected, rtol=0, atol=ROUNDED_URDF)


# ---------------------------------------------------------------- meshes are never opened


def test_the_mesh_handler_refuses_every_path() -> None:
    # Loading *with* meshes goes through the handler, so the handler is what guards it ...
    from fkcheck.backends import yourdfpy_urdf

    with pytest.raises(MeshAccessError, match=r"asked for 'package://nowhere/tip.stl'"):
        yourdfpy.URDF.load(
            io.BytesIO(ARM3_URDF.encode()),
            load_meshes=True,
            filename_handler=yourdfpy_urdf._refuse_mesh,
        )


def test_the_backend_loads_no_mesh(
    backend: YourdfpyUrdf, monkeypatch: pytest.MonkeyPatch, tmp_path
) -> None:
    # ... and the backend never asks for one: trimesh.load would fail if it were called.
    import trimesh

    def no_load(*args: object, **kwargs: object) -> None:
        raise AssertionError(f"trimesh.load called with {args}")

    monkeypatch.setattr(trimesh, "load", no_load)
    for model in (load_model("panda"), arm3_model(tmp_path)):
        poses = backend.frame_poses(model, np.zeros((1, model.dof)), mapped_frames(model))
        assert np.isfinite(poses).all()


# ---------------------------------------------------------------- yourdfpy facts we rely on


def test_get_transform_is_the_pose_of_frame_to_in_frame_from() -> None:
    # ROS 1's ur5_robot.urdf, where shoulder_pan_joint's parent is base_link itself (ROS 2's
    # is base_link_inertia, base_link turned π about z).
    ur5_text = load_urdf(ur5_ros1()).text
    robot = load_text(ur5_text)
    robot.update_cfg({"shoulder_pan_joint": 0.5})
    T = robot.get_transform("shoulder_link", "base_link")
    # shoulder_pan_joint: origin xyz (0, 0, 0.089159), rotation about z.
    np.testing.assert_allclose(T[:3, 3], [0.0, 0.0, 0.089159], rtol=0, atol=SAME_CHAIN)
    np.testing.assert_allclose(T[1, 0], math.sin(0.5), rtol=0, atol=SAME_CHAIN)
    assert_pose_close(robot.get_transform("base_link", "shoulder_link"), np.linalg.inv(T), 1e-15)


def test_update_cfg_does_not_clip_to_urdf_limits(backend: YourdfpyUrdf) -> None:
    ur5 = load_model("ur5")
    q = np.array([[0.3, -1.0, 4.0, 7.0, -6.5, 0.2]])  # elbow past ±π, wrists past ±2π
    got = backend.frame_poses(ur5, q, ["base", "tool0"])
    pos, rot = pair_errors(ur5, q, "base", "tool0", got)
    assert pos.max() < ROUNDED_URDF
    assert rot.max() < ROUNDED_URDF
    clipped = np.clip(q, -math.pi, math.pi)
    clipped[0, [0, 1, 3, 4, 5]] = np.clip(q[0, [0, 1, 3, 4, 5]], -6.28318530718, 6.28318530718)
    pos_c, _ = pair_errors(ur5, clipped, "base", "tool0", got)
    assert pos_c.max() > 0.01  # clipping would have been visible


def test_mimic_joints_follow_their_leader() -> None:
    robot = load_text(load_urdf(load_model("panda")).text)
    robot.update_cfg({"panda_finger_joint1": 0.03})
    left = robot.get_transform("panda_leftfinger", "panda_hand")
    right = robot.get_transform("panda_rightfinger", "panda_hand")
    # finger_joint1 slides along +y, finger_joint2 (mimic, multiplier 1) along -y.
    np.testing.assert_allclose(left[:3, 3], [0.0, 0.03, 0.0584], rtol=0, atol=1e-15)
    np.testing.assert_allclose(right[:3, 3], [0.0, -0.03, 0.0584], rtol=0, atol=1e-15)


def test_near_identity_edges_are_dropped_on_multi_edge_paths() -> None:
    # trimesh's SceneGraph.get skips edges within 1e-8 of the identity on paths of
    # two or more edges: a joint with an identity origin at |q| < 1e-8 reads as 0.
    # This is the resolution floor of the yourdfpy backend near such configurations.
    robot = load_text(ARM3_URDF.replace('xyz="0 0 0.3"', 'xyz="0 0 0"'))
    robot.update_cfg({"j1": 5e-9})
    assert robot.get_transform("l1", "base")[1, 0] == pytest.approx(5e-9, rel=1e-12)  # one edge
    assert robot.get_transform("l2", "base")[1, 3] == 0.0  # two edges: the turn is lost
    robot.update_cfg({"j1": 2e-8})
    assert robot.get_transform("l2", "base")[1, 3] == pytest.approx(0.4 * 2e-8, rel=1e-9)
