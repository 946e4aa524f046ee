"""Reading a UR calibration in its three forms, and refusing what is not one."""

from __future__ import annotations

from pathlib import Path

import pytest

from fkcheck.calibration.ur_files import CalibrationError, read_ur_calibration
from fkcheck.io.files import InputFileError
from fkcheck.model.read import load_model
from tests.calibration.ur_test_data import (
    DELTAS,
    composed,
    write_conf,
    write_kinematics_info,
    write_yaml,
)


@pytest.mark.parametrize("name", sorted(DELTAS))
def test_conf_gives_urs_deltas_exactly(tmp_path: Path, name: str) -> None:
    _, status, d, a, theta, alpha = DELTAS[name]
    cal = read_ur_calibration(write_conf(tmp_path / "calibration.conf", name))
    assert cal.form == "calibration.conf"
    assert cal.delta is not None
    assert cal.delta.d == tuple(float(v) for v in d)
    assert cal.delta.a == tuple(float(v) for v in a)
    assert cal.delta.theta == tuple(float(v) for v in theta)
    assert cal.delta.alpha == tuple(float(v) for v in alpha)
    assert cal.status == status
    assert cal.checksums[0] == "0xb3241580"
    assert len(cal.sha256) == 64


@pytest.mark.parametrize("name", sorted(DELTAS))
def test_kinematics_info_gives_the_table_to_its_fifteen_digits(tmp_path: Path, name: str) -> None:
    nominal = load_model(DELTAS[name][0])
    table = composed(nominal.joints, name)
    cal = read_ur_calibration(write_kinematics_info(tmp_path / "info.txt", table, 2))
    assert cal.form == "KinematicsInfo"
    assert cal.table is not None
    for field in ("theta", "a", "d", "alpha"):
        for got, want in zip(cal.table.row(field), getattr(table, field), strict=True):
            assert got == pytest.approx(want, rel=1e-14, abs=1e-15)


def test_yaml_gives_the_links_and_the_hash(tmp_path: Path) -> None:
    nominal = load_model("ur10e")
    table = composed(nominal.joints, "ur10e-test-b")
    cal = read_ur_calibration(write_yaml(tmp_path / "calib.yaml", table, hash_="calib_42"))
    assert cal.form == "ur_calibration YAML"
    assert cal.hash == "calib_42"
    assert cal.links is not None
    assert [link.link for link in cal.links] == [
        "shoulder", "upper_arm", "forearm", "wrist_1", "wrist_2", "wrist_3"
    ]  # fmt: skip
    assert cal.links[0].xyz[2] == pytest.approx(table.d[0], abs=1e-15)


def test_urs_own_default_kinematics_yaml_is_read(tmp_path: Path) -> None:
    # The shape of UR's config/<type>/default_kinematics.yaml (ints, floats, -0).
    text = (
        "kinematics:\n"
        + "".join(
            f"  {link}:\n    x: 0\n    y: -0\n    z: 0.1625\n    roll: 1.570796327\n"
            "    pitch: 0\n    yaw: -0\n"
            for link in ("shoulder", "upper_arm", "forearm", "wrist_1", "wrist_2", "wrist_3")
        )
        + "  hash: calib_12788084448423163542\n"
    )
    path = tmp_path / "default_kinematics.yaml"
    path.write_text(text, encoding="utf-8")
    cal = read_ur_calibration(path)
    assert cal.links is not None
    assert cal.links[1].rpy == (1.570796327, 0.0, 0.0)


