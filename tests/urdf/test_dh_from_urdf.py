"""table-from: the extracted table must pass the check against the URDF it came from."""

from __future__ import annotations

import math

import numpy as np
import pytest

import fkcheck.backends.registry as registry
from fkcheck import load_model
from fkcheck.cli.main import main
from fkcheck.core.tolerances import ROUNDED_URDF
from fkcheck.engine.runner import run_check
from fkcheck.errors import FrameError, UrdfError
from fkcheck.urdf.chain import axis_rotation, read_urdf_file
from fkcheck.urdf.locate import example_robot_data_dir
from fkcheck.urdf.to_dh import dh_from_urdf
from tests.backend_cases import URDF_BACKENDS

#: Every serial arm (or serial chain of a robot) in example-robot-data: URDF, base, tip.
ARMS = [
    ("ur_description/urdf/ur3_robot.urdf", "base_link", "tool0"),
    ("ur_description/urdf/ur5_robot.urdf", "base", "ee_link"),  # base hangs off base_link
    ("ur_description/urdf/ur10_robot.urdf", "base_link", "tool0"),
    ("ur_description/urdf/ur5_joint_limited_robot.urdf", "base_link", "tool0"),
    ("panda_description/urdf/panda.urdf", "panda_link0", "panda_hand_tcp"),
    ("kinova_description/robots/kinova.urdf", "base", "j2s6s200_end_effector"),
    ("xarm_description/urdf/xarm7.urdf", "world", "link_eef"),
    ("z1_description/urdf/z1.urdf", "world", "gripperMover"),
    ("so_arm_description/urdf/so100.urdf", "base", "jaw"),
    ("so_arm_description/urdf/so101.urdf", "base_link", "gripper_frame_link"),
    ("bravo7_description/urdf/bravo7_no_ee.urdf", "link1", "end_effector_ball"),
    ("talos_data/robots/talos_left_arm.urdf", "arm_left_1_link", "gripper_left_base_link"),
    ("finger_edu_description/robots/finger_edu.urdf", "base_link", "finger_tip_link"),
    ("double_pendulum_description/urdf/double_pendulum.urdf", "base_link", "link2"),
    ("asr_twodof_description/urdf/TwoDofs.urdf", "world", "Tip"),
    ("anymal_b_simple_description/robots/anymal-kinova.urdf", "base", "j2s6s200_end_effector"),
    ("tiago_description/robots/tiago.urdf", "base_footprint", "arm_tool_link"),  # prismatic torso
]


def urdf_backends(spec):
    """The registry's URDF backends (every one parses every ARMS file: geometry-free
    parsers get the links and joints alone, so talos' cut-down <transmission> naming a
    joint the file lacks no longer stops Robotics Toolbox's reader)."""
    return [registry.make_backend(n) for n in URDF_BACKENDS]


def extract(spec, base, tip, convention):
    _, _, kin = read_urdf_file("example-robot-data:" + spec)
    return dh_from_urdf(kin, base, tip, convention, urdf_spec="example-robot-data:" + spec)


@pytest.mark.parametrize("convention", ["standard", "modified"])
@pytest.mark.parametrize(("spec", "base", "tip"), ARMS, ids=[a[0].split("/")[-1] for a in ARMS])
def test_extracted_table_passes_the_check_in_every_urdf_backend(
    spec, base, tip, convention, tmp_path
):
    out = tmp_path / "arm.toml"
    assert (
        main(
            [
                "table-from",
                "example-robot-data:" + spec,
                "--base",
                base,
                "--tip",
                tip,
                "--convention",
                convention,
                "-o",
                str(out),
            ]
        )
        == 0
    )
    model = load_model(out)  # the written file follows the model schema
    assert model.convention == convention
    assert not any(j.flip for j in model.joints)
    result = run_check(model, urdf_backends(spec), samples=64, seed=3)
    for r in result.backends:
        assert r.status == "pass", f"{r.name}: {r.message}"
        assert r.max_position_error_m < ROUNDED_URDF
    assert result.verdict == "pass"


