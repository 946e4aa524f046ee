"""The mujoco-urdf backend: the reference URDF through MuJoCo's importer, and MuJoCo's facts.

Each trap of MuJoCo's URDF import (fixed links fused away, massless or
ill-conditioned bodies refused, meshes opened, mimic joints left to the
dynamics) has a test here that fails without the backend's handling of it; the
"MuJoCo fact" tests show the trap on MuJoCo itself, so a MuJoCo that stops
setting it is noticed too.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from fkcheck.backends import registry
from fkcheck.backends.base import BackendUnavailable, SharesDHFrames
from fkcheck.backends.mujoco_urdf import MujocoUrdf
from fkcheck.backends.registry import make_backend
from fkcheck.backends.urdf_common import kinematic_text
from fkcheck.core.tolerances import FINITE_DIFFERENCE, FINITE_DIFFERENCE_STEP, ROUNDED_URDF
from fkcheck.core.typing import JACOBIAN_REFERENCES
from fkcheck.errors import UnmappedFrameError, UrdfError
from fkcheck.model.frames import reference_poses, relative_pose
from fkcheck.model.read import load_model
from fkcheck.model.types import Model
from fkcheck.urdf.locate import locate_urdf
from fkcheck.urdf.source import load_urdf
from tests.backend_cases import (
    ARM3_TOML,
    ARM3_URDF,
    URDF_MODELS,
    arm3_model,
    assert_every_pair_agrees,
    edited_ur5_ros1,
    mapped_frames,
    pair_errors,
)
from tests.helpers import assert_pose_close, random_q

mujoco = pytest.importorskip("mujoco")

#: One small chain (arm3: three joints) in two float64 libraries: a few ulps.
ARM3_TOL = 1e-12

#: The bundled UR5's URDF: UR's ROS 2 description, bundled with fkcheck.
UR5_XACRO = "fkcheck:ur_description/urdf/ur.urdf.xacro"
#: UR5's older, plain ROS 1 URDF (example-robot-data's), for a copy to seed a fault into.
UR5_ROS1_URDF = "example-robot-data:ur_description/urdf/ur5_robot.urdf"


@pytest.fixture(scope="module")
def backend() -> MujocoUrdf:
    return MujocoUrdf()


def _compiled(text: str, **compiler: object) -> object:
    """MuJoCo's model of URDF text with fixed links kept and the given compiler options."""
    spec = mujoco.MjSpec.from_string(text)
    spec.compiler.fusestatic = False
    for option, value in compiler.items():
        setattr(spec.compiler, option, value)
    return spec.compile()


def _body_names(mjmodel: object) -> list[str]:
    n = mjmodel.nbody  # type: ignore[attr-defined]
    return [mujoco.mj_id2name(mjmodel, mujoco.mjtObj.mjOBJ_BODY, i) for i in range(n)]


def _arm3_with(tmp_path: Path, old: str, new: str, toml_extra: str = "") -> Model:
    """arm3 with one exact piece of its URDF replaced (and lines added to its model file)."""
    assert ARM3_URDF.count(old) == 1, old
    (tmp_path / "arm3.urdf").write_text(ARM3_URDF.replace(old, new))
    path = tmp_path / "arm3.toml"
    path.write_text(ARM3_TOML + toml_extra)
    return load_model(path)


def _placed(backend: MujocoUrdf, model: Model, q: np.ndarray, frames: list[str]) -> np.ndarray:
    """``world_T_root``: where the backend's root (the URDF's root) sits in the DH world."""
    root_T_anchor = backend.frame_poses(model, q[:1], frames[:1])[0, 0]
    world_T_anchor = reference_poses(model, q[:1], frames[:1])[0, 0]
    placed: np.ndarray = world_T_anchor @ np.linalg.inv(root_T_anchor)
    return placed


def _in_dh_world(jac: np.ndarray, world_T_root: np.ndarray, reference: str) -> np.ndarray:
    """A Jacobian in the URDF root's axes moved into the DH world's (``local`` has no root)."""
    R, t = world_T_root[:3, :3], world_T_root[:3, 3]
    v, w = R @ jac[:, :3], R @ jac[:, 3:]
    if reference == "local":
        return jac
    if reference == "world":
        v = v + np.cross(t[None, :, None], w, axis=1)
    return np.concatenate([v, w], axis=1)


