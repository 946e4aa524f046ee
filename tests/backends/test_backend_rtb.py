"""The Robotics Toolbox backends: rtb-dh, rtb-urdf and rtb-model:<Name>."""

from __future__ import annotations

import dataclasses
import importlib.util
import math
import sys
import tempfile
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from fkcheck.backends.base import Backend, BackendUnavailable, FrameUnavailable, SharesDHFrames
from fkcheck.backends.registry import BackendOptions, make_backend
from fkcheck.backends.rtb_common import INSTALL_HINT
from fkcheck.backends.rtb_dh import RtbDH, dh_robot
from fkcheck.backends.rtb_model import RtbModel
from fkcheck.backends.rtb_urdf import RtbUrdf
from fkcheck.backends.urdf_common import kinematic_text
from fkcheck.cli.main import main
from fkcheck.core.geometry import invert, matrix_from_xyz_rpy
from fkcheck.core.tolerances import SAME_CHAIN
from fkcheck.errors import BackendNotFoundError, FkcheckError, UnmappedFrameError, UrdfError
from fkcheck.model.frames import relative_pose
from fkcheck.model.read import load_model, model_from_dict
from fkcheck.model.types import Model, Offset
from fkcheck.urdf.source import load_urdf
from fkcheck.urdf.tree import chain_between
from tests.backend_cases import (
    core_frame_poses,
    mapped_frames,
)
from tests.helpers import BUNDLED, assert_pose_close, assert_se3, random_q

pytest.importorskip("roboticstoolbox")

MESH_SUFFIXES = (".stl", ".dae", ".obj")


# --------------------------------------------------------------------------- rtb-dh


def test_backends_satisfy_the_protocols() -> None:
    dh, urdf, packaged = (
        make_backend("rtb-dh"),
        make_backend("rtb-urdf"),
        make_backend("rtb-model:UR5"),
    )
    assert isinstance(dh, RtbDH)
    assert isinstance(urdf, RtbUrdf)
    assert isinstance(packaged, RtbModel)
    for backend in (dh, urdf, packaged):
        assert isinstance(backend, Backend)
        assert "eval" in backend.method  # names the RTB call actually used
    assert (dh.name, urdf.name, packaged.name) == ("rtb-dh", "rtb-urdf", "rtb-model:UR5")
    assert isinstance(dh, SharesDHFrames)
    assert not isinstance(urdf, SharesDHFrames)
    assert not isinstance(packaged, SharesDHFrames)


@pytest.mark.parametrize("name", BUNDLED)
def test_rtb_dh_agrees_with_core_on_every_dh_frame(name: str, rng: np.random.Generator) -> None:
    model = load_model(name)
    q = random_q(model, rng, 300)
    backend = RtbDH("", BackendOptions())
    assert backend.unavailable_reason(model) is None
    frames = backend.dh_frames(model, q)
    assert frames.shape == (300, model.dof + 1, 4, 4)
    assert_pose_close(frames, model.fk(q, all_frames=True), SAME_CHAIN, what=f"{name} DH frames")
    assert_se3(frames, SAME_CHAIN)


@pytest.mark.parametrize("name", BUNDLED)
def test_rtb_dh_agrees_with_core_on_every_named_frame(name: str, rng: np.random.Generator) -> None:
    model = load_model(name)
    q = random_q(model, rng, 300)
    names = list(model.frames)
    poses = RtbDH().frame_poses(model, q, names)
    assert poses.shape == (len(names), 300, 4, 4)
    for frame, got, want in zip(names, poses, core_frame_poses(model, q, names), strict=True):
        assert_pose_close(got, want, SAME_CHAIN, what=f"{name} {frame}")
    (tcp,) = RtbDH().frame_poses(model, q, ["tcp"])
    assert_pose_close(tcp, model.fk(q), SAME_CHAIN, what=f"{name} tcp")
    # Without "tcp" the backend skips the TCP (and unused DH frames): same answers.
    rest = [frame for frame in names if frame != "tcp"]
    for frame, got, want in zip(
        rest, RtbDH().frame_poses(model, q, rest), core_frame_poses(model, q, rest), strict=True
    ):
        assert_pose_close(got, want, SAME_CHAIN, what=f"{name} {frame} without tcp")


