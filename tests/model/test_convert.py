"""Model files written back out, and standard ⇄ modified conversion, proven equivalent."""

from __future__ import annotations

import math
import tomllib
from dataclasses import replace

import numpy as np
import pytest

from fkcheck import load_model
from fkcheck.cli.main import main
from fkcheck.core.geometry import matrix_from_rpy, matrix_from_xyz_rpy, rpy_from_matrix
from fkcheck.core.tolerances import ROUNDED_URDF, SAME_CHAIN
from fkcheck.engine.runner import run_check
from fkcheck.model.convert import convert_model, equivalence_error
from fkcheck.model.frames import reference_poses
from fkcheck.model.offsets import offset_from_matrix, snap
from fkcheck.model.read import model_from_dict
from fkcheck.model.types import UrdfSpec
from fkcheck.model.write import model_to_toml, relocate_urdf_path, toml_number
from tests.helpers import BUNDLED, assert_pose_close, random_q


def reload(model, **kwargs):
    return model_from_dict(tomllib.loads(model_to_toml(model, **kwargs)), model.path)


@pytest.mark.parametrize("name", BUNDLED)
def test_written_model_reads_back_as_the_same_model(name, rng):
    model = load_model(name)
    back = reload(model)
    assert back.name == model.name
    assert back.convention == model.convention
    assert back.joint_names == model.joint_names
    assert back.urdf == model.urdf
    assert back.check == model.check
    assert back.known_differences == model.known_differences  # xarm7, jaco2_6s, baxter_*
    assert back.lint_ignore == model.lint_ignore
    assert list(back.frames) == list(model.frames)
    for a, b in zip(back.joints, model.joints, strict=True):
        assert (a.type, a.flip) == (b.type, b.flip)
        np.testing.assert_allclose(
            [a.a, a.alpha, a.d, a.theta], [b.a, b.alpha, b.d, b.theta], rtol=0, atol=1e-15
        )
    q = random_q(model, rng, 50)
    assert_pose_close(
        reference_poses(back, q, list(model.frames)),
        reference_poses(model, q, list(model.frames)),
        SAME_CHAIN,
        name,
    )


def test_radians_are_written_exactly():
    model = load_model("panda")
    back = reload(model)
    assert back.joints == model.joints  # repr round-trips every float exactly
    assert reload(model, angle_unit="deg").angle_unit == "deg"


def test_degrees_read_back_are_snapped_to_the_written_value():
    # The worked_example pose: 30° → 0.5235987755982988 rad → 29.999999999999996°.
    model = load_model("ur5")
    text = model_to_toml(model)
    assert "worked_example = [30.0, -60.0, 90.0, -120.0, -90.0, 45.0]" in text
    assert "rpy = [0.0, 0.0, 180.0]" in text


def test_toml_number_refuses_non_finite_and_cleans_negative_zero():
    assert toml_number(-0.0) == "0.0"
    assert toml_number(1e-5) == "1e-05"
    assert tomllib.loads(f"x = {toml_number(1e-5)}")["x"] == 1e-5
    with pytest.raises(ValueError, match="finite"):
        toml_number(math.inf)


def test_rpy_from_matrix_inverts_urdf_rpy(rng):
    for rpy in rng.uniform(-3, 3, size=(100, 3)) * [1, 0.5, 1]:  # pitch within ±1.5
        np.testing.assert_allclose(rpy_from_matrix(matrix_from_rpy(rpy)), rpy, atol=1e-12)
    batch = rng.uniform(-1.5, 1.5, size=(7, 3))
    np.testing.assert_allclose(
        rpy_from_matrix(np.stack([matrix_from_rpy(r) for r in batch])), batch, atol=1e-12
    )


@pytest.mark.parametrize(
    ("pitch", "roll"),
    # Rz(0.5)·Ry(+π/2)·Rx(0.3) = Ry(+π/2)·Rx(0.3 - 0.5); Rz(0.5)·Ry(-π/2)·Rx(0.3) = Ry(-π/2)·Rx(0.8)
    [(math.pi / 2, 0.3 - 0.5), (-math.pi / 2, 0.3 + 0.5)],
)
def test_gimbal_lock_rule_is_one_rule_for_every_caller(pitch, roll):
    from fkcheck.core.pose_formats import pose_from_matrix
    from fkcheck.report.measures import pose_forms

    T = matrix_from_xyz_rpy([0.1, 0.2, 0.3], [0.3, pitch, 0.5])
    rpy = rpy_from_matrix(T)
    # The rule: yaw is 0 and roll carries the whole rotation about the locked axis.
    np.testing.assert_allclose(rpy, [roll, pitch, 0.0], atol=1e-15)
    assert rpy[2] == 0.0
    np.testing.assert_allclose(matrix_from_rpy(rpy), T[:3, :3], atol=1e-15)
    # Every caller reports that same triple.
    np.testing.assert_allclose(offset_from_matrix(T).rpy, rpy, atol=1e-15)
    np.testing.assert_allclose(pose_from_matrix(T, "rpy")[3:], rpy, atol=0)
    np.testing.assert_allclose(pose_from_matrix(T, "zyx")[3:], rpy[::-1], atol=0)
    degrees = ", ".join(f"{v:.6f}" for v in np.degrees(rpy))
    assert pose_forms(T).rpy == f"({degrees})°"


def test_snap_cleans_round_off_only():
    assert snap(3.1415926535897927, angle=True) == math.pi
    assert snap(-1.5707963267948963, angle=True) == -math.pi / 2
    assert snap(1.5708, angle=True) == 1.5708  # a rounded design value is kept
    assert snap(3e-17, angle=False) == 0.0
    offset = offset_from_matrix(matrix_from_xyz_rpy([1e-17, 0.2, 0], [0, 0, math.pi]))
    assert offset.xyz == (0.0, 0.2, 0.0)
    assert offset.rpy == (0.0, 0.0, math.pi)