# ---------------------------------------------------------------- registry, contract, availability


def test_registry_builds_it_as_a_default_urdf_reader() -> None:
    # The contract itself is the conformance suite's (tests/backends/test_conformance.py).
    backend = make_backend("mujoco-urdf")
    assert isinstance(backend, MujocoUrdf)
    assert not isinstance(backend, SharesDHFrames)
    assert (backend.evidence, backend.reads, backend.isolated) == ("table", "urdf", False)
    assert backend.imports == ("mujoco",)
    assert backend.jacobian_method is not None
    assert "mj_jacBody" in backend.jacobian_method
    assert set(backend.jacobian_references) == set(JACOBIAN_REFERENCES)
    defaults = registry.default_names()
    assert defaults[defaults.index("rtb-urdf") + 1] == "mujoco-urdf"
    assert "mujoco-urdf" in registry.names(reads="urdf")
    assert "mujoco-urdf" in registry.known_difference_names()


def test_a_model_without_urdf_is_unavailable_and_reads_nothing(backend: MujocoUrdf) -> None:
    planar = load_model("planar2")
    assert backend.unavailable_reason(planar) == "model has no [urdf]"
    assert backend.inputs(planar) == ()
    with pytest.raises(BackendUnavailable, match=r"model has no \[urdf\]"):
        backend.frame_poses(planar, np.zeros((1, 2)), ["tcp"])


def test_inputs_is_the_models_urdf(backend: MujocoUrdf, tmp_path: Path) -> None:
    assert backend.inputs(load_model("ur5")) == (locate_urdf(UR5_XACRO)[0],)
    assert backend.inputs(arm3_model(tmp_path)) == (tmp_path / "arm3.urdf",)


def test_missing_mujoco_is_reported_with_the_install_command(
    backend: MujocoUrdf, monkeypatch: pytest.MonkeyPatch
) -> None:
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util, "find_spec", lambda name, *a: None if name == "mujoco" else real(name)
    )
    reason = backend.unavailable_reason(load_model("ur5"))
    assert reason == "mujoco is not installed (pip install 'fkcheck[reference]')"


# ---------------------------------------------------------------- against the core


@pytest.mark.parametrize("name", URDF_MODELS)
def test_jacobians_agree_with_core_in_every_reference(
    backend: MujocoUrdf, rng: np.random.Generator, name: str
) -> None:
    model = load_model(name)
    q = random_q(model, rng, 10)
    frames = mapped_frames(model)
    world_T_root = _placed(backend, model, q, frames)
    for frame in frames:
        for reference in JACOBIAN_REFERENCES:
            jac = backend.frame_jacobian(model, q, frame, reference)
            assert jac.shape == (10, 6, model.dof)
            np.testing.assert_allclose(
                _in_dh_world(jac, world_T_root, reference),
                model.jacobian(q, frame, reference),
                rtol=0,
                atol=ROUNDED_URDF,
                err_msg=f"{name} {frame} {reference}",
            )


def test_continuous_flipped_and_prismatic_joints(
    backend: MujocoUrdf, tmp_path: Path, rng: np.random.Generator
) -> None:
    model = arm3_model(tmp_path)
    q = random_q(model, rng, 50)
    frames = mapped_frames(model)
    poses = backend.frame_poses(model, q, frames)
    assert_every_pair_agrees(model, q, frames, poses, ARM3_TOL)
    world_T_root = _placed(backend, model, q, frames)
    for frame in frames:
        for reference in JACOBIAN_REFERENCES:
            np.testing.assert_allclose(
                _in_dh_world(backend.frame_jacobian(model, q, frame, reference), world_T_root,
                             reference),
                model.jacobian(q, frame, reference),
                rtol=0, atol=ARM3_TOL, err_msg=f"{frame} {reference}",
            )  # fmt: skip


def test_the_urdf_root_is_the_root_of_the_poses(backend: MujocoUrdf, tmp_path: Path) -> None:
    # arm3's root link `base` becomes a body at MuJoCo's world origin; the UR5's root
    # link is named `world`, which *is* MuJoCo's world body.
    model = arm3_model(tmp_path)
    q = np.array([[0.4, -1.1, 0.05]])
    np.testing.assert_array_equal(backend.frame_poses(model, q, ["base"])[0, 0], np.eye(4))
    ur5 = _compiled(
        kinematic_text(load_urdf(load_model("ur5")), inertials=False),
        boundmass=1.0,
        boundinertia=1.0,
    )
    assert _body_names(ur5)[0] == "world"
    assert "world" in load_urdf(load_model("ur5")).links