def _synthetic(convention: str, rows: list[dict[str, Any]]) -> Model:
    return model_from_dict(
        {
            "name": f"synthetic-{convention}",
            "convention": convention,
            "joint": rows,
            "base": {"xyz": [0.12, -0.05, 0.3], "rpy": [0.2, -0.4, 1.1]},
            "tool": {"xyz": [0.01, 0.02, 0.15], "rpy": [-0.3, 0.5, 0.7]},
            "frames": {"mid": {"dh": 2, "xyz": [0.0, 0.1, 0.0], "rpy": [0.0, 0.0, 0.5]}},
        }
    )


SYNTHETIC_ROWS = [
    {"name": "r", "a": 0.2, "alpha": 0.6, "d": 0.3, "theta": 0.25},
    {"name": "r_flip", "a": -0.15, "alpha": -1.2, "d": 0.05, "theta": -0.7, "flip": True},
    {"name": "p", "type": "prismatic", "a": 0.1, "alpha": 0.9, "d": 0.2, "theta": 0.4},
    {
        "name": "p_flip",
        "type": "prismatic",
        "a": 0.05,
        "alpha": -0.3,
        "d": -0.1,
        "theta": -1.0,
        "flip": True,
    },
    {"name": "r_plain", "a": 0.3, "alpha": 0.0, "d": 0.0},
]


@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_rtb_dh_handles_flips_offsets_prismatic_base_and_tool(
    convention: str, rng: np.random.Generator
) -> None:
    model = _synthetic(convention, SYNTHETIC_ROWS)
    q = rng.uniform(-1.5, 1.5, size=(200, model.dof))
    backend = RtbDH()
    assert_pose_close(backend.dh_frames(model, q), model.fk(q, all_frames=True), SAME_CHAIN)
    names = ["world", "tcp", "mid"]
    poses = backend.frame_poses(model, q, names)
    for frame, got, want in zip(names, poses, core_frame_poses(model, q, names), strict=True):
        assert_pose_close(got, want, SAME_CHAIN, what=frame)


@pytest.mark.parametrize("convention", ["standard", "modified"])
@pytest.mark.parametrize("joint_type", ["revolute", "prismatic"])
def test_rtb_flip_means_the_joint_value_enters_negated(
    convention: str, joint_type: str, rng: np.random.Generator
) -> None:
    # Our meaning of flip: θ = −q + theta (revolute), d = −q + d (prismatic). So a
    # flipped joint at q is the unflipped joint at −q — checked on RTB alone.
    row = {"a": 0.2, "alpha": 0.7, "d": 0.3, "theta": 0.4, "type": joint_type}
    flipped = _synthetic(
        convention, [row, {**row, "flip": True, "name": "j2"}, row | {"name": "j3"}]
    )
    plain = _synthetic(convention, [row, {**row, "name": "j2"}, row | {"name": "j3"}])
    q = rng.uniform(-1.0, 1.0, size=(50, 3))
    q_neg = q * np.array([1.0, -1.0, 1.0])
    assert_pose_close(RtbDH().dh_frames(flipped, q), RtbDH().dh_frames(plain, q_neg), SAME_CHAIN)
    # ... and flip is not a no-op.
    moved = np.abs(RtbDH().dh_frames(flipped, q) - RtbDH().dh_frames(plain, q)).max()
    assert moved > 0.1