CONF = "[mounting]\ndelta_theta = [ 0, 0, 0, 0, 0, 0]\ndelta_a = [ 0, 0, 0, 0, 0, 0]\n"


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("hello\n", "not a UR calibration: expected the controller's calibration.conf"),
        (CONF, r"\[mounting\] has no delta_d"),
        (CONF + "delta_d = [ 0, 0, 0, 0, 0]\ndelta_alpha = [0,0,0,0,0,0]\n",
         "delta_d: expected 6 numbers, got 5"),
        (CONF + "delta_d = [ 0, 0, nan, 0, 0, 0]\ndelta_alpha = [0,0,0,0,0,0]\n",
         r"delta_d\[2\]: must be finite"),
        (CONF + "delta_d = [ 0, 0, 1e9, 0, 0, 0]\ndelta_alpha = [0,0,0,0,0,0]\n",
         r"delta_d\[2\]: 1e\+09 is beyond ±1000"),
        (CONF + "delta_d = 0\ndelta_alpha = [0,0,0,0,0,0]\n",
         r"delta_d: expected six numbers in \[ \]"),
        (CONF + "delta_d = [0,0,0,0,0,0]\ndelta_alpha = [0,0,0,0,0,0]\ncalibration_status = 7\n",
         "calibration_status: expected 0 .not initialised., 1 .not linearised. or 2"),
        (CONF + "delta_a = [0,0,0,0,0,0]\n", "not a calibration.conf: .*delta_a"),
        ("dh_theta: [0 0 0 0 0 0 ]\ndh_a: [0 0 0 0 0 0 ]\n",
         "KinematicsInfo without dh_d, dh_alpha"),
        ("dh_theta: [0 0 0 0 0 0 ]\ndh_theta: [0 0 0 0 0 0 ]\n", "dh_theta is given twice"),
        ("kinematics:\n  shoulder: {x: 0}\n", r"kinematics.shoulder.y: missing"),
        ("kinematics:\n  shoulder: 3\n", r"kinematics.shoulder: missing \(the links are"),
        ("kinematics: [1, 2]\n", "no 'kinematics' mapping"),
        ("kinematics:\n  shoulder: {x: !!python/object:os.system 1}\n", "line 2: "),
        ("kinematics:\n  shoulder: {x: .nan, y: 0, z: 0, roll: 0, pitch: 0, yaw: 0}\n",
         r"kinematics.shoulder.x: must be finite"),
        ("kinematics:\n  shoulder: {x: '1', y: 0, z: 0, roll: 0, pitch: 0, yaw: 0}\n",
         r"kinematics.shoulder.x: expected a number"),
    ],
)  # fmt: skip
def test_bad_calibration_is_one_line_naming_the_field(
    tmp_path: Path, text: str, match: str
) -> None:
    path = tmp_path / "cal.conf"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(CalibrationError, match=match) as info:
        read_ur_calibration(path)
    assert "\n" not in str(info.value)
    assert str(path) in str(info.value)


def test_a_yaml_of_aliases_is_refused_before_it_is_expanded(tmp_path: Path) -> None:
    lines = ["a0: &a0 [1, 1, 1, 1, 1, 1, 1, 1, 1]"]
    lines += [f"a{i}: &a{i} [*a{i - 1}, *a{i - 1}, *a{i - 1}, *a{i - 1}]" for i in range(1, 30)]
    lines += ["kinematics: *a29"]
    path = tmp_path / "bomb.yaml"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    with pytest.raises(CalibrationError, match="line 1: an anchor or alias"):
        read_ur_calibration(path)


@pytest.mark.parametrize("kind", ["missing", "directory", "large", "binary"])
def test_unreadable_files_are_one_line(tmp_path: Path, kind: str) -> None:
    path = tmp_path / "calibration.conf"
    if kind == "directory":
        path.mkdir()
    elif kind == "large":
        path.write_bytes(b"#" * (2 << 20))
    elif kind == "binary":
        path.write_bytes(b"[mounting]\n\xff\xfe\x00")
    with pytest.raises(InputFileError, match=str(path)) as info:
        read_ur_calibration(path)
    assert "\n" not in str(info.value)


def test_the_docs_calibration_files_are_urs_test_data_as_the_writers_write_it(tmp_path: Path):
    """The how-to's example files (tests/data/calibration/) are written, not hand-edited."""
    shipped = Path(__file__).parents[1] / "data" / "calibration" / "ur10e-test-b"
    conf = write_conf(tmp_path / "calibration.conf", "ur10e-test-b")
    table = composed(load_model("ur10e").joints, "ur10e-test-b")
    yaml = write_yaml(tmp_path / "robot_calibration.yaml", table)
    for written in (conf, yaml):
        assert (shipped / written.name).read_bytes() == written.read_bytes(), written.name