@pytest.mark.parametrize("name", BUNDLED)
def test_conversion_keeps_every_named_frame(name, rng):
    model = load_model(name)
    other = "modified" if model.convention == "standard" else "standard"
    converted = convert_model(model, other)
    assert converted.convention == other
    q = random_q(model, rng, 200)
    pos, rot = equivalence_error(model, converted, q)
    assert pos <= SAME_CHAIN
    assert rot <= SAME_CHAIN
    # Through a file and back, and converted back again: the original table, except
    # that the end link's Tx(a)·Rx(α) has moved into the tool (standard: last row) or
    # the base (modified: first row).
    back = convert_model(reload(converted), model.convention)
    moved = -1 if model.convention == "standard" else 0
    for i, (a, b) in enumerate(zip(back.joints, model.joints, strict=True)):
        expected = [b.a, b.alpha, b.d, b.theta]
        if i % model.dof == moved % model.dof:
            expected[:2] = [0.0, 0.0]
        np.testing.assert_allclose([a.a, a.alpha, a.d, a.theta], expected, rtol=0, atol=1e-15)
    end = model.joints[moved]
    factor = matrix_from_xyz_rpy([end.a, 0, 0], [end.alpha, 0, 0])
    if model.convention == "standard":
        np.testing.assert_allclose(back.tool.matrix, factor @ model.tool.matrix, atol=1e-15)
    else:
        np.testing.assert_allclose(back.base.matrix, model.base.matrix @ factor, atol=1e-15)


def test_panda_as_standard_dh_has_the_shifted_rows():
    std = convert_model(load_model("panda"), "standard")
    # Row i takes modified row i+1's a and α (Craig → standard), the last row has none.
    assert [j.a for j in std.joints] == [0.0, 0.0, 0.0825, -0.0825, 0.0, 0.088, 0.0]
    half = math.pi / 2
    assert [j.alpha for j in std.joints] == [-half, half, half, -half, half, half, 0.0]
    assert [j.d for j in std.joints] == [0.333, 0.0, 0.316, 0.0, 0.384, 0.0, 0.0]
    assert std.base.is_identity  # modified row 1 has a = α = 0
    assert std.tool.xyz == (0.0, 0.0, 0.107)


def test_ur5_as_modified_dh_moves_nothing_into_the_tool():
    mod = convert_model(load_model("ur5"), "modified")
    assert [j.a for j in mod.joints] == [0.0, 0.0, -0.425, -0.39225, 0.0, 0.0]
    assert mod.tool.is_identity  # UR5's a6 = α6 = 0
    # DH frame 1 of the standard table is modified frame 1 · Rx(π/2): tool0 at dh 6 stays.
    assert mod.frames["tool0"].offset.is_identity


@pytest.mark.parametrize(
    ("name", "pair"),
    [
        ("panda", ("panda_link0", "panda_link3")),
        ("panda", ("panda_link2", "panda_hand")),
        ("ur5", ("base_link", "flange")),
    ],
)
def test_converted_model_passes_the_check_against_its_urdf_mid_chain(name, pair):
    from fkcheck.backends.registry import make_backend

    model = load_model(name)
    converted = convert_model(model, "modified" if model.convention == "standard" else "standard")
    result = run_check(
        converted,
        [make_backend("pinocchio-urdf")],
        samples=200,
        frame_from=pair[0],
        frame_to=pair[1],
    )
    assert result.verdict == "pass", result.backends[0].message
    assert result.backends[0].max_position_error_m < ROUNDED_URDF


def test_relocated_urdf_path_points_at_the_same_file(tmp_path):
    (tmp_path / "robots" / "urdf").mkdir(parents=True)
    urdf = tmp_path / "robots" / "urdf" / "arm.urdf"
    urdf.write_text("<robot name='arm'/>")
    model = replace(
        load_model("ur5"),
        path=tmp_path / "robots" / "arm.toml",
        urdf=UrdfSpec("urdf/arm.urdf", load_model("ur5").urdf.joints),
    )
    moved = relocate_urdf_path(model, tmp_path / "out" / "deep" / "arm_mod.toml")
    assert moved.urdf.path == "../../robots/urdf/arm.urdf"
    assert (tmp_path / "out" / "deep" / moved.urdf.path).resolve() == urdf.resolve()
    assert relocate_urdf_path(load_model("ur5"), tmp_path / "x.toml").urdf == load_model("ur5").urdf


def test_cli_convert_writes_a_loadable_equivalent_file(tmp_path, capsys):
    out = tmp_path / "panda_std.toml"
    assert main(["convert", "panda", "--to", "standard", "-o", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "panda modified → standard: equivalent" in printed
    written = load_model(out)
    assert written.convention == "standard"
    q = random_q(written, np.random.default_rng(1), 100)
    pos, rot = equivalence_error(load_model("panda"), written, q)
    assert max(pos, rot) <= SAME_CHAIN


def test_cli_convert_prints_toml_without_output(capsys):
    assert main(["convert", "ur5", "--to", "modified"]) == 0
    out, err = capsys.readouterr()
    assert tomllib.loads(out)["convention"] == "modified"
    assert "equivalent over" in err


def test_cli_convert_bad_convention_is_a_usage_error(capsys):
    assert main(["convert", "ur5", "--to", "craig"]) == 2
    assert "invalid choice: 'craig'" in capsys.readouterr().err