@pytest.mark.parametrize("name", ["ur5", "panda", "stanford"])
def test_rtb_dh_batched_path_matches_rtbs_own_fkine_all(
    name: str, rng: np.random.Generator
) -> None:
    # fkine_all (a Python loop of SE3 products) returns n+1 frames: frame 0 is
    # robot.base, and the tool is not applied — for standard and modified tables.
    offset = Offset(xyz=(0.1, 0.2, -0.3), rpy=(0.3, 0.2, -0.1))
    model = dataclasses.replace(load_model(name), base=offset, tool=offset)
    q = random_q(load_model(name), rng, 20)
    robot = dh_robot(model)
    loop = np.array([[T.A for T in robot.fkine_all(row)] for row in q])
    assert loop.shape == (20, model.dof + 1, 4, 4)
    np.testing.assert_array_equal(loop[:, 0], np.broadcast_to(model.base.matrix, (20, 4, 4)))
    assert_pose_close(RtbDH().dh_frames(model, q), loop, SAME_CHAIN)
    fkine = np.array([robot.fkine(row).A for row in q])
    (tcp,) = RtbDH().frame_poses(model, q, ["tcp"])
    assert_pose_close(tcp, fkine, SAME_CHAIN)


@pytest.mark.parametrize("n_samples", [1, 2, 7])
def test_rtb_dh_one_joint_chain_over_a_batch(n_samples: int) -> None:
    # Regression: RTB's C eval takes a (N, 1) q as one configuration; the backend pads q.
    model = model_from_dict(
        {"name": "one", "convention": "standard", "joint": [{"a": 0.5, "alpha": 0.3, "d": 0.1}]}
    )
    q = np.linspace(-1.0, 1.0, n_samples).reshape(-1, 1)
    frames = RtbDH().dh_frames(model, q)
    assert frames.shape == (n_samples, 2, 4, 4)
    assert_pose_close(frames, model.fk(q, all_frames=True), SAME_CHAIN)
    # By hand: the link end sits at a·(cos q, sin q, 0) + (0, 0, d).
    expected = np.stack([0.5 * np.cos(q[:, 0]), 0.5 * np.sin(q[:, 0]), np.full(n_samples, 0.1)], 1)
    np.testing.assert_allclose(frames[:, 1, :3, 3], expected, rtol=0, atol=SAME_CHAIN)


# --------------------------------------------------------------------------- rtb-urdf


def test_rtb_urdf_frame_without_twin_is_an_unmapped_frame_error() -> None:
    model = load_model("ur5")
    with pytest.raises(
        UnmappedFrameError, match=r"frame 'tcp' \(at the tcp\) has no URDF twin.*base_link"
    ):
        RtbUrdf().frame_poses(model, np.zeros((1, 6)), ["base", "tcp"])


def test_rtb_urdf_without_urdf_table_is_unavailable() -> None:
    model = load_model("puma560")
    assert RtbUrdf().unavailable_reason(model) == "model has no [urdf]"
    with pytest.raises(BackendUnavailable, match=r"model has no \[urdf\]"):
        RtbUrdf().frame_poses(model, np.zeros((1, 6)), ["world", "tcp"])


_WATCHED: list[str] | None = None


def _audit(event: str, args: tuple[Any, ...]) -> None:
    if _WATCHED is not None and event == "open" and isinstance(args[0], str | Path):
        _WATCHED.append(str(args[0]))


@pytest.fixture
def opened_files() -> Any:
    """Every file opened while the test runs (a process-wide audit hook, armed per test)."""
    global _WATCHED
    if not getattr(sys, "_fkcheck_rtb_audit", False):
        sys.addaudithook(_audit)
        sys._fkcheck_rtb_audit = True  # type: ignore[attr-defined]
    _WATCHED = []
    yield _WATCHED
    _WATCHED = None


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_rtb_urdf_never_opens_a_mesh_file(name: str, opened_files: list[str]) -> None:
    model = load_model(name)
    poses = RtbUrdf().frame_poses(model, np.zeros((3, model.dof)), mapped_frames(model))
    assert np.isfinite(poses).all()
    assert "<mesh" in load_urdf(model).text  # the URDF does name mesh files
    assert [p for p in opened_files if p.lower().endswith(MESH_SUFFIXES)] == []


