"""The Pinocchio backends: a model built from the DH table, and the reference URDF."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from fkcheck.backends.base import Backend, BackendUnavailable, SharesDHFrames
from fkcheck.backends.pinocchio_dh import PinocchioChain, PinocchioDH
from fkcheck.backends.pinocchio_urdf import PinocchioUrdf
from fkcheck.backends.registry import make_backend
from fkcheck.core.geometry import matrix_from_xyz_rpy, rot_x, rot_z, translation
from fkcheck.core.tolerances import ROUNDED_URDF, SAME_CHAIN
from fkcheck.errors import JointInputError, UnmappedFrameError
from fkcheck.model.frames import relative_pose
from fkcheck.model.read import load_model, model_from_dict
from fkcheck.model.types import Model
from tests.backend_cases import (
    arm3_model,
    assert_every_pair_agrees,
    core_frame_poses,
    edited_bundled_model,
    edited_ur5_ros1,
    mapped_frames,
    pair_errors,
    rpy_rotation,
    urdf_origin_rpy,
)
from tests.helpers import BUNDLED, assert_pose_close, assert_se3, random_q

pin = pytest.importorskip("pinocchio")


@pytest.fixture(scope="module")
def dh_backend() -> PinocchioDH:
    return PinocchioDH()


@pytest.fixture(scope="module")
def urdf_backend() -> PinocchioUrdf:
    return PinocchioUrdf()


# ---------------------------------------------------------------- registry, availability


@pytest.mark.parametrize(
    ("name", "cls"), [("pinocchio-dh", PinocchioDH), ("pinocchio-urdf", PinocchioUrdf)]
)
def test_registry_builds_the_backend(name: str, cls: type) -> None:
    backend = make_backend(name)
    assert isinstance(backend, cls)
    assert isinstance(backend, Backend)
    assert backend.name == name
    assert "forwardKinematics" in backend.method or "framesForwardKinematics" in backend.method


def test_only_the_dh_backend_shares_dh_frames() -> None:
    assert isinstance(PinocchioDH(), SharesDHFrames)
    assert not isinstance(PinocchioUrdf(), SharesDHFrames)


def test_availability_is_decided_without_importing_pinocchio() -> None:
    code = (
        "import sys\n"
        "from fkcheck.model import load_model\n"
        "from fkcheck.backends.pinocchio_dh import PinocchioDH\n"
        "from fkcheck.backends.pinocchio_urdf import PinocchioUrdf\n"
        "m = load_model('ur5')\n"
        "print(PinocchioDH().unavailable_reason(m), PinocchioUrdf().unavailable_reason(m))\n"
        "print('pinocchio' in sys.modules)\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=120
    ).stdout.split("\n")
    assert out[:2] == ["None None", "False"]


def test_a_model_without_urdf_is_unavailable_to_the_urdf_backend(
    urdf_backend: PinocchioUrdf,
) -> None:
    puma = load_model("puma560")
    assert puma.urdf is None
    assert urdf_backend.unavailable_reason(puma) == "model has no [urdf]"
    assert PinocchioDH().unavailable_reason(puma) is None
    with pytest.raises(BackendUnavailable, match=r"model has no \[urdf\]"):
        urdf_backend.frame_poses(puma, np.zeros((1, 6)), ["tcp"])


def test_missing_pinocchio_is_reported_with_the_install_command(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util, "find_spec", lambda name, *a: None if name == "pinocchio" else real(name)
    )
    ur5 = load_model("ur5")
    for backend in (PinocchioDH(), PinocchioUrdf()):
        reason = backend.unavailable_reason(ur5)
        assert reason == "pinocchio is not installed (pip install 'fkcheck[reference]')"


# ---------------------------------------------------------------- pinocchio-dh vs the core


@pytest.mark.parametrize("name", BUNDLED)
def test_dh_model_agrees_with_core_on_tcp_and_every_dh_frame(
    dh_backend: PinocchioDH, rng: np.random.Generator, name: str
) -> None:
    model = load_model(name)
    q = random_q(model, rng, 200)
    tcp = dh_backend.frame_poses(model, q, ["tcp"])
    assert tcp.shape == (1, 200, 4, 4)
    assert_pose_close(tcp[0], model.fk(q), SAME_CHAIN, f"{name} tcp")
    frames = dh_backend.dh_frames(model, q)
    assert frames.shape == (200, model.dof + 1, 4, 4)
    assert_pose_close(frames, model.fk(q, all_frames=True), SAME_CHAIN, f"{name} DH frames")
    assert_se3(frames, SAME_CHAIN)


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_the_benchmark_times_the_backends_model_with_only_a_tcp_frame(
    rng: np.random.Generator, name: str
) -> None:
    from fkcheck.bench.peers import pinocchio_model

    model = load_model(name)
    chain = PinocchioChain(model, tcp_only=True)
    ops = [f.name for f in chain.pmodel.frames if f.type == pin.FrameType.OP_FRAME]
    assert ops == ["tcp"]
    assert (chain.dh_frame_ids, chain.named_frame_ids) == ([], {})
    q = random_q(model, rng, 20)
    assert chain.tcp_frame_id is not None
    assert_pose_close(chain.poses(q, [chain.tcp_frame_id])[:, 0], model.fk(q), SAME_CHAIN, name)
    bench_model = pinocchio_model(model)
    assert [f.name for f in bench_model.frames if f.type == pin.FrameType.OP_FRAME] == ["tcp"]
    assert bench_model.nq == model.dof


@pytest.mark.parametrize("name", BUNDLED)
def test_dh_model_gives_every_named_frame(
    dh_backend: PinocchioDH, rng: np.random.Generator, name: str
) -> None:
    model = load_model(name)
    q = random_q(model, rng, 50)
    names = list(model.frames)
    poses = dh_backend.frame_poses(model, q, names)
    assert poses.shape == (len(names), 50, 4, 4)
    for frame, got, want in zip(names, poses, core_frame_poses(model, q, names), strict=True):
        assert_pose_close(got, want, SAME_CHAIN, f"{name} {frame}")


def _synthetic(convention: str, flip: bool) -> Model:
    """Revolute and prismatic joints with offsets, optionally flipped, plus base and tool."""
    rows = [
        {"name": "r1", "a": 0.10, "alpha": 0.3, "d": 0.20, "theta": 0.4},
        {"name": "p2", "type": "prismatic", "a": 0.05, "alpha": -1.1, "d": 0.15, "theta": 0.7},
        {"name": "r3", "a": 0.30, "alpha": 1.2, "d": -0.05, "theta": -0.9},
        {"name": "p4", "type": "prismatic", "a": -0.2, "alpha": 0.5, "d": 0.10, "theta": -0.3},
        {"name": "r5", "a": 0.00, "alpha": -0.6, "d": 0.25, "theta": 2.0},
    ]
    for row in rows[1:3]:
        row["flip"] = flip
    return model_from_dict(
        {
            "name": f"synthetic-{convention}",
            "convention": convention,
            "joint": rows,
            "base": {"xyz": [0.1, -0.2, 0.3], "rpy": [0.2, -0.4, 1.3]},
            "tool": {"xyz": [0.01, 0.02, 0.12], "rpy": [-0.7, 0.25, 0.5]},
        }
    )


@pytest.mark.parametrize("flip", [False, True])
@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_dh_model_agrees_with_core_on_synthetic_tables(
    dh_backend: PinocchioDH, rng: np.random.Generator, convention: str, flip: bool
) -> None:
    model = _synthetic(convention, flip)
    q = rng.uniform(-2.0, 2.0, size=(100, model.dof))
    assert_pose_close(dh_backend.frame_poses(model, q, ["tcp"])[0], model.fk(q), SAME_CHAIN, "tcp")
    assert_pose_close(
        dh_backend.dh_frames(model, q), model.fk(q, all_frames=True), SAME_CHAIN, "DH frames"
    )


@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_a_flipped_joint_is_the_unflipped_joint_at_minus_q(
    dh_backend: PinocchioDH, rng: np.random.Generator, convention: str
) -> None:
    q = rng.uniform(-2.0, 2.0, size=(20, 5))
    q_mirror = q.copy()
    q_mirror[:, 1:3] *= -1.0  # joints 2 (prismatic) and 3 (revolute) are the flipped ones
    flipped = dh_backend.dh_frames(_synthetic(convention, True), q)
    plain = dh_backend.dh_frames(_synthetic(convention, False), q_mirror)
    assert_pose_close(flipped, plain, SAME_CHAIN)
    # ... and the flip is not a no-op.
    assert np.abs(flipped - dh_backend.dh_frames(_synthetic(convention, False), q)).max() > 0.1


def _one_joint(convention: str, joint: dict[str, object]) -> Model:
    return model_from_dict(
        {
            "name": "one",
            "convention": convention,
            "joint": [{"name": "j", **joint}],
            "base": {"xyz": [0.3, 0.1, -0.2], "rpy": [0.0, 0.0, 0.5]},
            "tool": {"xyz": [0.0, 0.0, 0.1]},
        }
    )


@pytest.mark.parametrize("convention", ["standard", "modified"])
@pytest.mark.parametrize("jtype", ["revolute", "prismatic"])
def test_one_flipped_joint_with_offsets_by_hand(
    dh_backend: PinocchioDH, convention: str, jtype: str
) -> None:
    a, alpha, d, theta, q = 0.2, 0.6, 0.15, 0.4, 0.35
    model = _one_joint(
        convention,
        {"type": jtype, "a": a, "alpha": alpha, "d": d, "theta": theta, "flip": True},
    )
    # A flipped joint enters as -q: θ = -q + θ_off (revolute), d = -q + d_off (prismatic).
    th, dd = (theta - q, d) if jtype == "revolute" else (theta, d - q)
    if convention == "standard":
        A = rot_z(th) @ translation(0, 0, dd) @ translation(a, 0, 0) @ rot_x(alpha)
    else:
        A = rot_x(alpha) @ translation(a, 0, 0) @ rot_z(th) @ translation(0, 0, dd)
    base = translation(0.3, 0.1, -0.2) @ rot_z(0.5)
    expected = base @ A @ translation(0, 0, 0.1)
    got = dh_backend.frame_poses(model, np.array([[q]]), ["tcp"])[0, 0]
    assert_pose_close(got, expected, SAME_CHAIN, f"{convention} {jtype}")


def test_dh_model_base_and_tool_use_urdf_rpy(dh_backend: PinocchioDH) -> None:
    # Base and tool rpy are rebuilt with Pinocchio's rpyToMatrix: same URDF convention.
    model = _synthetic("standard", False)
    frames = dh_backend.dh_frames(model, np.zeros((1, model.dof)))
    assert_pose_close(
        frames[0, 0], matrix_from_xyz_rpy([0.1, -0.2, 0.3], [0.2, -0.4, 1.3]), SAME_CHAIN
    )


def test_dh_model_rejects_bad_joint_values(dh_backend: PinocchioDH) -> None:
    ur5 = load_model("ur5")
    with pytest.raises(JointInputError, match="expected 6 joint values"):
        dh_backend.frame_poses(ur5, np.zeros((3, 5)), ["tcp"])
    with pytest.raises(JointInputError, match="must be finite"):
        dh_backend.dh_frames(ur5, np.full((1, 6), np.nan))


# ---------------------------------------------------------------- Panda: modified DH vs URDF


def test_modified_dh_panda_matches_the_panda_urdf_link_frames(
    dh_backend: PinocchioDH, urdf_backend: PinocchioUrdf, rng: np.random.Generator
) -> None:
    panda = load_model("panda")
    assert panda.convention == "modified"
    q = random_q(panda, rng, 200)
    names = [f"panda_link{i}" for i in range(9)]
    from_dh = dh_backend.frame_poses(panda, q, names)
    from_urdf = urdf_backend.frame_poses(panda, q, names)
    # This URDF writes π/2 to full double precision, so the two chains agree to round-off.
    for i, name in enumerate(names):
        assert_pose_close(
            relative_pose(from_dh[0], from_dh[i]),
            relative_pose(from_urdf[0], from_urdf[i]),
            SAME_CHAIN,
            f"panda_link0 -> {name}",
        )


# ---------------------------------------------------------------- pinocchio-urdf


def test_urdf_continuous_flipped_and_prismatic_joints(
    urdf_backend: PinocchioUrdf, tmp_path, rng: np.random.Generator
) -> None:
    model = arm3_model(tmp_path)
    pmodel = pin.buildModelFromXML((tmp_path / "arm3.urdf").read_text())
    assert [pmodel.joints[i].nq for i in range(1, pmodel.njoints)] == [2, 2, 1]  # (cos, sin)
    q = random_q(model, rng, 100)
    frames = mapped_frames(model)
    assert_every_pair_agrees(model, q, frames, urdf_backend.frame_poses(model, q, frames), 1e-12)


def test_urdf_frame_without_twin_is_an_unmapped_frame_error(urdf_backend: PinocchioUrdf) -> None:
    ur5 = load_model("ur5")
    with pytest.raises(
        UnmappedFrameError, match=r"frame 'tcp' \(at the tcp\) has no URDF twin.*base, base_link"
    ):
        urdf_backend.frame_poses(ur5, np.zeros((1, 6)), ["base", "tcp"])


def test_urdf_wrong_tool_mapping_shows_the_tool0_to_ee_link_rotation(
    urdf_backend: PinocchioUrdf, tmp_path, rng: np.random.Generator
) -> None:
    # ee_link is ROS 1's (example-robot-data's ur5_robot.urdf); the bundled UR5 reads ROS 2's.
    model = load_model(edited_ur5_ros1(tmp_path, 'urdf = "tool0"', 'urdf = "ee_link"'))
    # Expected: the fixed rotation between the two links, from the URDF's own origins.
    expected = (
        rpy_rotation(urdf_origin_rpy(model, "tool0")).inv()
        * rpy_rotation(urdf_origin_rpy(model, "ee_link"))
    ).magnitude()
    assert math.isclose(expected, 2 * math.pi / 3, abs_tol=ROUNDED_URDF)
    q = random_q(model, rng, 50)
    pos, rot = pair_errors(
        model, q, "base", "tool0", urdf_backend.frame_poses(model, q, ["base", "tool0"])
    )
    np.testing.assert_allclose(rot, expected, rtol=0, atol=ROUNDED_URDF)
    assert pos.max() < ROUNDED_URDF  # same origin: only the rotation is wrong


def test_urdf_base_link_without_its_pi_turn_shows_a_pi_rotation(
    urdf_backend: PinocchioUrdf, tmp_path, rng: np.random.Generator
) -> None:
    old = 'rpy = [0, 0, 180]\nurdf = "base_link"'
    model = edited_bundled_model(tmp_path, "ur5", old, 'urdf = "base_link"')
    expected = rpy_rotation(urdf_origin_rpy(model, "base")).magnitude()
    assert math.isclose(expected, math.pi, abs_tol=ROUNDED_URDF)
    q = random_q(model, rng, 50)
    poses = urdf_backend.frame_poses(model, q, ["base_link", "tool0"])
    _, rot = pair_errors(model, q, "base_link", "tool0", poses)
    np.testing.assert_allclose(rot, expected, rtol=0, atol=ROUNDED_URDF)