def test_joint_values_beyond_the_urdf_limits_are_used_as_given(backend: MujocoUrdf) -> None:
    ur5 = load_model("ur5")
    q = np.array([[0.3, -1.0, 4.0, 7.0, -6.5, 0.2]])  # elbow past ±π, wrists past ±2π
    pos, rot = pair_errors(ur5, q, "base", "tool0", backend.frame_poses(ur5, q, ["base", "tool0"]))
    assert pos.max() < ROUNDED_URDF
    assert rot.max() < ROUNDED_URDF


def test_frame_without_twin_is_an_unmapped_frame_error(backend: MujocoUrdf) -> None:
    ur5 = load_model("ur5")
    with pytest.raises(UnmappedFrameError, match=r"frame 'tcp' \(at the tcp\) has no URDF twin"):
        backend.frame_poses(ur5, np.zeros((1, 6)), ["base", "tcp"])


# ---------------------------------------------------------------- a wrong URDF shows up


@pytest.fixture
def ur5_with_a_longer_upper_arm(tmp_path: Path) -> Path:
    """The UR5 on a copy of its plain ROS 1 URDF (``ur5_ros1``: the bundled model reads
    ROS 2's xacro) whose elbow joint sits 0.1 mm further out."""
    text = locate_urdf(UR5_ROS1_URDF)[0].read_text()
    old = 'xyz="0.0 -0.1197 0.425"'
    assert text.count(old) == 1
    (tmp_path / "ur5.urdf").write_text(text.replace(old, 'xyz="0.0 -0.1197 0.4251"'))
    return edited_ur5_ros1(tmp_path, UR5_ROS1_URDF, "ur5.urdf")


def test_a_seeded_urdf_fault_makes_it_disagree_with_the_core(
    backend: MujocoUrdf, ur5_with_a_longer_upper_arm: Path, rng: np.random.Generator
) -> None:
    model = load_model(ur5_with_a_longer_upper_arm)
    q = random_q(model, rng, 50)
    pos, _ = pair_errors(
        model, q, "base", "tool0", backend.frame_poses(model, q, ["base", "tool0"])
    )
    assert pos.min() > 0.5e-4  # the 0.1 mm shows at every configuration ...
    assert pos.max() < 1.5e-4  # ... and is all there is
    world_T_root = _placed(backend, model, q, ["base"])
    jac = _in_dh_world(backend.frame_jacobian(model, q, "tool0", "world-aligned"), world_T_root,
                       "world-aligned")  # fmt: skip
    gap = np.abs(jac - model.jacobian(q, "tool0", "world-aligned"))
    assert gap[:, :3, :3].max() > 0.5e-4  # the shoulder and elbow columns see the longer arm


# ---------------------------------------------------------------- the command line


def test_fkcheck_check_ur5_against_mujoco_urdf_passes(capsys: pytest.CaptureFixture[str]) -> None:
    from fkcheck.cli.main import main

    code = main(["check", "ur5", "--against", "mujoco-urdf", "--samples", "200"])
    out, err = capsys.readouterr()
    assert code == 0, out + err
    assert "mujoco-urdf" in out
    assert "verdict: pass" in out
    for reference in JACOBIAN_REFERENCES:  # its own Jacobians, not differences of its poses
        argv = ["check", "ur5", "--against", "mujoco-urdf", "--samples", "50", "--jacobian"]
        code = main([*argv, "--jacobian-reference", reference])
        out, err = capsys.readouterr()
        assert code == 0, out + err
        assert f"Jacobian of tool0, {reference}," in out
        assert "mj_jacBody" in out