# A 2R arm whose DH table is known by construction: a1 = 0.5, a2 = 0.3, the second
# joint turning about −z (flip), an unmapped prismatic finger, the joints declared
# out of order. Meshes come from a package next to the model.
_URDF = """<?xml version="1.0"?>
<robot name="two_r">
  <link name="base"/>
  <link name="l1">
    <visual><geometry><mesh filename="package://meshpkg/meshes/l1.stl"/></geometry></visual>
  </link>
  <link name="l2"/>
  <link name="tip"/>
  <link name="finger"/>
  <joint name="finger_joint" type="prismatic">
    <parent link="l2"/><child link="finger"/><origin xyz="0.3 0 0" rpy="0 0 0"/>
    <axis xyz="1 0 0"/><limit lower="0" upper="0.1" effort="1" velocity="1"/>
  </joint>
  <joint name="tip_joint" type="fixed">
    <parent link="l2"/><child link="tip"/><origin xyz="0.3 0 0" rpy="0 0 0"/>
  </joint>
  <joint name="j2" type="revolute">
    <parent link="l1"/><child link="l2"/><origin xyz="0.5 0 0" rpy="0 0 0"/>
    <axis xyz="{j2_axis}"/><limit lower="-3" upper="3" effort="1" velocity="1"/>
  </joint>
  <joint name="j1" type="continuous">
    <parent link="base"/><child link="l1"/><origin xyz="0 0 0" rpy="0 0 0"/>
    <axis xyz="0 0 1"/>
  </joint>
  {extra}
</robot>
"""


def _two_r(tmp_path: Path, *, mesh: bool = True, extra: str = "", j2_axis: str = "0 0 -1") -> Model:
    urdf = tmp_path / "robot" / "urdf" / "two_r.urdf"
    urdf.parent.mkdir(parents=True)
    urdf.write_text(_URDF.replace("{extra}", extra).replace("{j2_axis}", j2_axis))
    if mesh:
        (tmp_path / "meshpkg" / "meshes").mkdir(parents=True)
        (tmp_path / "meshpkg" / "meshes" / "l1.stl").write_text("solid l1\nendsolid l1\n")
    data = {
        "name": "two_r",
        "convention": "standard",
        "joint": [{"name": "q1", "a": 0.5, "alpha": 0, "d": 0},
                  {"name": "q2", "a": 0.3, "alpha": 0, "d": 0, "flip": True}],
        "urdf": {"path": "urdf/two_r.urdf", "joints": ["j1", "j2"]},
        "frames": {"base": {"dh": 0, "urdf": "base"}, "tip": {"dh": 2, "urdf": "tip"},
                   "finger": {"dh": 2, "urdf": "finger"}, "l1": {"dh": 1, "urdf": "l1"}},
    }  # fmt: skip
    return model_from_dict(data, tmp_path / "robot" / "two_r.toml")


def test_rtb_urdf_maps_joints_by_name_and_leaves_others_at_zero(
    tmp_path: Path, rng: np.random.Generator, opened_files: list[str]
) -> None:
    model = _two_r(tmp_path)
    opened_files.clear()  # _two_r wrote the mesh file itself
    q = rng.uniform(-3.0, 3.0, size=(100, 2))
    base, l1, tip, finger = RtbUrdf().frame_poses(model, q, ["base", "l1", "tip", "finger"])
    # By hand: tip = Rz(q1)·Tx(0.5)·Rz(−q2)·Tx(0.3) in the root.
    q1, q2 = q[:, 0], q[:, 1]
    expected_xy = np.stack(
        [0.5 * np.cos(q1) + 0.3 * np.cos(q1 - q2), 0.5 * np.sin(q1) + 0.3 * np.sin(q1 - q2)], 1
    )
    np.testing.assert_array_equal(base, np.broadcast_to(np.eye(4), (100, 4, 4)))
    np.testing.assert_allclose(tip[:, :2, 3], expected_xy, rtol=0, atol=SAME_CHAIN)
    np.testing.assert_allclose(tip[:, 0, 0], np.cos(q1 - q2), rtol=0, atol=SAME_CHAIN)
    np.testing.assert_allclose(l1[:, 0, 0], np.cos(q1), rtol=0, atol=SAME_CHAIN)
    assert_pose_close(finger, tip, SAME_CHAIN, what="unmapped finger joint at 0")
    ours = core_frame_poses(model, q, ["base", "tip"])
    assert_pose_close(relative_pose(base, tip), relative_pose(ours[0], ours[1]), SAME_CHAIN)
    assert [p for p in opened_files if p.endswith(".stl")] == []