@pytest.mark.parametrize(("spec", "base", "tip"), ARMS, ids=[a[0].split("/")[-1] for a in ARMS])
def test_every_chain_link_agrees_mid_chain(spec, base, tip):
    model = extract(spec, base, tip, "standard").model
    mapped = [n for n, f in model.frames.items() if f.urdf is not None]
    middle = mapped[len(mapped) // 2]
    backend = registry.make_backend("pinocchio-urdf")
    for pair in ((base, middle), (middle, tip)):
        result = run_check(model, [backend], samples=32, frame_from=pair[0], frame_to=pair[1])
        assert result.verdict == "pass", (pair, result.backends[0].message)


def test_ur5_table_has_the_published_lengths():
    ex = extract("ur_description/urdf/ur5_robot.urdf", "base_link", "tool0", "standard")
    model = ex.model
    assert ex.relations == ("intersecting", "parallel", "parallel", "intersecting", "intersecting")
    # UR's published d and |a| (the signs of a and α depend on the x directions chosen).
    np.testing.assert_allclose(
        [j.d for j in model.joints], [0.089159, 0, 0, 0.10915, 0.09465, 0.0823], atol=1e-12
    )
    np.testing.assert_allclose(
        [abs(j.a) for j in model.joints], [0, 0.425, 0.39225, 0, 0, 0], atol=1e-12
    )
    np.testing.assert_allclose(
        [abs(j.alpha) for j in model.joints],
        [math.pi / 2, 0, 0, math.pi / 2, math.pi / 2, 0],
        atol=1e-11,
    )
    # θ offsets within ±90° by construction, except where the tip's x decides (the last).
    assert all(abs(j.theta) <= math.pi / 2 + 1e-9 for j in model.joints[:-1])
    assert model.urdf.path == "example-robot-data:ur_description/urdf/ur5_robot.urdf"
    assert model.check.frame_from == "base_link"
    assert model.check.frame_to == "tool0"
    assert model.frames["base_link"].dh == "world"
    assert model.frames["tool0"].dh == "tcp"


def test_panda_modified_table_matches_franka_up_to_frame_choices():
    model = extract(
        "panda_description/urdf/panda.urdf", "panda_link0", "panda_link8", "modified"
    ).model
    # Franka publishes a = [0, 0, 0, 0.0825, -0.0825, 0, 0.088], d = [0.333, 0, 0.316, 0,
    # 0.384, 0, 0] and a 0.107 flange; lengths agree up to the signs of the chosen x.
    np.testing.assert_allclose(
        [abs(j.a) for j in model.joints], [0, 0, 0, 0.0825, 0.0825, 0, 0.088], atol=1e-12
    )
    np.testing.assert_allclose(
        [abs(j.d) for j in model.joints], [0.333, 0, 0.316, 0, 0.384, 0, 0.107], atol=1e-12
    )


def test_prismatic_joint_is_extracted_as_prismatic():
    model = extract(
        "tiago_description/robots/tiago.urdf", "base_footprint", "arm_tool_link", "standard"
    ).model
    assert model.joints[0].type == "prismatic"
    assert model.joints[0].name == "torso_lift_joint"
    assert all(j.type == "revolute" for j in model.joints[1:])


def test_errors_name_the_problem():
    _, _, kin = read_urdf_file("example-robot-data:ur_description/urdf/ur5_robot.urdf")
    with pytest.raises(FrameError, match=r"frame 'flange' not in URDF ur5_robot\.urdf"):
        dh_from_urdf(kin, "base_link", "flange")
    with pytest.raises(UrdfError, match="'base_link' is not below link 'tool0'"):
        dh_from_urdf(kin, "tool0", "base_link")
    with pytest.raises(UrdfError, match="through the movable joint 'wrist_3_joint'"):
        dh_from_urdf(kin, "tool0", "base")
    with pytest.raises(UrdfError, match="no movable joint between 'base_link' and 'base'"):
        dh_from_urdf(kin, "base_link", "base")


def test_mimic_joint_is_refused(tmp_path):
    urdf = tmp_path / "mimic.urdf"
    urdf.write_text(
        "<robot name='m'><link name='a'/><link name='b'/><link name='c'/>"
        "<joint name='j1' type='revolute'><parent link='a'/><child link='b'/>"
        "<axis xyz='0 0 1'/><limit lower='-1' upper='1' effort='1' velocity='1'/></joint>"
        "<joint name='j2' type='revolute'><parent link='b'/><child link='c'/>"
        "<origin xyz='1 0 0'/><axis xyz='0 0 1'/><mimic joint='j1'/>"
        "<limit lower='-1' upper='1' effort='1' velocity='1'/></joint></robot>"
    )
    _, _, kin = read_urdf_file(urdf)
    with pytest.raises(UrdfError, match="joint 'j2' mimics 'j1'"):
        dh_from_urdf(kin, "a", "c")


def test_cli_missing_urdf_is_exit_2(capsys, tmp_path):
    assert main(["table-from", str(tmp_path / "nope.urdf"), "--base", "a", "--tip", "b"]) == 2
    assert "nope.urdf: no such file" in capsys.readouterr().err


def test_cli_prints_the_model_without_output(capsys):
    import tomllib

    spec = "example-robot-data:double_pendulum_description/urdf/double_pendulum.urdf"
    assert main(["table-from", spec, "--base", "base_link", "--tip", "link2"]) == 0
    out, err = capsys.readouterr()
    data = tomllib.loads(out)
    assert [j["name"] for j in data["joint"]] == ["joint1", "joint2"]
    assert "consecutive axes: parallel" in err


def test_urdf_fk_matches_pinocchio(rng):
    """fkcheck's own URDF FK (used for geometry) against Pinocchio, on every arm."""
    import pinocchio as pin

    for spec, base, tip in ARMS:
        _, text, kin = read_urdf_file("example-robot-data:" + spec)
        chain = kin.chain(base, tip)
        movable = kin.movable(chain)
        pmodel = pin.buildModelFromXML(text)
        data = pmodel.createData()
        for _ in range(5):
            q = rng.uniform(-2, 2, len(movable))
            q_pin = pin.neutral(pmodel)
            for joint, value in zip(movable, q, strict=True):
                jm = pmodel.joints[pmodel.getJointId(joint.name)]
                if jm.nq == 1:
                    q_pin[jm.idx_q] = value
                else:
                    q_pin[jm.idx_q : jm.idx_q + 2] = math.cos(value), math.sin(value)
            pin.framesForwardKinematics(pmodel, data, q_pin)
            oMb = data.oMf[pmodel.getFrameId(base)].homogeneous
            oMt = data.oMf[pmodel.getFrameId(tip)].homogeneous
            ours = kin.chain_poses(chain, q[None])[0, -1]
            np.testing.assert_allclose(ours, np.linalg.inv(oMb) @ oMt, atol=1e-12, err_msg=spec)


def test_axis_rotation_is_rodrigues():
    axis = np.array([0.0, 0.0, 1.0])
    np.testing.assert_allclose(
        axis_rotation(axis, math.pi / 2)[:3, :3], [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-16
    )
    # Batched: one 4×4 per angle; about x, a quarter turn takes y to z.
    batch = axis_rotation(np.array([1.0, 0.0, 0.0]), np.array([0.0, math.pi / 2, math.pi]))
    assert batch.shape == (3, 4, 4)
    np.testing.assert_allclose(batch[0], np.eye(4), atol=1e-16)
    np.testing.assert_allclose(batch[1, :3, 1], [0, 0, 1], atol=1e-16)
    np.testing.assert_allclose(batch[2], np.diag([1.0, -1.0, -1.0, 1.0]), atol=1e-15)


def test_every_listed_urdf_exists():
    robots = example_robot_data_dir()
    assert all((robots / spec).is_file() for spec, _, _ in ARMS)