def test_fkcheck_check_fails_on_the_seeded_fault(
    ur5_with_a_longer_upper_arm: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from fkcheck.cli.main import main

    argv = ["check", str(ur5_with_a_longer_upper_arm), "--against", "mujoco-urdf"]
    code = main([*argv, "--samples", "50", "--no-diagnose"])
    out, err = capsys.readouterr()
    assert code == 1, out + err
    assert "verdict: fail" in out


# ---------------------------------------------------------------- trap: fixed links are fused


def test_mujoco_fact_fixed_links_are_fused_by_default() -> None:
    spec = mujoco.MjSpec.from_string(kinematic_text(load_urdf(load_model("ur5")), inertials=False))
    assert spec.compiler.fusestatic  # the URDF importer's default
    spec.compiler.boundmass = spec.compiler.boundinertia = 1.0
    bodies = _body_names(spec.compile())
    assert not {"base", "base_link", "flange", "tool0"} & set(bodies)


def test_fixed_links_are_kept_by_name(backend: MujocoUrdf, rng: np.random.Generator) -> None:
    ur5 = load_model("ur5")
    q = random_q(ur5, rng, 20)
    frames = ["base", "base_link", "tool0", "flange"]
    assert_every_pair_agrees(ur5, q, frames, backend.frame_poses(ur5, q, frames), ROUNDED_URDF)


# ---------------------------------------------------------------- trap: massless, bad inertia


def test_mujoco_fact_massless_moving_bodies_and_bad_inertias_are_refused(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="mass and inertia of moving bodies"):
        _compiled(ARM3_URDF)  # arm3's links have no <inertial>
    bad = ARM3_URDF.replace('<link name="l1"/>', f'<link name="l1">{_BAD_INERTIAL}</link>')
    with pytest.raises(ValueError, match=r"inertia must satisfy A \+ B >= C"):
        _compiled(bad, boundmass=1.0, boundinertia=1.0)


_BAD_INERTIAL = (
    '<inertial><mass value="1"/>'
    '<inertia ixx="1" iyy="1" izz="5" ixy="0" ixz="0" iyz="0"/></inertial>'
)


def test_massless_links_and_a_bad_inertia_do_not_stop_kinematics(
    backend: MujocoUrdf, tmp_path: Path, rng: np.random.Generator
) -> None:
    model = _arm3_with(tmp_path, '<link name="l1"/>', f'<link name="l1">{_BAD_INERTIAL}</link>')
    q = random_q(model, rng, 20)
    frames = mapped_frames(model)
    assert_every_pair_agrees(model, q, frames, backend.frame_poses(model, q, frames), ARM3_TOL)


# ---------------------------------------------------------------- trap: meshes


_COLLISION_MESH = (
    '<link name="l2"><collision><geometry><mesh filename="package://nowhere/l2.stl"/>'
    '</geometry></collision><visual><geometry><mesh filename="/no/such/l2.dae"/></geometry>'
    "</visual></link>"
)


def test_mujoco_fact_it_opens_collision_meshes_and_cannot_resolve_package_urls() -> None:
    text = ARM3_URDF.replace('<link name="l2"/>', _COLLISION_MESH)
    with pytest.raises(ValueError, match=r"Error opening file 'package:/nowhere/l2.stl'"):
        _compiled(text, boundmass=1.0, boundinertia=1.0)


def test_no_mesh_reaches_mujoco(backend: MujocoUrdf, tmp_path: Path) -> None:
    model = _arm3_with(tmp_path, '<link name="l2"/>', _COLLISION_MESH)
    q = np.array([[0.3, -0.2, 0.1]])
    frames = mapped_frames(model)
    assert_every_pair_agrees(model, q, frames, backend.frame_poses(model, q, frames), ARM3_TOL)
    text = kinematic_text(load_urdf(model), inertials=False)
    for tag in ("<mesh", "<collision", "<visual", "<inertial"):
        assert tag not in text
    mjmodel = backend._build(mujoco, model, load_urdf(model)).mjmodel
    assert (mjmodel.nmesh, mjmodel.ngeom) == (0, 0)


def test_the_kinematic_text_keeps_links_and_joints_only(tmp_path: Path) -> None:
    extension = '<mujoco><compiler meshdir="/etc" fusestatic="true"/></mujoco>'
    model = _arm3_with(tmp_path, '<link name="base"/>', '<link name="base"/>' + extension)
    text = kinematic_text(load_urdf(model), inertials=False)
    assert "<mujoco" not in text
    root = load_urdf(model)
    assert text.count("<link ") == len(root.links)
    assert text.count("<joint ") == len(root.joints)


# ---------------------------------------------------------------- trap: mimic joints


def test_a_dh_joint_mapped_onto_a_mimic_joint_is_refused_in_one_line(
    backend: MujocoUrdf, tmp_path: Path
) -> None:
    model = _arm3_with(
        tmp_path, '<axis xyz="0 0 -1"/>', '<axis xyz="0 0 -1"/><mimic joint="j1" multiplier="2"/>'
    )
    with pytest.raises(UrdfError, match=r"joint 'j2' mimics 'j1' in the URDF") as caught:
        backend.frame_poses(model, np.zeros((1, 3)), ["base", "tip"])
    assert "\n" not in str(caught.value)
    with pytest.raises(UrdfError, match=r"joint 'j2' mimics 'j1'"):
        backend.frame_jacobian(model, np.zeros((1, 3)), "tip", "local")


# Two unmapped mimic joints below arm3's tip: `grip` slides along x at 0.5·j1 + 0.02,
# `grip2` along y at −2·grip + 0.001 (a mimic of a mimic, declared before its leader).
_FINGERS = """<link name="tip"/>
  <link name="finger"/>
  <link name="finger2"/>
  <joint name="grip2" type="prismatic">
    <parent link="tip"/><child link="finger2"/><origin xyz="0 0 0" rpy="0 0 0"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/>
    <mimic joint="grip" multiplier="-2" offset="0.001"/>
  </joint>
  <joint name="grip" type="prismatic">
    <parent link="tip"/><child link="finger"/><origin xyz="0.01 0 0" rpy="0 0 0"/>
    <axis xyz="1 0 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/>
    <mimic joint="j1" multiplier="0.5" offset="0.02"/>
  </joint>"""
_FINGER_FRAMES = """
[frames.finger]
dh = "tcp"
urdf = "finger"

[frames.finger2]
dh = "tcp"
urdf = "finger2"
"""
_TIP_LINK = """<link name="tip">
    <visual><geometry><mesh filename="package://nowhere/tip.stl"/></geometry></visual>
  </link>"""


def test_mujoco_fact_a_mimic_tag_is_a_joint_equality() -> None:
    mjmodel = _compiled(ARM3_URDF.replace(_TIP_LINK, _FINGERS), boundmass=1.0, boundinertia=1.0)
    assert list(mjmodel.eq_type) == [mujoco.mjtEq.mjEQ_JOINT] * 2
    joints = [mujoco.mj_id2name(mjmodel, mujoco.mjtObj.mjOBJ_JOINT, i) for i in range(5)]
    pairs = {
        (joints[a], joints[b]) for a, b in zip(mjmodel.eq_obj1id, mjmodel.eq_obj2id, strict=True)
    }
    assert pairs == {("grip2", "grip"), ("grip", "j1")}
    coefs = sorted(tuple(row[:5]) for row in mjmodel.eq_data)
    assert coefs == [(0.001, -2.0, 0.0, 0.0, 0.0), (0.02, 0.5, 0.0, 0.0, 0.0)]


def test_unmapped_mimic_joints_follow_their_leader(
    backend: MujocoUrdf, tmp_path: Path, rng: np.random.Generator
) -> None:
    model = _arm3_with(tmp_path, _TIP_LINK, _FINGERS, _FINGER_FRAMES)
    q = random_q(model, rng, 20)
    tip, finger, finger2 = backend.frame_poses(model, q, ["tip", "finger", "finger2"])
    grip = 0.5 * q[:, 0] + 0.02
    expected = np.tile(np.eye(4), (20, 1, 1))
    expected[:, 0, 3] = 0.01 + grip
    assert_pose_close(relative_pose(tip, finger), expected, ARM3_TOL, "tip -> finger")
    expected = np.tile(np.eye(4), (20, 1, 1))
    expected[:, 1, 3] = -2.0 * grip + 0.001
    assert_pose_close(relative_pose(tip, finger2), expected, ARM3_TOL, "tip -> finger2")


@pytest.mark.parametrize("frame", ["finger", "finger2"])
def test_the_jacobian_of_a_mimic_follower_is_the_derivative_of_its_poses(
    backend: MujocoUrdf, tmp_path: Path, rng: np.random.Generator, frame: str
) -> None:
    # The mapped leader's column carries the followers' motion (chain rule).
    model = _arm3_with(tmp_path, _TIP_LINK, _FINGERS, _FINGER_FRAMES)
    q = random_q(model, rng, 5)
    h = FINITE_DIFFERENCE_STEP
    jac = backend.frame_jacobian(model, q, frame, "world-aligned")
    for j in range(model.dof):
        step = np.zeros(model.dof)
        step[j] = h
        plus = backend.frame_poses(model, q + step, [frame])[0]
        minus = backend.frame_poses(model, q - step, [frame])[0]
        velocity = (plus[:, :3, 3] - minus[:, :3, 3]) / (2 * h)
        np.testing.assert_allclose(jac[:, :3, j], velocity, rtol=0, atol=FINITE_DIFFERENCE)
    tip = backend.frame_jacobian(model, q, "tip", "world-aligned")
    assert np.abs(jac[:, :3, 0] - tip[:, :3, 0]).max() > 0.1  # j1's column moves the finger too


def test_mimic_joints_in_a_cycle_are_refused(backend: MujocoUrdf, tmp_path: Path) -> None:
    cycle = _FINGERS.replace('<mimic joint="j1"', '<mimic joint="grip2"')
    model = _arm3_with(tmp_path, _TIP_LINK, cycle, _FINGER_FRAMES)
    with pytest.raises(UrdfError, match=r"mimic joints follow each other in a cycle"):
        backend.frame_poses(model, np.zeros((1, 3)), ["tip"])


# ---------------------------------------------------------------- MuJoCo refusing a URDF


def test_a_urdf_mujoco_refuses_leaves_it_unavailable_in_one_line(
    backend: MujocoUrdf, tmp_path: Path
) -> None:
    # An axis shorter than MuJoCo's mjMINVAL (1e-15), which fkcheck's screen lets through:
    # MuJoCo's limit, not the input's, so the other readers still answer (issue 31).
    model = _arm3_with(tmp_path, '<axis xyz="0 0 -1"/>', '<axis xyz="0 0 1e-16"/>')
    match = r"^MuJoCo cannot read arm3\.urdf: Error: axis too small"
    with pytest.raises(BackendUnavailable, match=match) as caught:
        backend.frame_poses(model, np.zeros((1, 3)), ["base", "tip"])
    assert "\n" not in str(caught.value)


def test_poses_do_not_depend_on_the_chunk_size(
    backend: MujocoUrdf, monkeypatch: pytest.MonkeyPatch, rng: np.random.Generator
) -> None:
    import fkcheck.backends.mujoco_urdf as mujoco_urdf

    panda = load_model("panda")
    q = random_q(panda, rng, 10)
    frames = mapped_frames(panda)
    whole = backend.frame_poses(panda, q, frames)
    monkeypatch.setattr(mujoco_urdf, "_CHUNK", 3)  # chunks of 3, 3, 3 and 1
    np.testing.assert_array_equal(backend.frame_poses(panda, q, frames), whole)
    one_by_one = [backend.frame_poses(panda, q[k : k + 1], frames)[:, 0] for k in range(10)]
    np.testing.assert_array_equal(np.stack(one_by_one, axis=1), whole)


def test_an_unknown_jacobian_reference_is_refused(backend: MujocoUrdf) -> None:
    with pytest.raises(ValueError, match=r"unknown reference 'base'; references are: world-al"):
        backend.frame_jacobian(load_model("ur5"), np.zeros((1, 6)), "tool0", "base")  # type: ignore[arg-type]


def test_a_mujoco_warning_writes_no_file_in_the_working_directory(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # Equal joint limits make MuJoCo warn; by default it appends the warning to
    # MUJOCO_LOG.TXT in the working directory, a file no run asked for.
    import mujoco

    (tmp_path / "arm3.toml").write_text(ARM3_TOML)
    urdf = ARM3_URDF.replace('<limit lower="0" upper="0.2"', '<limit lower="0.1" upper="0.1"')
    assert urdf != ARM3_URDF
    (tmp_path / "arm3.urdf").write_text(urdf)
    monkeypatch.chdir(tmp_path)
    before = mujoco.get_mju_user_warning()
    poses = make_backend("mujoco-urdf").frame_poses(
        load_model(tmp_path / "arm3.toml"), np.zeros((2, 3)), ["base", "tip"]
    )
    assert poses.shape == (2, 2, 4, 4)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["arm3.toml", "arm3.urdf"]
    assert mujoco.get_mju_user_warning() is before  # the process's handler is put back