def test_rtb_urdf_needs_no_mesh_file(tmp_path: Path, opened_files: list[str]) -> None:
    # Geometry never reaches RTB's reader: a URDF whose meshes are absent — a
    # package nobody can find, a path that does not exist — is read all the same.
    model = _two_r(tmp_path, mesh=False)
    urdf = tmp_path / "robot" / "urdf" / "two_r.urdf"
    urdf.write_text(
        urdf.read_text().replace(
            '<link name="l2"/>',
            '<link name="l2"><collision><geometry><mesh filename="/no/such/l2.stl"/>'
            "</geometry></collision></link>",
        )
    )
    opened_files.clear()
    q = np.array([[0.3, -0.2]])
    base, tip = RtbUrdf().frame_poses(model, q, ["base", "tip"])
    expected = [0.5 * np.cos(0.3) + 0.3 * np.cos(0.5), 0.5 * np.sin(0.3) + 0.3 * np.sin(0.5)]
    np.testing.assert_allclose(
        relative_pose(base, tip)[0, :2, 3], expected, rtol=0, atol=SAME_CHAIN
    )
    assert [p for p in opened_files if p.endswith(".stl")] == []


def test_kinematic_text_keeps_links_and_joints_verbatim(tmp_path: Path) -> None:
    model = _two_r(tmp_path)
    text = kinematic_text(load_urdf(model))
    assert "<mesh" not in text
    assert "<visual" not in text
    assert '<link name="l1"' in text
    assert '<axis xyz="0 0 -1" />' in text
    assert '<origin xyz="0.5 0 0" rpy="0 0 0" />' in text


def test_a_mimic_naming_no_joint_is_refused_before_rtb_reads_it(tmp_path: Path) -> None:
    # A <mimic> without the joint it mimics: RTB's reader refused it, others ignored it;
    # fkcheck's screen now refuses it for every reader (issue 31).
    extra = (
        '<link name="ghost"/><joint name="dangling" type="fixed"><parent link="tip"/>'
        '<child link="ghost"/><origin xyz="0 0 0" rpy="0 0 0"/><mimic/></joint>'
    )
    model = _two_r(tmp_path, extra=extra)
    before = set(Path(tempfile.gettempdir()).glob("rtb-expanded-*"))
    with pytest.raises(
        UrdfError, match=r"two_r\.urdf: line \d+: joint 'dangling': <mimic joint> names no joint"
    ):
        RtbUrdf().frame_poses(model, np.zeros((1, 2)), ["base", "tip"])
    # URDF_file would save the text it failed on in the temp directory; it is never used.
    assert set(Path(tempfile.gettempdir()).glob("rtb-expanded-*")) <= before


def test_rtb_urdf_refuses_links_below_a_crooked_axis(tmp_path: Path) -> None:
    # RTB's reader turns axis v = (0, 0.6, 0.8) into a fixed rotation by |v| = 1 rad
    # about v followed by a z joint: wrong even at q = 0 (upstream limitation).
    model = _two_r(tmp_path, j2_axis="0 0.6 0.8")
    q = np.array([[0.4, 0.0]])
    with pytest.raises(BackendUnavailable, match=r"joint 'j2' has axis \(0 0\.6 0\.8\).*'tip'"):
        RtbUrdf().frame_poses(model, q, ["base", "tip"])
    # Links above that joint are still computed: l1 = Rz(0.4).
    base, l1 = RtbUrdf().frame_poses(model, q, ["base", "l1"])
    np.testing.assert_allclose(relative_pose(base, l1)[0, :2, 0], [np.cos(0.4), np.sin(0.4)],
                               rtol=0, atol=SAME_CHAIN)  # fmt: skip


def test_one_chain_walk_serves_the_urdf_summary_and_the_joint_model(tmp_path: Path) -> None:
    from fkcheck.urdf.chain import urdf_kinematics

    info = load_urdf(_two_r(tmp_path, j2_axis="0 0.6 0.8"))
    kin = urdf_kinematics(info)
    assert [j.name for j in chain_between(info.joints, "base", "tip")] == ["j1", "j2", "tip_joint"]
    assert [j.name for j in info.chain("l1", "finger")] == ["j2", "finger_joint"]
    assert [j.name for j in kin.chain("l1", "finger")] == ["j2", "finger_joint"]
    assert chain_between(info.joints, "tip", "tip") == []
    assert chain_between(info.joints, "finger", "tip") is None  # a sibling, not below
    with pytest.raises(UrdfError, match="no chain connects 'finger' to 'tip'"):
        info.chain("finger", "tip")
    # The summary keeps each <axis xyz> as written; the RTB backend reads it there.
    assert {j.name: j.axis for j in info.joints.values()} == {
        "finger_joint": "1 0 0",
        "tip_joint": None,
        "j2": "0 0.6 0.8",
        "j1": "0 0 1",
    }


# --------------------------------------------------------------------------- rtb-model


def test_rtb_model_ur5_differs_by_its_d1_alone(rng: np.random.Generator) -> None:
    # RTB's UR5 (models/DH/UR5.py) has d = [0.089459, 0, 0, 0.10915, 0.09465, 0.0823],
    # a = [0, -0.425, -0.39225, 0, 0, 0]: only d1 differs from UR's 0.089159. In
    # standard DH, Rz(q1)·Tz(d1) = Tz(d1)·Rz(q1), so a longer d1 lifts the whole
    # arm along the base z axis: every TCP is moved by (0, 0, 0.0003) m exactly,
    # for every q, and no orientation changes.
    model = load_model("ur5")
    q = random_q(model, rng, 500)
    world, tcp = make_backend("rtb-model:UR5").frame_poses(model, q, ["world", "tcp"])
    np.testing.assert_array_equal(world, np.broadcast_to(np.eye(4), (500, 4, 4)))
    ours = model.fk(q)
    delta = tcp[:, :3, 3] - ours[:, :3, 3]
    d1_rtb, d1_ur = 0.089459, 0.089159
    np.testing.assert_allclose(delta, [[0.0, 0.0, d1_rtb - d1_ur]] * 500, rtol=0, atol=SAME_CHAIN)
    position_error = np.linalg.norm(delta, axis=1)
    assert position_error.min() >= 2.9e-4
    assert position_error.max() <= 3.1e-4
    np.testing.assert_allclose(tcp[:, :3, :3], ours[:, :3, :3], rtol=0, atol=SAME_CHAIN)


def test_rtb_model_puma560_table_is_ours(rng: np.random.Generator) -> None:
    # Same numbers both sides (RTB: d1 = 26.45 in = 0.67183 m, a2 = d4 = 0.4318,
    # a3 = 0.0203, d3 = 0.15005, α = 90, 0, −90, 90, −90, 0°; no base, no tool).
    model = load_model("puma560")
    q = random_q(model, rng, 500)
    (tcp,) = make_backend("rtb-model:Puma560").frame_poses(model, q, ["tcp"])
    assert_pose_close(tcp, model.fk(q), SAME_CHAIN)


def test_rtb_model_panda_puts_flange_in_d7_and_adds_its_hand_tool(
    rng: np.random.Generator,
) -> None:
    # RTB's Panda: d7 = 0.107 (the flange) and tool = Tz(0.103)·Rz(−45°); ours: d7 = 0
    # and tool = Tz(0.107). Tz(d7) follows Rz(q7) in A7, so RTB's TCP is ours
    # followed by Tz(0.103)·Rz(−45°), a constant, for every q.
    model = load_model("panda")
    q = random_q(model, rng, 300)
    (tcp,) = make_backend("rtb-model:Panda").frame_poses(model, q, ["tcp"])
    expected = matrix_from_xyz_rpy((0.0, 0.0, 0.103), (0.0, 0.0, -math.pi / 4))
    assert_pose_close(invert(model.fk(q)) @ tcp, np.broadcast_to(expected, (300, 4, 4)), SAME_CHAIN)


def test_rtb_model_frames_attached_to_base_or_flange_only(rng: np.random.Generator) -> None:
    model = load_model("panda")
    q = random_q(model, rng, 10)
    backend = make_backend("rtb-model:Panda")
    base, flange = backend.frame_poses(model, q, ["panda_link0", "panda_link7"])
    np.testing.assert_array_equal(base, np.broadcast_to(np.eye(4), (10, 4, 4)))
    assert_se3(flange, SAME_CHAIN)
    with pytest.raises(FrameUnavailable, match=r"'panda_link3' sits at DH frame 3, mid-chain"):
        backend.frame_poses(model, q, ["panda_link0", "panda_link3"])


def test_rtb_model_name_is_matched_case_insensitively() -> None:
    backend = make_backend("rtb-model:puma560")
    assert backend.name == "rtb-model:Puma560"
    assert "models.DH.Puma560()" in backend.method


def test_rtb_model_unknown_name_lists_the_models() -> None:
    with pytest.raises(
        BackendNotFoundError,
        match=r"unknown backend 'rtb-model:UR6'; backends are: .*rtb-model:UR5",
    ):
        make_backend("rtb-model:UR6")


def test_rtb_model_unknown_name_exits_2_with_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["check", "ur5", "--against", "rtb-model:NoSuchArm"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert "unknown backend 'rtb-model:NoSuchArm'" in err
    assert "rtb-model:Puma560" in err


def test_rtb_model_joint_count_mismatch_is_bad_input() -> None:
    with pytest.raises(FkcheckError, match=r"Panda has 7 joints but model ur5 has 6"):
        make_backend("rtb-model:Panda").frame_poses(load_model("ur5"), np.zeros((1, 6)), ["tcp"])


def test_rtb_model_joint_type_mismatch_is_bad_input() -> None:
    # RTB's Stanford has a prismatic third joint; the PUMA's is revolute.
    with pytest.raises(FkcheckError, match=r"joint 3 is prismatic .* but revolute in model"):
        make_backend("rtb-model:Stanford").frame_poses(
            load_model("puma560"), np.zeros((1, 6)), ["tcp"]
        )


# --------------------------------------------------------------------------- availability


def test_missing_library_is_reported_without_importing_it(monkeypatch: pytest.MonkeyPatch) -> None:
    real_find_spec = importlib.util.find_spec

    def find_spec(name: str, *args: Any) -> Any:
        return None if name == "roboticstoolbox" else real_find_spec(name, *args)

    model = load_model("ur5")
    backends = [RtbDH(), RtbUrdf(), make_backend("rtb-model:UR5")]
    monkeypatch.setattr(importlib.util, "find_spec", find_spec)
    for backend in backends:
        assert backend.unavailable_reason(model) == INSTALL_HINT
    assert RtbModel("UR5").name == "rtb-model:UR5"  # built without the library: not validated
